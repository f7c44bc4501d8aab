/* view_render.c — see view_render.h. */
#include "ui/view_anim.h"
#include "ui/view_render.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gl/gl_context.h"
#include "base/log.h"
#include "frame/timings.h"
#include "gl/shader.h"
#include "gpu/targets.h"
#include "base/util.h"

enum { SLOTS = 3 };

/* A presentation slot: a finished frame's copies, shared with the window. */
typedef struct Slot {
    GLuint ldr, hdr;        /* owned by the thread (hdr only with a reference) */
    int width, height;
    GLsync ready;           /* the thread's copies into it are done (the window waits, then deletes) */
    GLsync released;        /* the window's last draw from it is done (the thread waits, then deletes) */
    float exposure;
    unsigned frame;
} Slot;

struct ViewRender {
    /* Fixed at start. */
    GLFWwindow *context;
    Scene *scene;
    const AbView *ab;
    ViewStatus *status;
    const char *gl_renderer;
    bool debug;
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t wake;    /* the thread waits for work */
    pthread_cond_t done;    /* the window waits for the thread (view_render_wait) */

    /* Under the lock: the window's side. */
    ViewRequest want;       /* the newest request; its jobs and sleep accumulate until taken */
    unsigned want_gen;      /* bumps when want.scene changes */
    bool force;             /* a forced frame is owed */
    bool quit;
    /* Under the lock: the thread's side. */
    ViewRenderState state;
    unsigned drawn_gen;     /* want_gen of the last frame drawn */
    bool working;           /* the thread is doing a request (not waiting) */
    bool ended;             /* the thread left its loop (failed or quit) */
    GLuint ab_program;      /* rebuilt by a reload, not yet taken by the window */
    ImageF ref_next;        /* view_render_set_reference's image, not yet taken by the thread ... */
    bool ref_next_display;
    bool ref_pending;       /* ... when this is set */
    ImageF ref;             /* the reference RMSE and the heat map's scale read (the thread's; swapped
                               with ref_next under the lock); empty: none */
    bool ref_display;
    unsigned ref_version;   /* bumps at each swap: the heat map's scale is measured again */
    unsigned diff_ref;      /* ref_version of the last scale measured */
    Slot slots[SLOTS];
    int front, pending, back; /* slot indices: shown / handed over / being written */
    bool pending_new;       /* pending holds a frame the window has not taken */

    /* The thread's own. */
    Renderer r;
    bool have_renderer;     /* renderer_create was called (destroy it, made or not) */
    ViewStats stats;
    int interval_frames;    /* frames in the timing interval ... */
    double interval_s;      /* ... their wall time on this thread */
    bool interval_clean;    /* no remake, reload or first frame in it: its time is a cost */
    Camera drawn_camera;    /* the last frame's camera (a radiance capture of a display-only frame) */
    ViewAnimApplied anim;   /* the time and light edits the scene holds (view_anim.h) */
};

static void publish_locked(ViewRender *vr)
{
    vr->state.version++;
    pthread_cond_broadcast(&vr->done);
}

/* ---- Timings ------------------------------------------------------------------ */

static void take_pass_table(ViewStats *s, const Renderer *r)
{
    const GpuTimer *t = &r->timer;
    s->pass_wall = t->sync;
    s->timer_frames = t->frames;
    s->gpu_ms = 0;
    s->pass_count = 0;
    for (int i = 0; i < t->pass_count && t->frames > 0; i++) {
        snprintf(s->pass_name[s->pass_count], sizeof s->pass_name[0], "%s", t->passes[i].name);
        s->pass_ms[s->pass_count] = (t->sync ? t->passes[i].cpu_ms : t->passes[i].gpu_ms) / t->frames;
        s->gpu_ms += s->pass_ms[s->pass_count++];
    }
}

/* Ends the timing interval: its timings recorded and, if it was clean,
 * the measured cost of the current technique and the gather rate. */
