/* test_math.c — light and camera matrices, sample patterns, light model.
 * No GL. Expected values are derived by hand in the comments. */
#include <math.h>

#include "test_util.h"
#include "core/camera.h"
#include "frame/pass_direct.h"
#include "gpu/shadow_frame.h"

static const vec3 k_min = {-1, -1, -1}, k_max = {1, 1, 1};

/* Sun straight down over the cube [-1,1]³: the ortho frame looks down from
 * the bounding sphere's top (r = √3·1.01 + 1e-3), up = +z, so right = -x.
 * u = 0.5 + x_view/(2r), x_view = -x; v = 0.5 + z/(2r); depth = (r - y)/(2r). */
static void directional_mvp_maps_known_points(void **state)
{
    (void)state;
    Light l = {.type = LIGHT_DIRECTIONAL, .direction = {0, -1, 0}};
    ShadowFrame f;
    shadow_frame_compute(&l, k_min, k_max, 1024, 0, &f);
    float r = sqrtf(3.f) * 1.01f + 1e-3f;
    vec3 uvd;
    shadow_frame_project(&f, &l, (vec3){0, 0, 0}, uvd);
    assert_float_equal(uvd[0], 0.5f, 1e-5);
    assert_float_equal(uvd[1], 0.5f, 1e-5);
    assert_float_equal(uvd[2], 0.5f, 1e-5);
    shadow_frame_project(&f, &l, (vec3){0.5f, -0.5f, 0.25f}, uvd);
    assert_float_equal(uvd[0], 0.5f - 0.25f / r, 1e-5);
    assert_float_equal(uvd[1], 0.5f + 0.125f / r, 1e-5);
    assert_float_equal(uvd[2], (r + 0.5f) / (2.f * r), 1e-5);
    /* The texel size is the ortho width over the resolution. */
    assert_float_equal(f.texel_k, 2.f * r / 1024.f, 1e-6);

    /* A slanted sun: points on the axis through the centre map to the
     * middle of the map at depth (r + t)/(2r). */
    Light s = {.type = LIGHT_DIRECTIONAL, .direction = {0.6f, -0.8f, 0}};
    shadow_frame_compute(&s, k_min, k_max, 512, 0, &f);
    for (float t = -1.f; t <= 1.f; t += 0.5f) {
        vec3 p = {0.6f * t, -0.8f * t, 0};
        shadow_frame_project(&f, &s, p, uvd);
        assert_float_equal(uvd[0], 0.5f, 1e-5);
        assert_float_equal(uvd[1], 0.5f, 1e-5);
        assert_float_equal(uvd[2], (r + t) / (2.f * r), 1e-5);
    }
}

/* Spot at (0,2,0) pointing down, outer 30°: fov = 63°. A floor point at x
 * lies at angle atan(x/2): u = 0.5 - (x/2)/(2·tan 31.5°) (right = -x),
 * depth = distance / far. */
static void spot_mvp_maps_known_points(void **state)
{
    (void)state;
    Light l = {.type = LIGHT_SPOT, .position = {0, 2, 0}, .direction = {0, -1, 0},
               .spot_inner = glm_rad(25.f), .spot_outer = glm_rad(30.f)};
    ShadowFrame f;
    shadow_frame_compute(&l, k_min, k_max, 256, 0, &f);
    vec3 uvd;
    shadow_frame_project(&f, &l, (vec3){0, 0, 0}, uvd);
    assert_float_equal(uvd[0], 0.5f, 1e-5);
    assert_float_equal(uvd[1], 0.5f, 1e-5);
    assert_float_equal(uvd[2] * f.far, 2.f, 1e-5);
    float t = tanf(glm_rad(31.5f));
    shadow_frame_project(&f, &l, (vec3){0.4f, 0, 0}, uvd);
    assert_float_equal(uvd[0], 0.5f - 0.5f * (0.4f / 2.f) / t, 1e-4);
    assert_float_equal(uvd[1], 0.5f, 1e-5);
    assert_float_equal(uvd[2] * f.far, sqrtf(4.f + 0.16f), 1e-5);
    shadow_frame_project(&f, &l, (vec3){0, 1, -0.3f}, uvd); /* up = +z, so v = 0.5 + (z/1)/(2t) */
    assert_float_equal(uvd[1], 0.5f - 0.5f * 0.3f / t, 1e-4);
    assert_float_equal(f.texel_k, 2.f * t / 256.f, 1e-6);
}

/* Point lights use six 90° faces; each face's centre direction maps to the
 * middle of that face. */
