/* test_crosscheck.c — one radiometry for both renderers: the Cornell box
 * with its light's size set to 0 (a point with I(θ) = L·A·cosθ), rendered by
 * the rasterizer with hard shadows and by the path tracer in direct mode
 * through pixel centres. They must agree apart from shadow-map resolution,
 * so pixels within one pixel of a disagreement about shadow (black in one
 * image, lit in the other) are excluded and counted. */
#include <math.h>

#include "test_util.h"
#include "io/metrics.h"
#include "reference/pathtracer.h"

enum { W = 128, H = 128 };

static void raster_matches_path_tracer_direct(void **state)
{
    (void)state;
    GlContext *gl = gl_context_create(false);
    assert_non_null(gl);
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    scene_rescale_lights(&s, 0.f);
    RenderSettings rs = test_settings(&s, W, H, SHADOW_MODE_HARD);
    ImageF raster, ref;
    test_render(&s, &rs, &raster);
    gl_context_destroy(gl);

    PtSettings set;
    pt_settings_default(&set);
    set.width = W;
    set.height = H;
    set.spp = 1; /* a point light through pixel centres: no randomness left */
    set.mode = PT_DIRECT;
    set.pixel_jitter = false;
    set.threads = 2;
    assert_true(pt_render(&s, &set, &ref, NULL, NULL));

    uint8_t mask[W * H];
    int excluded;
    test_shadow_boundary_mask(&raster, &ref, mask, &excluded);
    double rel_all = metric_relmse(&raster, &ref, NULL, NULL);
    double rel_in = metric_relmse(&raster, &ref, mask, NULL);
    print_message("relMSE all pixels %.3g, without %d shadow-boundary pixels (%.1f%%) %.3g\n", rel_all, excluded,
                  100.0 * excluded / (W * H), rel_in);
    /* Bounds (measured at 128²: 1.7e-4 over all pixels, 8e-8 without the
     * boundary): away from shadow boundaries the renderers differ only by
     * float rounding and the G-buffer's half-float normals and albedo
     * (relative error ≤ 1e-3, so relMSE ≤ 1e-6); we allow 2e-5. Over all
     * pixels the boundary pixels, under 2% of the image, dominate; 1e-3
     * bounds them. */
    assert_true(excluded < W * H / 50);
    assert_true(rel_in < 2e-5);
    assert_true(rel_all < 1e-3);
    /* And the images are not trivially black. */
    double mean = 0;
    for (int i = 0; i < W * H; i++)
        mean += luminance(ref.rgb + 3 * i) / (W * H);
    assert_true(mean > 0.02);
    image_free(&raster);
    image_free(&ref);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(raster_matches_path_tracer_direct)};
    return cmocka_run_group_tests_name("crosscheck", tests, NULL, NULL);
}
