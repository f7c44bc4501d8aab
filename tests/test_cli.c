/* test_cli.c — the CLI as users script it: bad input gives one clear
 * message naming the file or option and a non-zero exit, never a crash;
 * the default render has the red wall on the left, green on the right. */
#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "gi/gi.h"
#include "test_util.h"
#include "base/util.h"

static const char *tmp_file(const char *name, const char *content) { return test_tmp_file(name, content); }

static void missing_scene_file(void **state)
{
    (void)state;
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--scene", "/nonexistent/scene.json", "--size", "8x8", NULL);
    test_expect_cli_error(rc, err, 1, "/nonexistent/scene.json", "does not exist");
}

static void malformed_json_names_line(void **state)
{
    (void)state;
    const char *p = tmp_file("bad.json", "{\n  \"builtin\": \"cornell\",\n  \"exposure\": 2,,\n}\n");
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--scene", p, "--size", "8x8", NULL);
    test_expect_cli_error(rc, err, 1, "bad.json:3:", "malformed JSON");
}

static void wrong_json_types(void **state)
{
    (void)state;
    const char *p = tmp_file("badlight.json",
                             "{ \"builtin\": \"cornell\", \"lights\": [ { \"type\": \"laser\" } ] }\n");
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--scene", p, "--size", "8x8", NULL);
    test_expect_cli_error(rc, err, 1, "badlight.json", "unknown light type \"laser\"");
}

static void missing_mesh_file(void **state)
{
    (void)state;
    const char *p = tmp_file("nomesh.json", "{ \"mesh\": \"does_not_exist.obj\" }\n");
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--scene", p, "--size", "8x8", NULL);
    test_expect_cli_error(rc, err, 1, "does_not_exist.obj", "does not exist");
    rc = test_run_cli(&err, "render", "--scene", "/tmp/rtgi_no_such_mesh.gltf", NULL);
    test_expect_cli_error(rc, err, 1, "rtgi_no_such_mesh.gltf", "does not exist");
}

static void malformed_mesh_file(void **state)
{
    (void)state;
    const char *p = tmp_file("garbage.gltf", "{ this is not gltf");
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--scene", p, "--size", "8x8", NULL);
    test_expect_cli_error(rc, err, 1, "garbage.gltf", "cannot import mesh");
}

static void unknown_option_and_technique(void **state)
{
    (void)state;
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--bogus", NULL);
    test_expect_cli_error(rc, err, 2, "--bogus", "unknown option");
    rc = test_run_cli(&err, "render", "--shadow", "vsm", NULL);
    test_expect_cli_error(rc, err, 2, "--shadow", "unknown value 'vsm'");
    rc = test_run_cli(&err, "render", "--gi", "magic", NULL);
    test_expect_cli_error(rc, err, 2, "--gi", "'magic'");
    rc = test_run_cli(&err, "frobnicate", NULL);
    test_expect_cli_error(rc, err, 2, "frobnicate", "unknown command");
    rc = test_run_cli(&err, "render", "--exposure", NULL);
    test_expect_cli_error(rc, err, 2, "--exposure", "needs a value");
    rc = test_run_cli(&err, "render", "--pcf-samples", "0", NULL);
    test_expect_cli_error(rc, err, 2, "--pcf-samples", "out of range");
    /* no frame to time: the means would be inf */
    rc = test_run_cli(&err, "render", "--frames", "0", "--timings", NULL);
    test_expect_cli_error(rc, err, 2, "--frames 0", "no frame to time");
}

static void zero_or_huge_size(void **state)
{
    (void)state;
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--size", "0x0", NULL);
    test_expect_cli_error(rc, err, 2, "--size", "between 1 and");
    rc = test_run_cli(&err, "render", "--size", "100000x100000", NULL);
    test_expect_cli_error(rc, err, 2, "--size", "between 1 and");
    rc = test_run_cli(&err, "render", "--size", "64", NULL);
    test_expect_cli_error(rc, err, 2, "--size", "not a size");
    rc = test_run_cli(&err, "render", "--size", "-5x10", NULL);
    test_expect_cli_error(rc, err, 2, "--size", NULL);
}

/* The default render, read back from its PNG: a band along the left edge is
 * red, one along the right edge green. */
static void default_png_red_left_green_right(void **state)
{
    (void)state;
    char out[512];
    snprintf(out, sizeof out, "%s/default.png", RTGI_TEST_TMP);
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--size", "96x96", "--out", out, NULL);
    if (rc != 0)
        fail_msg("render failed (%d): %s", rc, err ? err : "");
    free(err);
    ImageF img;
    assert_true(image_read(out, &img));
    assert_int_equal(img.width, 96);
    double lr = test_mean(&img, 6, 48, 3, 0), lg = test_mean(&img, 6, 48, 3, 1);
    double rr = test_mean(&img, 89, 48, 3, 0), rg = test_mean(&img, 89, 48, 3, 1);
    print_message("left r %.3f g %.3f, right r %.3f g %.3f\n", lr, lg, rr, rg);
    assert_true(lr > 3 * lg);
    assert_true(rg > 3 * rr);
    image_free(&img);
}

/* A driver below the required OpenGL version: one clear line, exit 1. */
static void unsupported_gl_version(void **state)
{
    (void)state;
    setenv("RTGI_REQUIRE_GL", "99", 1);
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--size", "8x8", NULL);
    unsetenv("RTGI_REQUIRE_GL");
    test_expect_cli_error(rc, err, 1, "OpenGL 9.9 is required", "gives 4.");
}

/* A shader that fails to compile is reported by file and line, through
 * #include, when shaders come from disk (RTGI_SHADER_DIR). */
static void shader_error_names_file_and_line(void **state)
{
    (void)state;
    char dir[512], cmd[2048];
    snprintf(dir, sizeof dir, "%s/shaders_broken", RTGI_TEST_TMP);
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && cp -r '%s/shaders' '%s' && printf '\nvec3 broken( {\n' >> '%s/common/lights.glsl'",
             dir, RTGI_SOURCE_DIR, dir, dir);
    assert_int_equal(system(cmd), 0);
    /* After the append, the file's last line is the broken one. */
    char path[600];
    snprintf(path, sizeof path, "%s/common/lights.glsl", dir);
    char *text = util_read_file(path, NULL);
    assert_non_null(text);
    int lines = 0;
    for (char *c = text; *c; c++)
        lines += *c == '\n';
    free(text);
    char want[64];
    snprintf(want, sizeof want, "common/lights.glsl:%d:", lines);
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--size", "8x8", "--shader-dir", dir, NULL);
    assert_int_equal(rc, 1);
    assert_non_null(err);
    if (!strstr(err, want))
        fail_msg("expected '%s' in: %s", want, err);
    free(err);
}

/* A program that does not build fails the command, whichever program it
 * is: one the technique makes at its creation but after others (LPV's face
 * factors, whose failure lpv_create had overwritten), and the specialised
 * variants that fall back to a general program (the direct light per light
 * type, VCT's bounce over its opaque-voxel list), which drew the right
 * image, more slowly, with an error line and exit 0. Each is broken alone,
 * under the define only its variant has; `render --verbose` names the
 * variants a run builds (scripts/shader-failure-sweep.py breaks them all). */
static void every_program_failure_fails(void **state)
{
    (void)state;
    static const struct {
        const char *file, *guard, *program;
        const char *args[8];
    } cases[] = {
        {"gi/lpv/propagate.comp", "MODE_FACES", "lpv_propagate_faces", {"--gi", "lpv", "--lpv-size", "8", NULL}},
        {"frame/shade.comp", "LIGHT_FIXED_TYPE", "shade", {"--gi", "none", NULL}},
        {"gi/vct/bounce.comp", "OPAQUE_LIST", "vct_bounce_list",
         {"--gi", "vct", "--vct-size", "16", "--vct-bounces", "2", NULL}},
        /* an include of three programs: one line, the first's */
        {"gi/vct/cone.glsl", "VCT_CLIP_LEVELS", "vct_bounce",
         {"--gi", "vct", "--vct-size", "16", "--vct-bounces", "2", NULL}},
    };
    char dir[512], out[512], cmd[2048];
    snprintf(dir, sizeof dir, "%s/shaders_guarded", RTGI_TEST_TMP);
    snprintf(out, sizeof out, "%s/guarded.pfm", RTGI_TEST_TMP);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(cmd, sizeof cmd,
                 "rm -rf '%s' && cp -r '%s/shaders' '%s' && printf '\n#ifdef %s\n#error broken by the test\n#endif\n' >> '%s/%s'",
                 dir, RTGI_SOURCE_DIR, dir, cases[i].guard, dir, cases[i].file);
        assert_int_equal(system(cmd), 0);
        const char *const *a = cases[i].args; /* NULL after its last: the list ends there */
        remove(out);
        char *err = NULL;
        int rc = test_run_cli(&err, "render", "--size", "16x16", "--shader-dir", dir, "--out", out, a[0], a[1], a[2],
                              a[3], a[4], a[5], a[6], NULL);
        char want[128];
        snprintf(want, sizeof want, "(program %s)", cases[i].program);
        print_message("%s under %s: exit %d\n", cases[i].file, cases[i].guard, rc);
        /* Each driver words it its own way (Mesa: "#error broken by the test";
         * NVIDIA: "error C0000: broken by the test"): the text is the test's. */
        test_expect_cli_error(rc, err, 1, want, "broken by the test");
        assert_int_not_equal(access(out, F_OK), 0);
    }
}

