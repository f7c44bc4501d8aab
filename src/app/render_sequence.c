/* render_sequence.c — `rtgi render --time T` and `rtgi render --animate
 * --frames N`: the scene file's animation (animation.h) rendered at one
 * instant or as a sequence of frames into --out's pattern, with an
 * optional video (sequence.h). */
#include "app/render_sequence.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <epoxy/gl.h>

#include "core/animation.h"
#include "io/image.h"
#include "base/log.h"
#include "app/sequence.h"
#include "base/util.h"

bool render_time_apply(const RenderOptions *o, Scene *scene)
{
    if (o->time >= 0.0)
        return animation_check_time(scene, o->time, "--time");
    if (o->animate)
        return animation_check_frames(scene, o->frames, o->fps, "--animate");
    return true;
}

/* Frame `path` from the renderer's last frame: radiance for .pfm/.exr, the
 * display image for .png. false after logging (nothing written). */
static bool write_frame(Renderer *r, const char *path, bool hdr_out, bool half, const char *source)
{
    if (!renderer_frames_whole(r))
        return false;
    if (!hdr_out) {
        size_t bad = 0;
        int x = 0, y = 0;
        if (!renderer_count_nonfinite(r, &bad, &x, &y))
            return false;
        if (bad) {
            log_error("render", "%s: %s has %zu NaN or infinite pixels (first at x=%d y=%d); nothing written", source,
                      path, bad, x, y);
            return false;
        }
        uint8_t *rgb = renderer_read_ldr(r);
        bool ok = image_write_png8(path, r->settings.width, r->settings.height, rgb);
        free(rgb);
        return ok;
    }
    ImageF hdr = {0};
    if (!renderer_read_hdr(r, &hdr))
        return false;
    int x = 0, y = 0;
    size_t bad = image_count_nonfinite(&hdr, &x, &y);
    bool ok = bad == 0;
    if (!ok)
        log_error("render", "%s: %s has %zu NaN or infinite pixels (first at x=%d y=%d); nothing written", source,
                  path, bad, x, y);
    ok = ok && image_write(path, &hdr, 1.f, half);
    image_free(&hdr);
    return ok;
}

/* The tone-mapped frames for ffmpeg in a temporary directory beside the
 * video: its path into dir, the PNG pattern into pattern. */
static bool video_dir(const char *video, char *dir, size_t dcap, char *pattern, size_t pcap)
{
    char parent[UTIL_PATH_MAX - 32];
    util_dirname(video, parent, sizeof parent);
    snprintf(dir, dcap, "%s/.rtgi-video-XXXXXX", parent);
    if (!mkdtemp(dir)) {
        log_error("render", "--video %s: cannot make a directory for its frames in %s", video, parent);
        return false;
    }
    snprintf(pattern, pcap, "%s/%%06d.png", dir);
    return true;
}

int render_sequence(const RenderOptions *o, Scene *scene, const RenderSettings *rs_in, const char *gl_renderer)
{
    RenderSettings rs = *rs_in;
    rs.cache = true; /* what a moved light or object changes is redrawn; the rest is kept (tested equal) */
    bool hdr_out = util_ends_with(o->out, ".pfm") || util_ends_with(o->out, ".exr");
    rs.display_only = !hdr_out && !o->video;
    if (o->video && !sequence_ffmpeg_found()) {
        log_error("render", "--video %s: ffmpeg is not installed (Debian: apt install ffmpeg); nothing rendered",
                  o->video);
        return 1;
    }
    char vdir[UTIL_PATH_MAX] = "", vpattern[UTIL_PATH_MAX + 32] = "";
    if (o->video && !video_dir(o->video, vdir, sizeof vdir, vpattern, sizeof vpattern))
        return 1;
    animation_apply(scene, 0.0, NULL);
    Renderer r;
    int written = 0, rc = 1;
    double total_ms = 0;
    if (renderer_create(&r, scene, &rs)) {
        bool ok = true;
        for (int i = 0; i < o->frames && ok; i++) {
            double t = animation_frame_time(scene, i, o->frames, o->fps);
            SceneChange c;
            animation_apply(scene, t, &c);
            ok = renderer_scene_changed(&r, &c);
            double t0 = util_seconds();
            if (ok)
                renderer_frame(&r, &scene->camera);
            glFinish();
            double ms = 1e3 * (util_seconds() - t0);
            total_ms += ms;
            char path[UTIL_PATH_MAX];
            sequence_path(o->out, i, path, sizeof path);
            ok = ok && write_frame(&r, path, hdr_out, o->half, scene->source);
            written += ok;
            if (ok && o->video) {
                char png[UTIL_PATH_MAX + 64];
                sequence_path(vpattern, i, png, sizeof png);
                uint8_t *rgb = renderer_read_ldr(&r);
                ok = image_write_png8(png, rs.width, rs.height, rgb);
                free(rgb);
            }
            if (ok && ms > 1e3 * log_progress_seconds(2.0))
                log_progress("render: frame %d of %d (t = %.3f s) took %.1f s; about %.0f s left", i + 1, o->frames,
                             t, ms * 1e-3, ms * 1e-3 * (o->frames - 1 - i));
        }
        if (ok && o->video)
            ok = sequence_write_video(vpattern, o->frames, o->fps > 0 ? o->fps : 24.0, o->video);
        if (ok) {
            rc = 0;
            char first[UTIL_PATH_MAX], last[UTIL_PATH_MAX];
            sequence_path(o->out, 0, first, sizeof first);
            sequence_path(o->out, o->frames - 1, last, sizeof last);
            printf("frames: %d\n", o->frames);
            printf("time_s: %.6g to %.6g\n", animation_frame_time(scene, 0, o->frames, o->fps),
                   animation_frame_time(scene, o->frames - 1, o->frames, o->fps));
            printf("frame_ms: %.3f\n", total_ms / o->frames);
            log_info("render", "wrote %d frames %s to %s%s%s (%dx%d, %s, %s)", o->frames, first, last,
                     o->video ? " and " : "", o->video ? o->video : "", rs.width, rs.height, scene->source,
                     gl_renderer);
        }
    }
    renderer_destroy(&r);
    if (rc != 0)
        sequence_remove(o->out, written); /* all frames or none */
    if (vdir[0]) {
        sequence_remove(vpattern, o->frames);
        rmdir(vdir);
    }
    return rc;
}
