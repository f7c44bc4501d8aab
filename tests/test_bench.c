/* test_bench.c — `rtgi bench`: the bench.json schema (one entry per
 * technique, the measured values sane against the reference: no GI is
 * darker than the reference, a GI technique brings the mean nearer; the GPU
 * memory of the technique that counts it, vct), the
 * reference cache (a second run reuses it and measures the same), and
 * report.html in headless Chromium: it loads without errors and draws one
 * scatter point per technique. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <dirent.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "io/report_html.h"
#include "test_util.h"
#include "base/util.h"

typedef DIR DirStream; /* DIR is the output directory below */

#define DIR RTGI_TEST_TMP "/bench_out"
#define CACHE RTGI_TEST_TMP "/bench_cache"

static cJSON *g_doc;

static cJSON *load_json(void)
{
    size_t n = 0;
    char *text = util_read_file(DIR "/bench.json", &n);
    assert_non_null(text);
    cJSON *doc = cJSON_Parse(text);
    free(text);
    assert_non_null(doc);
    return doc;
}

static const cJSON *field(const cJSON *o, const char *key, int type_check)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!v)
        fail_msg("bench.json: no \"%s\"", key);
    switch (type_check) {
    case 's': assert_true(cJSON_IsString(v) && v->valuestring[0]); break;
    case 'n': assert_true(cJSON_IsNumber(v) && isfinite(v->valuedouble)); break;
    case 'o': assert_true(cJSON_IsObject(v)); break;
    case 'a': assert_true(cJSON_IsArray(v)); break;
    case 'b': assert_true(cJSON_IsBool(v)); break;
    }
    return v;
}

static int setup(void **state)
{
    (void)state;
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' '%s'", DIR, CACHE);
    if (system(cmd) != 0)
        return -1;
    char *err = NULL;
    int rc = test_run_cli(&err, "bench", "--size", "48x48", "--gi", "none,rsm,vpl-slc:vpls=1024,vct:vct.size=16",
                          "--spp", "16", "--frames", "1", "--threads", "2", "--cache", CACHE, "--out", DIR, NULL);
    if (rc != 0)
        fprintf(stderr, "bench failed (%d): %s\n", rc, err ? err : "");
    free(err);
    return rc;
}