/* --out FILE.pfm --png FILE.png writes one frame twice: the PNG is the PFM
 * through exposure, clamp and sRGB (the GPU's tone map and the CPU's agree
 * to rounding); the reference does the same on the CPU. */
static void png_beside_pfm(void **state)
{
    (void)state;
    char pfm[512], png[512];
    snprintf(pfm, sizeof pfm, "%s/both.pfm", RTGI_TEST_TMP);
    snprintf(png, sizeof png, "%s/both.png", RTGI_TEST_TMP);
    for (int pass = 0; pass < 2; pass++) {
        int rc = pass == 0 ? test_run_cli(NULL, "render", "--size", "32x32", "--shadow", "hard", "--exposure", "2",
                                          "--out", pfm, "--png", png, NULL)
                           : test_run_cli(NULL, "reference", "--size", "32x32", "--spp", "2", "--exposure", "2",
                                          "--out", pfm, "--png", png, "--quiet", NULL);
        assert_int_equal(rc, 0);
        ImageF lin, ldr;
        assert_true(image_read(pfm, &lin));
        assert_true(image_read(png, &ldr));
        float worst = 0;
        for (int i = 0; i < 32 * 32 * 3; i++) {
            float want = srgb_encode(lin.rgb[i] * 2.f), got = srgb_encode(ldr.rgb[i]);
            worst = fmaxf(worst, fabsf(want - got));
        }
        print_message("%s: PNG vs tone-mapped PFM, worst %.4f\n", pass ? "reference" : "render", worst);
        assert_true(worst <= 1.01f / 255.f);
        image_free(&lin);
        image_free(&ldr);
    }
}

/* `render` writes every output it was asked for or none. An output that
 * cannot be created is refused before anything renders; one whose write
 * fails later (here a file-size limit: the ambient-visibility PFM, written
 * last, is over it where the PNGs before it are not) removes the outputs
 * already written. */
static void failed_output_leaves_none(void **state)
{
    (void)state;
    char out[512], mask[512], ao[512];
    snprintf(out, sizeof out, "%s/none.png", RTGI_TEST_TMP);
    snprintf(mask, sizeof mask, "%s/none_mask.png", RTGI_TEST_TMP);
    snprintf(ao, sizeof ao, "%s/none_ao.pfm", RTGI_TEST_TMP);
    const char *bad = "/nonexistent/dir/x.png";
    for (int c = 0; c < 3; c++) {
        remove(out);
        remove(mask);
        remove(ao);
        char *err = NULL;
        struct rlimit was;
        assert_int_equal(getrlimit(RLIMIT_FSIZE, &was), 0);
        if (c == 2) { /* files of at most 2 KB; the write past it fails (EFBIG) instead of signalling */
            signal(SIGXFSZ, SIG_IGN);
            struct rlimit small = {2048, was.rlim_max};
            assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
        }
        int rc = c == 0 ? test_run_cli(&err, "render", "--size", "16x16", "--out", out, "--emitter-mask", bad, NULL)
               : c == 1 ? test_run_cli(&err, "render", "--size", "16x16", "--gi", "vct", "--vct-size", "16",
                                       "--vct-ao", "on", "--out", out, "--emitter-mask", mask, "--out-ao", bad, NULL)
                        : test_run_cli(&err, "render", "--size", "16x16", "--gi", "vct", "--vct-size", "16",
                                       "--vct-ao", "on", "--out", out, "--emitter-mask", mask, "--out-ao", ao, NULL);
        assert_int_equal(setrlimit(RLIMIT_FSIZE, &was), 0);
        print_message("case %d: rc %d: %s", c, rc, err ? err : "");
        test_expect_cli_error(rc, err, 1, c == 2 ? ao : bad, c == 2 ? "File too large" : "cannot create");
        assert_int_not_equal(access(out, F_OK), 0);
        assert_int_not_equal(access(mask, F_OK), 0);
        assert_int_not_equal(access(ao, F_OK), 0);
    }
    /* Unlimited, the same command writes all three. */
    assert_int_equal(test_run_cli(NULL, "render", "--size", "16x16", "--gi", "vct", "--vct-size", "16", "--vct-ao",
                                  "on", "--out", out, "--emitter-mask", mask, "--out-ao", ao, "--quiet", NULL),
                     0);
    assert_int_equal(access(out, F_OK), 0);
    assert_int_equal(access(mask, F_OK), 0);
    assert_int_equal(access(ao, F_OK), 0);
}

/* Runs `rtgi ARGS` (NULL-ended, at most 16; OUT among them) with the
 * preloaded allocation shim, once whole to count its allocations, then
 * with each of the last 7 refused (the read-back, the encoder's and the
 * last log lines' copies: a PNG's 16x16 write had its 8-bit image 4th from
 * the end): exit 1, one line and no OUT, or, where the allocation was not
 * needed, exit 0. Returns the refusals that failed the command. */
static int sweep_last_allocations(const char *const *args, const char *out, int last)
{
    char count[512], fired[512], preload[2048], env_count[600], env_fired[600], at[32] = "OOM_AT=0";
    snprintf(count, sizeof count, "%s/oom_count.txt", RTGI_TEST_TMP);
    snprintf(fired, sizeof fired, "%s/oom_fired.txt", RTGI_TEST_TMP);
    snprintf(env_count, sizeof env_count, "OOM_COUNT=%s", count);
    snprintf(env_fired, sizeof env_fired, "OOM_REPORT=%s", fired);
    const char *was = getenv("LD_PRELOAD"); /* make test-asan preloads its own */
    snprintf(preload, sizeof preload, "LD_PRELOAD=%s%s%s", was ? was : "", was ? ":" : "", RTGI_ALLOC_SHIM);
    const char *a[16] = {0};
    for (int i = 0; i < 16 && args[i]; i++)
        a[i] = args[i];
    /* The environment through env(1): the shim reaches rtgi only. */
#define RUN(err, report)                                                                                          \
    test_run_exe(err, "env", preload, at, report, RTGI_BINARY, a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8], \
                 a[9], a[10], a[11], a[12], a[13], a[14], a[15], NULL)
    assert_int_equal(RUN(NULL, env_count), 0);
    char *text = util_read_file(count, NULL);
    assert_non_null(text);
    int n = atoi(text), failed = 0;
    free(text);
    assert_true(n > 10);
    for (int k = n - last + 1; k <= n; k++) {
        snprintf(at, sizeof at, "OOM_AT=%d", k);
        remove(out);
        remove(fired);
        char *err = NULL;
        int rc = RUN(&err, env_fired);
        char *f = util_read_file(fired, NULL);
        assert_true(f && f[0] == '1'); /* the k-th allocation was refused */
        free(f);
        if (rc == 0) {
            free(err);
            continue;
        }
        print_message("%s, allocation %d of %d: %s", a[0], k, n, err ? err : "(nothing)\n");
        test_expect_cli_error(rc, err, 1, NULL, NULL);
        assert_int_not_equal(access(out, F_OK), 0);
        failed++;
    }
#undef RUN
    return failed;
}

/* A command's last allocations are its outputs' (the read-back, the 8-bit
 * image, the metrics' images): each refused in turn (scripts/
 * alloc_failure_shim.c, preloaded: the k-th allocation that rtgi's own code
 * asks for returns NULL) fails the command with one line and no file. The
 * whole sweep is scripts/alloc-failure-sweep.sh. render's last 7 to a PNG,
 * its last 3 to a PFM or EXR: the four before those are string copies that
 * the PNG's sweep refuses too (8 runs of CI's ASan time); compare's last 7. */
static void output_allocation_failures(void **state)
{
    (void)state;
    char out[512], a[512], b[512];
    static const char *const exts[] = {"png", "pfm", "exr"};
    static const int last[] = {7, 3, 3};
    for (int e = 0; e < 3; e++) {
        snprintf(out, sizeof out, "%s/oom_out.%s", RTGI_TEST_TMP, exts[e]);
        const char *args[] = {"render", "--size", "16x16", "--gi", "none", "--out", out, "--quiet", NULL};
        assert_true(sweep_last_allocations(args, out, last[e]) > 0);
    }
    snprintf(a, sizeof a, "%s/oom_a.pfm", RTGI_TEST_TMP);
    snprintf(b, sizeof b, "%s/oom_b.pfm", RTGI_TEST_TMP);
    snprintf(out, sizeof out, "%s/oom_heat.png", RTGI_TEST_TMP);
    assert_int_equal(test_run_cli(NULL, "render", "--size", "16x16", "--gi", "none", "--out", a, "--quiet", NULL), 0);
    assert_int_equal(test_run_cli(NULL, "render", "--size", "16x16", "--shadow", "hard", "--out", b, "--quiet", NULL), 0);
    const char *args[] = {"compare", a, b, "--heatmap", out, NULL};
    assert_true(sweep_last_allocations(args, out, 7) > 0);
}

