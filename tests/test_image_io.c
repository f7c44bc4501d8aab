/* test_image_io.c — EXR in and out (round trips, bad files, no partial
 * output) and the reference's Ctrl-C: a SIGINT to a running `rtgi
 * reference` writes the partial image with the samples reached, identical
 * to a render asked for that many samples. */
#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <openexr.h>

#include "test_util.h"
#include "base/util.h"

static const char *tmp(const char *name)
{
    static char path[4][512];
    static int k;
    k = (k + 1) % 4;
    snprintf(path[k], sizeof path[k], "%s/imageio_%s", RTGI_TEST_TMP, name);
    return path[k];
}

static bool exists(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0;
}

/* A 37×23 image with values over many octaves, negative and tiny ones. */
static void make_image(ImageF *img)
{
    assert_true(image_alloc(img, 37, 23));
    for (int i = 0; i < 37 * 23 * 3; i++)
        img->rgb[i] = (float)(pow(2.0, (i % 35) - 20) * ((i % 7) == 3 ? -1.0 : 1.0) * (1.0 + (i % 13) / 13.0));
}

static void exr_float_round_trip_is_exact(void **state)
{
    (void)state;
    ImageF a, b = {0};
    make_image(&a);
    const char *p = tmp("float.exr");
    ImageAttr attr = {"rtgi_spp", 123};
    assert_true(image_write_exr(p, &a, false, &attr, 1));
    assert_true(image_read(p, &b));
    assert_int_equal(b.width, 37);
    assert_int_equal(b.height, 23);
    assert_memory_equal(a.rgb, b.rgb, sizeof(float) * 37 * 23 * 3);
    int spp = 0;
    assert_true(image_read_exr_attr(p, "rtgi_spp", &spp));
    assert_int_equal(spp, 123);
    assert_false(image_read_exr_attr(p, "no_such_attr", &spp));
    /* image_write by extension writes float32 too. */
    const char *q = tmp("float2.exr");
    image_free(&b);
    assert_true(image_write(q, &a, 1.f, false));
    assert_true(image_read(q, &b));
    assert_memory_equal(a.rgb, b.rgb, sizeof(float) * 37 * 23 * 3);
    image_free(&a);
    image_free(&b);
}

/* `h` is `f` rounded to half floats: within half a unit of the 10-bit
 * mantissa (relative 2^-11; subnormals: absolute 2^-24), and not exact
 * everywhere (it really is half). Returns the worst relative error. */
static double expect_half_of(const ImageF *f, const ImageF *h)
{
    assert_int_equal(h->width, f->width);
    assert_int_equal(h->height, f->height);
    double worst = 0;
    for (size_t i = 0; i < (size_t)f->width * f->height * 3; i++) {
        float v = f->rgb[i];
        if (fabsf(v) < 6.2e-5f) /* subnormal halves: absolute step 2^-24 */
            assert_true(fabsf(h->rgb[i] - v) <= 0x1p-24f);
        else
            worst = fmax(worst, fabs((double)h->rgb[i] - v) / fabs(v));
    }
    assert_true(worst <= 0x1p-11); /* round to nearest, 10-bit mantissa */
    assert_true(worst > 0);
    return worst;
}

static void exr_half_round_trip_within_half_precision(void **state)
{
    (void)state;
    ImageF a, b = {0};
    make_image(&a);
    const char *p = tmp("half.exr");
    assert_true(image_write_exr(p, &a, true, NULL, 0));
    assert_true(image_read_exr(p, &b));
    expect_half_of(&a, &b);
    struct stat sf, sh;
    assert_int_equal(stat(tmp("float.exr"), &sf), 0);
    assert_int_equal(stat(p, &sh), 0);
    /* A value beyond half's range is refused; nothing is left behind. */
    const char *q = tmp("overflow.exr");
    remove(q);
    a.rgb[5] = 1e6f;
    assert_false(image_write_exr(q, &a, true, NULL, 0));
    assert_false(exists(q));
    /* So are NaNs, in float too. */
    a.rgb[5] = NAN;
    assert_false(image_write_exr(q, &a, false, NULL, 0));
    assert_false(exists(q));
    image_free(&a);
    image_free(&b);
}