static void schema(void **state)
{
    (void)state;
    cJSON *doc = g_doc = load_json();
    field(doc, "commit", 's');
    field(doc, "date", 's');
    field(doc, "device", 's');
    field(doc, "gl_renderer", 's');
    field(doc, "scene", 's');
    assert_int_equal((int)field(doc, "width", 'n')->valuedouble, 48);
    assert_int_equal((int)field(doc, "height", 'n')->valuedouble, 48);
    assert_int_equal((int)field(doc, "spp", 'n')->valuedouble, 16);
    field(doc, "display_exposure", 'n');
    field(doc, "metric_exposure", 'n');
    const cJSON *ref = field(doc, "reference", 'o');
    assert_string_equal(field(ref, "mode", 's')->valuestring, "full");
    assert_false(cJSON_IsTrue(field(ref, "reused", 'b')));
    assert_int_equal(access(field(ref, "cache", 's')->valuestring, R_OK), 0);
    const cJSON *t = field(doc, "techniques", 'a');
    assert_int_equal(cJSON_GetArraySize(t), 4);
    static const char *const gi[] = {"none", "rsm", "vpl-slc", "vct"};
    double ratio[4], mib = 0, light_mib[4][3];
    for (int i = 0; i < 4; i++) {
        const cJSON *e = cJSON_GetArrayItem(t, i);
        assert_string_equal(field(e, "gi", 's')->valuestring, gi[i]);
        assert_string_equal(field(e, "shadow", 's')->valuestring, "pcss");
        field(e, "label", 's');
        field(e, "id", 's');
        const cJSON *set = field(e, "settings", 'o');
        /* Each setting by its name, and by its old key (scripts read it). */
        assert_string_equal(field(set, "vpl.count", 's')->valuestring, i == 2 ? "1024" : "16384");
        assert_string_equal(field(set, "gi.vpls", 's')->valuestring, i == 2 ? "1024" : "16384");
        assert_string_equal(field(set, "vct.size", 's')->valuestring, i == 3 ? "16" : "128");
        const cJSON *passes = field(e, "passes", 'a');
        assert_true(cJSON_GetArraySize(passes) >= 3);
        double sum = 0;
        int gathers = 0;
        for (int k = 0; k < cJSON_GetArraySize(passes); k++) {
            const cJSON *p = cJSON_GetArrayItem(passes, k);
            const char *name = field(p, "name", 's')->valuestring;
            double ms = field(p, "gpu_ms", 'n')->valuedouble;
            assert_true(ms >= 0);
            field(p, "wall_ms", 'n');
            sum += ms;
            /* The gather pass (rsm's rsm_gather, vpl-slc's vpl_shade) carries
             * its evaluations per frame; no other pass does. */
            const cJSON *ev = cJSON_GetObjectItemCaseSensitive(p, "evaluations");
            bool gather = !strcmp(name, "rsm_gather") || !strcmp(name, "vpl_shade");
            assert_true(gather == (ev != NULL));
            if (ev) {
                assert_true(cJSON_IsNumber(ev) && ev->valuedouble > 0);
                gathers++;
            }
        }
        assert_int_equal(gathers, i == 1 || i == 2 ? 1 : 0);
        assert_true(fabs(sum - field(e, "gpu_ms", 'n')->valuedouble) < 1e-6 * (1 + sum));
        assert_true(field(e, "frame_ms", 'n')->valuedouble > 0);
        /* The GPU memory the technique counts: vct's volumes (16³: albedo,
         * normal, radiance (level 0: the directional chains start from it)
         * and six directional chains, 126384 bytes), its
         * opaque-voxel list (4 · (4 + 16³/8) = 2064), its two 24×24
         * RGBA32F images (18432), the voxelization's sums (32 · 16³ =
         * 131072) and compute work buffer (4 words a submesh, 1 a
         * triangle, of the Cornell box bench draws) and its parameters'
         * UBO; null without a technique. */
        const cJSON *mem = cJSON_GetObjectItemCaseSensitive(field(e, "stats", 'o'), "gi_memory_mib");
        if (!mem)
            fail_msg("bench.json: no \"stats.gi_memory_mib\" in %s", gi[i]);
        if (i == 3) {
            assert_true(cJSON_IsNumber(mem));
            mib = mem->valuedouble;
            Scene cornell;
            assert_true(scene_build_cornell(&cornell));
            scene_finalize(&cornell);
            double work = 4.0 * (4.0 * cornell.submesh_count + (double)(cornell.index_count / 3));
            scene_free(&cornell);
            assert_true(fabs(mib - (126384 + 2064 + 18432 + 131072 + work + sizeof(GpuVctParams)) / (1024.0 * 1024.0)) <
                        1e-9);
        } else if (i == 0) {
            assert_true(cJSON_IsNull(mem)); /* no technique */
        } else {
            assert_true(cJSON_IsNumber(mem) && mem->valuedouble > 0); /* rsm's and vpl-slc's buffers */
        }
        /* Every owner's memory, and the total their sum. */
        const cJSON *sj = field(e, "stats", 'o');
        double parts = cJSON_IsNumber(mem) ? mem->valuedouble : 0;
        static const char *const owners[] = {"light_memory_mib", "frame_memory_mib", "scene_memory_mib"};
        for (int k = 0; k < 3; k++) {
            light_mib[i][k] = field(sj, owners[k], 'n')->valuedouble;
            assert_true(light_mib[i][k] > 0);
            parts += light_mib[i][k];
        }
        assert_true(fabs(field(sj, "gpu_memory_mib", 'n')->valuedouble - parts) < 1e-9 * parts);
        const cJSON *m = field(e, "metrics", 'o');
        double rmse = field(m, "rmse", 'n')->valuedouble, relmse = field(m, "relmse", 'n')->valuedouble;
        double flip = field(m, "flip", 'n')->valuedouble, ssim = field(m, "ssim", 'n')->valuedouble;
        ratio[i] = field(m, "mean_ratio", 'n')->valuedouble;
        assert_true(rmse > 0 && relmse > 0 && flip > 0 && flip < 1 && ssim > 0 && ssim <= 1);
        const cJSON *img = field(e, "images", 'o');
        const char *keys[] = {"png", "exr", "flip_png"};
        for (int k = 0; k < 3; k++) {
            char path[1024];
            snprintf(path, sizeof path, "%s/%s", DIR, field(img, keys[k], 's')->valuestring);
            assert_int_equal(access(path, R_OK), 0);
        }
    }
    /* Measured: without GI the Cornell box lacks its indirect light (about
     * 40% of the mean); one bounce brings most of it back. */
    print_message("mean ratio: none %.3f, rsm %.3f, vpl-slc %.3f, vct %.3f; vct gi_memory_mib %.4f\n", ratio[0],
                  ratio[1], ratio[2], ratio[3], mib);
    /* rsm adds the quad light's RSM to the shadow map: six s² faces of a
     * 16-byte texel and a 4-byte depth, so the difference is 120·s² bytes
     * for a whole s (the frame and scene are the same for both). */
    double extra = (light_mib[1][0] - light_mib[0][0]) * 1024.0 * 1024.0 / 120.0, side = sqrt(extra);
    print_message("light products: none %.4f MiB, rsm %.4f MiB: an RSM of %.3f² texels a face\n", light_mib[0][0],
                  light_mib[1][0], side);
    assert_true(side >= 16 && fabs(side - round(side)) < 1e-6);
    assert_true(light_mib[1][1] == light_mib[0][1] && light_mib[1][2] == light_mib[0][2]);
    assert_true(ratio[0] < 0.75);
    for (int i = 1; i < 4; i++)
        assert_true(ratio[i] > ratio[0] + 0.1 && ratio[i] < 1.1);
}

/* One CSV record's fields (RFC 4180 quoting), from *p to its CRLF; *p moves
 * past it. Returns the field count (at most cap). */
static int csv_record(char **p, char fields[][256], int cap)
{
    int n = 0;
    char *s = *p;
    while (*s && n < cap) {
        size_t k = 0;
        if (*s == '"') {
            for (s++; *s && !(*s == '"' && s[1] != '"'); s++) {
                if (*s == '"')
                    s++; /* a doubled quote */
                if (k < 255)
                    fields[n][k++] = *s;
            }
            if (*s == '"')
                s++;
        } else {
            for (; *s && *s != ',' && *s != '\r'; s++)
                if (k < 255)
                    fields[n][k++] = *s;
        }
        fields[n++][k] = 0;
        if (*s == ',') {
            s++;
            continue;
        }
        break;
    }
    assert_true(s[0] == '\r' && s[1] == '\n');
    *p = s + 2;
    return n;
}

static int csv_column(char fields[][256], int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (!strcmp(fields[i], name))
            return i;
    fail_msg("bench.csv: no column %s", name);
    return -1;
}

/* bench.csv holds bench.json's techniques, a row each, and bench_passes.csv
 * their passes. */
