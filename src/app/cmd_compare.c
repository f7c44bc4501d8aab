/* cmd_compare.c — `rtgi compare A B`: error of test image A against
 * reference B, as text and JSON, with an optional heat map. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/cli.h"
#include "app/commands.h"
#include "app/options.h"
#include "io/image.h"
#include "base/log.h"
#include "io/metrics.h"
#include "core/scene.h"
#include "base/util.h"

static const char *const k_metrics[] = {"rmse", "relmse", "ssim", "flip", "all", NULL};

typedef struct CompareArgs {
    const char *files[2];   /* TEST, REFERENCE */
    const char *heatmap;    /* --heatmap FILE.png, or NULL */
    const char *mask_path;  /* --mask or --mask-emitters FILE, or NULL */
    const char *json;       /* --json FILE or "-", or NULL */
    const char *unshadowed; /* --unshadowed FILE, or NULL */
    int metric;             /* index into k_metrics; 4: all */
    int block;              /* --block N (0, 1: no block averages) */
    float exposure, ppd;    /* for SSIM and FLIP */
    bool allow_nonfinite;
} CompareArgs;

#define CA CompareArgs
static const OptionDesc k_compare_options[] = {
    OPT_CHOICE("--metric", CA, metric, k_metrics, "what to measure"),
    OPT_TEXT("--heatmap", CA, heatmap, "png", "per-pixel error of the first metric (FLIP map for all), with a colour bar below it labelled with the value at full heat (default: none)"),
    OPT_WORD("--mask", CA, mask_path, "FILE", "only pixels where the mask's luminance > 0.5 count (default: all)"),
    OPT_WORD("--mask-emitters", CA, mask_path, "FILE", "the same, with the mask that render/reference --emitter-mask write: pixels that see an emitter (and their neighbours) do not count (default: all)"),
    OPT_WORD("--unshadowed", CA, unshadowed, "FILE", "shadow artefacts: TEST and REFERENCE are direct light only (render --gi none, reference --mode direct), FILE is TEST's renderer without shadows (render --shadow none); prints shadow_lit_pixels and shadow_shadowed_pixels (where REFERENCE's visibility is >= 0.95, <= 0.05), false_shadow (share of the lit ones TEST darkens below 0.5: acne) and false_lit (of the shadowed ones it lights above 0.5: peter-panning, leaks) (default: none)"),
    OPT_INT("--block", CA, block, 0, 4096, "also rmse/relmse of N x N block averages (0: off): per-pixel noise and edge aliasing average out, bias does not"),
    OPT_FLOAT("--exposure", CA, exposure, SCENE_EXPOSURE_MIN, SCENE_EXPOSURE_MAX, "display exposure for SSIM and FLIP"),
    OPT_FLOAT("--ppd", CA, ppd, 1, 1000, "FLIP pixels per degree"),
    OPT_WORD("--json", CA, json, "FILE", "also write the results as JSON ('-': stdout, the text lines then go to stderr); non-finite values are written as null (default: none)"),
    OPT_FLAG("--allow-nonfinite", CA, allow_nonfinite, "compare images with NaN/Inf pixels (an error otherwise)"),
    OPT_END,
};
#undef CA

void cmd_compare_help(void)
{
    CompareArgs def = {.metric = 4, .block = 8, .exposure = 1.f, .ppd = FLIP_DEFAULT_PPD};
    printf("usage: rtgi compare TEST REFERENCE [options]\n"
           "  TEST, REFERENCE              .pfm or .exr (OpenEXR, half or float: linear radiance) or .png\n"
           "                               (sRGB, decoded to linear)\n");
    options_print_help(stdout, k_compare_options, &def);
    printf("  --quiet | --verbose          errors only on stderr | debug lines too\n"
           "  --                           ends the options: what follows are the two images\n"
           "Prints one 'metric: value' line per metric; with --metric all also\n"
           "'mean_ratio: X' (TEST's mean luminance over REFERENCE's, on the counted pixels)\n"
           "and 'mean_ratio_rgb: R G B' (per channel): a scale error shows there, noise averages out.\n");
}

