/* test_probe.c — `rtgi probe`: every kernel runs and reports a positive
 * rate, the JSON result round-trips, and
 * `--timings --probe run` states a gather's fraction of its bound and of
 * its reads-only twin;
 * `--json -` writes the JSON alone on stdout. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gl/gpu_timer.h"
#include "gpu/probe.h"
#include "test_util.h"
#include "base/util.h"

static void probe_measures_and_round_trips(void **state)
{
    (void)state;
    ProbeResult r, back;
    test_expect_no_gl_error("before probe_run");
    assert_true(probe_run(&r, 64));
    /* Its maps are filled with calls GL takes (the 2D ones had been given
     * glTextureSubImage3D, an error that left them unwritten). */
    test_expect_no_gl_error("probe_run");
    print_message("evals/s: arith %.3g, 2d fetch 1/2/3 %.3g %.3g %.3g, cube fetch 3 %.3g, ssbo %.3g\n",
                  r.evals_2d[0], r.evals_2d[1], r.evals_2d[2], r.evals_2d[3], r.evals_cube[3], r.evals_ssbo);
    for (int f = 0; f < 4; f++)
        assert_true(r.evals_2d[f] > 0 && r.evals_cube[f] > 0);
    assert_true(r.evals_ssbo > 0 && r.evals_texel_2d > 0 && r.evals_texel_cube > 0);
    assert_int_equal(r.map_size, 64);
    /* Gather rates divide by the timer queries on a GPU, by the synchronised
     * wall time on a software rasterizer (CI's llvmpipe). */
    GpuTimer t;
    gpu_timer_create(&t, true, true);
    assert_int_equal(t.exact, !gl_renderer_is_software((const char *)glGetString(GL_RENDERER)));
    assert_int_equal(gpu_timer_rates_use_wall(&t), !t.exact);
    gpu_timer_destroy(&t);
    /* Each kernel's timed dispatch is at least one 256² layer, at most 64
     * (a GPU takes more layers, to fill it and outlast its latency). */
    assert_true(r.lanes >= 65536 && r.lanes <= 64 * 65536);
    /* Which kernel is faster is a measurement, not a test: under load on
     * shared cores the 3-fetch kernel once timed faster than the 1-fetch
     * one. `rtgi probe` prints the rates. */
    const char *path = test_tmp_file("probe.json", "");
    assert_true(probe_write_json(path, &r));
    assert_true(probe_read_json(path, &back));
    /* cJSON prints 15 significant digits. */
    for (int f = 0; f < 4; f++)
        assert_true(fabs(back.evals_2d[f] / r.evals_2d[f] - 1) < 1e-12 &&
                    fabs(back.evals_cube[f] / r.evals_cube[f] - 1) < 1e-12);
    assert_true(fabs(back.evals_ssbo / r.evals_ssbo - 1) < 1e-12);
    assert_true(fabs(back.evals_texel_2d / r.evals_texel_2d - 1) < 1e-12 &&
                fabs(back.evals_texel_cube / r.evals_texel_cube - 1) < 1e-12);
    assert_int_equal(back.map_size, 64);
    assert_true(back.lanes == r.lanes);
    /* A result written before the packed-texel kernels still reads: 512²
     * maps, no texel rates (and no texel bound). */
    assert_true(probe_read_json(
        test_tmp_file("old_probe.json", "{\"evals_2d\": [1, 2, 3, 4], \"evals_cube\": [1, 2, 3, 4], \"evals_ssbo\": 5}"),
        &back));
    assert_int_equal(back.map_size, 512);
    assert_true(back.lanes == 0);
    assert_true(back.evals_texel_2d == 0 && probe_bound(&back, false, false, 0, true) == 0);
    assert_true(probe_bound(&back, false, false, 0, false) == 3);
    assert_false(probe_read_json(test_tmp_file("not_probe.json", "{\"evals_2d\": [1, 2]}"), &back));
}

