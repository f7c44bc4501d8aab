/* cmd_render.c — `rtgi render`: rasterize a scene headless to PNG, PFM or
 * OpenEXR. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

#include "app/cli.h"
#include "app/commands.h"
#include "gi/gi.h"
#include "gl/gl_context.h"
#include "io/image.h"
#include "base/log.h"
#include "app/render_options.h"
#include "frame/timings.h"
#include "app/render_sequence.h"
#include "reference/pathtracer.h"
#include "frame/renderer.h"
#include "base/util.h"

#ifdef RTGI_DEBUG
#define RTGI_DEBUG_BUILD true /* KHR_debug messages into the log */
#else
#define RTGI_DEBUG_BUILD false
#endif

/* Frames of one run. Work over RENDER_SLOW_S (RTGI_PROGRESS_S overrides
 * it, log_progress_seconds) is never silent: a frame estimated over it by
 * the cost model prints one line before the first frame, and after a first
 * frame measured over it every frame reports with the time left. */
#define RENDER_SLOW_S 2.0
typedef struct FrameClock {
    int done, total;  /* frames drawn, frames this run will draw */
    double first_s;   /* the first frame's time (s), < 0 before it */
    double slow_s;    /* frames over this report (s) */
} FrameClock;

static void frame(Renderer *r, const Camera *cam, FrameClock *c)
{
    bool measure = c->first_s < 0 || c->first_s > c->slow_s;
    double t0 = util_seconds();
    renderer_frame(r, cam);
    if (!measure)
        return;
    glFinish(); /* the frame's work, not only its submission */
    double s = util_seconds() - t0;
    c->done++;
    if (c->first_s < 0)
        c->first_s = s;
    if (c->first_s > c->slow_s && renderer_frames_whole(r)) /* a failed frame has logged its line, and only that */
        log_progress("render: frame %d of %d took %.1f s; about %.0f s left", c->done, c->total, s,
                     s * (c->total - c->done));
}

/* Applies `rs` to r, draws one untimed frame (it builds what the settings
 * changed), then `frames` timed ones on a reset timer; their mean wall time
 * (ms) in *ms. False if the settings do not apply. */
static bool timed_frames(Renderer *r, const RenderSettings *rs, const Camera *cam, FrameClock *c, int frames,
                         double *ms)
{
    if (!renderer_apply(r, rs))
        return false;
    frame(r, cam, c);
    gpu_timer_reset(&r->timer);
    double t0 = util_seconds();
    for (int f = 0; f < frames; f++)
        frame(r, cam, c);
    *ms = 1e3 * (util_seconds() - t0) / frames;
    return true;
}

/* One line before the first frame when the cost model (src/gi/cost.c, at
 * the default device rate: the window's estimate before it has measured
 * anything) puts a frame's gather over the clock's threshold. */
static void announce_estimate(const RenderSettings *rs, const Scene *scene, const FrameClock *c)
{
    int n = renderer_ssaa(rs);
    double px = (double)rs->width * rs->height * n * n;
    double s = gi_cost_seconds(rs->gi, &rs->set.gi, scene, px, GI_COST_DEFAULT_EVALS_PER_S);
    if (s > c->slow_s)
        log_progress("render: %s at %dx%d: about %.1f s per frame (estimate); %d frame%s to draw",
                     gi_techniques[rs->gi]->name, rs->width, rs->height, s, c->total, c->total == 1 ? "" : "s");
}

void cmd_render_help(void)
{
    printf("usage: rtgi render [options]\n");
    render_options_help(false);
}

/* The technique's ambient visibility (the irradiance image's alpha, --gi
 * vct) as a grey image at the shading size: linear in a PFM, 0..255 in a
 * PNG. */