static void end_interval(ViewRender *vr)
{
    Renderer *r = &vr->r;
    ViewStats *s = &vr->stats;
    if (vr->interval_frames > 0 && r->timer.frames > 0) {
        double frame_ms = 1e3 * vr->interval_s / vr->interval_frames;
        s->frame_ms = frame_ms;
        take_pass_table(s, r);
        /* The technique's counters and memory, read back once an interval. */
        const RenderStats *st = renderer_collect_stats(r);
        s->memory = renderer_gpu_memory(r);
        s->history[s->history_next] = (float)frame_ms;
        s->history_next = (s->history_next + 1) % VIEW_HISTORY;
        if (s->history_count < VIEW_HISTORY)
            s->history_count++;
        if (vr->interval_clean) {
            int gi = (int)r->settings.gi, n = renderer_ssaa(&r->settings);
            s->measured_ms[gi] = frame_ms;
            s->measured_px[gi] = (double)r->settings.width * r->settings.height * n * n;
            /* The device's gather rate, from this technique's counters and its gather passes. */
            double ms = renderer_gather_ms(r, st, -1, false);
            if (gi != GI_NONE && ms > 0.5 && st->gather_evaluations > 0)
                s->evals_per_s = (double)st->gather_evaluations / (ms * 1e-3);
        }
        pthread_mutex_lock(&vr->lock);
        vr->state.stats = *s;
        vr->state.stats_version++;
        pthread_mutex_unlock(&vr->lock);
    }
    gpu_timer_reset(&r->timer);
    vr->interval_frames = 0;
    vr->interval_s = 0;
    vr->interval_clean = true;
}

/* ---- Jobs ---------------------------------------------------------------------- */

/* P: the image as shown (.png) or its radiance (any other extension). */
static bool save_image(ViewRender *vr, const char *path, bool half)
{
    Renderer *r = &vr->r;
    util_ensure_parent_dir(path);
    bool ok;
    if (util_ends_with(path, ".png")) {
        uint8_t *rgb = renderer_read_ldr(r);
        ok = rgb && image_write_png8(path, r->settings.width, r->settings.height, rgb);
        free(rgb);
    } else {
        /* A display-only frame kept no radiance: draw it again with it (the
         * next frame's settings turn display_only back on). */
        if (!r->radiance_kept) {
            RenderSettings rs = r->settings;
            rs.display_only = false;
            if (renderer_apply(r, &rs))
                renderer_frame(r, &vr->drawn_camera);
        }
        ImageF img;
        ok = renderer_read_hdr(r, &img);
        if (ok) {
            ok = image_write(path, &img, r->settings.exposure, half);
            image_free(&img);
        }
    }
    if (ok)
        view_status(vr->status, false, "wrote %s", path);
    /* else what failed logged why, and the log hook put it on the panel */
    return ok;
}

/* F5: every program rebuilt from the shader files; a program that fails
 * keeps its previous build and the error shows in the panel. */
static void reload_shaders(ViewRender *vr)
{
    ViewStatus *s = vr->status;
    pthread_mutex_lock(&s->lock);
    s->text[0] = 0;
    s->error = false;
    s->reloading = true;
    pthread_mutex_unlock(&s->lock);
    bool ok = program_cache_reload(&vr->r.programs);
    GLuint ab = vr->ab ? ab_view_build_program() : 0;
    ok = (!vr->ab || ab) && ok;
    pthread_mutex_lock(&s->lock);
    s->reloading = false;
    bool had_error = s->error;
    pthread_mutex_unlock(&s->lock);
    if (ab) {
        pthread_mutex_lock(&vr->lock);
        if (vr->ab_program) /* an earlier rebuild the window never took */
            glDeleteProgram(vr->ab_program);
        vr->ab_program = ab;
        pthread_mutex_unlock(&vr->lock);
    }
    renderer_invalidate(&vr->r); /* uniforms set once per light product are set again */
    if (ok)
        view_status(s, false, "shaders reloaded from %s", shader_directory() ? shader_directory() : "(embedded)");
    else if (!had_error)
        view_status(s, true, "shader reload failed; the previous programs stay (see the terminal)");
}

/* The heat map's automatic scale for the last frame. */
static float diff_scale(ViewRender *vr)
{
    ImageF frame;
    if (!vr->ref.rgb || !vr->r.radiance_kept || !renderer_read_hdr(&vr->r, &frame))
        return 0;
    float s = ab_view_diff_quantile(&vr->ref, vr->ref_display, &frame, vr->r.settings.exposure, AB_AUTO_QUANTILE);
    image_free(&frame);
    return s;
}

/* ---- Frames -------------------------------------------------------------------- */

static bool slot_make(Slot *s, int w, int h, bool hdr)
{
    glDeleteTextures(1, &s->ldr);
    glDeleteTextures(1, &s->hdr);
    s->ldr = gl_texture_make(GL_TEXTURE_2D, GL_SRGB8_ALPHA8, w, h, "view.present_ldr");
    s->hdr = hdr && s->ldr ? gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, w, h, "view.present_hdr") : 0;
    s->width = s->ldr && (s->hdr || !hdr) ? w : 0;
    s->height = s->width ? h : 0;
    return s->width > 0;
}

