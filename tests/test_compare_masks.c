/* test_compare_masks.c — issue 10's metrics that mean what they say: block
 * averages separate bias from per-pixel noise (hand-made pairs), and the
 * emitter masks of `render` and `reference` agree and take the emitter's
 * aliased edge out of the error. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "io/metrics.h"
#include "test_util.h"
#include "base/util.h"

/* A reference of constant c; the test adds ±d in a checkerboard (noise
 * that averages out over 2×2 blocks) and a bias b. */
static void block_average_keeps_bias_drops_noise(void **state)
{
    (void)state;
    enum { S = 32 };
    const float c = 0.5f, d = 0.1f, b = 0.02f;
    ImageF t, r, tb, rb;
    assert_true(image_alloc(&t, S, S) && image_alloc(&r, S, S));
    for (int y = 0; y < S; y++)
        for (int x = 0; x < S; x++)
            for (int k = 0; k < 3; k++) {
                image_px(&r, x, y)[k] = c;
                image_px(&t, x, y)[k] = c + b + (((x + y) & 1) ? d : -d);
            }
    uint8_t *mt, *mr;
    assert_true(metric_block_average(&t, NULL, 2, &tb, &mt));
    assert_true(metric_block_average(&r, NULL, 2, &rb, &mr));
    double px = metric_rmse(&t, &r, NULL, NULL), blk = metric_rmse(&tb, &rb, mt, NULL);
    print_message("rmse per pixel %.4f (noise %.2f, bias %.2f), over 2x2 blocks %.4f\n", px, d, b, blk);
    assert_true(fabs(px - sqrtf(d * d + b * b)) < 1e-5);
    assert_true(fabs(blk - b) < 1e-5);
    /* A mask leaves pixels out of the blocks; a block with none is out too. */
    uint8_t mask[S * S];
    for (int i = 0; i < S * S; i++)
        mask[i] = (i % S) >= 2; /* the first block column holds no pixel */
    free(mt);
    image_free(&tb);
    assert_true(metric_block_average(&t, mask, 2, &tb, &mt));
    assert_int_equal(mt[0], 0);
    assert_int_equal(mt[1], 1);
    free(mt);
    free(mr);
    image_free(&t);
    image_free(&r);
    image_free(&tb);
    image_free(&rb);
}

static const char *tmp(const char *name)
{
    static char paths[6][512];
    static int k;
    k = (k + 1) % 6;
    snprintf(paths[k], sizeof paths[k], "%s/%s", RTGI_TEST_TMP, name);
    return paths[k];
}

static double metric_of(const char *out, const char *key)
{
    const char *p = strstr(out, key);
    return p ? atof(p + strlen(key)) : NAN;
}

static void emitter_masks_agree_and_exclude_the_light(void **state)
{
    (void)state;
    const char *img = tmp("em_render.pfm"), *ref = tmp("em_ref.pfm");
    const char *m1 = tmp("em_render_mask.png"), *m2 = tmp("em_ref_mask.png");
    char *err = NULL;
    assert_int_equal(test_run_cli(&err, "render", "--size", "48x48", "--out", img, "--emitter-mask", m1, "--quiet", NULL), 0);
    free(err);
    assert_int_equal(test_run_cli(&err, "reference", "--size", "48x48", "--spp", "16", "--out", ref, "--emitter-mask",
                                  m2, "--quiet", NULL), 0);
    free(err);
    size_t n1, n2;
    char *a = util_read_file(m1, &n1), *b = util_read_file(m2, &n2);
    assert_non_null(a);
    assert_non_null(b);
    assert_true(n1 == n2 && memcmp(a, b, n1) == 0); /* one function, one mask */
    free(a);
    free(b);
    ImageF mask;
    assert_true(image_read(m1, &mask));
    int excluded = 0;
    for (int i = 0; i < mask.width * mask.height; i++)
        excluded += luminance(mask.rgb + 3 * i) < 0.5f;
    image_free(&mask);
    /* The light's footprint and its one-pixel rim, and little else. */
    assert_true(excluded > 4 && excluded < 48 * 48 / 10);

    /* compare's output: the per-pixel RMSE is mostly the light's edge. */
    char cmd[2048], out[4096];
    snprintf(cmd, sizeof cmd, "%s compare %s %s --metric rmse 2>&1; %s compare %s %s --metric rmse --mask-emitters %s 2>&1",
             RTGI_BINARY, img, ref, RTGI_BINARY, img, ref, m1);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t len = fread(out, 1, sizeof out - 1, p);
    out[len] = 0;
    assert_int_equal(pclose(p), 0);
    char *second = strstr(out + 1, "rmse: "); /* the second compare's ("rmse_block: " does not match) */
    double all = metric_of(out, "rmse: "), masked = second ? metric_of(second, "rmse: ") : NAN;
    double blk = metric_of(out, "rmse_block: ");
    print_message("%d pixels masked; RMSE %.4f unmasked, %.4f without the emitter; 8x8 blocks %.4f\n", excluded, all,
                  masked, blk);
    assert_true(masked < 0.25 * all);
    assert_true(blk < all);
}

/* `compare --json -`: stdout is one valid JSON object, the text on stderr. */
static void json_stdout_is_json_alone(void **state)
{
    (void)state;
    const char *a = tmp("json_a.pfm"), *b = tmp("json_b.pfm");
    ImageF img;
    assert_true(image_alloc(&img, 4, 4));
    for (int i = 0; i < 48; i++)
        img.rgb[i] = 0.25f;
    assert_true(image_write_pfm(a, &img));
    img.rgb[0] = 0.5f;
    assert_true(image_write_pfm(b, &img));
    image_free(&img);
    char cmd[1400], out[4096];
    snprintf(cmd, sizeof cmd, "%s compare %s %s --json - 2>/dev/null", RTGI_BINARY, a, b);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t len = fread(out, 1, sizeof out - 1, p);
    out[len] = 0;
    assert_int_equal(pclose(p), 0);
    cJSON *j = cJSON_Parse(out);
    assert_non_null(j);
    assert_true(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(j, "rmse")));
    assert_true(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(j, "relmse_block")));
    cJSON_Delete(j);
    assert_null(strstr(out, "rmse: ")); /* the text lines went to stderr */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(block_average_keeps_bias_drops_noise),
        cmocka_unit_test(emitter_masks_agree_and_exclude_the_light),
        cmocka_unit_test(json_stdout_is_json_alone),
    };
    return cmocka_run_group_tests_name("compare_masks", tests, NULL, NULL);
}
