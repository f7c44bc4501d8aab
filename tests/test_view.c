/* test_view.c — `rtgi view`'s panel under a virtual X server (Xvfb,
 * GLX through Mesa llvmpipe): the window test's script (--ui-test) drives
 * the panel's actions and the test checks what it measured and captured
 * against the headless renderer's own images:
 *   - exposure is live: no program linked, nothing in the renderer remade
 *     (while a technique switch does remake: the counter counts);
 *   - a technique estimated over --slow-ms is not entered by the G key's
 *     path until confirmed;
 *   - "copy as scene JSON" loads back as the camera it was copied from;
 *   - hot reload with a broken shader on disk: the error names the file,
 *     the previous program stays and the relinked others draw the same;
 *   - the panel is drawn (the window differs from the render where the
 *     panel is, and only there); captures are valid PNG/PFM;
 *   - the A/B view of --compare shows the reference tone-mapped, the
 *     difference heat map and the split exactly as computed here, and its
 *     RMSE matches metric_rmse;
 *   - P to .exr writes the PFM's radiance within half precision;
 *   - the panel's per-pass timings match `render --timings` pass by pass;
 *   - the live reference (--live-reference) converges in the A/B view and
 *     restarts when the camera moves;
 *   - `view --help` is view's own, render-only options are refused,
 *     `view --out x.pfm` writes a PFM. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io/metrics.h"
#include "test_util.h"
#include "base/util.h"

enum { W = 192, H = 216, MAX_PASSES = 32, PANEL = 360 /* VIEW_PANEL_WIDTH */ };
/* The script's slow frame: the render thread sleeps this long first. */
#define SLOW_S 2.0

static char g_dir[512];

static void path_in(char *out, size_t cap, const char *name) { snprintf(out, cap, "%s/%s", g_dir, name); }

static ImageF read_image(const char *name)
{
    char p[1024];
    path_in(p, sizeof p, name);
    ImageF img;
    if (!image_read(p, &img))
        fail_msg("%s: not a readable image", p);
    return img;
}

/* The value of "ui-test: <key>" lines in `out`, or NULL. */
static const char *find_line(const char *out, const char *key)
{
    const char *p = strstr(out, key);
    return p ? p + strlen(key) : NULL;
}