/* A JSON number as %.8g, or null where it is not finite. */
static void json_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.8g", v);
    else
        fputs("null", f);
}

/* What the command line asked for. */

/* The images, checked (compare_inputs_free frees them). */
typedef struct CompareInputs {
    ImageF test, ref;     /* equal sizes */
    ImageF unshadowed;    /* with --unshadowed, else empty */
    uint8_t *mask;        /* a byte per pixel, non-zero: counts; NULL: all count (owned) */
} CompareInputs;

/* Every result, computed before any of it is printed or written
 * (compare_results_free frees the map). */
typedef struct CompareResults {
    int width, height;    /* of the images */
    bool want[4];         /* which of k_metrics[0..3] were asked for */
    double val[4];        /* those metrics */
    int block;            /* block size of the block averages; 0: none */
    double block_val[2];  /* rmse, relmse of the block averages (NaN: not asked) */
    double ratio[4];      /* mean ratio of luminance, then of r, g, b */
    ShadowArtefacts sa;   /* with --unshadowed */
    float *map;           /* with --heatmap: per-pixel values in [0,1] (owned), else NULL */
    int map_metric;       /* the metric it shows (index of rmse, relmse, ssim, flip) */
    double map_full;      /* that metric's value at 1 (full heat) */
} CompareResults;

/* The results as one JSON object; strings escaped, non-finite numbers as
 * null. To stdout for "-", else atomically to the file. */
