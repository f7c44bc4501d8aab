/* test_culling.c — frustum culling and front-to-back order (issue 11, item
 * 5) change what is drawn, never the image: the culled renders equal the
 * unculled ones bit for bit — the G-buffer seen by the camera, and shadow
 * maps and RSMs (cube faces of a point light) seen by the lights — while
 * the camera and the faces skip clusters; and untextured materials drawn
 * by programs without texture code change no pixel either. */
#include <stdio.h>
#include <string.h>

#include "test_util.h"

static size_t differing_pixels(const ImageF *a, const ImageF *b)
{
    size_t n = 0;
    for (int i = 0; i < a->width * a->height; i++)
        n += memcmp(a->rgb + 3 * i, b->rgb + 3 * i, 3 * sizeof(float)) != 0;
    return n;
}

/* Renders `s` with and without culling; returns the differing pixels and
 * the clusters the G-buffer pass and the light maps skipped. */
static size_t render_both(const Scene *s, RenderSettings rs, int *culled, int *light_culled)
{
    ImageF img[2];
    for (int c = 0; c < 2; c++) {
        rs.no_cull = c == 1;
        Renderer r;
        assert_true(renderer_create(&r, s, &rs));
        renderer_frame(&r, &s->camera);
        assert_true(renderer_read_hdr(&r, &img[c]));
        if (c == 0) {
            *culled = r.pass_gbuffer.culled;
            *light_culled = r.lights.clusters_culled;
        } else {
            assert_int_equal(r.pass_gbuffer.culled + r.lights.clusters_culled, 0);
        }
        renderer_destroy(&r);
    }
    size_t n = differing_pixels(&img[0], &img[1]);
    assert_true(test_image_mean(&img[0]) > 0.0);
    image_free(&img[0]);
    image_free(&img[1]);
    return n;
}

/* A camera at the Cornell box's centre looking down at the floor: the
 * ceiling and the light's geometry are culled; a point light with PCSS
 * (cube shadow map: every face culls) and the RSM gather (cube RSM). */
static void cornell_culled_equals_unculled(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, "cornell"));
    s.lights[0].type = LIGHT_POINT;
    s.lights[0].position[1] -= 0.1f;
    Camera *c = &s.camera;
    for (int k = 0; k < 3; k++)
        c->position[k] = 0.5f * (s.bounds_min[k] + s.bounds_max[k]);
    glm_vec3_copy((vec3){0.f, -1.f, 0.f}, c->forward);
    glm_vec3_copy((vec3){0.f, 0.f, 1.f}, c->up);
    const GiMode modes[] = {GI_NONE, GI_RSM};
    for (int m = 0; m < 2; m++) {
        RenderSettings rs = test_settings(&s, 48, 48, SHADOW_MODE_PCSS);
        rs.gi = modes[m];
        rs.set.gi = s.settings.gi;
        rs.set.gi.rsm.size = 32;
        rs.set.gi.rsm.samples = 64;
        rs.set.shadow.map_size = 128;
        int culled = 0, light_culled = 0;
        size_t diff = render_both(&s, rs, &culled, &light_culled);
        print_message("cornell (%s): %d clusters culled by the camera, %d by the light's faces, %zu pixels differ\n",
                      m ? "rsm" : "none", culled, light_culled, diff);
        assert_true(culled > 0);
        assert_true(light_culled > 0);
        assert_int_equal(diff, 0);
    }
    scene_free(&s);
}

/* Opaque materials without textures are drawn by programs built without
 * the texture code (gpu_scene.h DrawPrograms; Cornell G-buffer 800×600
 * 10.9 -> 9.0 ms): the G-buffer and the RSM they write equal the general
 * programs' bit for bit (every Cornell material is untextured). */
static void untextured_programs_change_nothing(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, "cornell"));
    RenderSettings rs = test_settings(&s, 48, 48, SHADOW_MODE_PCF);
    rs.gi = GI_RSM;
    rs.set.gi = s.settings.gi;
    rs.set.gi.rsm.size = 32;
    rs.set.gi.rsm.samples = 64;
    ImageF img[2];
    for (int general = 0; general < 2; general++) {
        Renderer r;
        assert_true(renderer_create(&r, &s, &rs));
        assert_true(r.pass_gbuffer.program_untextured != 0 && r.lights.rsm_program_untextured != 0);
        if (general) { /* the general opaque programs draw them instead */
            r.pass_gbuffer.program_untextured = r.pass_gbuffer.program_opaque;
            r.lights.rsm_program_untextured = r.lights.rsm_program_opaque;
        }
        renderer_frame(&r, &s.camera);
        assert_true(renderer_read_hdr(&r, &img[general]));
        renderer_destroy(&r);
    }
    size_t diff = differing_pixels(&img[0], &img[1]);
    print_message("cornell, untextured programs vs the general ones: %zu pixels differ\n", diff);
    assert_true(test_image_mean(&img[0]) > 0.0);
    assert_int_equal(diff, 0);
    image_free(&img[0]);
    image_free(&img[1]);
    scene_free(&s);
}

/* Sponza (where present), from a camera that sees part of it: clusters are
 * culled and the image is the same. */
static void sponza_culled_equals_unculled(void **state)
{
    (void)state;
    test_skip_without_sponza();
    const char *path = test_sponza_gltf();
    Scene s;
    assert_true(scene_load(&s, path));
    /* From the middle of the atrium toward a side colonnade, under the sun
     * of scenes/sponza_nave.json (the glTF's default sun, high and from
     * behind this view, leaves every pixel of it in shadow: a black image). */
    glm_vec3_normalize_to((vec3){0.25f, -1.f, 0.12f}, s.lights[0].direction);
    glm_vec3_copy((vec3){0.f, 2.f, 0.f}, s.camera.position);
    glm_vec3_copy((vec3){0.f, 0.f, 1.f}, s.camera.forward);
    glm_vec3_copy((vec3){0.f, 1.f, 0.f}, s.camera.up);
    RenderSettings rs = test_settings(&s, 96, 54, SHADOW_MODE_PCF);
    int culled = 0, light_culled = 0;
    size_t diff = render_both(&s, rs, &culled, &light_culled);
    print_message("sponza: %d clusters culled, %zu pixels differ\n", culled, diff);
    assert_true(culled > 0);
    assert_int_equal(diff, 0);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cornell_culled_equals_unculled),
        cmocka_unit_test(untextured_programs_change_nothing),
        cmocka_unit_test(sponza_culled_equals_unculled),
    };
    return cmocka_run_group_tests_name("culling", tests, test_gl_setup, test_gl_teardown);
}
