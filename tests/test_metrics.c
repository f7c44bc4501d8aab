/* test_metrics.c — metric values on image pairs whose answers are derived
 * by hand (in the comments) from the metrics' definitions. No GL. */
#include <math.h>
#include <string.h>

#include "test_util.h"
#include "io/metrics.h"

static void fill(ImageF *img, int w, int h, float r, float g, float b)
{
    assert_true(image_alloc(img, w, h));
    for (int i = 0; i < w * h; i++) {
        img->rgb[3 * i] = r;
        img->rgb[3 * i + 1] = g;
        img->rgb[3 * i + 2] = b;
    }
}

static void identical_images(void **state)
{
    (void)state;
    ImageF a;
    assert_true(image_alloc(&a, 32, 24));
    for (int i = 0; i < 32 * 24 * 3; i++)
        a.rgb[i] = 0.5f + 0.4f * sinf(0.37f * i);
    assert_float_equal(metric_rmse(&a, &a, NULL, NULL), 0.0, 0);
    assert_float_equal(metric_relmse(&a, &a, NULL, NULL), 0.0, 0);
    assert_float_equal(metric_ssim(&a, &a, 1.f, NULL, NULL), 1.0, 1e-6);
    assert_float_equal(metric_flip(&a, &a, 1.f, FLIP_DEFAULT_PPD, NULL, NULL), 0.0, 1e-7);
    image_free(&a);
}

/* 2×2 images differing by 1 in one channel of one pixel: MSE = 1/12. */
static void rmse_known_pair(void **state)
{
    (void)state;
    ImageF a, b;
    fill(&a, 2, 2, 0, 0, 0);
    fill(&b, 2, 2, 0, 0, 0);
    b.rgb[4] = 1.f;
    assert_float_equal(metric_rmse(&a, &b, NULL, NULL), sqrt(1.0 / 12.0), 1e-7);
    /* A mask that leaves out that pixel gives 0. */
    uint8_t mask[4] = {1, 0, 1, 1};
    assert_float_equal(metric_rmse(&a, &b, mask, NULL), 0.0, 0);
    image_free(&a);
    image_free(&b);
}

/* Test 1.1 against reference 1.0 everywhere: 0.1² / (1 + 0.01). */
static void relmse_known_pair(void **state)
{
    (void)state;
    ImageF t, r;
    fill(&t, 4, 4, 1.1f, 1.1f, 1.1f);
    fill(&r, 4, 4, 1.f, 1.f, 1.f);
    assert_float_equal(metric_relmse(&t, &r, NULL, NULL), 0.01 / 1.01, 1e-6);
    image_free(&t);
    image_free(&r);
}

/* Means: test (2, 1, 0.5) over reference (1, 1, 1) on a 2×2 image whose
 * pixel 1 the mask leaves out (it holds a 100 that would otherwise move
 * every ratio): per channel 2, 1, 0.5; luminance 0.2126·2 + 0.7152 +
 * 0.0722·0.5 over 1. A reference of mean 0 gives NaN. */
static void mean_ratio_known_pair(void **state)
{
    (void)state;
    ImageF t, r;
    fill(&t, 2, 2, 2.f, 1.f, 0.5f);
    fill(&r, 2, 2, 1.f, 1.f, 1.f);
    t.rgb[3] = t.rgb[4] = t.rgb[5] = 100.f;
    uint8_t mask[4] = {1, 0, 1, 1};
    double rgb[3];
    assert_float_equal(metric_mean_ratio(&t, &r, mask, rgb), 0.2126 * 2 + 0.7152 + 0.0722 * 0.5, 1e-6);
    assert_float_equal(rgb[0], 2.0, 1e-7);
    assert_float_equal(rgb[1], 1.0, 1e-7);
    assert_float_equal(rgb[2], 0.5, 1e-7);
    assert_true(metric_mean_ratio(&t, &r, NULL, NULL) > 20.0); /* the 100 counts without the mask */
    image_free(&r);
    fill(&r, 2, 2, 0.f, 0.f, 0.f);
    assert_true(isnan(metric_mean_ratio(&t, &r, NULL, rgb)) && isnan(rgb[1]));
    image_free(&t);
    image_free(&r);
}

/* Shadow artefacts on six grey pixels, unshadowed radiance 2 (pixel 5: 0,
 * no light reaches it). Reference visibility 1, 1, 0, 0.5 (penumbra: not
 * counted), 0, and test visibility 0.2, 1, 0.9, 0, 0.1: lit pixels 0, 1
 * (one darkened: false_shadow 1/2), shadowed 2, 4 (one lit: false_lit 1/2);
 * masking pixel 0 out leaves false_shadow 0 of 1. */