static float heat(float t, int c)
{
    t = fminf(fmaxf(t, 0.f), 1.f);
    return fminf(fmaxf(3.f * t - (float)c, 0.f), 1.f);
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Pixels of `img` in columns [x0, x1) that are the heat map's red
 * (1, 0, 0) or yellow (1, 1, 0), each counted in red[0] / yellow[0]. */
static void count_heat_colours(const ImageF *img, int x0, int x1, int *red, int *yellow)
{
    *red = *yellow = 0;
    for (int y = 0; y < img->height; y++)
        for (int x = x0; x < x1 && x < img->width; x++) {
            const float *p = image_px(img, x, y);
            float r = srgb_encode(p[0]), g = srgb_encode(p[1]), b = srgb_encode(p[2]);
            *red += r > 0.85f && g < 0.2f && b < 0.2f;
            *yellow += r > 0.85f && g > 0.85f && b < 0.2f;
        }
}

static void panel_script(void **state)
{
    (void)state;
    snprintf(g_dir, sizeof g_dir, "%s/view_ui", RTGI_TEST_TMP);
    util_ensure_parent_dir(g_dir);
    char none_pfm[1024], rsm_pfm[1024], size[32];
    snprintf(size, sizeof size, "%dx%d", W, H);
    path_in(none_pfm, sizeof none_pfm, "ref_none.pfm");
    path_in(rsm_pfm, sizeof rsm_pfm, "ref_rsm.pfm");
    assert_int_equal(test_run_cli(NULL, "render", "--size", size, "--out", none_pfm, "--quiet", NULL), 0);
    assert_int_equal(test_run_cli(NULL, "render", "--size", size, "--gi", "rsm", "--rsm-samples", "32", "--out",
                                  rsm_pfm, "--quiet", NULL),
                     0);

    char cmd[8192], log[1024];
    path_in(log, sizeof log, "view.log");
    /* Shaders from a copy on disk, so that the script's hot reload can meet
     * a broken one (it appends an #error to finish.comp, FXAA's tone map, before reloading). */
    test_x_display();
    snprintf(cmd, sizeof cmd,
             "rm -rf '%s/shaders' && cp -r '%s/shaders' '%s/shaders' && "
             "RTGI_UI_TEST_BREAK_SHADER='%s/shaders/frame/finish.comp' RTGI_UI_TEST_SLOW_S=%g "
             "'%s' view --size %s --rsm-samples 32 --exposure 1 --slow-ms 1 --compare '%s' "
             "--shader-dir '%s/shaders' --ui-test '%s' 2>'%s'",
             g_dir, RTGI_SOURCE_DIR, g_dir, g_dir, SLOW_S, RTGI_BINARY, size, none_pfm, g_dir, g_dir, log);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    char out[8192];
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = 0;
    int rc = pclose(p);
    if (rc != 0) {
        char *err = util_read_file(log, NULL);
        fail_msg("rtgi view --ui-test failed (%d): %s", rc, err ? err : "");
    }
    print_message("%s", out);

    /* Exposure: live. A technique switch: remade (the counter counts). */
    int links = -1, remakes = -1;
    const char *v = find_line(out, "ui-test: exposure x2: ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "program links +%d, renderer remakes +%d", &links, &remakes), 2);
    assert_int_equal(links, 0);
    assert_int_equal(remakes, 0);
    v = find_line(out, "ui-test: technique switch: renderer remakes +");
    assert_non_null(v);
    assert_true(atoi(v) >= 1);
    /* Slow techniques wait for their click, from the G key too; after
     * "Switch anyway" the confirm text is gone from the status line (it had
     * stayed: "rsm: about 0.1 s per frame at 192x144; confirm in the panel
     * to switch"). */
    assert_non_null(strstr(out, "ui-test: G: gi none, pending rsm,"));
    v = find_line(out, "ui-test: confirmed: gi rsm, pending none, status '");
    assert_non_null(v);
    const char *eol = strchr(v, '\n');
    assert_non_null(eol);
    const char *confirm = strstr(v, "confirm");
    assert_true(!confirm || confirm > eol);

    /* "Copy as scene JSON" is a scene file's camera: loaded back, it is the
     * camera the window started from (the scene's). */
    v = find_line(out, "ui-test: camera {");
    assert_non_null(v);
    char scene_json[512];
    int len = (int)(strchr(v, '\n') - v) - 1; /* without the closing brace */
    snprintf(scene_json, sizeof scene_json, "{\"builtin\": \"cornell\", %.*s}\n", len, v);
    Scene copied, cornell;
    assert_true(scene_load(&copied, test_tmp_file("camera_copy.json", scene_json)));
    assert_true(scene_load(&cornell, "cornell"));
    for (int i = 0; i < 3; i++) {
        assert_float_equal(copied.camera.position[i], cornell.camera.position[i], 1e-3);
        assert_float_equal(copied.camera.forward[i], cornell.camera.forward[i], 1e-3);
    }
    assert_float_equal(copied.camera.fov_y, cornell.camera.fov_y, 1e-3);
    scene_free(&copied);
    scene_free(&cornell);

    /* Hot reload: the broken shader's error names its file, its previous
     * program stays, and every other program, relinked, draws the same. */
    v = find_line(out, "ui-test: reload: ");
    assert_non_null(v);
    assert_true(!strncmp(v, "failed: ", 8));
    eol = strchr(v, '\n');
    const char *named = strstr(v, "finish.comp");
    assert_true(named && (!eol || named < eol));
    ImageF before = read_image("before_reload.png"), after = read_image("after_reload.png");
    assert_int_equal(before.width, W);
    assert_int_equal(after.width, W);
    double reload_diff = 0;
    for (int i = 0; i < W * H * 3; i++)
        reload_diff = fmax(reload_diff, fabsf(before.rgb[i] - after.rgb[i]));
    print_message("reload: max |after - before| %.4f\n", reload_diff);
    assert_true(reload_diff <= 1e-6);
    assert_true(test_image_mean(&after) > 0.05);
    image_free(&before);
    image_free(&after);

    /* The panel is docked beside the image: the window is the image and the
     * panel (it had covered the left half of the image); H hides it, the
     * window shrinks and the image keeps its size, and it comes back. */
    int ww = 0, wh = 0, iw = 0, ih = 0;
    v = find_line(out, "ui-test: window ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "%dx%d without the panel, image %dx%d", &ww, &wh, &iw, &ih), 4);
    assert_true(ww == W && wh == H && iw == W && ih == H);
    v = find_line(v, "ui-test: window ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "%dx%d with the panel again, image %dx%d", &ww, &wh, &iw, &ih), 4);
    assert_true(ww == W + PANEL && wh == H && iw == W && ih == H);
    /* A resize by the user: the image takes the window less the panel. */
    v = find_line(out, "ui-test: user resize to ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "%dx%d: image %dx%d", &ww, &wh, &iw, &ih), 4);
    assert_true(ww == W + PANEL + 32 && wh == H + 16 && iw == W + 32 && ih == H + 16);
    ImageF panel = read_image("window_panel.png"), bare = read_image("window_nopanel.png");
    ImageF shot = read_image("shot.png"), shot_hdr = read_image("shot.pfm");
    assert_int_equal(panel.width, W + PANEL);
    assert_int_equal(panel.height, H);
    assert_int_equal(bare.width, W);
    assert_int_equal(bare.height, H);
    assert_int_equal(shot_hdr.width, W);
    assert_int_equal(shot_hdr.height, H);
    /* The image in the window is `render`'s image at the same size and
     * exposure (2: the script doubled 1), nothing over it. */
    char render_png[1024];
    path_in(render_png, sizeof render_png, "render_fxaa.png");
    assert_int_equal(test_run_cli(NULL, "render", "--size", size, "--exposure", "2", "--aa", "fxaa", "--out",
                                  render_png, "--quiet", NULL),
                     0);
    ImageF rendered;
    assert_true(image_read(render_png, &rendered));
    double in_panel = 0, vs_render = 0, vs_bare = 0, vs_shot = 0, vs_hdr = 0;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++) {
                float w = image_px(&panel, x, y)[c];
                vs_render = fmax(vs_render, fabsf(w - image_px(&rendered, x, y)[c]));
                vs_bare = fmax(vs_bare, fabsf(w - image_px(&bare, x, y)[c]));
                vs_shot = fmax(vs_shot, fabsf(image_px(&shot, x, y)[c] - image_px(&bare, x, y)[c]));
                vs_hdr += fabsf(srgb_encode(fminf(image_px(&shot_hdr, x, y)[c] * 2.f, 1.f)) -
                                srgb_encode(image_px(&shot, x, y)[c]));
            }
        for (int x = W; x < W + PANEL; x++)
            for (int c = 0; c < 3; c++)
                in_panel += image_px(&panel, x, y)[c];
    }
    in_panel /= 3.0 * PANEL * H;
    vs_hdr /= 3.0 * W * H;
    print_message("window %dx%d: image area vs render max %.4f, vs the window without the panel max %.4f; panel "
                  "mean %.3f; P shot vs window max %.4f; PNG vs PFM x exposure mean %.4f\n",
                  panel.width, panel.height, vs_render, vs_bare, in_panel, vs_shot, vs_hdr);
    assert_true(vs_render <= 2.0 / 255);
    assert_true(vs_bare <= 1e-6);
    assert_true(in_panel > 0.02); /* the panel is drawn beside it */
    assert_true(vs_shot <= 1e-6);
    assert_true(vs_hdr < 0.01); /* FXAA only, on edges */
    assert_int_equal(image_count_nonfinite(&shot_hdr, NULL, NULL), 0);
    image_free(&rendered);

    /* P to .exr: the same radiance as the PFM within half precision, and,
     * before FXAA's edges, as the headless render of the same frame. */
    ImageF shot_exr = read_image("shot.exr"), headless;
    assert_int_equal(shot_exr.width, W);
    assert_int_equal(shot_exr.height, H);
    char plain_pfm[1024];
    path_in(plain_pfm, sizeof plain_pfm, "ref_noaa.pfm");
    assert_int_equal(test_run_cli(NULL, "render", "--size", size, "--out", plain_pfm, "--quiet", NULL), 0);
    assert_true(image_read(plain_pfm, &headless));
    double exr_vs_pfm = 0, exr_vs_render = 0, pfm_max = 0;
    for (int i = 0; i < W * H * 3; i++) {
        float e = shot_exr.rgb[i], f = shot_hdr.rgb[i];
        exr_vs_pfm = fmax(exr_vs_pfm, fabsf(e - f) / fmaxf(fabsf(f), 1e-4f));
        exr_vs_render += fabsf(e - headless.rgb[i]);
        pfm_max = fmax(pfm_max, f);
    }
    exr_vs_render /= 3.0 * W * H;
    print_message("EXR shot: max relative |exr - pfm| %.2e (half: 4.9e-4); mean |exr - headless render| %.4f "
                  "(peak %.2f)\n",
                  exr_vs_pfm, exr_vs_render, pfm_max);
    assert_true(pfm_max > 0.1);
    assert_true(exr_vs_pfm <= 1e-3);
    assert_true(exr_vs_render < 0.01 * test_image_mean(&headless) + 1e-4); /* FXAA only, on edges */
    image_free(&shot_exr);
    image_free(&headless);

    /* A/B: the reference alone, tone-mapped at the window's exposure (2);
     * the difference at its automatic scale (the 99th percentile of the
     * difference, computed here from the two radiance images) and at a
     * chosen one; the split. */
    ImageF none, rsm;
    assert_true(image_read(none_pfm, &none) && image_read(rsm_pfm, &rsm));
    float *m = malloc(sizeof(float) * W * H);
    assert_non_null(m);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const float *a = image_px(&rsm, x, y), *b = image_px(&none, x, y);
            float d = 0;
            for (int c = 0; c < 3; c++)
                d = fmaxf(d, fabsf(a[c] - b[c]) * 2.f);
            m[y * W + x] = d;
        }
    float *sorted = malloc(sizeof(float) * W * H);
    assert_non_null(sorted);
    memcpy(sorted, m, sizeof(float) * W * H);
    qsort(sorted, W * H, sizeof(float), cmp_float);
    double want_scale = sorted[(size_t)(0.99 * (W * H - 1))];
    free(sorted);
    double auto_scale = -1;
    char bar[4][32];
    v = find_line(out, "ui-test: heat scale auto ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "%lf (frame %*u), colour bar %31s %31s %31s %31s", &auto_scale, bar[0], bar[1], bar[2],
                            bar[3]),
                     5);
    ImageF ab_ref = read_image("ab_reference.png"), ab_diff = read_image("ab_difference.png");
    ImageF ab_manual = read_image("ab_difference_manual.png"), ab_split = read_image("ab_split.png");
    assert_int_equal(ab_diff.width, W + PANEL); /* with the panel: its colour bar */
    assert_int_equal(ab_manual.width, W);
    double worst_ref = 0, worst_diff = 0, worst_manual = 0, worst_split = 0;
    int hot_auto = 0, hot_default = 0, hot_manual = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float d = m[y * W + x];
            hot_auto += d >= auto_scale;
            hot_default += d >= 0.1f; /* the fixed default scale the view had */
            hot_manual += d >= 0.05f;
            for (int c = 0; c < 3; c++) {
                float want = srgb_encode(fminf(image_px(&none, x, y)[c] * 2.f, 1.f));
                worst_ref = fmax(worst_ref, fabsf(srgb_encode(image_px(&ab_ref, x, y)[c]) - want));
                /* the heat map is written as is (not sRGB-encoded) */
                worst_diff = fmax(worst_diff,
                                  fabsf(srgb_encode(image_px(&ab_diff, x, y)[c]) - heat(d / (float)auto_scale, c)));
                worst_manual = fmax(worst_manual,
                                    fabsf(srgb_encode(image_px(&ab_manual, x, y)[c]) - heat(d / 0.05f, c)));
                if (x > W / 2 + 1)
                    worst_split = fmax(worst_split, fabsf(srgb_encode(image_px(&ab_split, x, y)[c]) - want));
            }
        }
    free(m);
    int bar_red, bar_yellow, none_red, none_yellow;
    count_heat_colours(&ab_diff, W, W + PANEL, &bar_red, &bar_yellow);
    count_heat_colours(&panel, W, W + PANEL, &none_red, &none_yellow);
    const float *line = image_px(&ab_split, W / 2, H / 2);
    print_message("A/B: reference worst %.4f; difference at the auto scale %.5g (the 99th percentile here: %.5g) "
                  "worst %.4f, %.1f%% of pixels at full heat (at the old fixed 0.1: %.1f%%); colour bar %s..%s, "
                  "%d red and %d yellow pixels in the panel (none in difference mode: %d, %d); at 0.05 worst %.4f "
                  "(%.1f%% full); split right half worst %.4f, split line %.2f %.2f %.2f\n",
                  worst_ref, auto_scale, want_scale, worst_diff, 100.0 * hot_auto / (W * H),
                  100.0 * hot_default / (W * H), bar[0], bar[3], bar_red, bar_yellow, none_red, none_yellow,
                  worst_manual, 100.0 * hot_manual / (W * H), worst_split, (double)srgb_encode(line[0]),
                  (double)srgb_encode(line[1]), (double)srgb_encode(line[2]));
    assert_true(worst_ref <= 1.5 / 255);
    assert_true(fabs(auto_scale - want_scale) <= 1e-3 * want_scale);
    assert_true(worst_diff <= 2.5 / 255);
    assert_true(hot_auto <= 0.015 * W * H);    /* about 1% saturate ... */
    assert_true(hot_default >= 0.1 * W * H);   /* ... where the fixed default saturated a tenth or more */
    assert_true(atof(bar[0]) == 0.0 && fabs(atof(bar[3]) - auto_scale) <= 0.01 * auto_scale);
    assert_true(bar_red > 20 && bar_yellow > 20 && none_red == 0 && none_yellow == 0);
    assert_true(worst_manual <= 2.5 / 255);
    assert_true(hot_manual > 0.05 * W * H); /* the two differ: the heat map is not trivially black */
    assert_true(worst_split <= 1.5 / 255);
    assert_true(srgb_encode(line[0]) > 0.95f && srgb_encode(line[2]) < 0.05f);
    double rmse = -1;
    v = find_line(out, "ui-test: rmse ");
    assert_non_null(v);
    rmse = atof(v);
    double want = metric_rmse(&rsm, &none, NULL, NULL);
    print_message("A/B RMSE %.6g, metric_rmse of the headless renders %.6g\n", rmse, want);
    assert_true(want > 0);
    assert_true(fabs(rmse - want) <= 1e-4 * want + 1e-7);

    /* Idle: nothing drawn, neither the scene nor the window. */
    unsigned idle_frames = 99;
    int idle_redraws = 99, idle_passes = 99;
    double idle_s = 0;
    v = find_line(out, "ui-test: idle ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "%lf s: scene frames +%u, window redraws +%d, loop passes +%d", &idle_s, &idle_frames,
                            &idle_redraws, &idle_passes),
                     4);
    assert_true(idle_s >= 0.9);
    assert_int_equal(idle_frames, 0);
    assert_int_equal(idle_redraws, 0);
    assert_true(idle_passes <= 3); /* the script's own wake-up, not a loop that spins */

    /* A slow frame (the render thread sleeps SLOW_S first): the window
     * keeps drawing (its busy indicator ticks at 10 per second; a window
     * that waits for the frame draws none), and + pressed while it is in
     * flight is the next frame's exposure, with no frame between. */
    int slow_redraws = -1;
    double gap = 0, key_s = 0, e1 = 0, e2 = 0, drawn = 0;
    unsigned slow_frames = 0;
    char busy[64] = "";
    v = find_line(out, "ui-test: slow frame: ");
    assert_non_null(v);
    assert_int_equal(sscanf(v,
                            "window redraws %d during it (largest gap %lf s), busy '%63[^']'; key at %lf s into it: "
                            "exposure %lf then %lf, scene frames +%u, the last drawn at %lf",
                            &slow_redraws, &gap, busy, &key_s, &e1, &e2, &slow_frames, &drawn),
                     8);
    assert_true(slow_redraws >= 5);
    assert_true(key_s > 0 && key_s < SLOW_S);
    assert_non_null(strstr(busy, "rendering"));
    assert_true(fabs(e2 - 1.25 * e1) < 1e-3 * e2);
    assert_int_equal(slow_frames, 2);
    assert_true(fabs(drawn - e2) < 1e-4 * e2);
    /* The busy indicator, over the image's top-left corner and nowhere
     * else: the window during the slow frame is the last split view but
     * there. */
    ImageF busy_shot = read_image("window_busy.png");
    assert_int_equal(busy_shot.width, W);
    int differ = 0, differ_outside = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float d = 0;
            for (int c = 0; c < 3; c++)
                d = fmaxf(d, fabsf(image_px(&busy_shot, x, y)[c] - image_px(&ab_split, x, y)[c]));
            bool box = y < 48 && x < W - 8;
            differ += box && d > 0.05f;
            differ_outside += !box && d > 1e-6f;
        }
    print_message("slow frame: %d redraws during it (largest gap %.2f s), indicator '%s' (%d pixels, %d outside "
                  "its corner); key at %.2f s: exposure %.4g, the next frame drew %.4g\n",
                  slow_redraws, gap, busy, differ, differ_outside, key_s, e2, drawn);
    assert_true(differ > 100);
    assert_int_equal(differ_outside, 0);

    ImageF *all[] = {&panel, &bare, &shot, &shot_hdr, &none, &rsm, &ab_ref, &ab_diff, &ab_manual, &ab_split,
                     &busy_shot};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        image_free(all[i]);
}