static bool write_ao(Renderer *r, const char *path)
{
    ImageF img = {0};
    if (!renderer_read_gi_alpha(r, &img))
        return false;
    int w = img.width, h = img.height;
    bool ok;
    if (util_ends_with(path, ".pfm")) {
        ok = image_write_pfm(path, &img);
    } else {
        uint8_t *rgb = malloc(3 * (size_t)w * (size_t)h);
        ok = rgb != NULL;
        if (!ok)
            log_error("render", "%s: out of memory for a %dx%d image", path, w, h);
        for (size_t i = 0; ok && i < 3 * (size_t)w * (size_t)h; i++) {
            float v = img.rgb[i];
            rgb[i] = (uint8_t)(255.f * (v < 0.f ? 0.f : v > 1.f ? 1.f : v) + 0.5f);
        }
        ok = ok && image_write_png8(path, w, h, rgb);
        free(rgb);
    }
    image_free(&img);
    return ok;
}

/* The image --out names, from the frames drawn: linear radiance for .pfm
 * and .exr, else the display image. False (logged, nothing written) if the
 * frames are not whole or any pixel is NaN or infinite. */
static bool write_image(Renderer *r, const char *path, bool hdr_out, bool half, const char *source)
{
    /* Nothing non-finite leaves the renderer: the LDR image would hide it
     * (display-only frames count it as they shade). */
    ImageF hdr = {0};
    size_t bad = 0;
    int x = 0, y = 0;
    bool ok = renderer_frames_whole(r);
    ok = ok && (hdr_out ? renderer_read_hdr(r, &hdr) : renderer_count_nonfinite(r, &bad, &x, &y));
    if (ok && hdr_out)
        bad = image_count_nonfinite(&hdr, &x, &y);
    if (ok && bad) {
        log_error("render", "%s: the rendered HDR image has %zu NaN or infinite pixels (first at x=%d y=%d); "
                  "nothing written", source, bad, x, y);
        ok = false;
    }
    if (ok && hdr_out) {
        image_warn_if_black(&hdr, "render", path);
        ok = image_write(path, &hdr, 1.f, half); /* linear radiance */
    } else if (ok) {
        uint8_t *rgb = renderer_read_ldr(r); /* NULL: it logged; image_write_png8 refuses it */
        image_warn_if_black8(rgb, r->settings.width, r->settings.height, "render", path);
        ok = image_write_png8(path, r->settings.width, r->settings.height, rgb);
        free(rgb);
    }
    image_free(&hdr);
    return ok;
}

/* Removes the first n outputs the options name, in the order write_outputs
 * writes them: --out, --png, --emitter-mask, --out-ao. */
static void remove_outputs(const RenderOptions *o, int n)
{
    const char *paths[4] = {o->out, o->png, o->emitter_mask, o->out_ao};
    for (int i = 0; i < 4 && n > 0; i++)
        if (paths[i]) {
            remove(paths[i]);
            n--;
        }
}

/* Every output the options name, all or none: a failure removes the ones
 * already written. */
static bool write_outputs(Renderer *r, const RenderOptions *o, const Scene *scene, bool hdr_out)
{
    int written = 0;
    bool ok = write_image(r, o->out, hdr_out, o->half, scene->source);
    written += ok;
    if (ok && o->png) {
        uint8_t *rgb = renderer_read_ldr(r);
        ok = image_write_png8(o->png, r->settings.width, r->settings.height, rgb);
        free(rgb);
        written += ok;
    }
    if (ok && o->emitter_mask) {
        ok = pt_write_emitter_mask(scene, r->settings.width, r->settings.height, o->emitter_mask);
        written += ok;
    }
    if (ok && o->out_ao)
        ok = write_ao(r, o->out_ao);
    if (!ok)
        remove_outputs(o, written);
    return ok;
}

/* --timings after the cold frames (mean cold_ms): the per-pass table, then
 * steady frames, which keep the light products as the window does while
 * the lights stand still (the untimed first one draws them), then with
 * --probe the gathers' reads-only twin. False (logged) if the steady or
 * twin frames could not be made or drawn whole. */