static void bad_and_truncated_exr_are_errors(void **state)
{
    (void)state;
    ImageF a, b = {0};
    make_image(&a);
    const char *good = tmp("good.exr");
    assert_true(image_write_exr(good, &a, false, NULL, 0));
    size_t size = 0;
    char *data = util_read_file(good, &size);
    assert_non_null(data);
    /* Truncated at several points: header, offset table, pixel data. */
    size_t cuts[] = {3, 20, 200, size / 2, size - 1};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; k++) {
        const char *p = tmp("cut.exr");
        FILE *f = fopen(p, "wb");
        assert_non_null(f);
        fwrite(data, 1, cuts[k], f);
        fclose(f);
        assert_false(image_read(p, &b));
        assert_null(b.rgb);
    }
    /* Not an EXR at all, and an empty file. */
    assert_false(image_read(test_tmp_file("imageio_text.exr", "hello, this is not an EXR file\n"), &b));
    assert_false(image_read(test_tmp_file("imageio_empty.exr", ""), &b));
    /* Garbage in the pixel data (after the header): error or finite values, never a crash. */
    const char *p = tmp("garbage.exr");
    for (size_t i = size / 2; i < size; i++)
        data[i] = (char)(i * 37);
    FILE *f = fopen(p, "wb");
    fwrite(data, 1, size, f);
    fclose(f);
    if (image_read(p, &b))
        image_free(&b);
    free(data);
    /* Through the CLI: one line naming the file, exit 1. */
    char *err = NULL;
    int rc = test_run_cli(&err, "compare", tmp("cut.exr"), good, NULL);
    test_expect_cli_error(rc, err, 1, "cut.exr", "EXR");
    image_free(&a);
}

/* An EXR as other tools write them: w×h float scanlines, n channels named
 * names[c], channel c's pixel (x, y) = c + 0.01·(x + w·y). */
static void write_channels(const char *path, int w, int h, const char *const *names, int n)
{
    float *data = malloc(sizeof(float) * (size_t)(w * h * n));
    assert_non_null(data);
    for (int c = 0; c < n; c++)
        for (int i = 0; i < w * h; i++)
            data[c * w * h + i] = (float)c + 0.01f * (float)i;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_context_t f = NULL;
    int part = 0;
    assert_int_equal(exr_start_write(&f, path, EXR_WRITE_FILE_DIRECTLY, &init), EXR_ERR_SUCCESS);
    assert_int_equal(exr_add_part(f, "layers", EXR_STORAGE_SCANLINE, &part), EXR_ERR_SUCCESS);
    assert_int_equal(exr_initialize_required_attr_simple(f, part, w, h, EXR_COMPRESSION_NONE), EXR_ERR_SUCCESS);
    for (int c = 0; c < n; c++)
        assert_int_equal(exr_add_channel(f, part, names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1),
                         EXR_ERR_SUCCESS);
    assert_int_equal(exr_write_header(f), EXR_ERR_SUCCESS);
    int32_t lines = 1;
    assert_int_equal(exr_get_scanlines_per_chunk(f, part, &lines), EXR_ERR_SUCCESS);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    for (int y = 0; y < h; y += lines) {
        exr_chunk_info_t cinfo;
        assert_int_equal(exr_write_scanline_chunk_info(f, part, y, &cinfo), EXR_ERR_SUCCESS);
        assert_int_equal(y ? exr_encoding_update(f, part, &cinfo, &enc) : exr_encoding_initialize(f, part, &cinfo, &enc),
                         EXR_ERR_SUCCESS);
        for (int k = 0; k < enc.channel_count; k++) {
            exr_coding_channel_info_t *ch = &enc.channels[k];
            int c = 0;
            while (strcmp(names[c], ch->channel_name))
                c++;
            ch->encode_from_ptr = (const uint8_t *)(data + c * w * h + cinfo.start_y * w);
            ch->user_pixel_stride = sizeof(float);
            ch->user_line_stride = sizeof(float) * w;
            ch->user_bytes_per_element = sizeof(float);
            ch->user_data_type = EXR_PIXEL_FLOAT;
        }
        if (y == 0)
            assert_int_equal(exr_encoding_choose_default_routines(f, part, &enc), EXR_ERR_SUCCESS);
        assert_int_equal(exr_encoding_run(f, part, &enc), EXR_ERR_SUCCESS);
    }
    exr_encoding_destroy(f, &enc);
    assert_int_equal(exr_finish(&f), EXR_ERR_SUCCESS);
    free(data);
}