static void cube_faces_look_along_axes(void **state)
{
    (void)state;
    Light l = {.type = LIGHT_POINT, .position = {0.1f, 0.2f, 0.3f}};
    ShadowFrame f;
    shadow_frame_compute(&l, k_min, k_max, 128, 0, &f);
    assert_int_equal(f.face_count, 6);
    static const float dirs[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int i = 0; i < 6; i++) {
        vec4 p = {0.1f + 0.5f * dirs[i][0], 0.2f + 0.5f * dirs[i][1], 0.3f + 0.5f * dirs[i][2], 1};
        glm_mat4_mulv(f.view_proj[i], p, p);
        assert_float_equal(p[0] / p[3], 0.f, 1e-5);
        assert_float_equal(p[1] / p[3], 0.f, 1e-5);
        assert_true(p[3] > 0.f);
    }
    assert_float_equal(f.texel_k, 2.f / 128.f, 1e-7);
}

/* Camera: the point straight ahead projects to the image centre; a point at
 * the top of the vertical field of view to row 0. */
static void camera_projects_known_points(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    float px, py;
    const Camera *c = &s.camera;
    vec3 ahead = {c->position[0], c->position[1], c->position[2] + 1.f};
    assert_true(camera_project(c, 512, 256, ahead, &px, &py));
    assert_float_equal(px, 256.f, 1e-3);
    assert_float_equal(py, 128.f, 1e-3);
    vec3 top = {c->position[0], c->position[1] + tanf(0.5f * c->fov_y), c->position[2] + 1.f};
    assert_true(camera_project(c, 512, 256, top, &px, &py));
    assert_float_equal(py, 0.f, 1e-3);
    /* The red wall (x = 0.55) is on the left of the image. */
    vec3 red = {0.55f, 0.27f, 0.3f};
    assert_true(camera_project(c, 512, 512, red, &px, &py));
    assert_true(px < 100.f);
    vec3 dir;
    camera_ray(c, 512, 512, 256.f, 256.f, dir);
    assert_float_equal(dir[2], 1.f, 1e-6);
    scene_free(&s);
}

static void poisson_disk_inside_unit_disk(void **state)
{
    (void)state;
    float p[64][4];
    poisson_disk_spiral(20, 10, p);
    double mean_r = 0;
    for (int i = 0; i < 20; i++) {
        float r = sqrtf(p[i][0] * p[i][0] + p[i][1] * p[i][1]);
        assert_true(r > 0.f && r <= 1.f + 1e-6f);
        mean_r += r / 20;
        for (int j = 0; j < i; j++) /* distinct points */
            assert_true(fabsf(p[i][0] - p[j][0]) + fabsf(p[i][1] - p[j][1]) > 1e-3f);
    }
    /* r = ((i+1)/n)^0.75 averages to about 0.58 over a uniform-ish disk. */
    assert_true(mean_r > 0.5 && mean_r < 0.66);
}

/* The shared light model: spot smoothstep and quad L·A·cosθ. */
static void light_model_values(void **state)
{
    (void)state;
    Light spot = {.type = LIGHT_SPOT, .direction = {0, -1, 0}, .color = {2, 2, 2},
                  .spot_inner = glm_rad(20.f), .spot_outer = glm_rad(40.f)};
    assert_float_equal(light_spot_falloff(&spot, cosf(glm_rad(10.f))), 1.f, 1e-6);
    assert_float_equal(light_spot_falloff(&spot, cosf(glm_rad(45.f))), 0.f, 1e-6);
    float c_mid = 0.5f * (cosf(glm_rad(20.f)) + cosf(glm_rad(40.f)));
    assert_float_equal(light_spot_falloff(&spot, c_mid), 0.5f, 1e-5);
    Light q = {.type = LIGHT_QUAD, .direction = {0, -1, 0}, .color = {10, 5, 1}, .size = 1.f,
               .quad_u = {0.2f, 0, 0}, .quad_v = {0, 0, 0.5f}};
    vec3 dir = {0, -cosf(glm_rad(60.f)), sinf(glm_rad(60.f))}, out;
    light_intensity(&q, dir, out);
    assert_float_equal(out[0], 10.f * 0.1f * 0.5f, 1e-5);
    assert_float_equal(light_quad_area(&q), 0.1f, 1e-6);
    vec3 up = {0, 1, 0};
    light_intensity(&q, up, out); /* emits downward only */
    assert_float_equal(out[1], 0.f, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(directional_mvp_maps_known_points), cmocka_unit_test(spot_mvp_maps_known_points),
        cmocka_unit_test(cube_faces_look_along_axes),        cmocka_unit_test(camera_projects_known_points),
        cmocka_unit_test(poisson_disk_inside_unit_disk),     cmocka_unit_test(light_model_values),
    };
    return cmocka_run_group_tests_name("math", tests, NULL, NULL);
}