/* Copies the finished frame into the back slot and hands it to the window.
 * false after logging (a slot's texture could not be made). */
static bool present(ViewRender *vr)
{
    Renderer *r = &vr->r;
    Slot *s = &vr->slots[vr->back]; /* the thread's alone until it is handed over */
    if (s->released) { /* the window's draws from it are done (at once, in practice: they were swapped) */
        while (glClientWaitSync(s->released, GL_SYNC_FLUSH_COMMANDS_BIT, 100000000) == GL_TIMEOUT_EXPIRED)
            ;
        glDeleteSync(s->released);
        s->released = 0;
    }
    bool hdr = r->radiance_kept && !r->settings.display_only; /* the window compares with a reference */
    if ((s->width != r->ldr.width || s->height != r->ldr.height || (s->hdr != 0) != hdr) &&
        !slot_make(s, r->ldr.width, r->ldr.height, hdr))
        return false;
    glCopyImageSubData(r->ldr.texture, GL_TEXTURE_2D, 0, 0, 0, 0, s->ldr, GL_TEXTURE_2D, 0, 0, 0, 0, s->width,
                       s->height, 1);
    if (hdr)
        glCopyImageSubData(r->hdr.texture, GL_TEXTURE_2D, 0, 0, 0, 0, s->hdr, GL_TEXTURE_2D, 0, 0, 0, 0, s->width,
                           s->height, 1);
    if (s->ready)
        glDeleteSync(s->ready);
    s->ready = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    /* The frame is finished here, not later in the window's wait: on a
     * software rasterizer the work runs where it is waited for. */
    glFinish();
    s->exposure = r->settings.exposure;
    pthread_mutex_lock(&vr->lock);
    s->frame = vr->state.frames + 1;
    int t = vr->back;
    vr->back = vr->pending;
    vr->pending = t;
    vr->pending_new = true;
    pthread_mutex_unlock(&vr->lock);
    glfwPostEmptyEvent(); /* the window shows it without waiting for this request's other work */
    return true;
}

/* One frame of `req`: its settings applied, drawn, presented. false after
 * logging when the renderer could not take the settings. */
static bool draw_frame(ViewRender *vr, const ViewRequest *req)
{
    Renderer *r = &vr->r;
    if (req->test_sleep_s > 0) {
        struct timespec ts = {(time_t)req->test_sleep_s, (long)(fmod(req->test_sleep_s, 1.0) * 1e9)};
        nanosleep(&ts, NULL);
    }
    double t0 = glfwGetTime();
    const RenderSettings *was = &r->settings, *want = &req->scene.settings;
    if (memcmp(&was->set.gi, &want->set.gi, sizeof was->set.gi) ||
        memcmp(&was->set.shadow, &want->set.shadow, sizeof was->set.shadow) ||
        was->shadow != want->shadow || was->ssaa != want->ssaa || was->aa != want->aa)
        memset(vr->stats.measured_px, 0, sizeof vr->stats.measured_px); /* the costs were for other settings */
    int remakes = r->remakes;
    /* Remakes only what the change touches (nothing for exposure). */
    if (!renderer_apply(r, want))
        return false;
    /* The scene at the request's time with its light edits (light
     * products and moved geometry follow: renderer_scene_changed). */
    if (!view_anim_apply(&vr->anim, vr->scene, r, req->scene.time, &req->scene.lights))
        return false;
    if (r->remakes != remakes)
        vr->interval_clean = false;
    renderer_frame(r, &req->scene.camera);
    vr->drawn_camera = req->scene.camera;
    if (!present(vr))
        return false;
    double frame_s = glfwGetTime() - t0;
    vr->interval_frames++;
    vr->interval_s += frame_s;
    pthread_mutex_lock(&vr->lock);
    vr->state.frames++;
    if (vr->state.frames == 1)
        vr->interval_clean = false; /* the first frame compiles */
    vr->state.last_frame_s = frame_s;
    vr->state.last_exposure = r->settings.exposure;
    pthread_mutex_unlock(&vr->lock);
    return true;
}

/* Whether the heat map's automatic scale is owed (under the lock): wanted,
 * with a reference, and not yet measured for this frame and reference. */