static void csv_matches_json(void **state)
{
    (void)state;
    const cJSON *t = field(g_doc, "techniques", 'a');
    size_t n = 0;
    char *text = util_read_file(DIR "/bench.csv", &n), *p = text;
    assert_non_null(text);
    static char head[32][256], row[32][256];
    int cols = csv_record(&p, head, 32);
    int label = csv_column(head, cols, "label"), relmse = csv_column(head, cols, "relmse");
    int gpu = csv_column(head, cols, "gpu_ms"), mem = csv_column(head, cols, "gi_memory_mib");
    int renderer = csv_column(head, cols, "gl_renderer");
    for (int i = 0; i < cJSON_GetArraySize(t); i++) {
        const cJSON *e = cJSON_GetArrayItem(t, i);
        assert_int_equal(csv_record(&p, row, 32), cols);
        assert_string_equal(row[label], field(e, "label", 's')->valuestring);
        assert_string_equal(row[renderer], field(g_doc, "gl_renderer", 's')->valuestring); /* has a comma */
        double want = field(field(e, "metrics", 'o'), "relmse", 'n')->valuedouble;
        assert_true(fabs(atof(row[relmse]) - want) <= 1e-8 * want);
        assert_true(fabs(atof(row[gpu]) - field(e, "gpu_ms", 'n')->valuedouble) < 1e-6);
        const cJSON *m = cJSON_GetObjectItem(field(e, "stats", 'o'), "gi_memory_mib");
        assert_true(cJSON_IsNull(m) ? row[mem][0] == 0 : fabs(atof(row[mem]) - m->valuedouble) < 1e-6);
    }
    assert_int_equal(*p, 0);
    free(text);

    text = util_read_file(DIR "/bench_passes.csv", &n);
    p = text;
    assert_non_null(text);
    cols = csv_record(&p, head, 32);
    assert_int_equal(cols, 5);
    int passes = 0;
    for (int i = 0; i < cJSON_GetArraySize(t); i++) {
        const cJSON *e = cJSON_GetArrayItem(t, i), *pass;
        cJSON_ArrayForEach(pass, field(e, "passes", 'a')) {
            assert_int_equal(csv_record(&p, row, 32), 5);
            assert_string_equal(row[0], field(e, "id", 's')->valuestring);
            assert_string_equal(row[2], field(pass, "name", 's')->valuestring);
            assert_true(fabs(atof(row[3]) - field(pass, "gpu_ms", 'n')->valuedouble) < 1e-6);
            passes++;
        }
    }
    assert_int_equal(*p, 0);
    assert_true(passes >= 12);
    free(text);
}

/* A second run reuses the cached reference and measures the same errors. */
static void cache_reused(void **state)
{
    (void)state;
    char *err = NULL;
    int rc = test_run_cli(&err, "bench", "--size", "48x48", "--gi", "none", "--spp", "16", "--frames", "1",
                          "--cache", CACHE, "--out", DIR "/again", NULL);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(err, "reusing the cached reference"));
    free(err);
    size_t n = 0;
    char *text = util_read_file(DIR "/again/bench.json", &n);
    assert_non_null(text);
    cJSON *doc = cJSON_Parse(text);
    free(text);
    assert_true(cJSON_IsTrue(field(field(doc, "reference", 'o'), "reused", 'b')));
    const cJSON *a = field(cJSON_GetArrayItem(field(doc, "techniques", 'a'), 0), "metrics", 'o');
    const cJSON *b = field(cJSON_GetArrayItem(field(g_doc, "techniques", 'a'), 0), "metrics", 'o');
    assert_true(fabs(field(a, "relmse", 'n')->valuedouble - field(b, "relmse", 'n')->valuedouble) < 1e-9);
    cJSON_Delete(doc);
}

/* --ssaa reaches every item and is recorded: on the Cornell box's hard
 * shadows against the direct-light reference, 2×2 supersampling takes the
 * aliased edges out (measured at 48²: relMSE 0.0044 -> 0.0020), so its error
 * must fall well below the same bench's without it. */
static double bench_relmse(const char *out, const char *ssaa, int *recorded)
{
    char *err = NULL;
    int rc = test_run_cli(&err, "bench", "--size", "48x48", "--gi", "none", "--shadow", "hard", "--ref-mode",
                          "direct", "--spp", "64", "--frames", "1", "--ssaa", ssaa, "--cache", CACHE, "--out", out,
                          NULL);
    if (rc != 0)
        fail_msg("bench --ssaa %s failed (%d): %s", ssaa, rc, err ? err : "");
    free(err);
    char path[1024];
    snprintf(path, sizeof path, "%s/bench.json", out);
    size_t n = 0;
    char *text = util_read_file(path, &n);
    assert_non_null(text);
    cJSON *doc = cJSON_Parse(text);
    free(text);
    assert_non_null(doc);
    *recorded = (int)field(doc, "ssaa", 'n')->valuedouble;
    const cJSON *m = field(cJSON_GetArrayItem(field(doc, "techniques", 'a'), 0), "metrics", 'o');
    double relmse = field(m, "relmse", 'n')->valuedouble;
    cJSON_Delete(doc);
    return relmse;
}

static void ssaa_lowers_the_error(void **state)
{
    (void)state;
    int s1 = 0, s2 = 0;
    double plain = bench_relmse(DIR "/ssaa1", "1", &s1), super = bench_relmse(DIR "/ssaa2", "2", &s2);
    print_message("hard shadows against direct light, 48x48: relMSE %.5f, with --ssaa 2 %.5f\n", plain, super);
    assert_int_equal(s1, 1);
    assert_int_equal(s2, 2);
    assert_true(super < 0.7 * plain);
    char *err = NULL;
    int rc = test_run_cli(&err, "bench", "--out", DIR "/x", "--size", "4096x64", "--ssaa", "8", NULL);
    test_expect_cli_error(rc, err, 2, "--ssaa 8", "16384");
}

