/* test_sponza.c — Crytek Sponza (../shared/assets/sponza, not part of the
 * repository) loads through assimp with its textures and alpha masks, gets
 * a default sun and camera, and renders lit in both renderers. Skipped
 * (with a message) where the asset is not present. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "test_util.h"
#include "reference/pathtracer.h"

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
    test_skip_without_sponza();
    const char *path = test_sponza_gltf();
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

/* Share of a view's pixels a viewer sees lit: exposed luminance above
 * 0.01 (an sRGB code of 25 after the tone map, plainly above black). */
static double lit_share(const ImageF *im, float exposure)
{
    int lit = 0, n = im->width * im->height;
    for (int i = 0; i < n; i++) {
        const float *c = im->rgb + 3 * i;
        lit += exposure * (0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]) > 0.01f;
    }
    return (double)lit / n;
}

/* The view a newcomer opens (scenes/sponza.json, and the glTF on its own
 * with its default camera, sun and exposure) shows the atrium lit, most of
 * it by the bounce: with rsm most pixels are lit, with --gi none few are.
 * The nave view the measurements use (scenes/sponza_nave.json, the old
 * default) fails the first bound: mostly dark even with the bounce. */
static void sponza_default_view_shows_the_bounce(void **state)
{
    (void)state;
    test_skip_without_sponza();
    enum { W = 160, H = 90 };
    const char *files[] = {RTGI_SOURCE_DIR "/scenes/sponza.json", test_sponza_gltf(),
                           RTGI_SOURCE_DIR "/scenes/sponza_nave.json"};
    for (int f = 0; f < 3; f++) {
        Scene s;
        assert_true(scene_load(&s, files[f]));
        ImageF gi, none;
        test_render_gi(&s, W, H, GI_RSM, NULL, &gi);
        test_render_gi(&s, W, H, GI_NONE, NULL, &none);
        double lit = lit_share(&gi, s.exposure), lit0 = lit_share(&none, s.exposure);
        print_message("%s: lit pixels with rsm %.2f, with --gi none %.2f\n", files[f], lit, lit0);
        if (f < 2) {
            assert_true(lit > 0.6);
            assert_true(lit0 < 0.5 * lit);
        } else {
            assert_true(lit < 0.6);
        }
        image_free(&gi);
        image_free(&none);
        scene_free(&s);
    }
}

/* Issue 10: the default RSM gather recovers Sponza's one bounce from the
 * sun: its mean indirect light (gi − none) is within 15% of the path
 * tracer's (one-bounce-novis − direct); the paper's weighting, the old
 * default, recovered 38%. scenes/sponza_nave.json's camera down the nave.
 * RSM bounces are diffuse (SPEC §1b), so this compares the diffuse bounce:
 * Sponza's glTF materials are made Lambertian (specular 0, metallic 0) in
 * both renderers. With its glossy materials the reference's bounce is
 * larger by the specular part RSM leaves out (printed: RSM recovered 67%
 * of it when measured, issue 13). */
