/* cmd_compare.c — `rtgi compare A B`: error of test image A against
 * reference B, as text and JSON, with an optional heat map. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "commands.h"
#include "image.h"
#include "log.h"
#include "metrics.h"
#include "util.h"

void cmd_compare_help(void)
{
    printf("usage: rtgi compare TEST REFERENCE [options]\n"
           "  TEST, REFERENCE    .pfm or .exr (OpenEXR, half or float: linear radiance) or .png\n"
           "                     (sRGB, decoded to linear)\n"
           "  --metric rmse|relmse|ssim|flip|all   (default: all)\n"
           "  --heatmap FILE.png per-pixel error of the first metric (FLIP map for all)\n"
           "  --mask FILE        only pixels where the mask's luminance > 0.5 count\n"
           "  --mask-emitters FILE  the same, with the mask that render/reference --emitter-mask\n"
           "                     write: pixels that see an emitter (and their neighbours) do not count\n"
           "  --unshadowed FILE  shadow artefacts: TEST and REFERENCE are direct light only (render\n"
           "                     --gi none, reference --mode direct), FILE is TEST's renderer without\n"
           "                     shadows (render --shadow none); prints shadow_lit_pixels and\n"
           "                     shadow_shadowed_pixels (where REFERENCE's visibility is >= 0.95,\n"
           "                     <= 0.05), false_shadow (share of the lit ones TEST darkens below 0.5:\n"
           "                     acne) and false_lit (of the shadowed ones it lights above 0.5:\n"
           "                     peter-panning, leaks)\n"
           "  --block N          also rmse/relmse of N×N block averages (default 8; 0: off):\n"
           "                     per-pixel noise and edge aliasing average out, bias does not\n"
           "  --exposure E       display exposure for SSIM and FLIP (default: 1)\n"
           "  --ppd P            FLIP pixels per degree (default: 67.02)\n"
           "  --json FILE        also write the results as JSON ('-': stdout, the text lines then\n"
           "                     go to stderr); non-finite\n"
           "                     values are written as null\n"
           "  --allow-nonfinite  compare images with NaN/Inf pixels (an error otherwise)\n"
           "  --quiet | --verbose   errors only on stderr | debug lines too\n"
           "  --                 ends the options: what follows are the two images\n"
           "Prints one 'metric: value' line per metric; with --metric all also\n"
           "'mean_ratio: X' (TEST's mean luminance over REFERENCE's, on the counted pixels)\n"
           "and 'mean_ratio_rgb: R G B' (per channel): a scale error shows there, noise averages out.\n");
}

static const char *const k_metrics[] = {"rmse", "relmse", "ssim", "flip", "all", NULL};

/* A JSON number as %.8g, or null where it is not finite. */
static void json_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.8g", v);
    else
        fputs("null", f);
}

/* The results as one JSON object; strings escaped, non-finite numbers as
 * null. To stdout for "-", else atomically to the file. */
static bool write_json(const char *json, const char *const files[2], const ImageF *t, const double val[4],
                       const bool want[4], int block, const double block_val[2], const double ratio[4],
                       const char *unshadowed, const ShadowArtefacts *sa)
{
    AtomicFile af = {0};
    FILE *f = stdout;
    if (strcmp(json, "-") != 0) {
        if (!util_atomic_open(&af, "compare", json))
            return false;
        f = af.f;
    }
    fputs("{\"test\": ", f);
    util_json_string(f, files[0]);
    fputs(", \"reference\": ", f);
    util_json_string(f, files[1]);
    fprintf(f, ", \"width\": %d, \"height\": %d", t->width, t->height);
    for (int k = 0; k < 4; k++) {
        if (!want[k])
            continue;
        fprintf(f, ", \"%s\": ", k_metrics[k]);
        json_number(f, val[k]);
    }
    if (block > 0) {
        fprintf(f, ", \"block\": %d", block);
        for (int k = 0; k < 2; k++)
            if (want[k]) {
                fprintf(f, ", \"%s_block\": ", k_metrics[k]);
                json_number(f, block_val[k]);
            }
    }
    /* ratio: luminance, then r, g, b */
    fputs(", \"mean_ratio\": ", f);
    for (int c = 0; c < 4; c++) {
        json_number(f, ratio[c]);
        fputs(c == 0 ? ", \"mean_ratio_rgb\": [" : c < 3 ? ", " : "]", f);
    }
    if (unshadowed) {
        fputs(", \"shadow\": {\"unshadowed\": ", f);
        util_json_string(f, unshadowed);
        fprintf(f, ", \"lit_pixels\": %zu, \"shadowed_pixels\": %zu", sa->lit, sa->shadowed);
        fputs(", \"false_shadow\": ", f);
        json_number(f, sa->false_shadow);
        fputs(", \"false_lit\": ", f);
        json_number(f, sa->false_lit);
        fputs("}", f);
    }
    fputs("}\n", f);
    if (f == stdout) {
        if (fflush(stdout) != 0 || ferror(stdout)) {
            log_error("compare", "--json -: writing to stdout failed");
            return false;
        }
        return true;
    }
    return util_atomic_commit(&af, "compare");
}