static bool write_json(const CompareArgs *args, const CompareResults *res)
{
    AtomicFile af = {0};
    FILE *f = stdout;
    if (strcmp(args->json, "-") != 0) {
        if (!util_atomic_open(&af, "compare", args->json))
            return false;
        f = af.f;
    }
    fputs("{\"test\": ", f);
    util_json_string(f, args->files[0]);
    fputs(", \"reference\": ", f);
    util_json_string(f, args->files[1]);
    fprintf(f, ", \"width\": %d, \"height\": %d", res->width, res->height);
    for (int k = 0; k < 4; k++) {
        if (!res->want[k])
            continue;
        fprintf(f, ", \"%s\": ", k_metrics[k]);
        json_number(f, res->val[k]);
    }
    if (res->block > 0) {
        fprintf(f, ", \"block\": %d", res->block);
        for (int k = 0; k < 2; k++)
            if (res->want[k]) {
                fprintf(f, ", \"%s_block\": ", k_metrics[k]);
                json_number(f, res->block_val[k]);
            }
    }
    /* ratio: luminance, then r, g, b */
    fputs(", \"mean_ratio\": ", f);
    for (int c = 0; c < 4; c++) {
        json_number(f, res->ratio[c]);
        fputs(c == 0 ? ", \"mean_ratio_rgb\": [" : c < 3 ? ", " : "]", f);
    }
    if (args->unshadowed) {
        const ShadowArtefacts *sa = &res->sa;
        fputs(", \"shadow\": {\"unshadowed\": ", f);
        util_json_string(f, args->unshadowed);
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

/* The 'metric: value' lines to `txt`, in the order scripts read them by. */
static void print_results(FILE *txt, const CompareArgs *args, const CompareResults *res)
{
    for (int k = 0; k < 4; k++)
        if (res->want[k])
            fprintf(txt, "%s: %.6g\n", k_metrics[k], res->val[k]);
    if (args->metric == 4 && isnan(res->ratio[0]))
        log_warn("compare", "%s is black on the pixels compared: mean_ratio is undefined (nan)", args->files[1]);
    for (int k = 0; k < 2; k++)
        if (res->block > 0 && res->want[k])
            fprintf(txt, "%s_block: %.6g\n", k_metrics[k], res->block_val[k]);
    if (args->metric == 4) { /* after the older lines, which scripts may read by position */
        fprintf(txt, "mean_ratio: %.6g\n", res->ratio[0]);
        fprintf(txt, "mean_ratio_rgb: %.6g %.6g %.6g\n", res->ratio[1], res->ratio[2], res->ratio[3]);
    }
    if (args->unshadowed) {
        fprintf(txt, "shadow_lit_pixels: %zu\nshadow_shadowed_pixels: %zu\n", res->sa.lit, res->sa.shadowed);
        fprintf(txt, "false_shadow: %.6g\nfalse_lit: %.6g\n", res->sa.false_shadow, res->sa.false_lit);
    }
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

/* Parses argv into *args. 0: go on; -1: --help was shown; else an exit
 * status (2 for usage, 1 for an output that cannot be written:
 * cli_check_files), after logging. */
static int compare_parse_args(int argc, char **argv, CompareArgs *args)
{
    *args = (CompareArgs){.metric = 4, .block = 8, .exposure = 1.f, .ppd = FLIP_DEFAULT_PPD};
    int nfiles = 0;
    CliArgs a = {.argc = argc, .argv = argv, .operands = true};
    const char *opt;
    while ((opt = cli_next(&a))) {
        if (cli_operand(&a)) {
            if (nfiles == 2) {
                usage_error(NULL, "takes two images, got a third: '%s'", opt);
                return 2;
            }
            args->files[nfiles++] = opt;
        } else if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            cmd_compare_help();
            return -1;
        } else {
            bool mask = !strcmp(opt, "--mask") || !strcmp(opt, "--mask-emitters");
            if (mask && args->mask_path) {
                usage_error(NULL, "%s: give one of --mask and --mask-emitters", opt);
                return 2;
            }
            int took = options_take(k_compare_options, opt, &a, args);
            if (took < 0)
                return 2;
            if (!took) {
                options_unknown(opt, (const OptionDesc *const[]){k_compare_options, NULL}, false);
                return 2;
            }
        }
    }
    if (cli_failed(&a))
        return 2;
    if (nfiles != 2) {
        usage_error(NULL, "needs two images, TEST and REFERENCE");
        return 2;
    }
    const char *const opts[] = {"--heatmap", "--json", "TEST", "REFERENCE", "--mask", "--unshadowed"};
    const char *const paths[] = {args->heatmap, args->json, args->files[0], args->files[1], args->mask_path,
                                 args->unshadowed};
    return cli_check_files(6, 2, opts, paths);
}

static void compare_inputs_free(CompareInputs *in)
{
    image_free(&in->test);
    image_free(&in->ref);
    image_free(&in->unshadowed);
    free(in->mask);
    in->mask = NULL;
}

/* false after logging if one of t, r, u (u may be empty) has a NaN or
 * infinite pixel; names: their paths. */
static bool check_finite(const ImageF *const img[3], const char *const names[3])
{
    for (int k = 0; k < 3; k++) {
        if (!img[k]->rgb)
            continue;
        int x = 0, y = 0;
        size_t bad = image_count_nonfinite(img[k], &x, &y);
        if (bad) {
            log_error("compare", "%s: %zu of %zu pixels are NaN or infinite (first at x=%d y=%d); "
                      "--allow-nonfinite compares anyway", names[k], bad, (size_t)img[k]->width * img[k]->height, x,
                      y);
            return false;
        }
    }
    return true;
}

/* Reads the mask image at `path` (the size of `like`) into a byte per
 * pixel (*mask, caller frees): luminance > 0.5 counts. false after logging,
 * also when it selects no pixel. */
static bool read_mask(const char *path, const ImageF *like, uint8_t **mask)
{
    ImageF m = {0};
    size_t np = (size_t)like->width * like->height, selected = 0;
    bool ok = read_matching(path, "mask", like, &m) && (*mask = util_malloc("compare", "the mask", np, 1));
    for (size_t i = 0; ok && i < np; i++)
        selected += (*mask)[i] = luminance(m.rgb + 3 * i) > 0.5f;
    if (ok && selected == 0) {
        log_error("compare", "%s: the mask selects no pixel (luminance > 0.5 nowhere): nothing to compare", path);
        ok = false;
    }
    image_free(&m);
    return ok;
}

/* Reads TEST, REFERENCE, the --unshadowed image and the mask into *in and
 * checks them: equal sizes, finite pixels (unless --allow-nonfinite), room
 * for the metrics; negative values are only said. false after logging; *in
 * then holds what was read (compare_inputs_free). */
static bool compare_load_inputs(const CompareArgs *args, CompareInputs *in)
{
    const char *const *files = args->files;
    ImageF *t = &in->test, *r = &in->ref;
    if (!image_read(files[0], t) || !image_read(files[1], r))
        return false;
    log_debug("compare", "test %s: %dx%d; reference %s: %dx%d", files[0], t->width, t->height, files[1], r->width,
              r->height);
    /* A PNG holds a tone-mapped image (exposure, clamp, sRGB), a PFM or EXR
     * radiance: numbers between the two measure the tone mapping too. */
    bool display[2];
    for (int k = 0; k < 2; k++)
        display[k] = util_ends_with(files[k], ".png") || util_ends_with(files[k], ".PNG");
    if (display[0] != display[1])
        log_warn("compare", "%s is a tone-mapped image (PNG) but %s is linear radiance: the numbers measure the "
                 "exposure, clamp and sRGB curve too; compare two radiance files (.pfm, .exr) or two PNGs",
                 files[display[0] ? 0 : 1], files[display[0] ? 1 : 0]);
    if (t->width != r->width || t->height != r->height) {
        log_error("compare", "%s is %dx%d but %s is %dx%d: sizes must match", files[0], t->width, t->height,
                  files[1], r->width, r->height);
        return false;
    }
    if (args->unshadowed && !read_matching(args->unshadowed, "--unshadowed image", t, &in->unshadowed))
        return false;
    const ImageF *const imgs[3] = {t, r, &in->unshadowed};
    const char *const names[3] = {files[0], files[1], args->unshadowed};
    if (!args->allow_nonfinite && !check_finite(imgs, names))
        return false;
    /* Radiance is never negative: such pixels (a difference image given as
     * an input, a filter's ringing) are compared as they are, but said. */
    for (int k = 0; k < 2; k++) {
        size_t neg = 0, n3 = (size_t)imgs[k]->width * imgs[k]->height * 3;
        for (size_t i = 0; i < n3; i++)
            neg += imgs[k]->rgb[i] < 0.f;
        if (neg)
            log_warn("compare", "%s: %zu pixel values are negative (radiance is not)", files[k], neg);
    }
    /* FLIP holds about 30 float planes at once (metrics.c): check that
     * they fit before the metrics allocate. */
    size_t np = (size_t)t->width * t->height;
    size_t phys = util_physical_memory(), need = np * 32 * sizeof(float);
    if (phys && need > phys / 2) {
        log_error("compare", "%s: %dx%d images need %.1f GiB for the metrics, more than the limit of %.1f GiB "
                  "(half of this machine's memory)", files[0], t->width, t->height, need / 1073741824.0,
                  phys / 2 / 1073741824.0);
        return false;
    }
    return !args->mask_path || read_mask(args->mask_path, t, &in->mask);
}

static void compare_results_free(CompareResults *res)
{
    free(res->map);
    res->map = NULL;
}

/* rmse and relmse (those `want`ed) of the block×block averages of t and r
 * into block_val. false after logging if memory runs out. */
static bool block_metrics(const ImageF *t, const ImageF *r, const uint8_t *mask, int block, const bool want[2],
                          double block_val[2])
{
    ImageF tb = {0}, rb = {0};
    uint8_t *mt = NULL, *mr = NULL;
    bool ok = metric_block_average(t, mask, block, &tb, &mt) && metric_block_average(r, mask, block, &rb, &mr);
    if (ok && want[0])
        block_val[0] = metric_rmse(&tb, &rb, mt, NULL);
    if (ok && want[1])
        block_val[1] = metric_relmse(&tb, &rb, mt, NULL);
    image_free(&tb);
    image_free(&rb);
    free(mt);
    free(mr);
    return ok;
}

/* Scales the heat map of metric `k` to [0,1] with 1 the worst: RMSE by
 * its maximum, SSIM as 1 − SSIM; relMSE and FLIP as they are. Returns the
 * metric's value at 1 (the colour bar's label). */
static double heatmap_normalise(float *map, size_t np, int k)
{
    if (k == 0) {
        float mx = 0;
        for (size_t i = 0; i < np; i++)
            mx = map[i] > mx ? map[i] : mx;
        for (size_t i = 0; mx > 0 && i < np; i++)
            map[i] /= mx;
        return mx;
    }
    if (k == 2)
        for (size_t i = 0; i < np; i++)
            map[i] = 1.f - map[i];
    return 1.0;
}

/* The colour bar's name of metric k's heat map. */
static const char *const k_heatmap_names[] = {"rmse", "relmse", "1-ssim", "flip"};

/* Every metric asked for, the block averages', the mean ratios, the
 * shadow artefacts and the heat map into *res, before anything is printed:
 * a failed run prints no result. false after logging; *res then holds what
 * was made (compare_results_free). */
static bool compare_metrics(const CompareArgs *args, const CompareInputs *in, CompareResults *res)
{
    const ImageF *t = &in->test, *r = &in->ref;
    const uint8_t *mask = in->mask;
    size_t np = (size_t)t->width * t->height;
    *res = (CompareResults){.width = t->width, .height = t->height, .block = args->block > 1 ? args->block : 0,
                            .block_val = {NAN, NAN}};
    if (args->heatmap && !(res->map = util_calloc("compare", "the heat map", np, sizeof(float))))
        return false;
    for (int k = 0; k < 4; k++)
        res->want[k] = args->metric == 4 || args->metric == k;
    /* The heat map shows the first metric computed, or FLIP for "all". */
    int mm = args->metric == 4 ? 3 : args->metric;
    float *map = res->map;
    if (res->want[0])
        res->val[0] = metric_rmse(t, r, mask, mm == 0 ? map : NULL);
    if (res->want[1])
        res->val[1] = metric_relmse(t, r, mask, mm == 1 ? map : NULL);
    if (res->want[2])
        res->val[2] = metric_ssim(t, r, args->exposure, mask, mm == 2 ? map : NULL);
    if (res->want[3])
        res->val[3] = metric_flip(t, r, args->exposure, args->ppd, mask, mm == 3 ? map : NULL);
    if (metric_alloc_failures())
        return false; /* logged, with the size */
    if (args->unshadowed) {
        res->sa = metric_shadow_artefacts(t, r, &in->unshadowed, mask);
        if (res->sa.lit + res->sa.shadowed == 0) {
            log_error("compare", "--unshadowed %s: no pixel is fully lit or fully shadowed in %s (are they direct "
                      "light, and is %s the same view without shadows?)", args->unshadowed, args->files[1],
                      args->unshadowed);
            return false;
        }
    }
    res->ratio[0] = metric_mean_ratio(t, r, mask, res->ratio + 1);
    /* The same over block averages: what survives them is bias. */
    if (res->block && (res->want[0] || res->want[1]) &&
        !block_metrics(t, r, mask, res->block, res->want, res->block_val))
        return false;
    if (map) {
        res->map_full = heatmap_normalise(map, np, mm);
        res->map_metric = mm;
    }
    return true;
}

int cmd_compare(int argc, char **argv)
{
    CompareArgs args;
    int rc = compare_parse_args(argc, argv, &args);
    if (rc != 0)
        return rc < 0 ? 0 : rc;
    CompareInputs in = {0};
    CompareResults res = {0};
    rc = 1;
    if (!compare_load_inputs(&args, &in) || !compare_metrics(&args, &in, &res))
        goto done;
    /* With --json - the JSON alone goes to stdout, the lines to stderr. */
    print_results(args.json && !strcmp(args.json, "-") ? stderr : stdout, &args, &res);
    if (res.map && !metric_write_heatmap_bar(args.heatmap, res.map, res.width, res.height,
                                             k_heatmap_names[res.map_metric], res.map_full))
        goto done;
    if (args.json && !write_json(&args, &res)) {
        if (args.heatmap)
            remove(args.heatmap); /* all outputs or none */
        goto done;
    }
    rc = 0;
done:
    compare_results_free(&res);
    compare_inputs_free(&in);
    return rc;
}