static void sponza_rsm_recovers_the_bounce(void **state)
{
    (void)state;
    test_skip_without_sponza();
    char scene_file[1024];
    snprintf(scene_file, sizeof scene_file, "%s/scenes/sponza_nave.json", RTGI_SOURCE_DIR);
    Scene s;
    assert_true(scene_load(&s, scene_file));
    scene_rescale_lights(&s, 0.f); /* a parallel sun in both renderers */
    enum { W = 80, H = 45 };
    {
        GiParams gp = s.settings.gi;
        gp.rsm.size = 256;
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
    GiParams gp = s.settings.gi;
    gp.rsm.size = 256;
    ImageF gi, paper, none, novis, direct;
    test_render_gi(&s, W, H, GI_RSM, &gp, &gi);
    test_render_gi(&s, W, H, GI_NONE, &gp, &none);
    gp.rsm.weighting = RSM_WEIGHT_PAPER;
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

/* Issue 49: Sponza's direct light, rasterized (hard shadows, SSAA 2), is
 * the path tracer's (jittered: the box filter SSAA approximates), channel
 * by channel, away from the pixels where the two disagree about shadow
 * (shadow-map resolution, which this does not measure: found from both
 * renderers at the 2×2 subpixel centres SSAA 2 shades, as
 * test_shadow_boundary_mask finds them, and counted). The image means
 * agree within 0.5%, and each of 16×9 blocks within its noise: the
 * standard error of a 4-sample estimate of the block (the reference's
 * per-sample variance over 4 samples per pixel, what SSAA 2 takes) plus
 * 0.3% for texture filtering (trilinear mips against the footprint's
 * exact mean). Blue was 2.1% high (1.2% at SSAA 2) from the driver's sRGB
 * texture decoding and mip generation, and 1% of every channel from the
 * mip chain's alpha (gpu_scene.c, common/material.glsl). */
static void sponza_direct_matches_reference(void **state)
{
    (void)state;
    test_skip_without_sponza();
    Scene s;
    test_sponza_lambert(&s);
    enum { W = 320, H = 180, SPP = 64, BX = 16, BY = 9 };
    ImageF raster, ref, var, raster2, ref2;
    RenderSettings rs = test_settings(&s, W, H, SHADOW_MODE_HARD);
    rs.ssaa = 2;
    test_render(&s, &rs, &raster);
    rs = test_settings(&s, 2 * W, 2 * H, SHADOW_MODE_HARD);
    test_render(&s, &rs, &raster2);
    test_reference_var(&s, W, H, PT_DIRECT, SPP, true, &ref, &var);
    test_reference(&s, 2 * W, 2 * H, PT_DIRECT, 1, &ref2);

    static uint8_t mask2[4 * W * H];
    int excluded2;
    test_shadow_boundary_mask(&raster2, &ref2, mask2, &excluded2);
    static uint8_t mask[W * H];
    int excluded = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int k = 2 * y * 2 * W + 2 * x;
            mask[y * W + x] = mask2[k] && mask2[k + 1] && mask2[k + 2 * W] && mask2[k + 2 * W + 1];
            excluded += !mask[y * W + x];
        }
    double a[3] = {0}, b[3] = {0}, ta[3] = {0}, tb[3] = {0};
    double chi2[3] = {0}, zmax[3] = {0};
    int blocks = 0;
    for (int by = 0; by < BY; by++)
        for (int bx = 0; bx < BX; bx++) {
            double ab[3] = {0}, bb[3] = {0}, vb[3] = {0};
            int n = 0;
            for (int y = by * H / BY; y < (by + 1) * H / BY; y++)
                for (int x = bx * W / BX; x < (bx + 1) * W / BX; x++) {
                    const float *pa = image_px(&raster, x, y), *pb = image_px(&ref, x, y), *pv = image_px(&var, x, y);
                    for (int c = 0; c < 3; c++) {
                        ta[c] += pa[c];
                        tb[c] += pb[c];
                    }
                    if (!mask[y * W + x])
                        continue;
                    n++;
                    for (int c = 0; c < 3; c++) {
                        ab[c] += pa[c];
                        bb[c] += pb[c];
                        vb[c] += pv[c] * SPP / 4.0;
                    }
                }
            for (int c = 0; c < 3; c++) {
                a[c] += ab[c];
                b[c] += bb[c];
            }
            if (n < 20 || bb[1] / n < 1e-3)
                continue; /* in shadow, or mostly boundary */
            blocks++;
            for (int c = 0; c < 3; c++) {
                double sigma = sqrt(vb[c]) / n + 0.003 * bb[c] / n, z = (ab[c] - bb[c]) / n / sigma;
                chi2[c] += z * z;
                zmax[c] = fmax(zmax[c], fabs(z));
            }
        }
    print_message("excluded %d of %d pixels (%.1f%%); mean ratio away from them %.4f %.4f %.4f, of all %.4f %.4f %.4f;"
                  " %d lit blocks: chi2/block %.2f %.2f %.2f, max |z| %.2f %.2f %.2f\n",
                  excluded, W * H, 100.0 * excluded / (W * H), a[0] / b[0], a[1] / b[1], a[2] / b[2], ta[0] / tb[0],
                  ta[1] / tb[1], ta[2] / tb[2], blocks, chi2[0] / blocks, chi2[1] / blocks, chi2[2] / blocks, zmax[0],
                  zmax[1], zmax[2]);
    /* Measured: 6.9% excluded; away from them 0.9984 0.9986 0.9985 (before
     * the fixes 0.9911 0.9948 1.0060), of all 1.0029 1.0043 1.0040 (0.9973
     * 1.0019 1.0137); 38 lit blocks, chi2/block 0.61 0.54 0.50 (0.97 1.21
     * 0.96), max |z| 2.4 (2.8). */
    assert_true(excluded < W * H / 10);
    assert_true(blocks >= 30);
    for (int c = 0; c < 3; c++) {
        assert_true(fabs(a[c] / b[c] - 1.0) < 0.005);
        assert_true(chi2[c] / blocks < 1.0);
        assert_true(zmax[c] < 4.0);
    }
    image_free(&raster);
    image_free(&raster2);
    image_free(&ref);
    image_free(&ref2);
    image_free(&var);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(sponza_loads_and_renders),
                                       cmocka_unit_test(sponza_rsm_recovers_the_bounce),
                                       cmocka_unit_test(sponza_default_view_shows_the_bounce),
                                       cmocka_unit_test(sponza_direct_matches_reference)};
    return cmocka_run_group_tests_name("sponza", tests, test_gl_setup, test_gl_teardown);
}