static bool diff_owed(const ViewRender *vr)
{
    return vr->want.diff_scale && (vr->ref.rgb || vr->ref_pending) && vr->state.frames > 0 &&
           (vr->state.diff_frame != vr->state.frames || vr->diff_ref != vr->ref_version + (vr->ref_pending ? 1u : 0u));
}

/* Whether a request waits (under the lock). */
static bool work_waiting(const ViewRender *vr)
{
    return vr->want.jobs || vr->force || vr->want_gen != vr->drawn_gen || vr->ref_pending || diff_owed(vr);
}

/* The window's newest reference becomes the thread's (under the lock). */
static void take_reference_locked(ViewRender *vr)
{
    if (!vr->ref_pending)
        return;
    ImageF t = vr->ref;
    vr->ref = vr->ref_next;
    vr->ref_next = t;
    vr->ref_display = vr->ref_next_display;
    vr->ref_pending = false;
    vr->ref_version++;
}

/* One request: jobs before the frame, the frame, jobs after it. false
 * when the renderer failed (it logged). */
static bool do_request(ViewRender *vr, const ViewRequest *req, bool draw)
{
    Renderer *r = &vr->r;
    if (req->jobs & VIEW_JOB_RESET_TIMER)
        end_interval(vr);
    if (req->jobs & VIEW_JOB_RELOAD) {
        reload_shaders(vr);
        vr->interval_clean = false;
        draw = true;
    }
    if (draw && !draw_frame(vr, req))
        return false;
    if (req->jobs & VIEW_JOB_SAVE) {
        bool ok = save_image(vr, req->save_path, req->half);
        pthread_mutex_lock(&vr->lock);
        vr->state.saves++;
        vr->state.save_ok = ok;
        pthread_mutex_unlock(&vr->lock);
    }
    if (req->jobs & VIEW_JOB_RMSE) {
        double e = ab_view_rmse(&vr->ref, vr->ref_display, r);
        pthread_mutex_lock(&vr->lock);
        vr->state.rmse_count++;
        vr->state.rmse = e;
        pthread_mutex_unlock(&vr->lock);
    }
    pthread_mutex_lock(&vr->lock);
    take_reference_locked(vr);
    bool want_diff = diff_owed(vr);
    unsigned version = vr->ref_version;
    pthread_mutex_unlock(&vr->lock);
    if (want_diff) {
        float s = diff_scale(vr);
        pthread_mutex_lock(&vr->lock);
        vr->state.diff_scale = s;
        vr->state.diff_frame = vr->state.frames;
        vr->diff_ref = version;
        pthread_mutex_unlock(&vr->lock);
    }
    if (req->jobs & VIEW_JOB_PASS_TABLE) {
        take_pass_table(&vr->stats, r);
        pthread_mutex_lock(&vr->lock);
        vr->state.stats = vr->stats;
        vr->state.stats_version++;
        pthread_mutex_unlock(&vr->lock);
    }
    if (req->jobs & VIEW_JOB_PRINT_TIMINGS)
        timings_print(r, vr->gl_renderer,
                                     vr->stats.frame_ms > 0 ? vr->stats.frame_ms : 1e3 * vr->state.last_frame_s);
    /* The interval ends every half second of frames (or 30 of them), and
     * when no frame follows: an idle window shows its last frames' times. */
    pthread_mutex_lock(&vr->lock);
    bool more = vr->want_gen != vr->drawn_gen || vr->force;
    pthread_mutex_unlock(&vr->lock);
    if (!req->hold_timer && vr->interval_frames > 0 && (vr->interval_s > 0.5 || vr->interval_frames >= 30 || !more))
        end_interval(vr);
    return true;
}