static void timings_state_the_fraction(void **state)
{
    (void)state;
    char out[512], cmd[1400], text[8192];
    snprintf(out, sizeof out, "%s/probe_render.pfm", RTGI_TEST_TMP);
    snprintf(cmd, sizeof cmd,
             "%s render --size 32x32 --gi rsm --rsm-samples 64 --timings --frames 1 --probe run --out %s --quiet",
             RTGI_BINARY, out);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t len = fread(text, 1, sizeof text - 1, p);
    text[len] = 0;
    assert_int_equal(pclose(p), 0);
    assert_non_null(strstr(text, "gather_fraction_of_bound: "));
    /* the kernel that reads what the gather reads, on maps of its RSM size */
    assert_non_null(strstr(text, "gather_fraction_of_texel_bound: "));
    assert_non_null(strstr(text, "gather_probe_map_size: 512\n"));
    /* Cold frames draw the light products; steady frames (issue 11) keep
     * them: no shadow or RSM pass among the steady ones. */
    assert_non_null(strstr(text, "  shadow "));
    assert_non_null(strstr(text, "  rsm "));
    assert_non_null(strstr(text, "frame_cold_ms: "));
    assert_non_null(strstr(text, "frame_steady_ms: "));
    assert_non_null(strstr(text, "steady_rsm_gather_ms: "));
    assert_non_null(strstr(text, "frame_steady_gpu_ms: "));
    assert_null(strstr(text, "steady_shadow_ms"));
    assert_null(strstr(text, "steady_rsm_ms"));
}

/* With --probe, an RSM gather's reads-only twin (GiParams.rsm.reads_only)
 * runs after the report in every layout, map kind and weighting: its rate
 * is positive and the gather's fraction of it printed; VPL techniques have
 * no twin (their bound is the storage-buffer kernel's). */
static void reads_only_twin_runs(void **state)
{
    (void)state;
    static const struct {
        const char *args[4]; /* after the common ones, NULL-terminated */
        bool twin;
    } cases[] = {
        {{"--gi", "rsm"}, true},
        {{"--gi", "rsm-interp", "--rsm-weighting", "paper"}, true},
        {{"--gi", "rsm-interleaved", "--rsm-weighting", "unbiased"}, true},
        {{"--gi", "rsm-interleaved"}, true},
        /* every texel of a 64² cube (24,576 VPLs) for each pixel: at the
         * default 512² the three frames (cold, steady, twin) took 200 s */
        {{"--gi", "rsm", "--rsm-exhaustive", "--rsm-size=64"}, true},
        {{"--gi", "rsm-interp", "--scene", RTGI_SOURCE_DIR "/scenes/parity/rsm_spot.json"}, true},
        {{"--gi", "vpl-all"}, false},
    };
    char out[512], probe[512];
    snprintf(out, sizeof out, "%s/twin.pfm", RTGI_TEST_TMP);
    /* The probe's own run is timings_state_the_fraction's: here a result
     * made once on small maps (each `--probe run` at 512² took 10 s). */
    snprintf(probe, sizeof probe, "%s/twin_probe.json", RTGI_TEST_TMP);
    assert_int_equal(test_run_cli(NULL, "probe", "--map-size", "64", "--json", probe, "--quiet", NULL), 0);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *const *a = cases[i].args;
        char *text = NULL;
        int rc = test_run_cli_out(&text, NULL, "render", "--size", "32x32", "--rsm-samples", "64", "--timings",
                                  "--frames", "1", "--probe", probe, "--out", out, "--quiet", a[0], a[1], a[2], a[3],
                                  NULL);
        assert_int_equal(rc, 0);
        assert_non_null(text);
        const char *rate = strstr(text, "gather_reads_only_evals_per_s: ");
        print_message("%s %s: %s", a[0], a[1], rate ? rate : "no twin\n");
        if (!cases[i].twin) {
            assert_null(rate);
        } else {
            assert_non_null(rate);
            double v = strtod(rate + strlen("gather_reads_only_evals_per_s: "), NULL);
            assert_true(isfinite(v) && v > 0);
            assert_non_null(strstr(text, "gather_fraction_of_reads_only: "));
        }
        /* Each gather pass's lines: its evaluations (summing to the
         * gather's), its rate, its fraction of the bound and of its twin. */
        const char *passes[2] = {"rsm_gather", NULL};
        if (!strcmp(a[1], "rsm-interp")) {
            passes[0] = "rsm_gather_lowres";
            passes[1] = "rsm_gather_full";
        } else if (!strcmp(a[1], "rsm-interleaved")) {
            passes[0] = "rsm_gather_interleaved";
        } else if (!cases[i].twin) {
            passes[0] = "vpl_shade";
        }
        const char *total = strstr(text, "gather_evaluations: ");
        assert_non_null(total);
        unsigned long long want = strtoull(total + strlen("gather_evaluations: "), NULL, 10), sum = 0;
        for (int p = 0; p < 2 && passes[p]; p++) {
            char key[128];
            snprintf(key, sizeof key, "gather_pass_%s_evaluations: ", passes[p]);
            const char *at = strstr(text, key);
            assert_non_null(at);
            sum += strtoull(at + strlen(key), NULL, 10);
            const char *const suffixes[] = {"evals_per_s", "fraction_of_bound", "fraction_of_reads_only"};
            for (int k = 0; k < (cases[i].twin ? 3 : 2); k++) {
                snprintf(key, sizeof key, "gather_pass_%s_%s: ", passes[p], suffixes[k]);
                at = strstr(text, key);
                assert_non_null(at);
                double v = strtod(at + strlen(key), NULL);
                assert_true(isfinite(v) && v > 0);
            }
        }
        assert_true(sum == want);
        free(text);
    }
}