/* Runs `cmd` (stderr in its output), its output into out; fails the test,
 * with that output, if it exits non-zero. */
static void run_command(const char *cmd, char *out, size_t cap, const char *what)
{
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t n = fread(out, 1, cap - 1, p);
    out[n] = 0;
    if (pclose(p) != 0)
        fail_msg("%s failed: %s", what, out);
}

/* A PNG reference is display-referred: the A/B view shows it as it is (not
 * exposed again), and F5 without --shader-dir reloads from the source tree. */
static void png_reference(void **state)
{
    (void)state;
    char dir[600], ref[700], shot[700], cmd[4096];
    snprintf(dir, sizeof dir, "%s/view_png", RTGI_TEST_TMP);
    snprintf(ref, sizeof ref, "%s/ref.png", dir);
    snprintf(shot, sizeof shot, "%s/ab_reference.png", dir);
    util_ensure_parent_dir(ref);
    assert_int_equal(test_run_cli(NULL, "render", "--size", "64x48", "--exposure", "2", "--out", ref, "--quiet", NULL),
                     0);
    test_x_display();
    snprintf(cmd, sizeof cmd,
             "RTGI_UI_TEST_SLOW_S=0.3 '%s' view --size 64x48 --exposure 1 --compare '%s' --ui-test '%s' 2>&1",
             RTGI_BINARY, ref, dir);
    static char out[16384];
    run_command(cmd, out, sizeof out, "rtgi view --compare ref.png --ui-test");
    assert_non_null(strstr(out, "ui-test: reload: ok"));
    assert_non_null(strstr(out, "ui-test: rmse -1")); /* no RMSE against a display-referred image */
    ImageF want, got;
    assert_true(image_read(ref, &want) && image_read(shot, &got));
    double worst = 0;
    for (int i = 0; i < 64 * 48 * 3; i++)
        worst = fmax(worst, fabsf(srgb_encode(want.rgb[i]) - srgb_encode(got.rgb[i])));
    print_message("PNG reference shown as is: worst %.4f\n", worst);
    assert_true(worst <= 1.5 / 255);
    image_free(&want);
    image_free(&got);
}