static void *render_thread(void *arg)
{
    ViewRender *vr = arg;
    glfwMakeContextCurrent(vr->context);
    if (vr->debug)
        gl_install_debug_callback();
    pthread_mutex_lock(&vr->lock);
    RenderSettings first = vr->want.scene.settings;
    pthread_mutex_unlock(&vr->lock);
    vr->have_renderer = true;
    bool ok = renderer_create(&vr->r, vr->scene, &first);
    vr->interval_clean = true;
    pthread_mutex_lock(&vr->lock);
    vr->state.made = ok;
    while (ok) {
        vr->working = false;
        publish_locked(vr);
        while (!vr->quit && !work_waiting(vr))
            pthread_cond_wait(&vr->wake, &vr->lock);
        if (vr->quit)
            break;
        take_reference_locked(vr);
        ViewRequest req = vr->want;
        bool draw = vr->force || vr->want_gen != vr->drawn_gen;
        vr->drawn_gen = vr->want_gen;
        vr->force = false;
        vr->want.jobs = 0;
        vr->want.test_sleep_s = 0;
        vr->working = true;
        vr->state.busy = draw || (req.jobs & VIEW_JOB_RELOAD);
        vr->state.busy_since = glfwGetTime();
        publish_locked(vr);
        pthread_mutex_unlock(&vr->lock);
        if (vr->state.busy)
            glfwPostEmptyEvent(); /* the window wakes to time its busy indicator */

        ok = do_request(vr, &req, draw);

        pthread_mutex_lock(&vr->lock);
        vr->state.busy = false;
        vr->state.remakes = vr->r.remakes;
        vr->state.links = shader_link_count();
        vr->state.whole = renderer_frames_whole(&vr->r);
        publish_locked(vr);
        pthread_mutex_unlock(&vr->lock);
        glfwPostEmptyEvent(); /* the window wakes to show it */
        pthread_mutex_lock(&vr->lock);
    }
    vr->state.failed = !ok;
    vr->working = false;
    vr->ended = true;
    publish_locked(vr);
    glfwPostEmptyEvent();
    while (!vr->quit) /* the window may still draw the image it took */
        pthread_cond_wait(&vr->wake, &vr->lock);
    pthread_mutex_unlock(&vr->lock);
    /* What the thread made goes with it (the window draws no more). */
    if (vr->have_renderer)
        renderer_destroy(&vr->r);
    for (int i = 0; i < SLOTS; i++) {
        Slot *s = &vr->slots[i];
        glDeleteTextures(1, &s->ldr);
        glDeleteTextures(1, &s->hdr);
        if (s->ready)
            glDeleteSync(s->ready);
        if (s->released)
            glDeleteSync(s->released);
    }
    if (vr->ab_program)
        glDeleteProgram(vr->ab_program);
    image_free(&vr->ref);
    image_free(&vr->ref_next);
    glFinish();
    glfwMakeContextCurrent(NULL);
    return NULL;
}

/* ---- The window's side -------------------------------------------------------- */

ViewRender *view_render_start(const ViewRenderDesc *d)
{
    ViewRender *vr = calloc(1, sizeof *vr);
    if (!vr) {
        log_error("view", "out of memory for the render thread");
        return NULL;
    }
    vr->context = d->context;
    vr->scene = d->scene;
    vr->ab = d->ab;
    vr->status = d->status;
    vr->gl_renderer = d->gl_renderer;
    vr->debug = d->debug;
    vr->want = *d->first;
    vr->want.jobs = 0; /* the first frame comes with the window's first submit */
    vr->want.force = false;
    vr->front = 0;
    vr->pending = 1;
    vr->back = 2;
    vr->state.rmse = -1;
    if (d->ab && d->ab->reference.rgb) { /* --compare's: a copy of its own */
        if (!image_alloc(&vr->ref, d->ab->reference.width, d->ab->reference.height)) {
            log_error("view", "out of memory for the render thread's copy of the reference");
            free(vr);
            return NULL;
        }
        memcpy(vr->ref.rgb, d->ab->reference.rgb, sizeof(float) * 3 * (size_t)vr->ref.width * vr->ref.height);
        vr->ref_display = d->ab->display;
    }
    pthread_mutex_init(&vr->lock, NULL);
    pthread_cond_init(&vr->wake, NULL);
    pthread_cond_init(&vr->done, NULL);
    int err = pthread_create(&vr->thread, NULL, render_thread, vr);
    if (err) {
        log_error("view", "cannot start the render thread: %s", strerror(err));
        pthread_cond_destroy(&vr->done);
        pthread_cond_destroy(&vr->wake);
        pthread_mutex_destroy(&vr->lock);
        image_free(&vr->ref);
        free(vr);
        return NULL;
    }
    return vr;
}

void view_render_stop(ViewRender *vr)
{
    if (!vr)
        return;
    pthread_mutex_lock(&vr->lock);
    vr->quit = true;
    pthread_cond_signal(&vr->wake);
    pthread_mutex_unlock(&vr->lock);
    pthread_join(vr->thread, NULL);
    pthread_cond_destroy(&vr->done);
    pthread_cond_destroy(&vr->wake);
    pthread_mutex_destroy(&vr->lock);
    free(vr);
}