/* render --timings makes its renderer again for the steady frames and the
 * reads-only twin: each GPU make of the whole command refused (RTGI_FAIL_GL_
 * MAKE=k) gives exit 1, one line and no output file, never a crash (a
 * failed steady make had left the twin's technique over missing RSMs).
 * The cold frames' makes, in steps of 5 (test_lifetime refuses each of a
 * renderer's makes in one process); from the step that passes the cold
 * frames' timings, every make in turn. */
static void timings_make_failures(void **state)
{
    (void)state;
    char out[512], probe[512];
    snprintf(out, sizeof out, "%s/timings_fail.pfm", RTGI_TEST_TMP);
    snprintf(probe, sizeof probe, "%s/timings_fail_probe.json", RTGI_TEST_TMP);
    assert_int_equal(test_run_cli(NULL, "probe", "--map-size", "64", "--json", probe, "--quiet", NULL), 0);
    int k = 1, step = 5, steady = 0, runs = 0;
    for (;; k += step) {
        char num[16];
        snprintf(num, sizeof num, "%d", k);
        setenv("RTGI_FAIL_GL_MAKE", num, 1);
        remove(out);
        char *text = NULL, *err = NULL;
        int rc = test_run_cli_out(&text, &err, "render", "--size", "16x16", "--gi", "rsm-interp", "--rsm-size", "32",
                                  "--timings", "--frames", "1", "--probe", probe, "--out", out, NULL);
        unsetenv("RTGI_FAIL_GL_MAKE");
        runs++;
        bool after_cold = rc != 0 && text && strstr(text, "frame_cold_ms") != NULL;
        if (rc != 0) {
            test_expect_cli_error(rc, err, 1, "refused", NULL);
            assert_int_not_equal(access(out, F_OK), 0);
        } else {
            free(err);
        }
        free(text);
        if (step > 1 && (rc == 0 || after_cold)) { /* past the cold frames: back to the last step's next, one by one */
            k -= step;
            step = 1;
            continue;
        }
        if (rc == 0)
            break;
        steady += after_cold;
        assert_true(k < 200);
    }
    print_message("makes 1 to %d refused (%d runs), the %d after the cold frames' timings each in turn\n", k - 1, runs,
                  steady);
    assert_true(steady > 0);
    assert_int_equal(access(out, F_OK), 0);
}

/* The window: `rtgi view` under a virtual X server (Xvfb, installed by
 * scripts/install-deps.sh) renders through GLFW's GL 4.5 context exactly
 * the image `rtgi render` makes headless through EGL (the window's default
 * post-process AA, FXAA, asked for explicitly in `render`). */
static void view_matches_headless_render(void **state)
{
    (void)state;
    char view[512], headless[512];
    snprintf(view, sizeof view, "%s/view.png", RTGI_TEST_TMP);
    snprintf(headless, sizeof headless, "%s/headless.png", RTGI_TEST_TMP);
    char *err = NULL;
    test_x_display();
    int rc = test_run_cli(&err, "view", "--size", "64x64", "--shadow", "hard",
                          "--frames", "2", "--out", view, NULL);
    if (rc != 0)
        fail_msg("rtgi view under Xvfb failed (%d): %s", rc, err ? err : "");
    free(err);
    assert_int_equal(test_run_cli(NULL, "render", "--size", "64x64", "--shadow", "hard", "--aa", "fxaa", "--out", headless, NULL), 0);
    ImageF a, b;
    assert_true(image_read(view, &a));
    assert_true(image_read(headless, &b));
    assert_int_equal(a.width, 64);
    assert_int_equal(b.height, 64);
    int differ = 0;
    for (int i = 0; i < 64 * 64 * 3; i++)
        differ += fabsf(a.rgb[i] - b.rgb[i]) > 2.f / 255.f;
    assert_int_equal(differ, 0);
    assert_true(test_mean(&a, 4, 32, 2, 0) > 3 * test_mean(&a, 4, 32, 2, 1)); /* and it is the Cornell box */
    image_free(&a);
    image_free(&b);
}

/* compare --json writes the metrics; --mask restricts them to the mask's
 * white pixels (here: the half of the image where the two agree). */
static void compare_json_and_mask(void **state)
{
    (void)state;
    char a[512], b[512], mask[512], json[512];
    snprintf(a, sizeof a, "%s/cmp_j_a.pfm", RTGI_TEST_TMP);
    snprintf(b, sizeof b, "%s/cmp_j_b.pfm", RTGI_TEST_TMP);
    snprintf(mask, sizeof mask, "%s/cmp_j_mask.png", RTGI_TEST_TMP);
    snprintf(json, sizeof json, "%s/cmp_j.json", RTGI_TEST_TMP);
    ImageF ia, ib;
    assert_true(image_alloc(&ia, 16, 8));
    assert_true(image_alloc(&ib, 16, 8));
    uint8_t m[16 * 8 * 3];
    for (int y = 0; y < 8; y++)
        for (int x = 0; x < 16; x++) {
            for (int c = 0; c < 3; c++) {
                image_px(&ia, x, y)[c] = 0.5f;
                image_px(&ib, x, y)[c] = x < 8 ? 0.5f : 0.7f; /* the right half differs */
                m[3 * (y * 16 + x) + c] = x < 8 ? 255 : 0;
            }
        }
    assert_true(image_write_pfm(a, &ia) && image_write_pfm(b, &ib));
    assert_true(image_write_png8(mask, 16, 8, m));
    assert_int_equal(test_run_cli(NULL, "compare", a, b, "--json", json, NULL), 0);
    char *text = util_read_file(json, NULL);
    assert_non_null(text);
    cJSON *j = cJSON_Parse(text);
    free(text);
    assert_non_null(j);
    /* RMSE over all pixels: half of them differ by 0.2 → sqrt(0.02);
     * relMSE: half of 0.04 / (0.49 + 0.01) = 0.04. */
    assert_float_equal(cJSON_GetObjectItem(j, "rmse")->valuedouble, sqrt(0.02), 1e-6);
    assert_float_equal(cJSON_GetObjectItem(j, "relmse")->valuedouble, 0.04, 1e-6);
    assert_true(cJSON_IsNumber(cJSON_GetObjectItem(j, "ssim")) && cJSON_IsNumber(cJSON_GetObjectItem(j, "flip")));
    /* mean ratio: 0.5 over the reference's mean (0.5 + 0.7)/2 = 0.6 */
    assert_float_equal(cJSON_GetObjectItem(j, "mean_ratio")->valuedouble, 0.5 / 0.6, 1e-6);
    assert_float_equal(cJSON_GetArrayItem(cJSON_GetObjectItem(j, "mean_ratio_rgb"), 2)->valuedouble, 0.5 / 0.6, 1e-6);
    cJSON_Delete(j);
    assert_int_equal(test_run_cli(NULL, "compare", a, b, "--mask", mask, "--metric", "rmse", "--json", json, NULL), 0);
    text = util_read_file(json, NULL);
    j = cJSON_Parse(text);
    free(text);
    assert_non_null(j);
    assert_float_equal(cJSON_GetObjectItem(j, "rmse")->valuedouble, 0.0, 0);
    assert_null(cJSON_GetObjectItem(j, "ssim")); /* only the metric asked for */
    assert_float_equal(cJSON_GetObjectItem(j, "mean_ratio")->valuedouble, 1.0, 1e-6); /* the masked half agrees */
    cJSON_Delete(j);
    /* The heat map has its colour bar below: the map in the top 8 rows
     * (the right half at full heat: RMSE's scale is its maximum), then a
     * band from the darkest colour to the brightest. */
    char heat[512];
    snprintf(heat, sizeof heat, "%s/cmp_j_heat.png", RTGI_TEST_TMP);
    assert_int_equal(test_run_cli(NULL, "compare", a, b, "--metric", "rmse", "--heatmap", heat, NULL), 0);
    ImageF hm;
    assert_true(image_read(heat, &hm));
    assert_int_equal(hm.width, 16);
    assert_true(hm.height > 8 + 4);
    assert_true(image_px(&hm, 2, 4)[1] < 0.01f && image_px(&hm, 13, 4)[1] > 0.9f);
    int band = -1;
    for (int y = 8; y < hm.height && band < 0; y++)
        if (luminance(image_px(&hm, 15, y)) > 0.9f)
            band = y;
    assert_true(band > 8);
    for (int x = 1; x < 16; x++) /* darker to brighter, left to right */
        assert_true(luminance(image_px(&hm, x, band)) >= luminance(image_px(&hm, x - 1, band)));
    assert_true(luminance(image_px(&hm, 0, band)) < 0.01f);
    image_free(&hm);
    /* Radiance against a tone-mapped PNG: the numbers come with a warning;
     * two radiance files, none. */
    char *err = NULL;
    assert_int_equal(test_run_cli(&err, "compare", a, mask, "--metric", "rmse", NULL), 0);
    assert_non_null(strstr(err ? err : "", "warning [compare] "));
    assert_non_null(strstr(err, "cmp_j_mask.png is a tone-mapped image (PNG) but"));
    free(err);
    assert_int_equal(test_run_cli(&err, "compare", a, b, "--metric", "rmse", NULL), 0);
    assert_null(strstr(err ? err : "", "tone-mapped"));
    free(err);
    image_free(&ia);
    image_free(&ib);
}