static void bad_options(void **state)
{
    (void)state;
    char *err = NULL;
    int rc = test_run_cli(&err, "bench", "--gi", "rsm", NULL);
    test_expect_cli_error(rc, err, 2, "--out", NULL);
    rc = test_run_cli(&err, "bench", "--out", DIR "/x", "--gi", "rsn", NULL);
    test_expect_cli_error(rc, err, 2, "rsn", "rsm");
    rc = test_run_cli(&err, "bench", "--out", DIR "/x", "--gi", "rsm:samplez=4", NULL);
    test_expect_cli_error(rc, err, 2, "samplez", NULL);
    rc = test_run_cli(&err, "bench", "--out", DIR "/x", "--gi", "rsm:samples=0", NULL);
    test_expect_cli_error(rc, err, 2, "samples", NULL);
    rc = test_run_cli(&err, "bench", "--out", DIR "/x", "--shadow", "pcs", NULL);
    test_expect_cli_error(rc, err, 2, "pcs", "pcss");
    rc = test_run_cli(&err, "bench", "--out", DIR "/x", "--sise", "8x8", NULL);
    test_expect_cli_error(rc, err, 2, "--sise", "--size");
    assert_int_not_equal(access(DIR "/x", F_OK), 0); /* nothing written */
}

/* In --gi and --shadow lists a duplicate key (README: an error, as in
 * scene files), an empty item and an empty setting are usage errors naming
 * the option (and the key), not dropped or overridden silently. */
static void bad_lists(void **state)
{
    (void)state;
    static const char *const bad[][3] = {
        /* option, value, what the error line must hold besides the option */
        {"--gi", "rsm:samples=4:samples=8", "'samples' is given twice"},
        {"--gi", "rsm:samples=4:rsm.samples=8", "'rsm.samples' is given twice"},
        {"--gi", "vct:vct_bounces=2:vct_size=16:vct_bounces=1", "'vct_bounces' is given twice"},
        {"--gi", "none,,rsm", "empty item"},
        {"--gi", "none,", "empty item"},
        {"--gi", ",none", "empty item"},
        {"--gi", ",", "empty item"},
        {"--gi", "", "empty item"},
        {"--gi", "rsm:", "empty setting"},
        {"--gi", "rsm::", "empty setting"},
        {"--gi", "rsm::samples=4", "empty setting"},
        {"--gi", "rsm:samples=4:", "empty setting"},
        {"--gi", ":samples=4", "no technique"},
        {"--shadow", "pcf,", "empty item"},
        {"--shadow", ",pcf", "empty item"},
        {"--shadow", "pcf,,hard", "empty item"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char *err = NULL, opt[32];
        int rc = test_run_cli(&err, "bench", "--out", DIR "/x", bad[i][0], bad[i][1], NULL);
        snprintf(opt, sizeof opt, "bench: %s: ", bad[i][0]);
        test_expect_cli_error(rc, err, 2, opt, bad[i][2]);
    }
    assert_int_not_equal(access(DIR "/x", F_OK), 0); /* nothing written */
}

/* A 16x16, 1 spp, one-frame bench of `scene` with `--gi gi` into `out`
 * (the cache shared); returns the exit status and stderr in *err. */
static int small_bench(char **err, const char *out, const char *scene, const char *gi)
{
    return test_run_cli(err, "bench", "--scene", scene, "--size", "16x16", "--gi", gi, "--spp", "1", "--frames", "1",
                        "--threads", "2", "--cache", CACHE, "--out", out, NULL);
}

/* small_bench that must succeed: fails the test with its stderr if not. */
static void small_bench_ok(const char *out, const char *scene, const char *gi)
{
    char *err = NULL;
    int rc = small_bench(&err, out, scene, gi);
    if (rc != 0)
        fail_msg("bench --scene '%s' --gi '%s' --out %s failed (%d): %s", scene, gi, out, rc, err ? err : "");
    free(err);
}

/* `out`/bench.json parsed (fails the test if it is missing or not JSON). */
static cJSON *load_bench_json(const char *out)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/bench.json", out);
    char *text = util_read_file(path, NULL);
    assert_non_null(text);
    cJSON *doc = cJSON_Parse(text);
    free(text);
    assert_non_null(doc);
    return doc;
}

/* A --gi item longer than any fixed buffer is read whole: its last setting
 * is the one given (cut at 255 bytes, "samples=4096" had become
 * "samples=4"), and the label and overrides carry it. */
static void long_gi_item(void **state)
{
    (void)state;
    char item[400] = "rsm:scale=1.";
    size_t len = strlen(item);
    while (len < 300)
        item[len++] = '0';
    snprintf(item + len, sizeof item - len, ":samples=4096");
    small_bench_ok(DIR "/long", "cornell", item);
    cJSON *doc = load_bench_json(DIR "/long");
    const cJSON *e = cJSON_GetArrayItem(field(doc, "techniques", 'a'), 0);
    assert_string_equal(field(field(e, "settings", 'o'), "gi.samples", 's')->valuestring, "4096");
    assert_string_equal(field(field(e, "settings", 'o'), "rsm.samples", 's')->valuestring, "4096");
    assert_true(util_ends_with(field(e, "overrides", 's')->valuestring, ", samples=4096"));
    assert_true(util_ends_with(field(e, "label", 's')->valuestring, ", samples=4096)"));
    cJSON_Delete(doc);
}

/* A --cache that is a regular file is refused before DIR and DIR/images
 * are made (they were left behind, empty). */
static void bad_cache_leaves_no_dir(void **state)
{
    (void)state;
    const char *file = test_tmp_file("bench_cache_file", "not a directory\n");
    char *err = NULL;
    int rc = test_run_cli(&err, "bench", "--size", "16x16", "--gi", "none", "--spp", "1", "--frames", "1", "--cache",
                          file, "--out", DIR "/badcache", "--quiet", NULL);
    test_expect_cli_error(rc, err, 1, file, "not a directory");
    assert_int_not_equal(access(DIR "/badcache", F_OK), 0);
}