/* The "steady_<pass>_ms: X" lines of `render --timings`, into names/ms. */
static int parse_steady(const char *out, char names[][32], double *ms, int cap)
{
    int n = 0;
    for (const char *p = strstr(out, "\nsteady_"); p && n < cap; p = strstr(p + 1, "\nsteady_")) {
        char name[64];
        double v;
        if (sscanf(p + 8, "%63[^:]: %lf", name, &v) != 2 || strlen(name) < 4 ||
            strcmp(name + strlen(name) - 3, "_ms") || !strcmp(name, "total_ms"))
            continue;
        name[strlen(name) - 3] = 0;
        snprintf(names[n], 32, "%s", name);
        ms[n++] = v;
    }
    return n;
}

/* One measurement: `render --timings` then the window's table. Pass names
 * must match (a failure); returns how many passes' times are out of bounds. */
static int timings_attempt(const char *dir, const char *size)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "'%s' render --gi rsm-interp --size %s --aa fxaa --timings --out '%s/render.pfm' 2>&1",
             RTGI_BINARY, size, dir);
    static char out[65536];
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = 0;
    if (pclose(p) != 0)
        fail_msg("%s failed: %s", cmd, out);
    char names[MAX_PASSES][32];
    double ms[MAX_PASSES];
    int count = parse_steady(out, names, ms, MAX_PASSES);
    assert_true(count >= 5);

    test_x_display();
    snprintf(cmd, sizeof cmd, "'%s' view --gi rsm-interp --size %s --frames 3 --ui-test '%s' 2>&1",
             RTGI_BINARY, size, dir);
    p = popen(cmd, "r");
    assert_non_null(p);
    n = fread(out, 1, sizeof out - 1, p);
    out[n] = 0;
    if (pclose(p) != 0)
        fail_msg("%s failed: %s", cmd, out);
    const char *t = find_line(out, "ui-test: timings gi rsm-interp, ");
    assert_non_null(t);
    const char *eol = strchr(t, '\n');
    assert_non_null(eol);
    print_message("window: %.*s\n", (int)(eol - t), t);
    int seen = 0, bad = 0;
    for (const char *q = strchr(t, ' '); q && q < eol; q = strchr(q + 1, ' ')) {
        char name[64];
        double w;
        if (sscanf(q + 1, "%63[^= ]=%lf", name, &w) != 2)
            continue;
        int k = -1;
        for (int i = 0; i < count; i++)
            if (!strcmp(names[i], name))
                k = i;
        if (k < 0)
            fail_msg("the window's pass '%s' is not among render --timings' steady passes", name);
        seen++;
        bool ok = w <= 8.0 * ms[k] + 0.25 && w >= ms[k] / 8.0 - 0.25;
        bad += !ok;
        print_message("  %-24s window %9.3f ms, render %9.3f ms%s\n", name, w, ms[k], ok ? "" : "  <- out of bounds");
    }
    assert_int_equal(seen, count); /* every pass of render's frame, and no other */
    return bad;
}

/* The panel's per-pass table against `render --timings` of the same frame:
 * the same passes, and none credited with another's time (on llvmpipe,
 * unfenced timestamps put rsm-interp's compute passes in the wrong rows:
 * 1806 ms for rsm_interp against 19 ms headless; 0.06 ms against 3.8 ms
 * here). Wall times on a shared machine are noisy (a descheduled process
 * stretches a 0.4 ms pass tenfold): each pass within a factor 8, plus
 * 0.25 ms, measured again (up to twice) while any is out of bounds. */
static void timings_match_render(void **state)
{
    (void)state;
    char dir[600], size[32], parent[700];
    snprintf(dir, sizeof dir, "%s/view_timings", RTGI_TEST_TMP);
    snprintf(size, sizeof size, "%dx%d", W, H);
    snprintf(parent, sizeof parent, "%s/x", dir);
    util_ensure_parent_dir(parent);
    int bad = timings_attempt(dir, size);
    for (int again = 0; bad > 0 && again < 2; again++) {
        print_message("%d pass(es) out of bounds; measuring again\n", bad);
        bad = timings_attempt(dir, size);
    }
    assert_int_equal(bad, 0);
}

static void help_and_options(void **state)
{
    (void)state;
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "'%s' view --help", RTGI_BINARY);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    static char out[65536];
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = 0;
    assert_int_equal(pclose(p), 0);
    assert_non_null(strstr(out, "usage: rtgi view"));
    assert_non_null(strstr(out, "--compare FILE"));
    assert_non_null(strstr(out, "F5"));
    assert_non_null(strstr(out, "--rsm-samples")); /* the settings table */
    assert_null(strstr(out, "--warmup"));
    assert_null(strstr(out, "--png"));
    assert_null(strstr(out, "--timings"));
    assert_null(strstr(out, "default: 3"));
    char *err = NULL;
    int rc = test_run_cli(&err, "view", "--png", "x.png", NULL);
    test_expect_cli_error(rc, err, 2, "--png", "rtgi render");
    rc = test_run_cli(&err, "view", "--warmup=2", NULL);
    test_expect_cli_error(rc, err, 2, "--warmup", "rtgi render");
    rc = test_run_cli(&err, "view", "--slow-ms", "-1", NULL);
    test_expect_cli_error(rc, err, 2, "--slow-ms", "out of range");
    rc = test_run_cli(&err, "view", "--compare", NULL);
    test_expect_cli_error(rc, err, 2, "--compare", "needs a value");
}

/* --frames N --window-out FILE: the capture is an output of the command, so
 * a capture that cannot be written fails it (exit 1, the write's one error
 * line, no file), where it had exited 0. Files may not grow here (ulimit -f
 * 0, SIGXFSZ ignored), which fails the write even for root. */