/* `rtgi probe --json -`: the JSON alone on stdout (it parses as the
 * result), the text lines on stderr. */
static void json_to_stdout(void **state)
{
    (void)state;
    char cmd[1400], errpath[600];
    snprintf(errpath, sizeof errpath, "%s/probe_stderr.txt", RTGI_TEST_TMP);
    snprintf(cmd, sizeof cmd, "%s probe --map-size 64 --json - 2>%s", RTGI_BINARY, errpath);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    static char text[8192];
    size_t len = fread(text, 1, sizeof text - 1, p);
    text[len] = 0;
    assert_int_equal(pclose(p), 0);
    const char *path = test_tmp_file("probe_stdout.json", text);
    ProbeResult r;
    if (!probe_read_json(path, &r))
        fail_msg("probe --json -: stdout is not the probe's JSON: %s", text);
    assert_true(r.evals_ssbo > 0);
    char *err = util_read_file(errpath, NULL);
    assert_non_null(err);
    assert_non_null(strstr(err, "probe_ssbo_vpl_evals_per_s: "));
    assert_null(strstr(text, "evals_per_s:"));
    free(err);
}

/* --map-size out of range: a clear error naming the option, exit 2. */
static void map_size_is_checked(void **state)
{
    (void)state;
    char *err = NULL;
    int rc = test_run_cli(&err, "probe", "--map-size", "16", NULL);
    test_expect_cli_error(rc, err, 2, "--map-size", "64");
}

/* Every GPU resource the probe makes (eight maps and the VPL buffer),
 * refused in turn (RTGI_FAIL_GL_MAKE=k): exit 1, one line naming it and
 * nothing on stdout; past the last, the probe runs. */
static void every_make_failure_fails(void **state)
{
    (void)state;
    int k = 1;
    for (;; k++) {
        char num[16];
        snprintf(num, sizeof num, "%d", k);
        setenv("RTGI_FAIL_GL_MAKE", num, 1);
        char *out = NULL, *err = NULL;
        int rc = test_run_cli_out(&out, &err, "probe", "--map-size", "64", NULL);
        unsetenv("RTGI_FAIL_GL_MAKE");
        if (rc == 0) {
            free(out);
            free(err);
            break;
        }
        assert_true(out == NULL || out[0] == 0);
        free(out);
        test_expect_cli_error(rc, err, 1, k <= 8 ? "probe.map" : "probe.vpls", "refused");
        assert_true(k < 20);
    }
    assert_int_equal(k, 10);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(probe_measures_and_round_trips),
        cmocka_unit_test(timings_state_the_fraction),
        cmocka_unit_test(reads_only_twin_runs),
        cmocka_unit_test(json_to_stdout),
        cmocka_unit_test(map_size_is_checked),
        cmocka_unit_test(every_make_failure_fails),
    };
    return cmocka_run_group_tests_name("probe", tests, test_gl_setup, test_gl_teardown);
}