/* Size of `dir`/name in bytes (-1 if missing). */
static long file_size(const char *dir, const char *name)
{
    char path[1024];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

/* `dir`/name's bytes (free them), NULL if missing. */
static char *file_bytes(const char *dir, const char *name, size_t *n)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return util_read_file(path, n);
}

/* The entries of `dir` and `dir`/images, sorted, as "a,b,images/c,...",
 * hidden ones included (at most 64). */
static void list_dir(const char *dir, char *out, size_t cap)
{
    char names[64][288];
    int n = 0;
    for (int level = 0; level < 2; level++) {
        char path[1024];
        snprintf(path, sizeof path, level ? "%s/images" : "%s", dir);
        DirStream *d = opendir(path);
        for (struct dirent *de; d && (de = readdir(d)) && n < 64;)
            if (strcmp(de->d_name, ".") && strcmp(de->d_name, ".."))
                snprintf(names[n++], sizeof names[0], "%s%s", level ? "images/" : "", de->d_name);
        if (d)
            closedir(d);
    }
    for (int i = 0; i < n; i++)
        for (int k = i + 1; k < n; k++)
            if (strcmp(names[k], names[i]) < 0) {
                char t[288];
                memcpy(t, names[i], sizeof t);
                memcpy(names[i], names[k], sizeof t);
                memcpy(names[k], t, sizeof t);
            }
    out[0] = 0;
    for (int i = 0; i < n; i++)
        snprintf(out + strlen(out), cap - strlen(out), "%s,", names[i]);
}

/* A 40x40 bench into `out` with writes over `limit` bytes failing (EFBIG:
 * RLIMIT_FSIZE, as a full disk); returns the exit status and stderr. */
static int bench_with_file_limit(char **err, const char *out, long limit)
{
    struct rlimit old, rl;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    rl = old;
    rl.rlim_cur = (rlim_t)limit;
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN); /* inherited: writes fail instead of killing */
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &rl), 0);
    int rc = test_run_cli(err, "bench", "--size", "40x40", "--gi", "none", "--spp", "1", "--frames", "1",
                          "--threads", "2", "--cache", CACHE, "--out", out, "--quiet", NULL);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, old_handler);
    return rc;
}

/* A killed run's staging directory (its process gone) is removed by the
 * next run into DIR; a running one's (this test's own PID) is left. */
static void killed_runs_staging_is_removed(void **state)
{
    (void)state;
    const char *out = DIR "/stale";
    mkdir(out, 0777);
    pid_t child = fork(); /* a PID that has certainly ended */
    assert_true(child >= 0);
    if (child == 0)
        _exit(0);
    waitpid(child, NULL, 0);
    char dead[600], live[600], file[700];
    snprintf(dead, sizeof dead, "%s/.bench-%d-abcdef", out, (int)child);
    snprintf(live, sizeof live, "%s/.bench-%d-ghijkl", out, (int)getpid());
    const char *dirs[2] = {dead, live};
    for (int i = 0; i < 2; i++) {
        mkdir(dirs[i], 0777);
        snprintf(file, sizeof file, "%s/images", dirs[i]);
        mkdir(file, 0777);
        static const char *const names[] = {"images/e00_pcss_none.exr", "bench.json"};
        for (int k = 0; k < 2; k++) {
            snprintf(file, sizeof file, "%s/%s", dirs[i], names[k]);
            FILE *f = fopen(file, "w");
            assert_non_null(f);
            fputs("partial", f);
            fclose(f);
        }
    }
    small_bench_ok(out, "cornell", "none");
    struct stat st;
    assert_int_not_equal(stat(dead, &st), 0);
    assert_int_equal(stat(live, &st), 0);
}

/* Entries of directory `path` whose names start with `prefix` ("" for
 * all), . and .. left out. */
static int count_entries(const char *path, const char *prefix)
{
    struct dirent **list = NULL;
    int n = scandir(path, &list, NULL, NULL), count = 0;
    for (int i = 0; i < n; i++) {
        const char *name = list[i]->d_name;
        count += strcmp(name, ".") && strcmp(name, "..") && strncmp(name, prefix, strlen(prefix)) == 0;
        free(list[i]);
    }
    free(list);
    return count;
}

/* A bench killed by SIGTERM while it renders leaves nothing: not its
 * staging directory (it had been left until the next run into DIR), not
 * the DIR it made. (SIGKILL cannot be caught: killed_runs_staging_is_removed
 * checks that the next run removes what such a run leaves.) */
static void killed_run_leaves_nothing(void **state)
{
    (void)state;
    const char *out = DIR "/killed";
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", out);
    assert_int_equal(system(cmd), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        if (!freopen("/dev/null", "w", stderr))
            _exit(127);
        execl(RTGI_BINARY, RTGI_BINARY, "bench", "--out", out, "--cache", DIR "/cache", "--size", "32x32", "--spp",
              "64", "--gi", "none,rsm,vct", "--quiet", (char *)NULL);
        _exit(127);
    }
    /* Until its staging directory appears (it is made before the reference
     * renders, seconds before any output is moved). */
    bool staged = false;
    for (int i = 0; i < 2000 && !staged; i++) {
        staged = count_entries(out, ".bench-") > 0;
        if (!staged)
            nanosleep(&(struct timespec){0, 5000000}, NULL);
    }
    assert_true(staged);
    kill(pid, SIGTERM);
    int status = 0;
    waitpid(pid, &status, 0);
    assert_true(WIFSIGNALED(status) || WEXITSTATUS(status) != 0);
    struct stat st;
    if (stat(out, &st) == 0)
        system("ls -la " DIR "/killed >&2");
    assert_int_not_equal(stat(out, &st), 0);
}

/* A second run into the same DIR replaces the first's results, and says
 * so, naming the run it replaces. */