/* EXRs from other tools: plain R, G, B; a lone Y; Blender's multilayer
 * files (LAYER.R, .G, .B; of several layers the ...Combined one). Each
 * read channel must land in its place; files whose colour is ambiguous or
 * absent are refused naming the file and the reason, never read grey or
 * from a guessed layer. */
static void exr_channels_of_other_tools(void **state)
{
    (void)state;
    enum { W = 5, H = 3 };
    static const struct {
        const char *names[10];
        int n;
        int r, g, b;           /* the channels (indices in names) read into R, G, B; -1: refused */
        const char *why;       /* the refusal's reason */
    } cases[] = {
        {{"B", "G", "R", "A"}, 4, 2, 1, 0, NULL},
        {{"Y"}, 1, 0, 0, 0, NULL},
        {{"A", "ViewLayer.Combined.A", "ViewLayer.Combined.B", "ViewLayer.Combined.G", "ViewLayer.Combined.R",
          "ViewLayer.Depth.Z"}, 6, 4, 3, 2, NULL},
        {{"L.Diffuse.R", "L.Diffuse.G", "L.Diffuse.B", "L.Combined.R", "L.Combined.G", "L.Combined.B"}, 6, 3, 4, 5,
         NULL},
        {{"R", "G", "B", "L.Combined.R", "L.Combined.G", "L.Combined.B"}, 6, 0, 1, 2, NULL},
        {{"L.Y"}, 1, 0, 0, 0, NULL},
        {{"a.R", "a.G", "a.B", "b.R", "b.G", "b.B"}, 6, -1, -1, -1, "2 layers hold R, G, B (a, b) and none"},
        {{"a.Combined.R", "a.Combined.G", "a.Combined.B", "b.Combined.R", "b.Combined.G", "b.Combined.B"}, 6, -1, -1,
         -1, "more than one is named"},
        {{"Y", "RY", "BY"}, 3, -1, -1, -1, "luminance/chroma"},
        {{"A", "Z", "L.R", "L.G"}, 4, -1, -1, -1, "no R, G, B (or Y) channels"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *p = tmp("channels.exr");
        write_channels(p, W, H, cases[i].names, cases[i].n);
        ImageF img = {0};
        if (cases[i].r < 0) {
            char *err = NULL;
            int rc = test_run_cli(&err, "compare", p, p, NULL);
            print_message("case %zu: %s", i, err ? err : "(no error)\n");
            test_expect_cli_error(rc, err, 1, p, cases[i].why);
            continue;
        }
        assert_true(image_read(p, &img));
        assert_int_equal(img.width, W);
        assert_int_equal(img.height, H);
        const int want[3] = {cases[i].r, cases[i].g, cases[i].b};
        for (int px = 0; px < W * H; px++)
            for (int k = 0; k < 3; k++)
                assert_float_equal(img.rgb[3 * px + k], (float)want[k] + 0.01f * (float)px, 1e-6);
        image_free(&img);
    }
}

/* render --out x.exr and reference --out x.exr are read back by compare. */
static void cli_writes_and_compares_exr(void **state)
{
    (void)state;
    char *err = NULL;
    const char *r = tmp("render.exr"), *ref = tmp("ref.exr"), *rp = tmp("render.pfm");
    assert_int_equal(test_run_cli(&err, "render", "--size", "32x32", "--out", r, NULL), 0);
    free(err);
    assert_int_equal(test_run_cli(&err, "render", "--size", "32x32", "--out", rp, NULL), 0);
    free(err);
    assert_int_equal(test_run_cli(&err, "reference", "--size", "32x32", "--spp", "4", "--quiet", "--out", ref, NULL), 0);
    free(err);
    ImageF a = {0}, b = {0};
    assert_true(image_read(r, &a));
    assert_true(image_read(rp, &b));
    assert_memory_equal(a.rgb, b.rgb, sizeof(float) * 32 * 32 * 3); /* EXR float32 = PFM */
    int spp = 0;
    assert_true(image_read_exr_attr(ref, "rtgi_spp", &spp));
    assert_int_equal(spp, 4);
    assert_int_equal(test_run_cli(&err, "compare", r, ref, NULL), 0);
    free(err);
    image_free(&a);
    image_free(&b);
}

/* Ctrl-C: the running reference finishes its pass and writes what it has. */
static void reference_sigint_writes_partial_image(void **state)
{
    (void)state;
    const char *out = tmp("partial.exr"), *log = tmp("partial_stdout.txt");
    remove(out);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        if (!freopen(log, "w", stdout) || !freopen("/dev/null", "w", stderr))
            _exit(127);
        execl(RTGI_BINARY, RTGI_BINARY, "reference", "--size", "64x64", "--spp", "1000000", "--threads", "2",
              "--out", out, (char *)NULL);
        _exit(127);
    }
    /* Long enough for the scene and BVH, short of 10^6 spp (hours). */
    nanosleep(&(struct timespec){3, 0}, NULL);
    kill(pid, SIGINT);
    int status = 0;
    waitpid(pid, &status, 0);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
    int spp = 0;
    assert_true(image_read_exr_attr(out, "rtgi_spp", &spp));
    print_message("interrupted at %d spp\n", spp);
    assert_true(spp >= 1 && spp < 1000000);
    char *text = util_read_file(log, NULL);
    assert_non_null(text);
    char want[64];
    snprintf(want, sizeof want, "spp: %d\n", spp);
    assert_non_null(strstr(text, want));
    assert_non_null(strstr(text, "interrupted:"));
    free(text);
    /* The partial image is the image of that many samples. */
    char spp_s[16];
    snprintf(spp_s, sizeof spp_s, "%d", spp);
    const char *full = tmp("asked.exr");
    char *err = NULL;
    assert_int_equal(test_run_cli(&err, "reference", "--size", "64x64", "--spp", spp_s, "--threads", "2", "--quiet",
                                  "--out", full, NULL), 0);
    free(err);
    ImageF a = {0}, b = {0};
    assert_true(image_read(out, &a));
    assert_true(image_read(full, &b));
    assert_memory_equal(a.rgb, b.rgb, sizeof(float) * 64 * 64 * 3);
    image_free(&a);
    image_free(&b);
}