/* compare --unshadowed: reference visibility 1 1 0 0 in each of two rows,
 * test visibility 0.1 1 0 0.8: of 4 lit pixels 2 darkened, of 4 shadowed 2
 * lit. An unshadowed image of another size, and one under which nothing is
 * fully lit or shadowed, are errors naming it. */
static void compare_unshadowed(void **state)
{
    (void)state;
    char t[512], r[512], u[512], u2[512], json[512];
    snprintf(t, sizeof t, "%s/sa_t.pfm", RTGI_TEST_TMP);
    snprintf(r, sizeof r, "%s/sa_r.pfm", RTGI_TEST_TMP);
    snprintf(u, sizeof u, "%s/sa_u.pfm", RTGI_TEST_TMP);
    snprintf(u2, sizeof u2, "%s/sa_u2.pfm", RTGI_TEST_TMP);
    snprintf(json, sizeof json, "%s/sa.json", RTGI_TEST_TMP);
    const float vr[4] = {1, 1, 0, 0}, vt[4] = {0.1f, 1, 0, 0.8f};
    ImageF it, ir, iu, iu2;
    assert_true(image_alloc(&it, 4, 2) && image_alloc(&ir, 4, 2) && image_alloc(&iu, 4, 2) && image_alloc(&iu2, 3, 2));
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 4; x++)
            for (int c = 0; c < 3; c++) {
                image_px(&iu, x, y)[c] = 2.f;
                image_px(&ir, x, y)[c] = 2.f * vr[x];
                image_px(&it, x, y)[c] = 2.f * vt[x];
            }
    assert_true(image_write_pfm(t, &it) && image_write_pfm(r, &ir) && image_write_pfm(u, &iu) &&
                image_write_pfm(u2, &iu2));
    assert_int_equal(test_run_cli(NULL, "compare", t, r, "--unshadowed", u, "--json", json, NULL), 0);
    char *text = util_read_file(json, NULL);
    assert_non_null(text);
    cJSON *j = cJSON_Parse(text);
    free(text);
    const cJSON *sh = cJSON_GetObjectItem(j, "shadow");
    assert_true(cJSON_IsObject(sh));
    assert_int_equal(cJSON_GetObjectItem(sh, "lit_pixels")->valueint, 4);
    assert_int_equal(cJSON_GetObjectItem(sh, "shadowed_pixels")->valueint, 4);
    assert_float_equal(cJSON_GetObjectItem(sh, "false_shadow")->valuedouble, 0.5, 1e-9);
    assert_float_equal(cJSON_GetObjectItem(sh, "false_lit")->valuedouble, 0.5, 1e-9);
    cJSON_Delete(j);
    char *err = NULL;
    int rc = test_run_cli(&err, "compare", t, r, "--unshadowed", u2, NULL);
    test_expect_cli_error(rc, err, 1, "sa_u2.pfm", "3x2");
    rc = test_run_cli(&err, "compare", t, t, "--unshadowed", t, NULL); /* V = 1 where lit, 0/0 elsewhere */
    assert_int_equal(rc, 0);
    free(err);
    for (int i = 0; i < 4 * 2 * 3; i++)
        it.rgb[i] = 1.f; /* visibility 0.5 everywhere: all penumbra */
    assert_true(image_write_pfm(t, &it));
    rc = test_run_cli(&err, "compare", t, t, "--unshadowed", u, NULL);
    test_expect_cli_error(rc, err, 1, "--unshadowed", "no pixel is fully lit or fully shadowed");
    image_free(&it);
    image_free(&ir);
    image_free(&iu);
    image_free(&iu2);
}

static void reference_bad_input(void **state)
{
    (void)state;
    char *err = NULL;
    int rc = test_run_cli(&err, "reference", "--spp", "0", NULL);
    test_expect_cli_error(rc, err, 2, "--spp", "out of range");
    rc = test_run_cli(&err, "reference", "--mode", "two-bounce", NULL);
    test_expect_cli_error(rc, err, 2, "--mode", "unknown value 'two-bounce'");
    rc = test_run_cli(&err, "reference", "--scene", "/nonexistent/x.json", NULL);
    test_expect_cli_error(rc, err, 1, "/nonexistent/x.json", "does not exist");
    rc = test_run_cli(&err, "reference", "--target-relmse", "0", NULL);
    test_expect_cli_error(rc, err, 2, "--target-relmse", "out of range");
    rc = test_run_cli(&err, "reference", "--target-relmse", "-0.01", NULL);
    test_expect_cli_error(rc, err, 2, "--target-relmse", "out of range");
    rc = test_run_cli(&err, "reference", "--target-relmse", "tiny", NULL);
    test_expect_cli_error(rc, err, 2, "--target-relmse", "not a number");
    rc = test_run_cli(&err, "reference", "--time", "0", NULL);
    test_expect_cli_error(rc, err, 2, "--time", "out of range");
    rc = test_run_cli(&err, "reference", "--time", "inf", NULL);
    test_expect_cli_error(rc, err, 2, "--time", "not a finite number");
    rc = test_run_cli(&err, "reference", "--time", NULL);
    test_expect_cli_error(rc, err, 2, "--time", "value");
}

/* The value of line "key: " in text, or -1. */
static double out_value(const char *text, const char *key)
{
    const char *p = strstr(text, key);
    return p ? atof(p + strlen(key)) : -1.0;
}

/* --time stops the render before the samples asked for (the budget is far
 * below what 10^5 spp take), says so on stdout and writes the image with
 * the samples reached; --target-relmse stops once the estimate reaches it;
 * before a render of more than one pass, one line says what it will take
 * (none with --quiet). */
static void reference_stops_on_budget(void **state)
{
    (void)state;
    char out[512];
    snprintf(out, sizeof out, "%s/budget_ref.exr", RTGI_TEST_TMP);
    char *text = NULL, *err = NULL;
    /* 32x32: passes of 256 spp (2^18 samples), well under a second each. */
    int rc = test_run_cli_out(&text, &err, "reference", "--size", "32x32", "--spp", "100000", "--time", "0.5",
                              "--out", out, NULL);
    assert_int_equal(rc, 0);
    double spp = out_value(text, "\nspp: ");
    print_message("--time 0.5: %g spp; stderr: %s", spp, err);
    assert_true(spp >= 256 && spp < 100000);
    assert_non_null(strstr(text, "stopped: time 0.5 s reached at"));
    assert_non_null(strstr(err, "time budget 0.5 s: about"));
    ImageF img;
    assert_true(image_read(out, &img));
    image_free(&img);
    free(text);
    free(err);

    /* The first pass's estimate is about 1e-3 (0.0033 at 64 spp), the
     * second's 5e-4: two passes. */
    rc = test_run_cli_out(&text, &err, "reference", "--size", "32x32", "--target-relmse", "0.0006", "--out", out,
                          "--quiet", NULL);
    assert_int_equal(rc, 0);
    spp = out_value(text, "\nspp: ");
    double est = out_value(text, "relmse_estimate: ");
    print_message("--target-relmse 0.0006: %g spp, estimate %g\n", spp, est);
    assert_true(spp > 256 && spp < 1 << 24);
    assert_true(est > 0 && est <= 0.0006);
    assert_non_null(strstr(text, "stopped: target-relmse 0.0006 reached at"));
    assert_true(err == NULL || strstr(err, "relMSE") == NULL); /* --quiet: no forecast */
    free(text);
    free(err);

    /* A render of several passes forecasts its time after the first. */
    rc = test_run_cli_out(&text, &err, "reference", "--size", "32x32", "--spp", "512", "--out", out, NULL);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(err, "512 spp: about"));
    free(text);
    free(err);
}

static void compare_bad_input(void **state)
{
    (void)state;
    char a[512], b[512];
    snprintf(a, sizeof a, "%s/cmp_a.pfm", RTGI_TEST_TMP);
    snprintf(b, sizeof b, "%s/cmp_b.pfm", RTGI_TEST_TMP);
    assert_int_equal(test_run_cli(NULL, "reference", "--size", "8x8", "--spp", "1", "--out", a, "--quiet", NULL), 0);
    assert_int_equal(test_run_cli(NULL, "reference", "--size", "8x6", "--spp", "1", "--out", b, "--quiet", NULL), 0);
    char *err = NULL;
    int rc = test_run_cli(&err, "compare", a, b, NULL);
    test_expect_cli_error(rc, err, 1, "8x8", "sizes must match");
    rc = test_run_cli(&err, "compare", a, "/nonexistent/ref.pfm", NULL);
    test_expect_cli_error(rc, err, 1, "/nonexistent/ref.pfm", "cannot read");
    const char *junk = tmp_file("junk.pfm", "PF\n8 8\n-1.0\nshort");
    rc = test_run_cli(&err, "compare", a, junk, NULL);
    test_expect_cli_error(rc, err, 1, "junk.pfm", "truncated");
    junk = tmp_file("junk.png", "not a png at all");
    rc = test_run_cli(&err, "compare", a, junk, NULL);
    test_expect_cli_error(rc, err, 1, "junk.png", "cannot read image");
    rc = test_run_cli(&err, "compare", a, NULL);
    test_expect_cli_error(rc, err, 2, "needs two images", NULL);
    rc = test_run_cli(&err, "compare", a, a, "--metric", "psnr", NULL);
    test_expect_cli_error(rc, err, 2, "--metric", "'psnr'");
}