static void window_out_failure_fails(void **state)
{
    (void)state;
    test_x_display();
    char png[1024], cmd[8192];
    snprintf(png, sizeof png, "%s/view_window_fsize.png", RTGI_TEST_TMP);
    remove(png);
    snprintf(cmd, sizeof cmd,
             "trap '' XFSZ; ulimit -f 0; '%s' view --size 32x32 --frames 1 --window-out '%s' 2>&1; echo \"exit $?\"",
             RTGI_BINARY, png);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    static char out[8192];
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = 0;
    pclose(p);
    print_message("%s", out);
    assert_non_null(strstr(out, "exit 1\n"));
    assert_non_null(strstr(out, "write failed"));
    assert_non_null(strstr(out, png));
    int lines = 0;
    for (const char *c = out; *c; c++)
        lines += *c == '\n';
    assert_int_equal(lines, 2); /* the error and the exit line */
    assert_int_not_equal(access(png, F_OK), 0);
    /* A scripted run writes images, so a program that did not build fails
     * it as it fails render (the specialised direct light's, which falls
     * back to the general one): its one error line, exit 1, neither file. */
    char dir[1024], guarded[1024];
    snprintf(dir, sizeof dir, "%s/view_shaders_guarded", RTGI_TEST_TMP);
    snprintf(guarded, sizeof guarded, "%s/view_guarded.png", RTGI_TEST_TMP);
    remove(guarded);
    snprintf(cmd, sizeof cmd,
             "rm -rf '%s' && cp -r '%s/shaders' '%s' && printf '\\n#ifdef LIGHT_FIXED_TYPE\\n#error broken by the test\\n#endif\\n' >> "
             "'%s/frame/shade.comp'",
             dir, RTGI_SOURCE_DIR, dir, dir);
    assert_int_equal(system(cmd), 0);
    char *err = NULL;
    int rc = test_run_cli(&err, "view", "--size", "32x32", "--frames", "1", "--shader-dir", dir, "--out", guarded,
                          "--window-out", png, NULL);
    test_expect_cli_error(rc, err, 1, "(program shade)", "broken by the test"); /* Mesa: "#error …", NVIDIA: "error C0000: …" */
    assert_int_not_equal(access(guarded, F_OK), 0);
    assert_int_not_equal(access(png, F_OK), 0);
}

/* Dear ImGui uses its allocations unchecked, so the window's allocator
 * ends the command with one line when one fails (RTGI_FAIL_UI_ALLOC=k
 * refuses the k-th): every seventh k from the context's creation through
 * the first frames' font atlas and draw lists (steps of 3 took a minute of
 * CI for the same paths) gives exit 1, that line and no
 * output, never a crash; past the last one the run is whole. */
static void ui_allocation_failure_ends_cleanly(void **state)
{
    (void)state;
    test_x_display();
    char out[1024];
    snprintf(out, sizeof out, "%s/view_ui_alloc.pfm", RTGI_TEST_TMP);
    int k = 1, failed = 0;
    for (;; k += 7) {
        char num[16];
        snprintf(num, sizeof num, "%d", k);
        setenv("RTGI_FAIL_UI_ALLOC", num, 1);
        remove(out);
        char *err = NULL;
        int rc = test_run_cli(&err, "view", "--size", "32x32", "--frames", "2", "--out", out, NULL);
        unsetenv("RTGI_FAIL_UI_ALLOC");
        if (rc == 0) {
            free(err);
            break;
        }
        test_expect_cli_error(rc, err, 1, "[ui] out of memory", "Dear ImGui");
        assert_int_not_equal(access(out, F_OK), 0);
        failed++;
        assert_true(k < 3000);
    }
    print_message("UI allocations 1 to %d failed in steps of 7: %d runs, each one line and exit 1\n", k - 7, failed);
    assert_true(failed >= 10); /* the context and at least one frame's allocations */
    assert_int_equal(access(out, F_OK), 0);
}

/* The window's GPU objects are made on the render thread (the renderer,
 * the presentation slots) and on the window's (the reference texture):
 * each make refused (RTGI_FAIL_GL_MAKE=k; every eighth, then the last
 * four, the presentation slots' of the two frames) ends the command with
 * the refusal's one line, exit 1 and no output file, never a hang or a
 * crash; past the last one the run is whole. */
static int gl_make_refused_run(int k, const char *ref, const char *out, char **err)
{
    char num[16];
    snprintf(num, sizeof num, "%d", k);
    setenv("RTGI_FAIL_GL_MAKE", num, 1);
    remove(out);
    int rc = test_run_cli(err, "view", "--size", "16x16", "--frames", "2", "--compare", ref, "--out", out, "--quiet",
                          NULL);
    unsetenv("RTGI_FAIL_GL_MAKE");
    if (rc == 0)
        assert_int_equal(access(out, F_OK), 0);
    else
        assert_int_not_equal(access(out, F_OK), 0);
    return rc;
}

static void gl_make_failures_end_cleanly(void **state)
{
    (void)state;
    test_x_display();
    char out[1024], ref[1024];
    snprintf(out, sizeof out, "%s/view_gl_make.pfm", RTGI_TEST_TMP);
    snprintf(ref, sizeof ref, "%s/view_gl_make_ref.pfm", RTGI_TEST_TMP);
    assert_int_equal(test_run_cli(NULL, "render", "--size", "16x16", "--out", ref, "--quiet", NULL), 0);
    int k = 1, failed = 0;
    for (;; k += 8) {
        char *err = NULL;
        int rc = gl_make_refused_run(k, ref, out, &err);
        if (rc == 0) {
            free(err);
            break;
        }
        test_expect_cli_error(rc, err, 1, "refused (fault injection)", NULL);
        failed++;
        assert_true(k < 400);
    }
    int whole = k, slots = 0;
    for (k = whole - 1; k > whole - 13 && slots < 4; k--) { /* down to the last makes: the slots' */
        char *err = NULL;
        int rc = gl_make_refused_run(k, ref, out, &err);
        if (rc == 0) {
            free(err);
            continue;
        }
        test_expect_cli_error(rc, err, 1, "refused (fault injection)", "view.present_");
        slots++;
    }
    print_message("GPU makes refused at every eighth up to %d (%d runs) and the last %d, the presentation slots': "
                  "each one line and exit 1\n",
                  whole, failed, slots);
    assert_true(failed >= 3);
    assert_int_equal(slots, 4);
}

/* --out x.pfm: linear radiance, not PNG bytes; a bad --compare file is one
 * clear error. */