/* Entries of `dir` whose name holds ".tmp-" (an AtomicFile's temporary). */
static int temporaries_in(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += strstr(e->d_name, ".tmp-") != NULL;
    closedir(d);
    return n;
}

/* A second signal while the reference writes its outputs (a second
 * Ctrl-C, or SIGTERM), sent as soon as the first temporary file appears:
 * the outputs are whole, all three, and no temporary file is left. Before,
 * the writes ran under the default action, and a second SIGINT left the
 * temporaries (2 of 8 runs of a review, with no output or with the PFM and
 * no PNG). */
static void reference_second_signal_leaves_whole_outputs(void **state)
{
    (void)state;
    char dir[600];
    snprintf(dir, sizeof dir, "%s/second_signal", RTGI_TEST_TMP);
    mkdir(dir, 0777);
    const char *names[3] = {"r.pfm", "p.png", "v.pfm"};
    for (int k = 0; k < 2; k++) {
        char paths[3][700];
        for (int i = 0; i < 3; i++) {
            snprintf(paths[i], sizeof paths[i], "%s/%s", dir, names[i]);
            remove(paths[i]);
        }
        pid_t pid = fork();
        assert_true(pid >= 0);
        if (pid == 0) {
            if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr))
                _exit(127);
            execl(RTGI_BINARY, RTGI_BINARY, "reference", "--size", "256x256", "--spp", "1000000", "--threads", "2",
                  "--out", paths[0], "--png", paths[1], "--variance", paths[2], (char *)NULL);
            _exit(127);
        }
        nanosleep(&(struct timespec){2, 0}, NULL);
        kill(pid, SIGINT);
        int status = 0, seen = 0;
        for (int t = 0; t < 300000 && !seen; t++) { /* up to a minute */
            seen = temporaries_in(dir);
            if (!seen && waitpid(pid, &status, WNOHANG) == pid)
                break;
            if (!seen)
                nanosleep(&(struct timespec){0, 200000L}, NULL);
        }
        if (seen) {
            kill(pid, k ? SIGTERM : SIGINT);
            waitpid(pid, &status, 0);
        }
        int present = 0;
        for (int i = 0; i < 3; i++)
            present += access(paths[i], F_OK) == 0;
        int left = temporaries_in(dir);
        print_message("%s during the writes: %d of 3 outputs, %d temporaries left\n", k ? "SIGTERM" : "second SIGINT",
                      present, left);
        assert_true(seen); /* the signal reached the writes */
        assert_int_equal(left, 0);
        assert_int_equal(present, 3);
        ImageF img = {0};
        assert_true(image_read(paths[0], &img));
        assert_true(test_image_mean(&img) > 0.0);
        image_free(&img);
    }
}