static void second_run_says_it_replaces(void **state)
{
    (void)state;
    const char *out = DIR "/twice";
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", out);
    assert_int_equal(system(cmd), 0);
    small_bench_ok(out, "cornell", "none");
    char *err = NULL;
    int rc = test_run_cli(&err, "bench", "--out", out, "--cache", CACHE, "--size", "16x16", "--spp", "2", "--gi",
                          "none", "--frames", "1", NULL);
    assert_int_equal(rc, 0);
    print_message("%s", err ? err : "");
    assert_non_null(strstr(err ? err : "", "warning [bench] " DIR "/twice: replacing the results of an earlier run ("));
    free(err);
}

/* A run that fails while writing its outputs (the page, the largest file,
 * over a file-size limit the images are under) leaves DIR as it was: the
 * previous run's bench.json, page and images byte for byte, no file more
 * or less, no staging directory; into a new DIR it leaves no DIR. */
static void failed_run_leaves_dir_as_it_was(void **state)
{
    (void)state;
    const char *old = DIR "/atomic", *fresh = DIR "/atomic_fresh", *sizes = DIR "/atomic_40";
    char *err = NULL;
    int rc = small_bench(&err, old, "cornell", "none"); /* 16x16 */
    assert_int_equal(rc, 0);
    free(err);
    rc = test_run_cli(&err, "bench", "--size", "40x40", "--gi", "none", "--spp", "1", "--frames", "1", "--threads",
                      "2", "--cache", CACHE, "--out", sizes, "--quiet", NULL); /* caches the 40x40 reference */
    assert_int_equal(rc, 0);
    free(err);
    long image_max = 0, page = file_size(sizes, "report.html");
    static const char *const images[] = {"images/reference.exr", "images/reference.png", "images/e00_pcss_none.exr",
                                         "images/e00_pcss_none.png", "images/e00_pcss_none_flip.png",
                                         "bench.json", "bench.csv", "bench_passes.csv"};
    for (int i = 0; i < 8; i++)
        if (file_size(sizes, images[i]) > image_max)
            image_max = file_size(sizes, images[i]);
    print_message("40x40: largest image or table %ld bytes, report.html %ld\n", image_max, page);
    assert_true(page > image_max);

    char before[4096], after[4096];
    list_dir(old, before, sizeof before);
    size_t n_json = 0, n_page = 0, n_ref = 0;
    char *json = file_bytes(old, "bench.json", &n_json), *html = file_bytes(old, "report.html", &n_page),
         *ref = file_bytes(old, "images/reference.exr", &n_ref);
    assert_true(json && html && ref);
    rc = bench_with_file_limit(&err, old, image_max + 1);
    test_expect_cli_error(rc, err, 1, "report.html", "not written");
    list_dir(old, after, sizeof after);
    assert_string_equal(after, before); /* no .bench-XXXXXX, nothing new */
    size_t n = 0;
    char *now = file_bytes(old, "bench.json", &n);
    assert_true(now && n == n_json && !memcmp(now, json, n));
    free(now);
    now = file_bytes(old, "report.html", &n);
    assert_true(now && n == n_page && !memcmp(now, html, n));
    free(now);
    now = file_bytes(old, "images/reference.exr", &n);
    assert_true(now && n == n_ref && !memcmp(now, ref, n));
    free(now);
    free(json);
    free(html);
    free(ref);

    rc = bench_with_file_limit(&err, fresh, image_max + 1);
    test_expect_cli_error(rc, err, 1, "report.html", "not written");
    assert_int_not_equal(access(fresh, F_OK), 0);
}

/* The page's default exposure keys on the mean log luminance: the bench's
 * reference thumbnail has its median in a sane sRGB range, and a Sponza-like
 * image (90% dim pixels over two decades, 10% sunlit ones 300x brighter),
 * which the 99th-percentile rule left at a median of sRGB 0.04, too. */
static double median_srgb(const ImageF *img, double exposure)
{
    int n = img->width * img->height;
    float *v = malloc((size_t)n * sizeof(float));
    assert_non_null(v);
    for (int i = 0; i < n; i++) {
        const float *c = img->rgb + 3 * i;
        v[i] = srgb_encode(fminf(1.f, (float)exposure * (0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2])));
    }
    for (int i = 1; i < n; i++) /* insertion sort: small images */
        for (int k = i; k > 0 && v[k - 1] > v[k]; k--) {
            float t = v[k];
            v[k] = v[k - 1];
            v[k - 1] = t;
        }
    double m = v[n / 2];
    free(v);
    return m;
}

static void display_exposure(void **state)
{
    (void)state;
    ImageF ref;
    assert_true(image_read(DIR "/images/reference.png", &ref));
    double thumb = median_srgb(&ref, 1.0); /* written at the page's default exposure */
    image_free(&ref);
    ImageF sponza = {0};
    assert_true(image_alloc(&sponza, 100, 100));
    for (int i = 0; i < 100 * 100; i++) {
        float y = i % 10 == 0 ? 0.3f : 0.001f * powf(10.f, (float)((i * 7919) % 1000) / 1000.f * 2.f - 1.f);
        for (int c = 0; c < 3; c++)
            sponza.rgb[3 * i + c] = y;
    }
    double e = report_display_exposure(&sponza, NULL);
    double synth = median_srgb(&sponza, e);
    int clipped = 0;
    for (int i = 0; i < 100 * 100; i++)
        clipped += sponza.rgb[3 * i] * e > 1.0;
    print_message("median sRGB at the default exposure: Cornell reference %.3f; Sponza-like %.3f "
                  "(exposure %.3g, %.1f%% clipped; the 99th-percentile rule gave %.3f)\n",
                  thumb, synth, e, clipped / 100.0, median_srgb(&sponza, 1.0 / 0.3));
    assert_true(thumb > 0.2 && thumb < 0.75);
    assert_true(synth > 0.2 && synth < 0.75);
    assert_true(clipped <= 1100);
    image_free(&sponza);
}