/* Issue 15's CLI conventions: "--opt=value", a value given to a flag is an
 * error, "did you mean" for options, choices and scene names in every
 * command (one hint style), and --version. */
static void cli_conventions(void **state)
{
    (void)state;
    char out[512], *err = NULL;
    snprintf(out, sizeof out, "%s/eq_form.png", RTGI_TEST_TMP);
    remove(out);
    char size_arg[] = "--size=8x8", gi_arg[] = "--gi=rsm", out_arg[600];
    snprintf(out_arg, sizeof out_arg, "--out=%s", out);
    int rc = test_run_cli(&err, "render", size_arg, gi_arg, "--rsm-size=16", out_arg, "--quiet", NULL);
    free(err);
    assert_int_equal(rc, 0);
    FILE *f = fopen(out, "rb");
    assert_non_null(f);
    fclose(f);
    rc = test_run_cli(&err, "render", "--size", "8x8", "--timings=1", NULL);
    test_expect_cli_error(rc, err, 2, "--timings", "takes no value");
    rc = test_run_cli(&err, "render", "--shadows", "pcf", NULL);
    test_expect_cli_error(rc, err, 2, "render: unknown option '--shadows'", "did you mean '--shadow'");
    rc = test_run_cli(&err, "view", "--sise", "8x8", NULL);
    test_expect_cli_error(rc, err, 2, "view: unknown option", "did you mean '--size'");
    rc = test_run_cli(&err, "render", "--pcf-sample", "4", NULL);
    test_expect_cli_error(rc, err, 2, "unknown option '--pcf-sample'", "did you mean '--pcf-samples'");
    rc = test_run_cli(&err, "render", "--gi", "rsn", NULL);
    test_expect_cli_error(rc, err, 2, "--gi", "did you mean 'rsm'");
    rc = test_run_cli(&err, "render", "--scene", "cornel", NULL);
    test_expect_cli_error(rc, err, 2, "render: --scene: 'cornel'", "did you mean 'cornell'? (see rtgi render --help)");
    /* view's own options go through the same parser: their typos get a
     * suggestion, and each command names the other's options as such. */
    static const char *const view_typos[][2] = {{"--compair", "--compare"},     {"--window-outt", "--window-out"},
                                                {"--slow-m", "--slow-ms"},      {"--no-pannel", "--no-panel"},
                                                {"--ui-tests", "--ui-test"}};
    for (size_t i = 0; i < sizeof view_typos / sizeof view_typos[0]; i++) {
        char want[64];
        snprintf(want, sizeof want, "did you mean '%s'", view_typos[i][1]);
        rc = test_run_cli(&err, "view", view_typos[i][0], "x", NULL);
        test_expect_cli_error(rc, err, 2, "view: unknown option", want);
    }
    rc = test_run_cli(&err, "view", "--slow-ms=0", NULL);
    test_expect_cli_error(rc, err, 2, "--slow-ms", "out of range");
    rc = test_run_cli(&err, "view", "--no-panel=1", NULL);
    test_expect_cli_error(rc, err, 2, "--no-panel", "takes no value");
    rc = test_run_cli(&err, "view", "--live-priority", "low", NULL);
    test_expect_cli_error(rc, err, 2, "--live-priority: unknown value 'low'", "idle, normal");
    rc = test_run_cli(&err, "view", "--live-threads", "0", NULL);
    test_expect_cli_error(rc, err, 2, "--live-threads", NULL);
    rc = test_run_cli(&err, "view", "--live-spp", "many", NULL);
    test_expect_cli_error(rc, err, 2, "--live-spp", NULL);
    rc = test_run_cli(&err, "render", "--live-reference", NULL);
    test_expect_cli_error(rc, err, 2, "--live-reference is an option of 'rtgi view'", NULL);
    rc = test_run_cli(&err, "view", "--window-out", "w.jpg", NULL);
    test_expect_cli_error(rc, err, 2, "--window-out", ".png");
    rc = test_run_cli(&err, "render", "--compare", "ref.pfm", NULL);
    test_expect_cli_error(rc, err, 2, "--compare", "option of 'rtgi view'");
    /* view had taken --out-ao and written nothing for it, with exit 0. */
    rc = test_run_cli(&err, "view", "--out-ao", "ao.pfm", NULL);
    test_expect_cli_error(rc, err, 2, "--out-ao", "option of 'rtgi render'");
    rc = test_run_cli(&err, "render", "--timing", NULL);
    test_expect_cli_error(rc, err, 2, "render: unknown option", "did you mean '--timings'");
    rc = test_run_cli(&err, "reference", "--sppp", "4", NULL);
    test_expect_cli_error(rc, err, 2, "reference: unknown option", "did you mean '--spp'");
    rc = test_run_cli(&err, "compare", "a.pfm", "b.pfm", "--mask-emiters", "m.png", NULL);
    test_expect_cli_error(rc, err, 2, "compare: unknown option", "did you mean '--mask-emitters'");
    char cmd[600], line[256] = "";
    snprintf(cmd, sizeof cmd, "%s --version", RTGI_BINARY);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    assert_non_null(fgets(line, sizeof line, p));
    assert_int_equal(pclose(p), 0);
    assert_true(strncmp(line, "rtgi ", 5) == 0 && strlen(line) > 6);
}

/* Long work is never silent (issue 15): when the cost model puts a frame
 * over the threshold (2 s, or RTGI_PROGRESS_S), render prints one line
 * before the first frame. The estimate is the model's, not a timing, so
 * the cases are deterministic: vpl-all at 64x64 with 4096 VPLs per light
 * (the Cornell quad light's half cube of 37² texels: 4107 slots) is
 * 4096 x 4107 / 4e7 = 0.42 s; rsm 4096 x 400 / 4e7 = 0.04 s. */
static void render_estimate_line(void **state)
{
    (void)state;
    char out[512], *err = NULL;
    snprintf(out, sizeof out, "%s/estimate.png", RTGI_TEST_TMP);
    static const char *const want = "render: vpl-all at 64x64: about 0.4 s per frame (estimate); 1 frame to draw\n";
    setenv("RTGI_PROGRESS_S", "0.2", 1);
    int rc = test_run_cli(&err, "render", "--size", "64x64", "--gi", "vpl-all", "--out", out, NULL);
    print_message("vpl-all, threshold 0.2 s: %s", err ? err : "");
    assert_int_equal(rc, 0);
    assert_non_null(err);
    assert_non_null(strstr(err, want));
    free(err);
    rc = test_run_cli(&err, "render", "--size", "64x64", "--gi", "rsm", "--out", out, NULL);
    assert_int_equal(rc, 0);
    assert_null(strstr(err ? err : "", "(estimate)"));
    free(err);
    rc = test_run_cli(&err, "render", "--size", "64x64", "--gi", "vpl-all", "--out", out, "--quiet", NULL);
    assert_int_equal(rc, 0);
    assert_null(strstr(err ? err : "", "(estimate)")); /* --quiet: no progress */
    free(err);
    unsetenv("RTGI_PROGRESS_S");
    rc = test_run_cli(&err, "render", "--size", "64x64", "--gi", "vpl-all", "--out", out, NULL);
    test_progress_off();
    assert_int_equal(rc, 0);
    assert_null(strstr(err ? err : "", "(estimate)")); /* 0.42 s is under the default 2 s */
    free(err);
}

/* Every command takes --quiet (errors only on stderr: no info or progress
 * lines) and --verbose (debug lines too), before or after its other
 * options, and lists both in its --help. */