void view_render_submit(ViewRender *vr, const ViewRequest *req)
{
    pthread_mutex_lock(&vr->lock);
    if (memcmp(&req->scene, &vr->want.scene, sizeof req->scene) != 0)
        vr->want_gen++;
    unsigned jobs = vr->want.jobs | req->jobs;
    double sleep_s = fmax(vr->want.test_sleep_s, req->test_sleep_s);
    char save_path[sizeof vr->want.save_path];
    memcpy(save_path, vr->want.save_path, sizeof save_path);
    bool half = vr->want.half;
    vr->want = *req;
    vr->want.jobs = jobs;
    vr->want.test_sleep_s = sleep_s;
    if (!(req->jobs & VIEW_JOB_SAVE)) { /* a save still waiting keeps its path */
        memcpy(vr->want.save_path, save_path, sizeof save_path);
        vr->want.half = half;
    }
    vr->force = vr->force || req->force;
    pthread_cond_signal(&vr->wake);
    pthread_mutex_unlock(&vr->lock);
}

void view_render_jobs(ViewRender *vr, unsigned jobs, const char *save_path, bool half)
{
    pthread_mutex_lock(&vr->lock);
    vr->want.jobs |= jobs;
    if (save_path) {
        snprintf(vr->want.save_path, sizeof vr->want.save_path, "%s", save_path);
        vr->want.half = half;
    }
    pthread_cond_signal(&vr->wake);
    pthread_mutex_unlock(&vr->lock);
}

void view_render_wait(ViewRender *vr)
{
    pthread_mutex_lock(&vr->lock);
    while (!vr->ended && (vr->working || !vr->state.made || work_waiting(vr)))
        pthread_cond_wait(&vr->done, &vr->lock);
    pthread_mutex_unlock(&vr->lock);
}

void view_render_state(ViewRender *vr, ViewRenderState *out)
{
    pthread_mutex_lock(&vr->lock);
    *out = vr->state;
    pthread_mutex_unlock(&vr->lock);
}

bool view_render_take(ViewRender *vr, ViewImage *out)
{
    pthread_mutex_lock(&vr->lock);
    bool fresh = vr->pending_new; /* only this thread clears it */
    pthread_mutex_unlock(&vr->lock);
    if (fresh) {
        /* The front slot is this thread's alone until it is handed back:
         * its release fence is made outside the lock (a flush may wait for
         * a software rasterizer's queue, the render thread's work in it). */
        Slot *old = &vr->slots[vr->front];
        if (old->ldr) {
            if (old->released)
                glDeleteSync(old->released);
            old->released = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
            glFlush();
        }
        pthread_mutex_lock(&vr->lock);
        int t = vr->front;
        vr->front = vr->pending;
        vr->pending = t;
        vr->pending_new = false;
        pthread_mutex_unlock(&vr->lock);
    }
    Slot *s = &vr->slots[vr->front];
    GLsync ready = s->ready;
    s->ready = 0;
    *out = (ViewImage){.ldr = s->ldr, .hdr = s->hdr, .width = s->width, .height = s->height,
                       .exposure = s->exposure, .frame = s->frame};
    if (ready) {
        glWaitSync(ready, 0, GL_TIMEOUT_IGNORED);
        glDeleteSync(ready);
    }
    return fresh;
}

bool view_render_set_reference(ViewRender *vr, const ImageF *img, bool display)
{
    ImageF copy = {0};
    if (img && img->rgb) {
        if (!image_alloc(&copy, img->width, img->height)) {
            log_error("view", "out of memory for the render thread's copy of the reference (%dx%d)", img->width,
                      img->height);
            return false;
        }
        memcpy(copy.rgb, img->rgb, sizeof(float) * 3 * (size_t)img->width * img->height);
    }
    pthread_mutex_lock(&vr->lock);
    ImageF old = vr->ref_next;
    vr->ref_next = copy;
    vr->ref_next_display = display;
    vr->ref_pending = true;
    pthread_cond_signal(&vr->wake);
    pthread_mutex_unlock(&vr->lock);
    image_free(&old);
    return true;
}

GLuint view_render_take_program(ViewRender *vr)
{
    pthread_mutex_lock(&vr->lock);
    GLuint p = vr->ab_program;
    vr->ab_program = 0;
    pthread_mutex_unlock(&vr->lock);
    return p;
}
