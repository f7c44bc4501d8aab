/* test_sponza.c — Crytek Sponza (../shared/assets/sponza, not part of the
 * repository) loads through assimp with its textures and alpha masks, gets
 * a default sun and camera, and renders lit in both renderers. Skipped
 * (with a message) where the asset is not present. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "test_util.h"
#include "reference/pathtracer.h"

static const char *sponza_path(void)
{
    static char path[1024];
    snprintf(path, sizeof path, "%s/assets/sponza/Sponza.gltf", RTGI_SHARED_DIR);
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fclose(f);
    return path;
}

static double lit_fraction(const ImageF *img)
{
    int lit = 0;
    for (int i = 0; i < img->width * img->height; i++)
        lit += luminance(img->rgb + 3 * i) > 0.01f;
    return (double)lit / (img->width * img->height);
}

static void sponza_loads_and_renders(void **state)
{
    (void)state;
    const char *path = sponza_path();
    if (!path) {
        print_message("Sponza not found under %s/assets/sponza: skipped\n", RTGI_SHARED_DIR);
        skip();
    }
    Scene s;
    assert_true(scene_load(&s, path));
    int masked = 0, textured = 0;
    for (int i = 0; i < s.material_count; i++) {
        masked += s.materials[i].alpha_mask;
        textured += s.materials[i].albedo_tex >= 0;
    }
    /* A masked texture really has holes. */
    int holes = 0;
    for (int i = 0; i < s.material_count && !holes; i++)
        if (s.materials[i].alpha_mask && s.materials[i].albedo_tex >= 0) {
            const Texture *t = &s.textures[s.materials[i].albedo_tex];
            for (long k = 0; k < (long)t->width * t->height; k++)
                holes += t->rgba[4 * k + 3] < 128;
        }
    print_message("%u triangles, %d materials (%d textured, %d alpha-masked), %d textures, %d lights; "
                  "bounds %.1f x %.1f x %.1f m\n",
                  s.index_count / 3, s.material_count, textured, masked, s.texture_count, s.light_count,
                  s.bounds_max[0] - s.bounds_min[0], s.bounds_max[1] - s.bounds_min[1],
                  s.bounds_max[2] - s.bounds_min[2]);
    assert_true(s.index_count / 3 >= 262000);      /* README: 262,267 */
    assert_int_equal(masked, 3);                    /* leaves, plant, chain */
    assert_true(textured >= 24 && s.texture_count >= 24);
    assert_true(holes > 0);
    assert_int_equal(s.light_count, 1);             /* the default sun */
    assert_true(s.bounds_max[0] - s.bounds_min[0] > 25.f); /* metres, at the node's 0.008 scale */

    ImageF raster, ref;
    RenderSettings rs = test_settings(&s, 96, 54, SHADOW_MODE_PCF);
    test_render(&s, &rs, &raster);
    PtSettings set;
    pt_settings_default(&set);
    set.width = 96;
    set.height = 54;
    set.spp = 2;
    set.mode = PT_DIRECT;
    set.threads = 2;
    assert_true(pt_render(&s, &set, &ref, NULL, NULL));
    double fr = lit_fraction(&raster), fp = lit_fraction(&ref);
    print_message("sunlit pixels: raster %.1f%%, path tracer %.1f%%\n", 100 * fr, 100 * fp);
    assert_true(fr > 0.05 && fp > 0.05);
    assert_true(fabs(fr - fp) < 0.1); /* the same sunlit regions */
    image_free(&raster);
    image_free(&ref);
    scene_free(&s);
}

/* Issue 10: the default RSM gather recovers Sponza's one bounce from the
 * sun: its mean indirect light (gi − none) is within 15% of the path
 * tracer's (one-bounce-novis − direct); the paper's weighting, the old
 * default, recovered 38%. scenes/sponza.json's camera down the nave.
 * RSM bounces are diffuse (SPEC §1b), so this compares the diffuse bounce:
 * Sponza's glTF materials are made Lambertian (specular 0, metallic 0) in
 * both renderers. With its glossy materials the reference's bounce is
 * larger by the specular part RSM leaves out (printed: RSM recovered 67%
 * of it when measured, issue 13). */
static void sponza_rsm_recovers_the_bounce(void **state)
{
    (void)state;
    if (!sponza_path()) {
        print_message("Sponza not found under %s/assets/sponza: skipped\n", RTGI_SHARED_DIR);
        skip();
    }
    char scene_file[1024];
    snprintf(scene_file, sizeof scene_file, "%s/scenes/sponza.json", RTGI_SOURCE_DIR);
    Scene s;
    assert_true(scene_load(&s, scene_file));
    scene_rescale_lights(&s, 0.f); /* a parallel sun in both renderers */
    enum { W = 80, H = 45 };
    {
        GiParams gp = s.gi;
        gp.rsm_size = 256;
        ImageF gi, none, novis, direct;
        test_render_gi(&s, W, H, GI_RSM, &gp, &gi);
        test_render_gi(&s, W, H, GI_NONE, &gp, &none);
        test_reference(&s, W, H, PT_ONE_BOUNCE_NOVIS, 16, &novis);
        test_reference(&s, W, H, PT_DIRECT, 16, &direct);
        double r = (test_image_mean(&gi) - test_image_mean(&none)) / (test_image_mean(&novis) - test_image_mean(&direct));
        print_message("Sponza with its glossy materials: RSM indirect mean / reference's glossy bounce %.3f\n", r);
        image_free(&gi);
        image_free(&none);
        image_free(&novis);
        image_free(&direct);
    }
    for (int i = 0; i < s.material_count; i++)
        if (s.materials[i].light_index < 0)
            s.materials[i].specular = s.materials[i].metallic = 0.f;
    GiParams gp = s.gi;
    gp.rsm_size = 256;
    ImageF gi, paper, none, novis, direct;
    test_render_gi(&s, W, H, GI_RSM, &gp, &gi);
    test_render_gi(&s, W, H, GI_NONE, &gp, &none);
    gp.weighting = RSM_WEIGHT_PAPER;
    test_render_gi(&s, W, H, GI_RSM, &gp, &paper);
    test_reference(&s, W, H, PT_ONE_BOUNCE_NOVIS, 64, &novis);
    test_reference(&s, W, H, PT_DIRECT, 64, &direct);
    double m_ref = test_image_mean(&novis) - test_image_mean(&direct), m0 = test_image_mean(&none);
    double r = (test_image_mean(&gi) - m0) / m_ref, rp = (test_image_mean(&paper) - m0) / m_ref;
    print_message("Sponza indirect mean / reference: default %.3f, paper %.3f\n", r, rp);
    assert_true(fabs(r - 1.0) < 0.15);
    assert_true(fabs(rp - 1.0) > 0.15); /* a bound the old default fails */
    image_free(&gi);
    image_free(&paper);
    image_free(&none);
    image_free(&novis);
    image_free(&direct);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(sponza_loads_and_renders),
                                       cmocka_unit_test(sponza_rsm_recovers_the_bounce)};
    return cmocka_run_group_tests_name("sponza", tests, test_gl_setup, test_gl_teardown);
}