static void quiet_and_verbose_everywhere(void **state)
{
    (void)state;
    char png[512], pfm[512], *err = NULL;
    snprintf(png, sizeof png, "%s/qv.png", RTGI_TEST_TMP);
    snprintf(pfm, sizeof pfm, "%s/qv.pfm", RTGI_TEST_TMP);
    static const char *const commands[] = {"render", "view", "reference", "compare", "probe", "bench"};
    char cmd[700];
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        for (int verbose = 0; verbose < 2; verbose++) {
            int rc = test_run_cli(&err, commands[i], verbose ? "--verbose" : "--quiet", "--help", NULL);
            if (rc != 0)
                fail_msg("%s %s --help: exit %d: %s", commands[i], verbose ? "--verbose" : "--quiet", rc, err);
            free(err);
        }
        snprintf(cmd, sizeof cmd, "%s %s --help | grep -q -e --verbose && %s %s --help | grep -q -e --quiet",
                 RTGI_BINARY, commands[i], RTGI_BINARY, commands[i]);
        if (system(cmd) != 0)
            fail_msg("rtgi %s --help does not list both --quiet and --verbose", commands[i]);
    }
    /* The meaning, where a run is cheap: quiet leaves stderr empty, verbose
     * adds debug lines. */
    int rc = test_run_cli(&err, "render", "--quiet", "--size", "8x8", "--out", png, NULL);
    assert_int_equal(rc, 0);
    assert_true(!err || !*err);
    free(err);
    rc = test_run_cli(&err, "render", "--size", "8x8", "--out", png, "--verbose", NULL);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(err, "rtgi: debug ["));
    free(err);
    rc = test_run_cli(&err, "reference", "--size", "8x8", "--spp", "1", "--out", pfm, "--quiet", NULL);
    assert_int_equal(rc, 0);
    assert_true(!err || !*err);
    free(err);
    rc = test_run_cli(&err, "compare", "--quiet", pfm, pfm, NULL);
    assert_int_equal(rc, 0);
    assert_true(!err || !*err);
    free(err);
    rc = test_run_cli(&err, "compare", pfm, pfm, "--verbose", NULL);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(err, "rtgi: debug [compare] test "));
    free(err);
    test_x_display();
    rc = test_run_cli(&err, "view", "--size", "16x16", "--frames", "1", "--out", png, "--quiet", NULL);
    assert_int_equal(rc, 0);
    assert_true(!err || !*err);
    free(err);
    rc = test_run_cli(&err, "probe", "--quiet", "--map-size", "64", NULL);
    assert_int_equal(rc, 0);
    assert_true(!err || !*err);
    free(err);
    rc = test_run_cli(&err, "render", "--quiet=1", NULL);
    test_expect_cli_error(rc, err, 2, "render: --quiet takes no value", "(see rtgi render --help)");
    rc = test_run_cli(&err, "bench", "--verbos", NULL);
    test_expect_cli_error(rc, err, 2, "bench: unknown option '--verbos'", "did you mean '--verbose'?");
}

/* One hint style for every usage error of every command:
 * "<command>: <what>; did you mean '<y>'? (see rtgi <command> --help)",
 * exit 2; suggestions by optimal-string-alignment distance, so a swapped
 * pair of letters ("pfc") is one edit. */
static void one_error_hint_style(void **state)
{
    (void)state;
    char *err = NULL;
    static const char *const commands[] = {"render", "view", "reference", "compare", "probe", "bench"};
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        char want[128], hint[64];
        snprintf(want, sizeof want, "%s: unknown option '--bogus-option'", commands[i]);
        snprintf(hint, sizeof hint, " (see rtgi %s --help)", commands[i]);
        int rc = test_run_cli(&err, commands[i], "--bogus-option", NULL);
        test_expect_cli_error(rc, err, 2, want, hint);
        snprintf(want, sizeof want, "%s: --json needs a value", commands[i]);
        if (!strcmp(commands[i], "compare") || !strcmp(commands[i], "probe")) {
            rc = test_run_cli(&err, commands[i], "--json", NULL);
            test_expect_cli_error(rc, err, 2, want, hint);
        }
    }
    int rc = test_run_cli(&err, "render", "--shadow", "pfc", NULL);
    test_expect_cli_error(rc, err, 2, "render: --shadow: unknown value 'pfc'",
                          "; did you mean 'pcf'? (see rtgi render --help)");
    rc = test_run_cli(&err, "render", "--shadow", "PCSS", NULL); /* case alone: suggested, at any length */
    test_expect_cli_error(rc, err, 2, "render: --shadow: unknown value 'PCSS'", "; did you mean 'pcss'?");
    rc = test_run_cli(&err, "render", "--gi", "VPL-METALIGHTS", NULL);
    test_expect_cli_error(rc, err, 2, "render: --gi: unknown value 'VPL-METALIGHTS'", "did you mean 'vpl-metalights'?");
    rc = test_run_cli(&err, "reference", "--mode", "one-bounse", NULL);
    test_expect_cli_error(rc, err, 2, "reference: --mode: unknown value 'one-bounse'",
                          "; did you mean 'one-bounce'? (see rtgi reference --help)");
    rc = test_run_cli(&err, "render", "--exposure", NULL);
    test_expect_cli_error(rc, err, 2, "render: --exposure needs a value", "(see rtgi render --help)");
    rc = test_run_cli(&err, "view", "--no-panel=yes", NULL);
    test_expect_cli_error(rc, err, 2, "view: --no-panel takes no value", "(see rtgi view --help)");
    rc = test_run_cli(&err, "render", "--rsm-weighting", "papre", NULL);
    test_expect_cli_error(rc, err, 2, "render: --rsm-weighting: unknown value 'papre'", "did you mean 'paper'? (see rtgi render --help)");
    rc = test_run_cli(&err, "reference", "--scene", "cornel", NULL);
    test_expect_cli_error(rc, err, 2, "reference: --scene: 'cornel'", "did you mean 'cornell'? (see rtgi reference --help)");
    rc = test_run_cli(&err, "rendr", "--size", "8x8", NULL);
    test_expect_cli_error(rc, err, 2, "unknown command 'rendr'", "did you mean 'render'? (see rtgi --help)");
    rc = test_run_cli(&err, "bench", "--out", RTGI_TEST_TMP "/bench_typo", "--gi", "rsm:samplez=4", NULL);
    test_expect_cli_error(rc, err, 2, "bench: --gi: 'samplez' is not a setting key",
                          "did you mean 'samples'? (see rtgi bench --help)");
    rc = test_run_cli(&err, "bench", "--out", RTGI_TEST_TMP "/bench_typo", "--gi", "rsm,vpl-sl", NULL);
    test_expect_cli_error(rc, err, 2, "bench: --gi: unknown value 'vpl-sl'", "did you mean 'vpl-slc'? (see rtgi bench --help)");
    /* An output that cannot be written is the command's error, not a usage one. */
    rc = test_run_cli(&err, "render", "--size", "8x8", "--out", "/proc/rtgi_test.png", NULL);
    test_expect_cli_error(rc, err, 1, "rtgi: error [render] /proc/rtgi_test.png: cannot create output file", NULL);
    rc = test_run_cli(&err, "reference", "--size", "8x8", "--spp", "1", "--out", "/proc/rtgi_test.pfm", NULL);
    test_expect_cli_error(rc, err, 1, "rtgi: error [reference] /proc/rtgi_test.pfm: cannot create output file", NULL);
    rc = test_run_cli(&err, "render", "stray", NULL);
    test_expect_cli_error(rc, err, 2, "render: unexpected argument 'stray'", "(see rtgi render --help)");
}

/* A large mesh is never silent (issue 43: an 8M-triangle OBJ sat five
 * minutes in assimp's post-processing without a line): each step says it
 * runs and how long it took. RTGI_MESH_LARGE_VERTICES makes this quad
 * "large"; an OBJ without normals gets smooth normals and its unshared
 * corners joined; --quiet keeps it silent. */
static void large_mesh_says_each_step(void **state)
{
    (void)state;
    const char *obj = test_tmp_file("large_quad.obj", "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 2 3 4\n");
    char out[512], *err = NULL;
    snprintf(out, sizeof out, "%s/large_quad.png", RTGI_TEST_TMP);
    setenv("RTGI_MESH_LARGE_VERTICES", "1", 1);
    int rc = test_run_cli(&err, "render", "--scene", obj, "--size", "16x16", "--out", out, NULL);
    print_message("%s", err ? err : "");
    assert_int_equal(rc, 0);
    const char *steps[] = {"triangulating", "smooth normals", "joining identical vertices",
                           "flipping texture coordinates"};
    for (size_t i = 0; i < sizeof steps / sizeof steps[0]; i++) {
        char want[128];
        snprintf(want, sizeof want, "large_quad.obj: %s took ", steps[i]);
        if (!strstr(err, want))
            fail_msg("no line '%s'", want);
    }
    free(err);
    rc = test_run_cli(&err, "render", "--scene", obj, "--size", "16x16", "--out", out, "--quiet", NULL);
    unsetenv("RTGI_MESH_LARGE_VERTICES");
    assert_int_equal(rc, 0);
    assert_null(strstr(err ? err : "", "took"));
    free(err);
}

/* "--" ends the options: what follows is an operand whatever it looks like
 * (compare's images), and commands without operands refuse it. */
static void double_dash_ends_options(void **state)
{
    (void)state;
    char a[512], *err = NULL;
    snprintf(a, sizeof a, "%s/dd_a.pfm", RTGI_TEST_TMP);
    assert_int_equal(test_run_cli(NULL, "reference", "--size", "8x8", "--spp", "1", "--out", a, "--quiet", NULL), 0);
    int rc = test_run_cli(&err, "compare", "--metric", "rmse", "--", a, a, NULL);
    if (rc != 0)
        fail_msg("compare -- A B: exit %d: %s", rc, err ? err : "");
    free(err);
    /* After "--", "--json" is an image's name, not the option. */
    rc = test_run_cli(&err, "compare", a, "--", "--json", NULL);
    test_expect_cli_error(rc, err, 1, "--json", "does not exist");
    rc = test_run_cli(&err, "compare", "--", a, a, "-x", NULL);
    test_expect_cli_error(rc, err, 2, "compare: takes two images, got a third: '-x'", NULL);
    rc = test_run_cli(&err, "render", "--size", "8x8", "--", "--gi", NULL);
    test_expect_cli_error(rc, err, 2, "render: unexpected argument '--gi'", NULL);
}

