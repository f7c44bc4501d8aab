/* test_direct.c — the direct pass draws each light with a program built for
 * its light type, shadow mode and filter bias (and, without glossy
 * materials, the diffuse BRDF only), the first light of a frame unblended
 * into an uncleared target (issue 11). None of that may change the image:
 * every variant's frame equals the general program's bit for bit, for each
 * light type, shadow mode and filter bias, with one and with two lights
 * (the second blended onto the first), diffuse-only and glossy. */
#include <stdlib.h>
#include <string.h>

#include "test_util.h"

static size_t differing_pixels(const ImageF *a, const ImageF *b)
{
    size_t n = 0;
    for (int i = 0; i < a->width * a->height; i++)
        n += memcmp(a->rgb + 3 * i, b->rgb + 3 * i, 3 * sizeof(float)) != 0;
    return n;
}

/* The Cornell box with its light turned into `type`, optionally a second
 * (point) light and a glossy floor. */
static void make_scene(Scene *s, LightType type, bool two_lights, bool glossy)
{
    assert_true(scene_load(s, "cornell"));
    Light *l = &s->lights[0];
    l->type = type;
    if (type != LIGHT_QUAD)
        l->position[1] -= 0.1f;
    if (type == LIGHT_DIRECTIONAL) {
        glm_vec3_copy((vec3){-0.3f, -0.8f, 0.52f}, l->direction);
        glm_vec3_normalize(l->direction);
        glm_vec3_copy((vec3){1.f, 1.f, 1.f}, l->color);
        l->size = 0.02f; /* angular diameter (rad): PCSS penumbrae */
    }
    if (type == LIGHT_SPOT) {
        l->spot_inner = 0.6f;
        l->spot_outer = 0.9f;
    }
    if (two_lights) {
        Light *more = realloc(s->lights, 2 * sizeof *more);
        assert_non_null(more);
        s->lights = more;
        s->lights[1] = s->lights[0];
        s->lights[1].type = LIGHT_POINT;
        glm_vec3_copy((vec3){0.15f, 0.3f, 0.2f}, s->lights[1].position);
        glm_vec3_copy((vec3){0.05f, 0.04f, 0.03f}, s->lights[1].color);
        s->lights[1].size = 0.05f;
        s->light_count = 2;
    }
    if (glossy)
        for (int i = 0; i < s->material_count; i++)
            if (strcmp(s->materials[i].name, "floor") == 0) {
                s->materials[i].specular = 1.f;
                s->materials[i].roughness = 0.3f;
            }
}

static void variants_equal_general(void **state)
{
    (void)state;
    const LightType types[] = {LIGHT_DIRECTIONAL, LIGHT_SPOT, LIGHT_POINT, LIGHT_QUAD};
    int frames = 0;
    for (int t = 0; t < 4; t++) {
        Scene s;
        bool two = t % 2 == 1, glossy = t >= 2;
        make_scene(&s, types[t], two, glossy);
        RenderSettings rs = test_settings(&s, 40, 40, SHADOW_MODE_NONE);
        rs.shadow_params.map_size = 128;
        Renderer r;
        assert_true(renderer_create(&r, &s, &rs));
        for (int mode = SHADOW_MODE_NONE; mode <= SHADOW_MODE_PCSS; mode++)
            for (int bias = 0; bias < 2; bias++) {
                rs.shadow = (ShadowMode)mode;
                rs.shadow_params.filter_bias = bias;
                assert_true(renderer_apply(&r, &rs));
                ImageF img[2];
                for (int g = 0; g < 2; g++) {
                    r.pass_direct.general = g == 1;
                    renderer_frame(&r, &s.camera);
                    assert_true(renderer_read_hdr(&r, &img[g]));
                }
                size_t diff = differing_pixels(&img[0], &img[1]);
                double mean = test_image_mean(&img[0]);
                if (diff)
                    print_message("light type %d, shadow mode %d, bias %d, %s, %s: %zu pixels differ\n", types[t],
                                  mode, bias, two ? "two lights" : "one light", glossy ? "glossy" : "diffuse", diff);
                assert_true(mean > 0.0);
                assert_int_equal(diff, 0);
                image_free(&img[0]);
                image_free(&img[1]);
                frames++;
            }
        renderer_destroy(&r);
        scene_free(&s);
    }
    print_message("%d light/shadow configurations: variants equal the general program\n", frames);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(variants_equal_general),
    };
    return cmocka_run_group_tests_name("direct", tests, test_gl_setup, test_gl_teardown);
}