/* render --half and view --half (its --out capture) write half-float EXR
 * through the same writer: the float render's radiance within half
 * precision. */
static void render_and_view_write_half_exr(void **state)
{
    (void)state;
    static const char *const commands[] = {"render", "view"};
    for (int c = 0; c < 2; c++) {
        if (c == 1)
            test_x_display();
        const char *f = tmp("frame_float.exr"), *h = tmp("frame_half.exr");
        char *err = NULL;
        int rc = test_run_cli(&err, commands[c], "--size", "32x32", "--frames", "1", "--out", f, "--quiet", NULL);
        if (rc != 0)
            fail_msg("%s --out %s: exit %d: %s", commands[c], f, rc, err ? err : "");
        free(err);
        rc = test_run_cli(&err, commands[c], "--size", "32x32", "--frames", "1", "--out", h, "--half", "--quiet", NULL);
        if (rc != 0)
            fail_msg("%s --out %s --half: exit %d: %s", commands[c], h, rc, err ? err : "");
        free(err);
        ImageF a = {0}, b = {0};
        assert_true(image_read(f, &a));
        assert_true(image_read(h, &b));
        assert_true(test_image_mean(&a) > 0.01);
        print_message("%s --half: worst relative error %.2e (half: <= 4.9e-4)\n", commands[c], expect_half_of(&a, &b));
        image_free(&a);
        image_free(&b);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(exr_float_round_trip_is_exact),
        cmocka_unit_test(exr_half_round_trip_within_half_precision),
        cmocka_unit_test(bad_and_truncated_exr_are_errors),
        cmocka_unit_test(exr_channels_of_other_tools),
        cmocka_unit_test(cli_writes_and_compares_exr),
        cmocka_unit_test(render_and_view_write_half_exr),
        cmocka_unit_test(reference_sigint_writes_partial_image),
        cmocka_unit_test(reference_second_signal_leaves_whole_outputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