static void out_by_extension(void **state)
{
    (void)state;
    char pfm[1024];
    snprintf(pfm, sizeof pfm, "%s/view_out.pfm", RTGI_TEST_TMP);
    remove(pfm);
    char *err = NULL;
    test_x_display();
    int rc = test_run_cli(&err, "view", "--size", "32x32", "--shadow", "hard",
                          "--frames", "1", "--out", pfm, NULL);
    if (rc != 0)
        fail_msg("rtgi view --out x.pfm failed (%d): %s", rc, err ? err : "");
    free(err);
    ImageF img;
    assert_true(image_read_pfm(pfm, &img));
    assert_int_equal(img.width, 32);
    assert_int_equal(img.height, 32);
    assert_int_equal(image_count_nonfinite(&img, NULL, NULL), 0);
    assert_true(test_image_mean(&img) > 0.01);
    image_free(&img);
    rc = test_run_cli(&err, "view", "--size", "32x32", "--frames", "1", "--compare",
                      "/nonexistent/ref.pfm", NULL);
    assert_int_equal(rc, 1);
    assert_non_null(err);
    assert_non_null(strstr(err, "/nonexistent/ref.pfm"));
    free(err);
    /* A reference with a NaN pixel is refused, as compare refuses it (it
     * had been shown, and had made the panel's RMSE nan). */
    char nan_ref[1024];
    snprintf(nan_ref, sizeof nan_ref, "%s/view_nan_ref.pfm", RTGI_TEST_TMP);
    ImageF bad;
    assert_true(image_alloc(&bad, 2, 2));
    memset(bad.rgb, 0, sizeof(float) * 12);
    assert_true(image_write_pfm(nan_ref, &bad));
    FILE *f = fopen(nan_ref, "r+b");
    assert_non_null(f);
    float nan = NAN;
    fseek(f, -4, SEEK_END);
    fwrite(&nan, sizeof nan, 1, f);
    fclose(f);
    image_free(&bad);
    rc = test_run_cli(&err, "view", "--size", "32x32", "--frames", "1", "--compare", nan_ref, NULL);
    test_expect_cli_error(rc, err, 1, "view_nan_ref.pfm: 1 of 4 pixels are NaN or infinite", NULL);
    /* A reference wider than the driver's largest texture (16384 on
     * llvmpipe) is refused; it had been accepted and drawn black. */
    char wide_ref[1024];
    snprintf(wide_ref, sizeof wide_ref, "%s/view_wide_ref.pfm", RTGI_TEST_TMP);
    ImageF wide;
    assert_true(image_alloc(&wide, 40000, 1));
    for (size_t i = 0; i < 3 * 40000; i++)
        wide.rgb[i] = 0.5f;
    assert_true(image_write_pfm(wide_ref, &wide));
    image_free(&wide);
    rc = test_run_cli(&err, "view", "--size", "32x32", "--frames", "1", "--compare", wide_ref, NULL);
    test_expect_cli_error(rc, err, 1, "view_wide_ref.pfm: 40000x1 is larger than this driver's largest texture", NULL);
    /* An unwritable --out fails before the window opens, as render's does. */
    rc = test_run_cli(&err, "view", "--size", "32x32", "--frames", "1", "--out", "/proc/view.png", NULL);
    test_expect_cli_error(rc, err, 1, "/proc/view.png: cannot create output file", NULL);
}

/* A still scene with the orbit's spot light (scenes/cornell_orbit.json's
 * cone and size) where the window's line "ui-test: <what>: light ..." puts
 * it, rendered at the window's settings into `out`. */
static void render_printed_light(const char *ui_out, const char *what, const char *json_name, const char *args_size,
                                 const char *out)
{
    char key[96];
    snprintf(key, sizeof key, "ui-test: %s: light ", what);
    const char *v = find_line(ui_out, key);
    assert_non_null(v);
    int index = -1, type = -1;
    float p[3], d[3], c[3];
    assert_int_equal(sscanf(v, "%d type %d position %f %f %f direction %f %f %f power %f %f %f", &index, &type, &p[0],
                            &p[1], &p[2], &d[0], &d[1], &d[2], &c[0], &c[1], &c[2]),
                     11);
    assert_int_equal(index, 0);
    assert_int_equal(type, 1); /* LIGHT_SPOT */
    char json[1024], name[128];
    snprintf(json, sizeof json,
             "{\"builtin\": \"cornell\", \"lights\": [{\"type\": \"spot\", \"position\": [%.9g, %.9g, %.9g], "
             "\"direction\": [%.9g, %.9g, %.9g], \"intensity\": [%.9g, %.9g, %.9g], \"inner_deg\": 35, "
             "\"outer_deg\": 50, \"diameter\": 0.02}]}\n",
             (double)p[0], (double)p[1], (double)p[2], (double)d[0], (double)d[1], (double)d[2], (double)c[0],
             (double)c[1], (double)c[2]);
    snprintf(name, sizeof name, "%s", json_name);
    const char *scene = test_tmp_file(name, json);
    assert_int_equal(test_run_cli(NULL, "render", "--scene", scene, "--size", args_size, "--gi", "rsm",
                                  "--rsm-samples", "32", "--out", out, "--quiet", NULL),
                     0);
}

/* The largest relative difference of the mean radiance of a 4x4 grid of
 * tiles (where the light lands), and the relMSE of the whole image. */
static double tile_worst(const ImageF *a, const ImageF *b)
{
    double worst = 0;
    for (int ty = 0; ty < 4; ty++)
        for (int tx = 0; tx < 4; tx++) {
            double sa = 0, sb = 0;
            for (int y = ty * a->height / 4; y < (ty + 1) * a->height / 4; y++)
                for (int x = tx * a->width / 4; x < (tx + 1) * a->width / 4; x++)
                    for (int c = 0; c < 3; c++) {
                        sa += image_px(a, x, y)[c];
                        sb += image_px(b, x, y)[c];
                    }
            worst = fmax(worst, fabs(sa - sb) / fmax(sb, 1e-6));
        }
    return worst;
}

static void compare_pair(const char *label, const char *got_path, const char *want_path, double *relmse,
                         double *tiles)
{
    ImageF got, want;
    if (!image_read(got_path, &got) || !image_read(want_path, &want))
        fail_msg("%s: %s or %s not readable", label, got_path, want_path);
    assert_int_equal(got.width, want.width);
    assert_int_equal(got.height, want.height);
    *relmse = metric_relmse(&got, &want, NULL, NULL);
    *tiles = tile_worst(&got, &want);
    print_message("%-34s relMSE %.3g, worst tile %.3g\n", label, *relmse, *tiles);
    image_free(&got);
    image_free(&want);
}

/* `rtgi view --ui-test DIR` on an animated scene (the animation script)
 * at the time slider's `at`, rsm at 32 samples, no FXAA; its stdout into
 * out. */
static void run_anim_script(const char *scene, const char *dir, const char *at, const char *size, char *out,
                            size_t cap)
{
    char cmd[4096], log[700], parent[700];
    snprintf(log, sizeof log, "%s/view.log", dir);
    snprintf(parent, sizeof parent, "%s/x", dir);
    util_ensure_parent_dir(parent);
    test_x_display();
    snprintf(cmd, sizeof cmd,
             "RTGI_UI_TEST_TIME=%s '%s' view --scene '%s' --size %s --gi rsm --rsm-samples 32 --aa none "
             "--ui-test '%s' 2>'%s'",
             at, RTGI_BINARY, scene, size, dir, log);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t n = fread(out, 1, cap - 1, p);
    out[n] = 0;
    int rc = pclose(p);
    if (rc != 0) {
        char *err = util_read_file(log, NULL);
        fail_msg("rtgi view --ui-test on %s failed (%d): %s", scene, rc, err ? err : "");
    }
    print_message("%s", out);
}

/* The mean column of the pixels brighter than `above` (the emitter seen),
 * and how many there are. */
static double bright_column(const ImageF *img, float above, int *count)
{
    double sum = 0;
    *count = 0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            if (image_px(img, x, y)[0] > above) {
                sum += x;
                (*count)++;
            }
    return *count ? sum / *count : -1;
}

/* The camera follows the animation's camera tracks (a field of view
 * widening over a second: the scrubbed frame is `render --time`'s, the
 * first frame's is not), and the arrow keys move a quad light's emitter:
 * the Cornell box's ceiling light, seen, moves right in the image. */