/* What `rtgi <args>` prints on stdout (a shell command line; caller
 * frees); fails unless it exits 0. */
static char *cli_stdout(const char *args)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s %s", RTGI_BINARY, args);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    StrBuf b = {0};
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0)
        strbuf_append(&b, buf, n);
    if (pclose(p) != 0)
        fail_msg("rtgi %s failed", args);
    assert_non_null(b.data);
    return b.data;
}

/* What `rtgi [<command>] --help` prints on stdout (caller frees). */
static char *help_text(const char *command)
{
    char args[64];
    snprintf(args, sizeof args, "%s --help", command);
    return cli_stdout(args);
}

/* The line of `text` holding `key`, copied into `line`; fails if none. */
static const char *line_with(const char *text, const char *key, char *line, size_t cap)
{
    const char *k = strstr(text, key);
    if (!k)
        fail_msg("no line with '%s' in:\n%s", key, text);
    const char *a = k, *e = strchr(k, '\n');
    while (a > text && a[-1] != '\n')
        a--;
    snprintf(line, cap, "%.*s", (int)((e ? e : k + strlen(k)) - a), a);
    return line;
}

/* The help texts name EXR wherever an image is read or written. */
static void help_names_exr(void **state)
{
    (void)state;
    char line[512];
    char *top = help_text(""), *compare = help_text("compare"), *view = help_text("view"), *render = help_text("render");
    assert_non_null(strstr(line_with(top, "  render ", line, sizeof line), "EXR"));
    assert_non_null(strstr(line_with(top, "  compare ", line, sizeof line), "EXR"));
    assert_non_null(strstr(line_with(compare, "TEST, REFERENCE", line, sizeof line), ".exr"));
    /* view: --out's and --compare's descriptions (two lines each) */
    const char *out = strstr(view, "  --out FILE"), *cmp = strstr(view, "  --compare FILE");
    assert_true(out && cmp);
    /* each option's description runs to the next option's line */
    const char *out_end = strstr(out + 1, "\n  --"), *cmp_end = strstr(cmp + 1, "\n  --");
    assert_true(strstr(out, ".exr") && out_end && strstr(out, ".exr") < out_end);
    assert_true(strstr(cmp, ".exr") && cmp_end && strstr(cmp, ".exr") < cmp_end);
    assert_non_null(strstr(line_with(render, "  --half", line, sizeof line), "EXR"));
    assert_non_null(strstr(line_with(view, "  --half", line, sizeof line), ".exr"));
    free(top);
    free(compare);
    free(view);
    free(render);
}

/* Runs rtgi with the arguments (NULL-terminated) and RTGI_PROGRESS_S=0,
 * so that every progress line shows; fails unless it exits 0. Returns its
 * stderr (caller frees). */
static char *progress_stderr(const char *arg0, ...)
{
    char *err = NULL;
    va_list ap;
    va_start(ap, arg0);
    setenv("RTGI_PROGRESS_S", "0", 1);
    int rc = test_run_cli_va(&err, arg0, ap);
    test_progress_off();
    va_end(ap);
    if (rc != 0 || !err)
        fail_msg("rtgi %s: exit %d: %s", arg0, rc, err ? err : "");
    print_message("%s", err);
    return err;
}

/* The reference's progress off a terminal (stderr to a file, as in logs):
 * a line every 5 s, and a last one, each with the samples reached, the
 * time, rays/s and the time left. RTGI_PROGRESS_S=0 makes a line at every
 * poll of a short render, and the last one. */
static void reference_progress_lines(void **state)
{
    (void)state;
    char out[512];
    snprintf(out, sizeof out, "%s/progress_ref.pfm", RTGI_TEST_TMP);
    char *err = progress_stderr("reference", "--size", "16x16", "--spp", "8", "--out", out, NULL);
    assert_null(strchr(err, '\r')); /* no bar redrawn in place */
    int lines = 0, pct = -1, spp = -1, of = -1;
    double secs = -1, mrays = -1, eta = -1;
    for (char *save = NULL, *l = strtok_r(err, "\n", &save); l; l = strtok_r(NULL, "\n", &save)) {
        if (strncmp(l, "reference [", 11))
            continue;
        const char *rest = strchr(l, ']');
        assert_non_null(rest);
        int n = sscanf(rest, "] %d%%  %d/%d spp  %lf s  %lf Mrays/s  ETA %lf s", &pct, &spp, &of, &secs, &mrays, &eta);
        /* Before the first pass ends the time left is unknown: "ETA ?". */
        if (n == 5)
            assert_true(spp == 0 && strstr(rest, "ETA ?") != NULL);
        else
            assert_int_equal(n, 6);
        lines++;
    }
    free(err);
    /* The last line: every sample, no time left, a positive ray rate. */
    assert_true(lines >= 1);
    assert_int_equal(pct, 100);
    assert_int_equal(spp, 8);
    assert_int_equal(of, 8);
    assert_true(secs >= 0 && mrays > 0);
    assert_true(eta == 0.0);
    /* Without the override, a render under 5 s prints none. */
    int rc = test_run_cli(&err, "reference", "--size", "16x16", "--spp", "8", "--out", out, NULL);
    assert_int_equal(rc, 0);
    assert_null(strstr(err ? err : "", "reference ["));
    free(err);
}

/* After a first frame over the threshold (2 s; RTGI_PROGRESS_S=0 here),
 * every frame of render reports: with --timings 1 warm-up + 1 timed + 1 +
 * 1 steady frame, "render: frame i of 4 took X s; about Y s left". */
static void render_frame_progress_lines(void **state)
{
    (void)state;
    char out[512];
    snprintf(out, sizeof out, "%s/progress_render.png", RTGI_TEST_TMP);
    char *err = progress_stderr("render", "--size", "16x16", "--timings", "--warmup", "1", "--frames", "1", "--out",
                                out, NULL);
    int next = 1;
    for (char *save = NULL, *l = strtok_r(err, "\n", &save); l; l = strtok_r(NULL, "\n", &save)) {
        int i = 0, n = 0;
        double took = -1, left = -1;
        if (sscanf(l, "render: frame %d of %d took %lf s; about %lf s left", &i, &n, &took, &left) != 4)
            continue;
        assert_int_equal(i, next++);
        assert_int_equal(n, 4);
        assert_true(took >= 0 && left >= 0);
    }
    assert_int_equal(next, 5);
    free(err);
}

/* render and reference default to the same size (256x256), so their images
 * compare as they are; --vpls defaults to 4096 per light (render --help
 * shows it, and the light stage makes at most its 3 x 37² slots for the
 * Cornell quad light). */
static void shared_defaults(void **state)
{
    (void)state;
    char r[512], ref[512];
    snprintf(r, sizeof r, "%s/default_size.pfm", RTGI_TEST_TMP);
    snprintf(ref, sizeof ref, "%s/default_size_ref.pfm", RTGI_TEST_TMP);
    assert_int_equal(test_run_cli(NULL, "render", "--out", r, "--quiet", NULL), 0);
    assert_int_equal(test_run_cli(NULL, "reference", "--spp", "1", "--out", ref, "--quiet", NULL), 0);
    ImageF a, b;
    assert_true(image_read(r, &a));
    assert_true(image_read(ref, &b));
    print_message("render %dx%d, reference %dx%d\n", a.width, a.height, b.width, b.height);
    assert_int_equal(a.width, 256);
    assert_int_equal(a.height, 256);
    assert_int_equal(b.width, 256);
    assert_int_equal(b.height, 256);
    image_free(&a);
    image_free(&b);
    char line[512], *help = help_text("render");
    assert_non_null(strstr(line_with(help, "  --vpl-count N", line, sizeof line), "(default 4096 "));
    assert_non_null(strstr(line, "also --vpls, gi.vpls")); /* the old spellings, still accepted */
    free(help);
    char args[700];
    snprintf(args, sizeof args, "render --size 8x8 --gi vpl-all --timings --frames 1 --out %s --quiet", r);
    char *out = cli_stdout(args);
    int vpls = (int)strtol(line_with(out, "vpl_count: ", line, sizeof line) + strlen("vpl_count: "), NULL, 10);
    print_message("vpl_count %d (--vpls 4096 by default: at most 4107 slots)\n", vpls);
    assert_true(vpls > 2048 && vpls <= 4107);
    free(out);
}

/* Long output paths: a 251-byte file name (its NAME.tmp-XXXXXX would be
 * 262 bytes, over the 255 a name may have: it had been refused) and a
 * parent directory path of over 1024 bytes (cut to 1024, it had made a
 * stray directory of that name) are written like any other. */
