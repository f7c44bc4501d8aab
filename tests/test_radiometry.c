/* test_radiometry.c — the rasterizer's direct light against closed forms:
 * a diffuse plane of albedo ρ under a directional light of irradiance E at
 * angle θ has radiance ρ·E·cosθ/π; under a spot/point light of intensity I
 * at distance d, ρ·I·cosθ/(π·d²). Each checked within 1% at pixels whose
 * world point is found by intersecting the pixel's ray with the plane. */
#include <math.h>

#include "test_util.h"

static const float k_rho = 0.5f;
enum { W = 128, H = 128 };

/* A 4 m × 4 m plane at y = 0 of albedo ρ, seen from above. */
static void plane_scene(Scene *s)
{
    scene_init(s);
    int m = scene_add_material(s, "plane", (vec3){k_rho, k_rho, k_rho});
    test_add_square(s, m, (vec3){0, 0, 0}, 4.f);
    glm_vec3_copy((vec3){0.1f, 3.f, 0.2f}, s->camera.position);
    glm_vec3_copy((vec3){0, -1, 0}, s->camera.forward);
    glm_vec3_copy((vec3){0, 0, -1}, s->camera.up);
    s->camera.fov_y = glm_rad(50.f);
}


static void expect_pixel(const ImageF *img, int x, int y, const float *expected)
{
    const float *px = image_px(img, x, y);
    for (int c = 0; c < 3; c++) {
        double rel = fabs(px[c] - expected[c]) / expected[c];
        if (rel > 0.01)
            fail_msg("pixel (%d,%d) channel %d: %g, expected %g (%.2f%% off)", x, y, c, px[c], expected[c],
                     100 * rel);
    }
}

static void directional_plane(void **state)
{
    (void)state;
    Scene s;
    plane_scene(&s);
    const float theta = glm_rad(30.f);
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {sinf(theta), -cosf(theta), 0},
                 .color = {2.f, 1.f, 0.5f}};
    scene_add_light(&s, &sun);
    scene_finalize(&s);
    RenderSettings rs = test_settings(&s, W, H, SHADOW_MODE_HARD);
    ImageF img;
    test_render(&s, &rs, &img);
    for (int y = 16; y < H; y += 24)
        for (int x = 16; x < W; x += 24) {
            float e[3];
            for (int c = 0; c < 3; c++)
                e[c] = k_rho * sun.color[c] * cosf(theta) / GLM_PIf;
            expect_pixel(&img, x, y, e);
        }
    image_free(&img);
    scene_free(&s);
}

/* Checks every 24th pixel against ρ·I(ω)·cosθ/(π·d²) of light `l`. */
static void check_local_light(const Scene *s, const Light *l, const ImageF *img)
{
    int checked = 0;
    for (int y = 8; y < H; y += 24)
        for (int x = 8; x < W; x += 24) {
            vec3 p, to_l, dir, inten;
            test_pixel_plane_point(s, W, H, x, y, p);
            glm_vec3_sub((float *)l->position, p, to_l);
            float d = glm_vec3_norm(to_l);
            glm_vec3_scale(to_l, -1.f / d, dir);
            light_intensity(l, dir, inten);
            float cos_t = to_l[1] / d;
            float e[3];
            for (int c = 0; c < 3; c++)
                e[c] = k_rho * inten[c] * cos_t / (GLM_PIf * d * d);
            if (e[0] < 1e-3f || e[1] < 1e-3f || e[2] < 1e-3f)
                continue; /* outside a cone */
            expect_pixel(img, x, y, e);
            checked++;
        }
    assert_true(checked >= 9);
}

static void spot_plane(void **state)
{
    (void)state;
    Scene s;
    plane_scene(&s);
    Light spot = {.type = LIGHT_SPOT, .position = {0.2f, 1.2f, -0.1f}, .direction = {0.1f, -1.f, 0.05f},
                  .color = {3.f, 2.f, 1.f}, .spot_inner = glm_rad(35.f), .spot_outer = glm_rad(55.f)};
    scene_add_light(&s, &spot);
    scene_finalize(&s);
    RenderSettings rs = test_settings(&s, W, H, SHADOW_MODE_HARD);
    ImageF img;
    test_render(&s, &rs, &img);
    check_local_light(&s, &s.lights[0], &img);
    image_free(&img);
    scene_free(&s);
}

static void point_plane(void **state)
{
    (void)state;
    Scene s;
    plane_scene(&s);
    Light pt = {.type = LIGHT_POINT, .position = {-0.3f, 0.9f, 0.25f}, .direction = {0, -1, 0},
                .color = {1.f, 2.f, 3.f}};
    scene_add_light(&s, &pt);
    scene_finalize(&s);
    RenderSettings rs = test_settings(&s, W, H, SHADOW_MODE_HARD); /* cube map, no self-shadow */
    ImageF img;
    test_render(&s, &rs, &img);
    check_local_light(&s, &s.lights[0], &img);
    image_free(&img);
    scene_free(&s);
}

/* A quad light of size 0 is a point with I(θ) = L·A·cosθ. */
static void quad_light_as_point(void **state)
{
    (void)state;
    Scene s;
    plane_scene(&s);
    Light q = {.type = LIGHT_QUAD, .position = {0.1f, 1.0f, 0.f}, .direction = {0, -1, 0},
               .color = {20.f, 10.f, 5.f}, .quad_u = {0.2f, 0, 0}, .quad_v = {0, 0, 0.3f}, .size = 0.f};
    scene_add_light(&s, &q);
    scene_finalize(&s);
    RenderSettings rs = test_settings(&s, W, H, SHADOW_MODE_HARD);
    ImageF img;
    test_render(&s, &rs, &img);
    check_local_light(&s, &s.lights[0], &img);
    image_free(&img);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(directional_plane),
        cmocka_unit_test(spot_plane),
        cmocka_unit_test(point_plane),
        cmocka_unit_test(quad_light_as_point),
    };
    return cmocka_run_group_tests_name("radiometry", tests, test_gl_setup, test_gl_teardown);
}