static void shadow_artefacts_known_images(void **state)
{
    (void)state;
    ImageF t, r, u;
    fill(&u, 6, 1, 2.f, 2.f, 2.f);
    fill(&r, 6, 1, 0.f, 0.f, 0.f);
    fill(&t, 6, 1, 0.f, 0.f, 0.f);
    const float vr[6] = {1, 1, 0, 0.5f, 0, 0}, vt[6] = {0.2f, 1, 0.9f, 0, 0.1f, 1};
    for (int i = 0; i < 6; i++)
        for (int c = 0; c < 3; c++) {
            r.rgb[3 * i + c] = 2.f * vr[i];
            t.rgb[3 * i + c] = 2.f * vt[i];
        }
    u.rgb[15] = u.rgb[16] = u.rgb[17] = 0.f;
    ShadowArtefacts a = metric_shadow_artefacts(&t, &r, &u, NULL);
    assert_int_equal(a.lit, 2);
    assert_int_equal(a.shadowed, 2);
    assert_float_equal(a.false_shadow, 0.5, 1e-12);
    assert_float_equal(a.false_lit, 0.5, 1e-12);
    uint8_t mask[6] = {0, 1, 1, 1, 1, 1};
    a = metric_shadow_artefacts(&t, &r, &u, mask);
    assert_int_equal(a.lit, 1);
    assert_float_equal(a.false_shadow, 0.0, 1e-12);
    uint8_t only_lit[6] = {1, 1, 0, 0, 0, 0};
    a = metric_shadow_artefacts(&t, &r, &u, only_lit);
    assert_int_equal(a.shadowed, 0);
    assert_true(isnan(a.false_lit));
    image_free(&t);
    image_free(&r);
    image_free(&u);
}

/* Uniform greys whose display values are 0.2 and 0.4: no variance, so
 * SSIM = (2·0.2·0.4 + C1)/(0.2² + 0.4² + C1) = 0.8000999. */
static void ssim_known_pair(void **state)
{
    (void)state;
    ImageF a, b;
    float g1 = srgb_decode(0.2f), g2 = srgb_decode(0.4f);
    fill(&a, 16, 16, g1, g1, g1);
    fill(&b, 16, 16, g2, g2, g2);
    assert_float_equal(metric_ssim(&a, &b, 1.f, NULL, NULL), 0.8000999500, 2e-5);
    image_free(&a);
    image_free(&b);
}

/* Uniform images have no features, so FLIP is the redistributed colour
 * error alone: black vs white gives HyAB = 100.0108 (white's a*, b* are not
 * exactly 0 with D65 as given), 100.0108^0.7 = 25.12 > 0.4·cmax with
 * cmax = HyAB(Hunt(green), Hunt(blue))^0.7 = 203.31^0.7 = 41.27, so FLIP =
 * 0.95 + (25.12 − 16.51)/(41.27 − 16.51)·0.05 = 0.967383; linear greys 0.5
 * and 0.6 give HyAB 5.76986 → 0.196236 (computed from the paper's formulas
 * independently of this code). */
static void flip_known_pairs(void **state)
{
    (void)state;
    ImageF a, b;
    fill(&a, 24, 24, 0, 0, 0);
    fill(&b, 24, 24, 1, 1, 1);
    assert_float_equal(metric_flip(&a, &b, 1.f, FLIP_DEFAULT_PPD, NULL, NULL), 0.967383, 2e-4);
    image_free(&a);
    image_free(&b);
    fill(&a, 24, 24, 0.5f, 0.5f, 0.5f);
    fill(&b, 24, 24, 0.6f, 0.6f, 0.6f);
    assert_float_equal(metric_flip(&a, &b, 1.f, FLIP_DEFAULT_PPD, NULL, NULL), 0.196236, 2e-4);
    image_free(&a);
    image_free(&b);
}

/* An edge that moves by one pixel is a feature difference: FLIP sees it
 * more than the colour difference alone would suggest, and it is
 * symmetric in magnitude. */
static void flip_sees_edges(void **state)
{
    (void)state;
    ImageF a, b;
    fill(&a, 32, 32, 0.2f, 0.2f, 0.2f);
    fill(&b, 32, 32, 0.2f, 0.2f, 0.2f);
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++) {
            if (x >= 16)
                memset(image_px(&a, x, y), 0, 0), image_px(&a, x, y)[0] = image_px(&a, x, y)[1] =
                                                      image_px(&a, x, y)[2] = 0.8f;
            if (x >= 17)
                image_px(&b, x, y)[0] = image_px(&b, x, y)[1] = image_px(&b, x, y)[2] = 0.8f;
        }
    float map[32 * 32];
    double f = metric_flip(&a, &b, 1.f, FLIP_DEFAULT_PPD, NULL, map);
    assert_true(f > 0.0);
    assert_true(map[16 * 32 + 16] > 0.3f); /* on the moved edge */
    assert_true(map[16 * 32 + 2] < 1e-3f); /* far from it */
    assert_float_equal(metric_flip(&b, &a, 1.f, FLIP_DEFAULT_PPD, NULL, NULL), f, 1e-3);
    image_free(&a);
    image_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(identical_images), cmocka_unit_test(rmse_known_pair), cmocka_unit_test(relmse_known_pair), cmocka_unit_test(mean_ratio_known_pair),
        cmocka_unit_test(shadow_artefacts_known_images),
        cmocka_unit_test(ssim_known_pair),  cmocka_unit_test(flip_known_pairs), cmocka_unit_test(flip_sees_edges),
    };
    return cmocka_run_group_tests_name("metrics", tests, NULL, NULL);
}