static void long_output_paths(void **state)
{
    (void)state;
    char name[252], seg[201], path[2048], dir[1800];
    memset(name, 'E', 247);
    strcpy(name + 247, ".png");
    memset(seg, 'A', 200);
    seg[200] = 0;
    snprintf(path, sizeof path, "%s/%s", RTGI_TEST_TMP, name);
    char *err = NULL;
    assert_int_equal(test_run_cli(&err, "render", "--size", "8x8", "--out", path, "--quiet", NULL), 0);
    free(err);
    assert_int_equal(access(path, F_OK), 0);
    remove(path);
    int n = snprintf(dir, sizeof dir, "%s/long_paths", RTGI_TEST_TMP);
    mkdir(dir, 0777);
    for (int k = 0; k < 5; k++) {
        n += snprintf(dir + n, sizeof dir - (size_t)n, "/%s", seg);
        mkdir(dir, 0777);
    }
    assert_true(n > 1024);
    snprintf(path, sizeof path, "%s/x.png", dir);
    assert_int_equal(test_run_cli(&err, "render", "--size", "8x8", "--out", path, "--quiet", NULL), 0);
    free(err);
    assert_int_equal(access(path, F_OK), 0);
    /* No directory beside the deepest one: nothing was made of a cut name. */
    char parent[1800];
    util_dirname(dir, parent, sizeof parent);
    DIR *d = opendir(parent);
    assert_non_null(d);
    int entries = 0;
    for (struct dirent *e; (e = readdir(d));)
        entries += e->d_name[0] != '.';
    closedir(d);
    assert_int_equal(entries, 1);
}

/* An output that is a symbolic link is written where it points, through
 * a chain of links and to a dangling link's target, and the links stay
 * links (the rename had replaced a link with a plain file, leaving its
 * target as it was). */
static void output_symlinks_are_followed(void **state)
{
    (void)state;
    char dir[600], target[700], link[700], link2[700], dangling[700], missing[700];
    snprintf(dir, sizeof dir, "%s/out_links", RTGI_TEST_TMP);
    mkdir(dir, 0777);
    snprintf(target, sizeof target, "%s/target.pfm", dir);
    snprintf(link, sizeof link, "%s/link.pfm", dir);
    snprintf(link2, sizeof link2, "%s/link2.pfm", dir);
    snprintf(dangling, sizeof dangling, "%s/dangling.pfm", dir);
    snprintf(missing, sizeof missing, "%s/missing.pfm", dir);
    const char *paths[] = {target, link, link2, dangling, missing};
    for (int i = 0; i < 5; i++)
        remove(paths[i]);
    FILE *f = fopen(target, "w");
    assert_non_null(f);
    fputs("old", f);
    fclose(f);
    assert_int_equal(symlink("target.pfm", link), 0);
    assert_int_equal(symlink(link, link2), 0);
    assert_int_equal(symlink("missing.pfm", dangling), 0);
    const char *outs[] = {link2, dangling};
    for (int i = 0; i < 2; i++) {
        char *err = NULL;
        assert_int_equal(test_run_cli(&err, "render", "--size", "8x8", "--out", outs[i], "--quiet", NULL), 0);
        free(err);
    }
    struct stat st;
    for (int i = 1; i < 4; i++)
        assert_true(lstat(paths[i], &st) == 0 && S_ISLNK(st.st_mode));
    ImageF img = {0};
    assert_true(image_read(target, &img)); /* "old" replaced by the image */
    image_free(&img);
    assert_true(image_read(missing, &img));
    image_free(&img);
}

/* A command's stdout lines are its results: when they cannot be written
 * (a full disk: /dev/full) the command fails with one line saying so,
 * where `compare` and `probe` had exited 0 with the metrics lost. */
static void failed_stdout_fails_the_command(void **state)
{
    (void)state;
    char img[512], errpath[512], cmd[2048];
    snprintf(img, sizeof img, "%s/stdout_full.pfm", RTGI_TEST_TMP);
    snprintf(errpath, sizeof errpath, "%s/stdout_full.txt", RTGI_TEST_TMP);
    char *err = NULL;
    assert_int_equal(test_run_cli(&err, "render", "--size", "8x8", "--out", img, "--quiet", NULL), 0);
    free(err);
    snprintf(cmd, sizeof cmd, "'%s' compare '%s' '%s' > /dev/full 2> '%s'", RTGI_BINARY, img, img, errpath);
    int status = system(cmd);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 1);
    char *text = util_read_file(errpath, NULL);
    assert_non_null(text);
    assert_non_null(strstr(text, "standard output: write failed (No space left on device)"));
    free(text);
}

/* Every technique and shadow filter, and a scene with an alpha-masked
 * material (its own depth pre-pass and shadow programs), rendered with a
 * GL debug context (--debug): the driver reports no error. Each technique
 * renders one of the two scenes, in turn (both scenes for every technique
 * had taken 16 s of make test). A program that
 * was given a uniform it does not declare (the depth pre-pass had been
 * given the material's and the eye's on every draw) is an error there
 * (GL_INVALID_OPERATION), logged as "[gl] debug message". */
static void debug_context_reports_no_gl_errors(void **state)
{
    (void)state;
#ifdef __SANITIZE_ADDRESS__
    /* A driver check, not a memory one: make test runs it; under make
     * test-asan every technique's C code runs in test_lifetime (its
     * renders had been a sixth of CI's ASan time). */
    print_message("skipped under AddressSanitizer: the GL debug output is make test's check\n");
    skip();
#endif
    test_masked_leaf_obj("debug_masked");
    const char *masked = test_tmp_file(
        "debug_masked.json",
        "{\"mesh\": \"debug_masked.obj\", \"camera\": {\"position\": [0, 4, 2], \"target\": [0, 0, 0]},"
        " \"lights\": [{\"type\": \"spot\", \"position\": [0.5, 3, 0.5], \"direction\": [0, -1, 0],"
        " \"intensity\": [5, 5, 5], \"inner_deg\": 40, \"outer_deg\": 50, \"diameter\": 0.1}]}");
    char out[512];
    snprintf(out, sizeof out, "%s/debug_context.png", RTGI_TEST_TMP);
    const char *shadows[] = {"none", "hard", "pcf", "pcss"};
    const char *const *gi = gi_technique_names();
    for (int i = 0; i < gi_technique_count(); i++) {
        /* the scenes in turn, and the filters so that every (scene, filter)
         * pair comes up within eight techniques */
        const char *scene = i % 2 ? masked : "cornell", *shadow = shadows[(i + i / 4) % 4];
        char *err = NULL;
        int rc = test_run_cli(&err, "render", "--scene", scene, "--gi", gi[i], "--shadow", shadow, "--size", "32x32",
                              "--rsm-size", "64", "--vpls", "256", "--frames", "1", "--out", out, "--debug", NULL);
        print_message("%s, %s, --shadow %s: exit %d\n", scene, gi[i], shadow, rc);
        if (rc != 0 || strstr(err ? err : "", "[gl]"))
            fail_msg("render --gi %s --scene %s --debug: exit %d: %s", gi[i], scene, rc, err ? err : "");
        free(err);
    }
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(missing_scene_file),
        cmocka_unit_test(malformed_json_names_line),
        cmocka_unit_test(wrong_json_types),
        cmocka_unit_test(missing_mesh_file),
        cmocka_unit_test(malformed_mesh_file),
        cmocka_unit_test(unknown_option_and_technique),
        cmocka_unit_test(zero_or_huge_size),
        cmocka_unit_test(default_png_red_left_green_right),
        cmocka_unit_test(unsupported_gl_version),
        cmocka_unit_test(shader_error_names_file_and_line),
        cmocka_unit_test(every_program_failure_fails),
        cmocka_unit_test(png_beside_pfm),
        cmocka_unit_test(failed_output_leaves_none),
        cmocka_unit_test(output_allocation_failures),
        cmocka_unit_test(timings_make_failures),
        cmocka_unit_test(view_matches_headless_render),
        cmocka_unit_test(compare_json_and_mask),
        cmocka_unit_test(compare_unshadowed),
        cmocka_unit_test(reference_bad_input),
        cmocka_unit_test(compare_bad_input),
        cmocka_unit_test(cli_conventions),
        cmocka_unit_test(render_estimate_line),
        cmocka_unit_test(quiet_and_verbose_everywhere),
        cmocka_unit_test(one_error_hint_style),
        cmocka_unit_test(double_dash_ends_options),
        cmocka_unit_test(large_mesh_says_each_step),
        cmocka_unit_test(help_names_exr),
        cmocka_unit_test(reference_progress_lines),
        cmocka_unit_test(reference_stops_on_budget),
        cmocka_unit_test(render_frame_progress_lines),
        cmocka_unit_test(shared_defaults),
        cmocka_unit_test(debug_context_reports_no_gl_errors),
        cmocka_unit_test(failed_stdout_fails_the_command),
        cmocka_unit_test(long_output_paths),
        cmocka_unit_test(output_symlinks_are_followed),
    };
    return test_run_group_part("cli", tests, sizeof tests / sizeof tests[0], argc, argv);
}