/* Reads `path` (what: how errors name it) into *out, which must be the
 * size of `like`; false after logging. */
static bool read_matching(const char *path, const char *what, const ImageF *like, ImageF *out)
{
    if (!image_read(path, out))
        return false;
    if (out->width != like->width || out->height != like->height) {
        log_error("compare", "%s: %s is %dx%d, images are %dx%d", path, what, out->width, out->height, like->width,
                  like->height);
        return false;
    }
    return true;
}

/* The options this command knows (for "did you mean"). */
static const char *const k_compare_options[] = {"--allow-nonfinite", "--block", "--exposure", "--heatmap", "--help", "--json", "--mask", "--mask-emitters", "--metric", "--ppd", "--unshadowed", NULL};

int cmd_compare(int argc, char **argv)
{
    int block = 8;
    const char *files[2] = {NULL, NULL}, *heatmap = NULL, *mask_path = NULL, *json = NULL, *unshadowed = NULL;
    int metric = 4, nfiles = 0;
    float exposure = 1.f, ppd = FLIP_DEFAULT_PPD;
    bool allow_nonfinite = false;
    CliArgs a = {.argc = argc, .argv = argv, .operands = true};
    const char *opt, *v;
    while ((opt = cli_next(&a))) {
        if (cli_operand(&a)) {
            if (nfiles == 2) {
                cli_error(NULL, "takes two images, got a third: '%s'", opt);
                return 2;
            }
            files[nfiles++] = opt;
        } else if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            cmd_compare_help();
            return 0;
        } else if (!strcmp(opt, "--metric")) {
            CLI_VALUE(&a, v);
            if ((metric = cli_choice(opt, v, k_metrics)) < 0)
                return 2;
        } else if (!strcmp(opt, "--heatmap")) {
            CLI_VALUE(&a, v);
            if (!util_ends_with(v, ".png")) {
                cli_error(NULL, "--heatmap: '%s' must end in .png", v);
                return 2;
            }
            heatmap = v;
        } else if (!strcmp(opt, "--block")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 0, 4096, &block))
                return 2;
        } else if (!strcmp(opt, "--mask") || !strcmp(opt, "--mask-emitters")) {
            if (mask_path) {
                cli_error(NULL, "%s: give one of --mask and --mask-emitters", opt);
                return 2;
            }
            CLI_VALUE(&a, v);
            mask_path = v;
        } else if (!strcmp(opt, "--json")) {
            CLI_VALUE(&a, v);
            json = v;
        } else if (!strcmp(opt, "--unshadowed")) {
            CLI_VALUE(&a, v);
            unshadowed = v;
        } else if (!strcmp(opt, "--allow-nonfinite")) {
            allow_nonfinite = true;
        } else if (!strcmp(opt, "--exposure")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, CLI_EXPOSURE_MIN, CLI_EXPOSURE_MAX, &exposure))
                return 2;
        } else if (!strcmp(opt, "--ppd")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 1.f, 1000.f, &ppd))
                return 2;
        } else {
            cli_unknown_option(opt, k_compare_options);
            return 2;
        }
    }
    if (cli_failed(&a))
        return 2;
    if (nfiles != 2) {
        cli_error(NULL, "needs two images, TEST and REFERENCE");
        return 2;
    }
    const char *const opts[] = {"--heatmap", "--json", "TEST", "REFERENCE", "--mask", "--unshadowed"};
    const char *const paths[] = {heatmap, json, files[0], files[1], mask_path, unshadowed};
    int checked = cli_check_files(6, 2, opts, paths);
    if (checked)
        return checked;
    ImageF t = {0}, r = {0}, m = {0}, u = {0};
    uint8_t *mask = NULL;
    float *map = NULL;
    int rc = 1;
    if (!image_read(files[0], &t) || !image_read(files[1], &r))
        goto done;
    log_debug("compare", "test %s: %dx%d; reference %s: %dx%d", files[0], t.width, t.height, files[1], r.width,
              r.height);
    if (t.width != r.width || t.height != r.height) {
        log_error("compare", "%s is %dx%d but %s is %dx%d: sizes must match", files[0], t.width, t.height, files[1],
                  r.width, r.height);
        goto done;
    }
    if (unshadowed && !read_matching(unshadowed, "--unshadowed image", &t, &u))
        goto done;
    for (int k = 0; k < 3 && !allow_nonfinite; k++) {
        const ImageF *img = k == 0 ? &t : k == 1 ? &r : &u;
        const char *name = k < 2 ? files[k] : unshadowed;
        if (!img->rgb)
            continue;
        int x = 0, y = 0;
        size_t bad = image_count_nonfinite(img, &x, &y);
        if (bad) {
            log_error("compare", "%s: %zu of %zu pixels are NaN or infinite (first at x=%d y=%d); "
                      "--allow-nonfinite compares anyway", name, bad, (size_t)img->width * img->height, x, y);
            goto done;
        }
    }
    /* Radiance is never negative: such pixels (a difference image given as
     * an input, a filter's ringing) are compared as they are, but said. */
    for (int k = 0; k < 2; k++) {
        const ImageF *img = k == 0 ? &t : &r;
        size_t neg = 0, n3 = (size_t)img->width * img->height * 3;
        for (size_t i = 0; i < n3; i++)
            neg += img->rgb[i] < 0.f;
        if (neg)
            log_warn("compare", "%s: %zu pixel values are negative (radiance is not)", files[k], neg);
    }
    size_t np = (size_t)t.width * t.height;
    /* FLIP holds about 30 float planes at once (metrics.c): check that
     * they fit before the metrics allocate. */
    size_t phys = util_physical_memory(), need = np * 32 * sizeof(float);
    if (phys && need > phys / 2) {
        log_error("compare", "%s: %dx%d images need %.1f GiB for the metrics, more than the limit of %.1f GiB "
                  "(half of this machine's memory)", files[0], t.width, t.height, need / 1073741824.0,
                  phys / 2 / 1073741824.0);
        goto done;
    }
    if (mask_path) {
        if (!read_matching(mask_path, "mask", &t, &m))
            goto done;
        if (!(mask = util_malloc("compare", "the mask", np, 1)))
            goto done;
        size_t selected = 0;
        for (size_t i = 0; i < np; i++)
            selected += mask[i] = luminance(m.rgb + 3 * i) > 0.5f;
        if (selected == 0) {
            log_error("compare", "%s: the mask selects no pixel (luminance > 0.5 nowhere): nothing to compare",
                      mask_path);
            goto done;
        }
    }
    if (heatmap && !(map = util_calloc("compare", "the heat map", np, sizeof(float))))
        goto done;
    double val[4] = {0};
    bool want[4];
    for (int k = 0; k < 4; k++)
        want[k] = metric == 4 || metric == k;
    /* The heat map shows the first metric computed, or FLIP for "all". */
    int map_metric = metric == 4 ? 3 : metric;
    if (want[0])
        val[0] = metric_rmse(&t, &r, mask, map_metric == 0 ? map : NULL);
    if (want[1])
        val[1] = metric_relmse(&t, &r, mask, map_metric == 1 ? map : NULL);
    if (want[2])
        val[2] = metric_ssim(&t, &r, exposure, mask, map_metric == 2 ? map : NULL);
    if (want[3])
        val[3] = metric_flip(&t, &r, exposure, ppd, mask, map_metric == 3 ? map : NULL);
    if (metric_alloc_failures())
        goto done; /* logged, with the size */
    /* Checked before any line is printed: a failed run prints no result. */
    ShadowArtefacts sa = {0};
    if (unshadowed) {
        sa = metric_shadow_artefacts(&t, &r, &u, mask);
        if (sa.lit + sa.shadowed == 0) {
            log_error("compare", "--unshadowed %s: no pixel is fully lit or fully shadowed in %s (are they direct "
                      "light, and is %s the same view without shadows?)", unshadowed, files[1], unshadowed);
            goto done;
        }
    }
    /* With --json - the JSON alone goes to stdout, the lines to stderr. */
    FILE *txt = json && !strcmp(json, "-") ? stderr : stdout;
    for (int k = 0; k < 4; k++)
        if (want[k])
            fprintf(txt, "%s: %.6g\n", k_metrics[k], val[k]);
    double ratio[4];
    ratio[0] = metric_mean_ratio(&t, &r, mask, ratio + 1);
    if (metric == 4 && isnan(ratio[0]))
        log_warn("compare", "%s is black on the pixels compared: mean_ratio is undefined (nan)", files[1]);
    /* The same over block averages: what survives them is bias. */
    double block_val[2] = {NAN, NAN};
    if (block > 1 && (want[0] || want[1])) {
        ImageF tb = {0}, rb = {0};
        uint8_t *mt = NULL, *mr = NULL;
        bool ok = metric_block_average(&t, mask, block, &tb, &mt) && metric_block_average(&r, mask, block, &rb, &mr);
        if (ok) {
            if (want[0])
                fprintf(txt, "rmse_block: %.6g\n", block_val[0] = metric_rmse(&tb, &rb, mt, NULL));
            if (want[1])
                fprintf(txt, "relmse_block: %.6g\n", block_val[1] = metric_relmse(&tb, &rb, mt, NULL));
        }
        image_free(&tb);
        image_free(&rb);
        free(mt);
        free(mr);
        if (!ok)
            goto done;
    }
    if (metric == 4) { /* after the older lines, which scripts may read by position */
        fprintf(txt, "mean_ratio: %.6g\n", ratio[0]);
        fprintf(txt, "mean_ratio_rgb: %.6g %.6g %.6g\n", ratio[1], ratio[2], ratio[3]);
    }
    if (unshadowed) {
        fprintf(txt, "shadow_lit_pixels: %zu\nshadow_shadowed_pixels: %zu\n", sa.lit, sa.shadowed);
        fprintf(txt, "false_shadow: %.6g\nfalse_lit: %.6g\n", sa.false_shadow, sa.false_lit);
    }
    if (map) {
        if (map_metric == 0) { /* normalise RMSE by its maximum */
            float mx = 0;
            for (size_t i = 0; i < np; i++)
                mx = map[i] > mx ? map[i] : mx;
            for (size_t i = 0; mx > 0 && i < np; i++)
                map[i] /= mx;
        } else if (map_metric == 2) {
            for (size_t i = 0; i < np; i++)
                map[i] = 1.f - map[i];
        }
        if (!metric_write_heatmap(heatmap, map, t.width, t.height))
            goto done;
    }
    if (json && !write_json(json, files, &t, val, want, block > 1 ? block : 0, block_val, ratio, unshadowed, &sa)) {
        if (heatmap)
            remove(heatmap); /* all outputs or none */
        goto done;
    }
    rc = 0;
done:
    free(map);
    free(mask);
    image_free(&t);
    image_free(&r);
    image_free(&m);
    image_free(&u);
    return rc;
}