static bool print_timings(Renderer *r, const RenderSettings *rs, const Camera *cam, FrameClock *clock, int frames,
                          double cold_ms, const char *device)
{
    double ms;
    GatherRates gather = timings_print(r, device, cold_ms);
    RenderSettings steady = *rs;
    steady.cache = true;
    if (!timed_frames(r, &steady, cam, clock, frames, &ms) || !renderer_frames_whole(r))
        return false;
    timings_print_steady(r, cold_ms, ms);
    RenderSettings twin = steady;
    twin.set.gi.rsm.reads_only = true;
    if (!timings_reads_twin(rs, &gather))
        return true;
    if (!timed_frames(r, &twin, cam, clock, frames, &ms) || !renderer_frames_whole(r))
        return false;
    timings_print_reads_twin(r, &gather);
    return true;
}

int cmd_render(int argc, char **argv)
{
    RenderOptions o;
    render_options_init(&o, false);
    int rc = render_options_parse(&o, argc, argv, cmd_render_help);
    if (rc != 0)
        return rc < 0 ? 0 : rc;
    if (o.timings && o.frames < 1) { /* the window's --frames 0 (run until closed) means nothing here */
        usage_error(NULL, "--frames 0 with --timings: there is no frame to time (at least 1)");
        return 2;
    }

    Scene scene;
    if (!render_options_load_scene(&o, &scene))
        return 1;
    if (!render_time_apply(&o, &scene)) { /* --time, --animate (render_sequence.c) */
        scene_free(&scene);
        return 1;
    }

    RenderSettings rs;
    render_options_settings(&o, &scene, &rs);
    /* A PNG is the final image only: frames that can skip the radiance do. */
    bool hdr_out = util_ends_with(o.out, ".pfm") || util_ends_with(o.out, ".exr");
    rs.display_only = !hdr_out;
    if (o.out_ao && (!(gi_techniques[rs.gi]->flags & GI_AO) || !rs.set.gi.vct.ao)) {
        usage_error(NULL, "--out-ao %s: ambient occlusion comes from --gi vct with --vct-ao on", o.out_ao);
        scene_free(&scene);
        return 2;
    }

    GlContext *gl = gl_context_create(o.debug || RTGI_DEBUG_BUILD);
    if (!gl) {
        scene_free(&scene);
        return 1;
    }
    if (o.animate) {
        rc = render_sequence(&o, &scene, &rs, gl_context_renderer(gl));
        gl_context_destroy(gl);
        scene_free(&scene);
        return rc;
    }
    rc = 1;
    Renderer r;
    if (renderer_create(&r, &scene, &rs)) {
        int frames = 1;
        /* warm-up + timed + one + steady frames with --timings (and one +
         * the reads-only twin's with --probe) */
        int timed = o.warmup + 2 * o.frames + 1 + (o.probe ? o.frames + 1 : 0);
        FrameClock clock = {0, o.timings ? timed : 1, -1.0, log_progress_seconds(RENDER_SLOW_S)};
        announce_estimate(&rs, &scene, &clock);
        double t0 = util_seconds();
        if (o.timings) { /* untimed warm-up frames, then the timed ones */
            for (int f = 0; f < o.warmup; f++)
                frame(&r, &scene.camera, &clock);
            gpu_timer_reset(&r.timer);
            t0 = util_seconds();
            frames = o.frames;
        }
        for (int f = 0; f < frames; f++)
            frame(&r, &scene.camera, &clock);
        double cold_ms = 1e3 * (util_seconds() - t0) / frames;
        if (write_outputs(&r, &o, &scene, hdr_out)) {
            rc = 0;
            /* The timings are an output too: frames that fail them fail
             * the command, and all outputs go, as for a failed write. */
            if (o.timings && !print_timings(&r, &rs, &scene.camera, &clock, frames, cold_ms, gl_context_renderer(gl))) {
                rc = 1;
                remove_outputs(&o, 4);
            } else {
                log_info("render", "wrote %s (%dx%d, %s, %s)", o.out, rs.width, rs.height, scene.source,
                         gl_context_renderer(gl));
            }
        }
    }
    renderer_destroy(&r);
    gl_context_destroy(gl);
    scene_free(&scene);
    return rc;
}