/* The DOM of `dir`/report.html after headless Chromium ran its scripts
 * (free it), its console log in RTGI_TEST_TMP/bench_chromium.log; skips the
 * test where Chromium is not installed. */
static char *chromium_dom(const char *dir)
{
    const char *chromium = access("/usr/bin/chromium", X_OK) == 0 ? "/usr/bin/chromium" : NULL;
    if (!chromium) {
        print_message("SKIP: /usr/bin/chromium is not installed (scripts/install-deps.sh installs it)\n");
        skip();
    }
    char cmd[2048];
    snprintf(cmd, sizeof cmd,
             "%s --headless --disable-gpu --no-sandbox --user-data-dir=%s/bench_chromium --enable-logging=stderr "
             "--virtual-time-budget=20000 --dump-dom 'file://%s/report.html' 2>%s/bench_chromium.log",
             chromium, RTGI_TEST_TMP, dir, RTGI_TEST_TMP);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    char *dom = NULL;
    size_t cap = 0, len = 0;
    char buf[65536];
    for (size_t k; (k = fread(buf, 1, sizeof buf, p)) > 0;) {
        if (len + k + 1 > cap) {
            cap = 2 * (len + k + 1);
            dom = realloc(dom, cap);
            assert_non_null(dom);
        }
        memcpy(dom + len, buf, k);
        len += k;
        dom[len] = 0;
    }
    int rc = pclose(p);
    assert_int_equal(rc, 0);
    assert_non_null(dom);
    return dom;
}

/* The page in headless Chromium: no errors, one scatter point per technique. */
static void report_in_chromium(void **state)
{
    (void)state;
    char *dom = chromium_dom(DIR);
    char *title = strstr(dom, "<title>");
    assert_non_null(title);
    print_message("%.60s\n", title);
    assert_true(strncmp(title, "<title>ok:4</title>", 19) == 0);
    /* The metrics table shows vct's GPU memory and the frame's in all. */
    assert_non_null(strstr(dom, "<th>GI MiB</th>"));
    assert_non_null(strstr(dom, "<th>GPU MiB (all)</th>"));
    const cJSON *vct = cJSON_GetArrayItem(cJSON_GetObjectItem(g_doc, "techniques"), 3);
    char cell[64];
    snprintf(cell, sizeof cell, "<td>%.3f</td>",
             cJSON_GetObjectItem(cJSON_GetObjectItem(vct, "stats"), "gi_memory_mib")->valuedouble);
    if (!strstr(dom, cell))
        fail_msg("report.html: no metrics cell %s for vct's GPU memory", cell);
    snprintf(cell, sizeof cell, "<td>%.1f</td>",
             cJSON_GetObjectItem(cJSON_GetObjectItem(vct, "stats"), "gpu_memory_mib")->valuedouble);
    if (!strstr(dom, cell))
        fail_msg("report.html: no metrics cell %s for vct's frame memory in all", cell);
    /* The scatter's labels were placed clear of each other and the points. */
    const char *ov = strstr(dom, "data-label-overlaps=\"");
    assert_non_null(ov);
    print_message("scatter labels overlapping: %d\n", atoi(ov + 21));
    assert_int_equal(atoi(ov + 21), 0);
    free(dom);
    /* Chromium logs page errors as "Uncaught ..." console lines. */
    char log[1024];
    snprintf(log, sizeof log, "%s/bench_chromium.log", RTGI_TEST_TMP);
    char *text = util_read_file(log, NULL);
    if (text) {
        assert_null(strstr(text, "Uncaught"));
        free(text);
    }
}

/* A scene path holding "<!--<script>" (HTML's "script data double escaped"
 * state: the page's first "</script>" then no longer ends the JSON's
 * block, and the page drew nothing) leaves no '<' in the page's embedded
 * JSON, the JSON still names the scene, and the page draws its point. */
static void report_scene_name_is_script_safe(void **state)
{
    (void)state;
    const char *scene = test_tmp_file("<!--<script>x.json", "{\"builtin\": \"cornell\"}\n");
    small_bench_ok(DIR "/html", scene, "none");
    char *page = util_read_file(DIR "/html/report.html", NULL);
    assert_non_null(page);
    char *json = strstr(page, "const BENCH = "), *end = json ? strstr(json, ";\nconst IMAGES") : NULL;
    assert_non_null(end);
    json += strlen("const BENCH = ");
    *end = 0;
    assert_null(strchr(json, '<'));
    assert_non_null(strstr(json, "\\u003c!--\\u003cscript>"));
    cJSON *doc = cJSON_Parse(json);
    assert_non_null(doc);
    assert_non_null(strstr(field(doc, "scene", 's')->valuestring, "<!--<script>x.json"));
    cJSON_Delete(doc);
    free(page);
    char *dom = chromium_dom(DIR "/html");
    char *title = strstr(dom, "<title>");
    assert_non_null(title);
    print_message("%.20s\n", title);
    assert_true(strncmp(title, "<title>ok:1</title>", 19) == 0);
    free(dom);
}

/* true if s is valid UTF-8 (RFC 3629: no overlong forms, no surrogates,
 * nothing over U+10FFFF). */
static bool valid_utf8(const char *s)
{
    for (const unsigned char *p = (const unsigned char *)s; *p;) {
        int len = *p < 0x80 ? 1 : *p >= 0xc2 && *p <= 0xdf ? 2 : *p >= 0xe0 && *p <= 0xef ? 3
                : *p >= 0xf0 && *p <= 0xf4 ? 4 : 0;
        if (!len)
            return false;
        unsigned cp = len == 1 ? *p : *p & (0x7f >> len);
        for (int k = 1; k < len; k++) {
            if ((p[k] & 0xc0) != 0x80)
                return false;
            cp = cp << 6 | (p[k] & 0x3f);
        }
        if ((len == 3 && (cp < 0x800 || (cp >= 0xd800 && cp <= 0xdfff))) || (len == 4 && (cp < 0x10000 || cp > 0x10ffff)))
            return false;
        p += len;
    }
    return true;
}