static void animation_camera_and_quad_light(void **state)
{
    (void)state;
    char dir[600], size[32] = "96x96", ref_t[800], got[800], got0[800], moved[800];
    snprintf(dir, sizeof dir, "%s/view_anim_quad", RTGI_TEST_TMP);
    const char *scene = test_tmp_file("view_anim_fov.json",
                                      "{\"builtin\": \"cornell\", \"animation\": {\"duration\": 1, \"tracks\": "
                                      "[{\"target\": \"camera\", \"key\": \"fov_y_deg\", \"times\": [0, 1], "
                                      "\"values\": [39, 45]}]}}\n");
    char scene_path[800];
    snprintf(scene_path, sizeof scene_path, "%s", scene);
    static char out[16384];
    run_anim_script(scene_path, dir, "1", size, out, sizeof out);
    snprintf(ref_t, sizeof ref_t, "%s/ref_t.pfm", dir);
    snprintf(got, sizeof got, "%s/anim_t.pfm", dir);
    snprintf(got0, sizeof got0, "%s/anim_t0.pfm", dir);
    snprintf(moved, sizeof moved, "%s/anim_moved.pfm", dir);
    assert_int_equal(test_run_cli(NULL, "render", "--scene", scene_path, "--time", "1", "--size", size, "--gi", "rsm",
                                  "--rsm-samples", "32", "--out", ref_t, "--quiet", NULL),
                     0);
    double e, tiles, e0, tiles0;
    compare_pair("fov track at 1 s vs render --time", got, ref_t, &e, &tiles);
    compare_pair("  (the frame at 0 s)", got0, ref_t, &e0, &tiles0);
    assert_true(e < 1e-6 && tiles < 1e-3);
    assert_true(e0 > 1e-2 && tiles0 > 0.05);
    assert_non_null(strstr(out, "ui-test: moved: light 0 type 3 ")); /* LIGHT_QUAD */
    ImageF before, after;
    assert_true(image_read(got, &before) && image_read(moved, &after));
    int n0 = 0, n1 = 0;
    double x0 = bright_column(&before, 5.f, &n0), x1 = bright_column(&after, 5.f, &n1);
    print_message("the quad light's emitter: %d pixels about column %.1f, after the keys %d about %.1f\n", n0, x0, n1,
                  x1);
    assert_true(n0 > 4 && n1 > 4);
    assert_true(x1 > x0 + 4);
    image_free(&before);
    image_free(&after);
}

/* Time and lights in the window (issue 50, item 4), on
 * scenes/cornell_orbit.json with rsm (deterministic): the time slider's
 * frame is `render --time T`'s; the light moved by the keys and brightened
 * in the panel is a still scene's with the light written there (each
 * against the frame before the change, which fails the same bound);
 * Space plays (frames drawn, temporal accumulation on and its pass in the
 * timings), Space pauses (temporal off again) and the paused window then
 * draws nothing. */
static void animation_script(void **state)
{
    (void)state;
    char dir[600], size[32] = "96x96", scene[700];
    snprintf(dir, sizeof dir, "%s/view_anim", RTGI_TEST_TMP);
    snprintf(scene, sizeof scene, "%s/scenes/cornell_orbit.json", RTGI_SOURCE_DIR);
    static char out[16384];
    run_anim_script(scene, dir, "1.3", size, out, sizeof out);
    assert_non_null(strstr(out, "ui-test: animation 4 s, 1 lights, time 0, temporal off (auto)"));

    char ref_t[800], ref_moved[800], ref_bright[800], got[800], got0[800], moved[800], bright[800];
    snprintf(ref_t, sizeof ref_t, "%s/ref_t.pfm", dir);
    snprintf(ref_moved, sizeof ref_moved, "%s/ref_moved.pfm", dir);
    snprintf(ref_bright, sizeof ref_bright, "%s/ref_bright.pfm", dir);
    snprintf(got, sizeof got, "%s/anim_t.pfm", dir);
    snprintf(got0, sizeof got0, "%s/anim_t0.pfm", dir);
    snprintf(moved, sizeof moved, "%s/anim_moved.pfm", dir);
    snprintf(bright, sizeof bright, "%s/anim_bright.pfm", dir);
    const char *v = find_line(out, "ui-test: scrubbed to ");
    assert_non_null(v);
    double t = atof(v);
    assert_true(fabs(t - 1.3) < 1e-6);
    assert_non_null(strstr(v, "temporal off, playing 0"));
    char at[32];
    snprintf(at, sizeof at, "%.9g", t);
    assert_int_equal(test_run_cli(NULL, "render", "--scene", scene, "--time", at, "--size", size, "--gi", "rsm",
                                  "--rsm-samples", "32", "--out", ref_t, "--quiet", NULL),
                     0);
    render_printed_light(out, "moved", "view_anim_moved.json", size, ref_moved);
    render_printed_light(out, "power x2", "view_anim_bright.json", size, ref_bright);

    /* Each capture against its render, and the frame before its change
     * (the time 0 frame, the unmoved light, the light at its old power)
     * against the same render: the bound tells them apart. */
    double e, tiles, e0, tiles0;
    compare_pair("scrubbed to 1.3 s vs render --time", got, ref_t, &e, &tiles);
    compare_pair("  (the frame at 0 s)", got0, ref_t, &e0, &tiles0);
    assert_true(e < 1e-6 && tiles < 1e-3);
    assert_true(e0 > 1e-2 && tiles0 > 0.05);
    compare_pair("light moved vs a still scene's", moved, ref_moved, &e, &tiles);
    compare_pair("  (before the move)", got, ref_moved, &e0, &tiles0);
    assert_true(e < 1e-6 && tiles < 1e-3);
    assert_true(e0 > 1e-2 && tiles0 > 0.05);
    compare_pair("power x2 vs a still scene's", bright, ref_bright, &e, &tiles);
    compare_pair("  (before the change)", moved, ref_bright, &e0, &tiles0);
    assert_true(e < 1e-6 && tiles < 1e-3);
    assert_true(e0 > 1e-2 && tiles0 > 0.05);

    /* Playing draws frames with temporal accumulation; paused and idle,
     * nothing. */
    unsigned frames = 0;
    double t0 = -1, t1 = -1;
    char temporal[8] = "", passes[512] = "";
    v = find_line(out, "ui-test: played ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "%*f s: scene frames +%u, time %lf to %lf, temporal %7[a-z], passes %511s", &frames,
                            &t0, &t1, temporal, passes),
                     5);
    print_message("played: %u frames, %.3f -> %.3f s, temporal %s, passes %s\n", frames, t0, t1, temporal, passes);
    assert_true(frames >= 3);
    assert_true(t1 != t0);
    assert_string_equal(temporal, "on");
    assert_non_null(strstr(passes, "temporal"));
    unsigned idle_frames = 99;
    int idle_redraws = 99, idle_passes = 99, playing = 1;
    double idle_s = 0;
    v = find_line(out, "ui-test: paused at ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "%*f s, idle %lf s: scene frames +%u, window redraws +%d, loop passes +%d, temporal "
                               "%7[a-z], playing %d",
                            &idle_s, &idle_frames, &idle_redraws, &idle_passes, temporal, &playing),
                     6);
    assert_true(idle_s >= 0.9);
    assert_int_equal(idle_frames, 0);
    assert_int_equal(idle_redraws, 0);
    assert_true(idle_passes <= 3);
    assert_string_equal(temporal, "off");
    assert_int_equal(playing, 0);
}

/* The live reference (--live-reference; the panel's box): the path
 * tracer converging in the A/B view. The script (view_script.h) turns it
 * off and on again, reports each image it publishes with its relMSE
 * against a converged image of the same camera (--compare), captures the
 * A/B view showing it, moves the camera and comes home (R). Checked: the
 * images come in growing sample counts and their error against the
 * converged image falls as Monte Carlo's does (it had no live reference at
 * all: no line); the panel's line shows the samples and the estimated
 * relMSE; the A/B view's reference is the live image, tone-mapped; a
 * camera move restarts it (fewer samples at the first image after than
 * before); the window drew frames while it converged. Its threads run at
 * the ordinary priority here: at the lowest (SCHED_IDLE, the default) a
 * machine busy with other tests leaves them almost nothing (a pass of 64
 * spp at 64x64 took 7 s instead of 1.5 under a load of 11 on 2 cores). */
static void live_reference(void **state)
{
    (void)state;
    enum { LW = 64, LH = 64, REF_SPP = 512, MIN_SPP = 192 };
    char dir[600], ref[700], size[32], cmd[4096];
    snprintf(dir, sizeof dir, "%s/view_live", RTGI_TEST_TMP);
    snprintf(ref, sizeof ref, "%s/converged.pfm", dir);
    snprintf(size, sizeof size, "%dx%d", LW, LH);
    util_ensure_parent_dir(ref);
    char spp[16];
    snprintf(spp, sizeof spp, "%d", REF_SPP);
    /* Another seed than the window's (1): the two images' noise is independent. */
    assert_int_equal(test_run_cli(NULL, "reference", "--size", size, "--spp", spp, "--seed", "1000", "--threads", "2",
                                  "--out", ref, "--quiet", NULL),
                     0);
    test_x_display();
    snprintf(cmd, sizeof cmd,
             "RTGI_UI_TEST_LIVE_MIN_SPP=%d RTGI_UI_TEST_LIVE_TARGET=0 RTGI_UI_TEST_LIVE_BUSY_S=1 "
             "'%s' view --size %s --exposure 1 --live-reference --live-threads 2 --live-priority normal "
             "--compare '%s' --ui-test '%s' 2>&1",
             MIN_SPP, RTGI_BINARY, size, ref, dir);
    static char out[32768];
    run_command(cmd, out, sizeof out, "rtgi view --live-reference --ui-test");
    print_message("%s", out);

    /* Off: not running, --compare's image in the A/B view again. */
    int running = -1, rw = 0, rh = 0;
    const char *v = find_line(out, "ui-test: live off: ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "running %d, A/B reference %dx%d", &running, &rw, &rh), 3);
    assert_int_equal(running, 0);
    assert_true(rw == LW && rh == LH);

    /* On again: its images until MIN_SPP, each with more samples, the error
     * against the converged image falling with them. */
    const char *end = find_line(out, "ui-test: live converged: ");
    assert_non_null(end);
    int count = 0, s0 = 0, s1 = 0;
    double e0 = 0, e1 = 0, est1 = 0;
    for (const char *q = strstr(v, "ui-test: live "); q && q < end; q = strstr(q + 1, "ui-test: live ")) {
        int s;
        double t, est, e;
        if (sscanf(q, "ui-test: live %d spp at %lf s: relMSE est %lf, vs --compare %lf", &s, &t, &est, &e) != 4)
            continue;
        assert_true(e >= 0 && isfinite(e) && (est > 0 || s < 2)); /* no variance of one sample */
        if (count == 0) {
            s0 = s;
            e0 = e;
        } else {
            assert_true(s > s1);
        }
        s1 = s;
        e1 = e;
        est1 = est;
        count++;
    }
    /* Expected: relMSE ≈ k (1/spp + 1/REF_SPP), the converged image's own
     * noise the second term; half that ratio is the bound. */
    double want = (1.0 / s1 + 1.0 / REF_SPP) / (1.0 / s0 + 1.0 / REF_SPP);
    print_message("live: %d images, %d spp relMSE %.5f -> %d spp relMSE %.5f (ratio %.3f, Monte Carlo's %.3f)\n",
                  count, s0, e0, s1, e1, e1 / e0, want);
    assert_true(count >= 2);
    assert_true(s1 >= MIN_SPP && s1 >= 2 * s0);
    assert_true(e1 < e0 * (0.5 + 0.5 * want));

    /* The panel's line: the last image's samples and its estimate. */
    v = find_line(out, "ui-test: live panel '");
    assert_non_null(v);
    int panel_spp = 0;
    double panel_est = 0;
    assert_int_equal(sscanf(v, "%d spp in %*f s, relMSE ~%lf (est.)", &panel_spp, &panel_est), 2);
    assert_int_equal(panel_spp, s1);
    assert_true(fabs(panel_est - est1) <= 0.05 * est1);

    /* The A/B view in reference mode shows the live image, tone-mapped at
     * the window's exposure (1), where the image is (left of the panel). */
    char live_pfm[700], shot_png[700];
    snprintf(live_pfm, sizeof live_pfm, "%s/live.pfm", dir);
    snprintf(shot_png, sizeof shot_png, "%s/live_ab_reference.png", dir);
    ImageF live, shot, conv;
    assert_true(image_read(live_pfm, &live) && image_read(shot_png, &shot) && image_read(ref, &conv));
    assert_int_equal(live.width, LW);
    assert_int_equal(shot.height, LH);
    double worst = 0;
    for (int y = 0; y < LH; y++)
        for (int x = 0; x < LW; x++)
            for (int c = 0; c < 3; c++)
                worst = fmax(worst, fabsf(srgb_encode(image_px(&shot, x, y)[c]) -
                                          srgb_encode(fminf(image_px(&live, x, y)[c], 1.f))));
    double live_vs_conv = metric_relmse(&live, &conv, NULL, NULL);
    print_message("A/B reference mode vs the live image: worst %.4f; the live image's relMSE %.5f\n", worst,
                  live_vs_conv);
    assert_true(worst <= 1.5 / 255);
    assert_true(live_vs_conv <= e0); /* the image shown is a converged one, not the first pass's */
    image_free(&live);
    image_free(&shot);
    image_free(&conv);

    /* A camera move restarts it. */
    unsigned long long r0 = 0, r1 = 0;
    int before = 0, after = 0;
    v = find_line(out, "ui-test: live camera moved: ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "restarts %llu -> %llu, %d spp before, %d at the first image after", &r0, &r1,
                            &before, &after),
                     4);
    assert_true(r1 == r0 + 1);
    assert_true(after > 0 && after < before);

    /* Frames were drawn while it converged (how many is a speed: printed). */
    unsigned frames = 0;
    v = find_line(out, "ui-test: live busy ");
    assert_non_null(v);
    assert_int_equal(sscanf(v, "%*f s: scene frames %u", &frames), 1);
    assert_true(frames >= 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(help_and_options),
        cmocka_unit_test(out_by_extension),
        cmocka_unit_test(window_out_failure_fails),
        cmocka_unit_test(ui_allocation_failure_ends_cleanly),
        cmocka_unit_test(gl_make_failures_end_cleanly),
        cmocka_unit_test(panel_script),
        cmocka_unit_test(png_reference),
        cmocka_unit_test(animation_script),
        cmocka_unit_test(animation_camera_and_quad_light),
        cmocka_unit_test(live_reference),
        cmocka_unit_test(timings_match_render),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