/* A scene named with a byte that is not UTF-8 (0xff) gives a bench.json,
 * bench.csv and page that are UTF-8, the byte as U+FFFD, as `compare
 * --json` writes it. */
static void scene_name_not_utf8(void **state)
{
    (void)state;
    const char *scene = test_tmp_file("na\xffme.json", "{\"builtin\": \"cornell\"}\n");
    small_bench_ok(DIR "/utf8", scene, "none");
    static const char *const files[] = {"bench.json", "bench.csv", "report.html"};
    for (int i = 0; i < 3; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", DIR "/utf8", files[i]);
        char *text = util_read_file(path, NULL);
        assert_non_null(text);
        if (!valid_utf8(text))
            fail_msg("%s is not valid UTF-8", files[i]);
        free(text);
    }
    cJSON *doc = load_bench_json(DIR "/utf8");
    assert_true(util_ends_with(field(doc, "scene", 's')->valuestring, "/na\xef\xbf\xbdme.json"));
    cJSON_Delete(doc);
}

/* Issue 50: bench --animate over the orbiting spot light. Every
 * technique gets techniques[i].temporal (a relMSE per frame, its flicker
 * and the reference's, a kymograph of the frames' middle row), bench.csv
 * the flicker columns, and the page's Over-time section one line per
 * technique in the error-over-time plot, in Chromium without errors. */
static void animate_temporal_results(void **state)
{
    (void)state;
    char scene[512], *err = NULL;
    snprintf(scene, sizeof scene, "%s/scenes/cornell_orbit.json", RTGI_SOURCE_DIR);
    const char *out = DIR "/animate";
    int rc = test_run_cli(&err, "bench", "--scene", scene, "--animate", "--frames", "4", "--fps", "60", "--size",
                          "16x16", "--spp", "4", "--gi", "rsm,vpl-slc:temporal=on", "--vpls", "256", "--threads", "2",
                          "--cache", CACHE, "--out", out, "--quiet", NULL);
    if (rc != 0)
        fail_msg("bench --animate failed (%d): %s", rc, err ? err : "");
    free(err);
    cJSON *doc = load_bench_json(out);
    const cJSON *anim = field(doc, "animation", 'o');
    assert_int_equal((int)field(anim, "frames", 'n')->valuedouble, 4);
    assert_int_equal(cJSON_GetArraySize(field(anim, "times", 'a')), 4);
    assert_float_equal(cJSON_GetArrayItem(field(anim, "times", 'a'), 3)->valuedouble, 3.0 / 60.0, 1e-9);
    double ref_flicker = field(anim, "reference_flicker", 'n')->valuedouble;
    assert_true(ref_flicker >= 0);
    const cJSON *t;
    int n = 0;
    cJSON_ArrayForEach(t, field(doc, "techniques", 'a')) {
        const cJSON *tj = field(t, "temporal", 'o'), *per = field(tj, "relmse_per_frame", 'a');
        assert_int_equal(cJSON_GetArraySize(per), 4);
        double mean = 0;
        for (int i = 0; i < 4; i++) {
            double v = cJSON_GetArrayItem(per, i)->valuedouble;
            assert_true(isfinite(v) && v > 0 && v < 10);
            mean += v / 4;
        }
        assert_float_equal(field(tj, "relmse_mean", 'n')->valuedouble, mean, 1e-9);
        assert_true(field(tj, "flicker", 'n')->valuedouble >= 0);
        assert_float_equal(field(tj, "reference_flicker", 'n')->valuedouble, ref_flicker, 0);
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", out, field(tj, "kymograph", 's')->valuestring);
        ImageF k;
        assert_true(image_read(path, &k));
        assert_int_equal(k.width, 16);
        assert_int_equal(k.height, 4); /* a row per frame */
        image_free(&k);
        n++;
    }
    assert_int_equal(n, 2);
    cJSON_Delete(doc);
    char path[1024];
    snprintf(path, sizeof path, "%s/bench.csv", out);
    char *csv = util_read_file(path, NULL);
    assert_non_null(csv);
    assert_non_null(strstr(csv, ",relmse_mean,flicker,reference_flicker\r\n"));
    free(csv);
    char *dom = chromium_dom(out);
    assert_true(strncmp(strstr(dom, "<title>"), "<title>ok:2</title>", 19) == 0);
    assert_non_null(strstr(dom, "data-lines=\"2\""));
    assert_non_null(strstr(dom, "temporal-table"));
    free(dom);
}

static int teardown(void **state)
{
    (void)state;
    cJSON_Delete(g_doc);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(schema),
        cmocka_unit_test(csv_matches_json),
        cmocka_unit_test(cache_reused),
        cmocka_unit_test(bad_options),
        cmocka_unit_test(bad_lists),
        cmocka_unit_test(long_gi_item),
        cmocka_unit_test(bad_cache_leaves_no_dir),
        cmocka_unit_test(failed_run_leaves_dir_as_it_was),
        cmocka_unit_test(killed_runs_staging_is_removed),
        cmocka_unit_test(killed_run_leaves_nothing),
        cmocka_unit_test(second_run_says_it_replaces),
        cmocka_unit_test(ssaa_lowers_the_error),
        cmocka_unit_test(display_exposure),
        cmocka_unit_test(report_in_chromium),
        cmocka_unit_test(report_scene_name_is_script_safe),
        cmocka_unit_test(scene_name_not_utf8),
        cmocka_unit_test(animate_temporal_results),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
