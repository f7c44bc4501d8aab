/* cmd_view.c — `rtgi view`: the renderer in a window (GLFW) with a Dear
 * ImGui panel (src/ui/view_panel.c): camera, technique and settings,
 * timings, captures, shader hot reload, the A/B view of --compare, and
 * the scene's animation and lights (src/ui/view_anim.c: play, pause,
 * scrub; lights moved with keys, their power edited).
 * The window is the image (its render size) with the panel docked on its
 * right. This file is the window's thread: events, input, layout, the
 * panel and the last finished image, drawn only when something changed;
 * frames are drawn on the render thread (src/ui/view_render.c), which it
 * asks for them without waiting, except in scripted runs. --frames N exits after
 * N frames and --out saves the last frame (scripted screenshots, e.g. under
 * xvfb-run); --ui-test DIR runs a fixed script through the panel's actions
 * and reports what it measured (src/ui/view_script.c; tests/test_view.c). */
#include <epoxy/gl.h> /* before GLFW, which must not pull in GL/gl.h */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/animation.h"
#include "app/commands.h"
#include "gl/gl_context.h"
#include "base/log.h"
#include "app/render_options.h"
#include "frame/renderer.h"
#include "gl/shader.h"
#include "ui/ab_view.h"
#include "ui/live_reference.h"
#include "ui/ui.h"
#include "ui/view_anim.h"
#include "ui/view_input.h"
#include "ui/view_panel.h"
#include "ui/view_render.h"
#include "ui/view_script.h"
#include "base/util.h"

void cmd_view_help(void)
{
    printf("usage: rtgi view [options]\n"
           "The renderer in a window with a panel (Dear ImGui): technique and shadow pickers,\n"
           "every technique setting with its range, live exposure, per-pass GPU ms and a\n"
           "history plot, the camera as scene JSON, captures, shader reload, A/B comparison.\n"
           "keys: WASD move, Q/E down/up, Shift faster, left-drag look, R reset camera,\n"
           "  1-4 shadows none/hard/pcf/pcss, G/Shift-G next/previous GI technique (slow ones\n"
           "  ask for a click first), +/- exposure, F FXAA on/off, C cycle the A/B view,\n"
           "  T print timings, P save the image, Shift-P save the window (panel included),\n"
           "  F5 reload shaders (from --shader-dir, else the source tree's shaders/),\n"
           "  H hide/show the panel (the window shrinks or grows by it; the image keeps its size),\n"
           "  Space play/pause the scene's animation (the panel's time slider scrubs it),\n"
           "  arrows move the selected light across the view, Page Up/Down raise/lower it (a\n"
           "  directional light: arrows turn it), Shift faster, L/Shift-L next/previous light\n"
           "  (its power: the panel's Lights),\n"
           "  Esc quit. Frames are drawn on a thread of their own: the window answers while a\n"
           "  slow one is drawn, and draws nothing while nothing changes.\n"
           "options:\n");
    render_options_help(true);
}

/* ---- The loop's state and the window's callbacks ------------------------------ */

/* What the window's loop carries from one pass to the next (the GLFW
 * window's user pointer). */
typedef struct ViewLoop {
    View *v;
    GLFWwindow *win;
    ViewRender *render;
    AbView *present;        /* draws the image area (the A/B view, or the frame alone) */
    ViewScript script;      /* --ui-test: its state (dir NULL: none) */
    bool sync;              /* scripted: each window frame asks for a scene frame and waits for it */
    int frame;              /* window frames drawn while sync: --frames and the script's steps count them */
    int passes;             /* passes of the loop (each after events or a timeout) */
    int redraws;            /* window frames drawn */
    double redraw_at;       /* when the last one was (glfwGetTime) */
    bool dirty;             /* something new to show: input, an image, the render thread's state */
    int settle;             /* window frames still owed after input (ImGui settles over a couple) */
    bool moving;            /* a movement key is held: the camera moves every pass */
    double last;            /* the last pass (camera movement) */
    ViewImage image;        /* the image shown */
    unsigned state_version, stats_version, rmse_count; /* of what was last taken from the render thread */
    char busy_shown[96];    /* the busy indicator as last drawn */
    bool panel_docked;      /* the window is sized for the panel beside the image */
    int expect_w, expect_h; /* a framebuffer size the loop asked for and has not seen yet */
    double expect_until;    /* when to stop waiting for it (a window manager may refuse) */
    float scale;            /* framebuffer pixels per screen coordinate */
    bool capture_failed;    /* the scripted --window-out capture failed: the command fails */
    LiveReference live;     /* the live reference (stopped unless v->live_wanted) */
    ImageF compare_file;    /* --compare's image (a copy), shown again when the live reference stops */
    bool compare_display;   /* it is display-referred (PNG): no relMSE against it */
} ViewLoop;

/* Any input: the window is drawn again (and a couple more times after, for
 * ImGui's hover and focus states). */
static void loop_wake(ViewLoop *l)
{
    l->dirty = true;
    l->settle = 2;
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    ViewLoop *l = glfwGetWindowUserPointer(w);
    loop_wake(l);
    if (action == GLFW_PRESS && !ui_wants_keyboard())
        view_key(l->v, key, mods);
}

static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    (void)mods;
    ViewLoop *l = glfwGetWindowUserPointer(w);
    loop_wake(l);
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
        l->v->dragging = action == GLFW_PRESS && !ui_wants_mouse();
        glfwGetCursorPos(w, &l->v->last_x, &l->v->last_y);
    }
}

static void on_cursor(GLFWwindow *w, double x, double y)
{
    ViewLoop *l = glfwGetWindowUserPointer(w);
    View *v = l->v;
    loop_wake(l);
    if (!v->dragging)
        return;
    v->yaw -= (float)(x - v->last_x) * 0.004f;
    v->pitch -= (float)(y - v->last_y) * 0.004f;
    v->pitch = fmaxf(-1.55f, fminf(1.55f, v->pitch));
    v->last_x = x;
    v->last_y = y;
}

static void on_scroll(GLFWwindow *w, double x, double y)
{
    (void)x;
    (void)y;
    loop_wake(glfwGetWindowUserPointer(w));
}

static void on_char(GLFWwindow *w, unsigned c)
{
    (void)c;
    loop_wake(glfwGetWindowUserPointer(w));
}

static void on_flag(GLFWwindow *w, int flag) /* focus, cursor enter */
{
    (void)flag;
    loop_wake(glfwGetWindowUserPointer(w));
}

static void on_refresh(GLFWwindow *w) { loop_wake(glfwGetWindowUserPointer(w)); }

/* The framebuffer's new size: the loop's own resize (H) keeps the image's
 * size; any other (the user's) gives the image what the panel leaves. */
static void on_framebuffer_size(GLFWwindow *w, int fw, int fh)
{
    ViewLoop *l = glfwGetWindowUserPointer(w);
    loop_wake(l);
    if (fw == l->expect_w && fh == l->expect_h) {
        l->expect_w = l->expect_h = 0;
        return;
    }
    if (fw <= 0 || fh <= 0) /* minimised */
        return;
    int panel = l->panel_docked ? (int)lroundf(VIEW_PANEL_WIDTH * l->scale) : 0;
    l->v->settings.width = fw - panel > 16 ? fw - panel : 16;
    l->v->settings.height = fh > 16 ? fh : 16;
}

/* GLFW's last error while the window is being made (the failure's one
 * line says it); afterwards each error is logged as it comes. */
static char s_glfw_error[256];
static bool s_glfw_window_up;

static void on_glfw_error(int code, const char *msg)
{
    if (s_glfw_window_up)
        log_error("view", "GLFW error %d: %s", code, msg);
    else
        snprintf(s_glfw_error, sizeof s_glfw_error, "%s", msg);
}

/* ---- The window -------------------------------------------------------------- */

/* GLFW, the window (the image of --size and the panel beside it) with an
 * OpenGL 4.5 core context made current, and a hidden window whose context
 * shares its objects (*render_context: the render thread's). NULL after
 * logging why (GLFW is terminated then). */
static GLFWwindow *view_window_open(const RenderOptions *o, GLFWwindow **render_context)
{
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        log_error("view", "cannot open a window (%s); use 'rtgi render' for headless images",
                  s_glfw_error[0] ? s_glfw_error : "no display?");
        return NULL;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, o->debug ? GLFW_TRUE : GLFW_FALSE);
    int width = o->width + (o->no_panel ? 0 : VIEW_PANEL_WIDTH);
    GLFWwindow *win = glfwCreateWindow(width, o->height, "rtgi", NULL, NULL);
    GLFWwindow *hidden = NULL;
    if (win) {
        glfwMakeContextCurrent(win);
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        hidden = glfwCreateWindow(1, 1, "rtgi render thread", NULL, win);
    }
    if (!hidden) {
        log_error("view", "cannot create a window with an OpenGL 4.5 core context%s%s%s",
                  win ? " shared with a second one (the render thread's)" : "", s_glfw_error[0] ? ": " : "",
                  s_glfw_error);
        if (win)
            glfwDestroyWindow(win);
        glfwTerminate();
        return NULL;
    }
    s_glfw_window_up = true;
    glfwSwapInterval(o->frames > 0 || o->ui_test ? 0 : 1);
    if (o->debug)
        gl_install_debug_callback();
    *render_context = hidden;
    return win;
}

/* The view's state from the options and the scene (needs the context:
 * the timer's mode depends on the GL renderer). */
static void view_init(View *v, const RenderOptions *o, const Scene *scene, ViewStatus *status)
{
    memset(v, 0, sizeof *v);
    v->scene = scene;
    v->status = status;
    v->slow_ms = o->slow_ms;
    v->half = o->half;
    v->pending_gi = -1;
    v->ab_rmse = -1;
    v->show_panel = !o->no_panel;
    snprintf(v->shot_path, sizeof v->shot_path, "%s", o->out ? o->out : "out/view.png");
    snprintf(v->window_path, sizeof v->window_path, "%s", o->window_out ? o->window_out : "out/window.png");
    render_options_settings(o, scene, &v->settings);
    v->settings.timings = true;
    v->settings.cache = true; /* the window's common case: lights still, camera moving */
    /* Per-pass times as `render --timings` measures them: on a software
     * rasterizer only with glFinish around each pass (see
     * gl_renderer_is_software); a GPU's timestamps need no stall. */
    v->settings.timing_sync = gl_renderer_is_software((const char *)glGetString(GL_RENDERER));
    /* The window shows the final image; the A/B view also reads the radiance. */
    v->live_wanted = o->live_reference;
    v->settings.display_only = o->compare == NULL && !v->live_wanted;
    v->edit.shadow = v->settings.set.shadow;
    v->edit.gi = v->settings.set.gi;
    v->camera = v->home = scene->camera;
    view_set_angles(v, &v->camera);
    view_update_camera(v);
    v->speed = 0.25f * glm_vec3_distance((float *)scene->bounds_min, (float *)scene->bounds_max);
    const SettingDesc *temporal = settings_find_name("frame.temporal");
    view_anim_init(v, scene, temporal && o->given[temporal - settings_table]);
}

/* The window's input callbacks, ImGui and the image area's view (with
 * --compare, its reference). False after a failure (it logged). */
static bool view_ui_open(ViewLoop *l, const RenderOptions *o, bool *have_present)
{
    GLFWwindow *win = l->win;
    glfwSetWindowUserPointer(win, l);
    /* Ours first: ImGui's callbacks chain to them. */
    glfwSetKeyCallback(win, on_key);
    glfwSetMouseButtonCallback(win, on_button);
    glfwSetCursorPosCallback(win, on_cursor);
    glfwSetScrollCallback(win, on_scroll);
    glfwSetCharCallback(win, on_char);
    glfwSetWindowFocusCallback(win, on_flag);
    glfwSetCursorEnterCallback(win, on_flag);
    glfwSetWindowRefreshCallback(win, on_refresh);
    glfwSetFramebufferSizeCallback(win, on_framebuffer_size);
    *have_present = false;
    if (!ui_create(win))
        return false;
    *have_present = ab_view_create(l->present);
    if (!*have_present)
        return false;
    if (o->compare && !ab_view_load_reference(l->present, o->compare))
        return false;
    l->v->ab = o->compare ? l->present : NULL;
    const AbView *ab = l->present;
    l->compare_display = ab->display;
    if (o->compare) { /* shown again after the live reference, and what its relMSE is measured against */
        if (!image_alloc(&l->compare_file, ab->reference.width, ab->reference.height)) {
            log_error("view", "--compare %s: out of memory for a copy of the reference", o->compare);
            return false;
        }
        memcpy(l->compare_file.rgb, ab->reference.rgb,
               sizeof(float) * 3 * (size_t)ab->reference.width * ab->reference.height);
    }
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    int threads = o->live_threads > 0 ? o->live_threads : cores > 0 ? (int)cores : 1;
    live_reference_init(&l->live, threads, o->live_spp, o->live_ordinary,
                        l->compare_file.rgb && !l->compare_display ? &l->compare_file : NULL);
    return true;
}

/* ---- The live reference ------------------------------------------------------- */

/* The A/B view's reference and the render thread's copy: `img` (NULL: none). */
static void live_show(ViewLoop *l, const ImageF *img, bool display)
{
    if (img && img->rgb) {
        ImageF copy;
        if (!image_alloc(&copy, img->width, img->height)) {
            log_error("view", "live reference: out of memory for a %dx%d image", img->width, img->height);
            return;
        }
        memcpy(copy.rgb, img->rgb, sizeof(float) * 3 * (size_t)img->width * img->height);
        if (!ab_view_set_reference(l->present, &copy, display, "live reference")) /* logs */
            image_free(&copy);
    } else {
        ab_view_clear_reference(l->present);
    }
    view_render_set_reference(l->render, img, display);
    l->dirty = true;
}

/* The live reference on, off, restarted or with a newer image, each pass
 * before the request (the frame's radiance is kept while it is on). */
static void loop_live(ViewLoop *l)
{
    View *v = l->v;
    LiveReference *live = &l->live;
    bool was = live->status.running;
    if (v->live_wanted) {
        int r = live_reference_update(live, v->scene, &v->camera, v->time, v->settings.width, v->settings.height);
        if (r < 0) {
            v->live_wanted = false; /* it logged why, on the panel's status line too */
        } else if (r > 0) {
            if (!was) {
                v->ab = l->present;
                v->settings.display_only = false;
                if (l->present->mode == AB_FRAME)
                    l->present->mode = AB_SPLIT;
            }
            live_show(l, NULL, false); /* the old state's image compared with the new frame would mislead */
        }
        if (live_reference_poll(live))
            live_show(l, &live->image, false);
    }
    if (!v->live_wanted && live->status.running) {
        live_reference_stop(live);
        live_show(l, l->compare_file.rgb ? &l->compare_file : NULL, l->compare_display);
        if (!l->compare_file.rgb) {
            v->ab = NULL;
            v->settings.display_only = true;
        }
    }
    if (memcmp(&v->live, &live->status, sizeof v->live)) {
        v->live = live->status;
        l->dirty = true;
    }
}

/* ---- The loop ------------------------------------------------------------------ */

/* Sizes the window for the image and, when shown, the panel beside it. */
static void loop_resize(ViewLoop *l)
{
    View *v = l->v;
    int panel = l->panel_docked ? (int)lroundf(VIEW_PANEL_WIDTH * l->scale) : 0;
    l->expect_w = v->settings.width + panel;
    l->expect_h = v->settings.height;
    l->expect_until = glfwGetTime() + 1.0;
    glfwSetWindowSize(l->win, (int)lroundf((float)l->expect_w / l->scale),
                      (int)lroundf((float)l->expect_h / l->scale));
    l->dirty = true;
    /* A scripted window waits for it (a window manager may refuse: then
     * the panel overlaps what it must). */
    while (l->sync && l->expect_w && glfwGetTime() < l->expect_until)
        glfwWaitEventsTimeout(0.01);
}

/* H (or the panel's close button) changed whether the panel is shown: the
 * window grows or shrinks by it, the image keeps its size. */
static void loop_layout(ViewLoop *l)
{
    if (l->v->show_panel == l->panel_docked)
        return;
    l->panel_docked = l->v->show_panel;
    loop_resize(l);
}

/* How long the window may sleep before its next pass (< 0: until an
 * event): a frame in flight ticks its busy indicator, a held key moves the
 * camera, input is followed by a couple of redraws, and the script's next
 * step is due; otherwise an idle window draws nothing. */
static double loop_timeout(const ViewLoop *l, const ViewRenderState *st, double now)
{
    double t = -1;
    if (l->moving || l->settle > 0)
        t = 1.0 / 60.0;
    else if (l->v->anim.playing && !st->busy) /* playback: the next frame as soon as the last is done */
        t = 1.0 / 120.0;
    else if (st->busy) {
        double busy = now - st->busy_since;
        t = busy < 0.25 ? 0.25 - busy : 0.1;
    }
    if (l->live.status.running && !l->live.status.done) /* the live reference's renderer or next image */
        t = t < 0 ? 0.1 : fmin(t, 0.1);
    if (l->script.async && l->script.deadline > 0) {
        double d = fmax(l->script.deadline - now, 0.0);
        t = t < 0 ? d : fmin(t, d);
    }
    return t;
}

/* What the render thread published since the last pass, into the View. */
static void loop_absorb(ViewLoop *l, const ViewRenderState *st, double now)
{
    View *v = l->v;
    if (st->version != l->state_version) {
        l->state_version = st->version;
        l->dirty = true;
    }
    v->busy = st->busy;
    v->busy_s = st->busy ? now - st->busy_since : 0;
    if (st->stats_version != l->stats_version) {
        l->stats_version = st->stats_version;
        v->stats = st->stats;
        char title[768];
        snprintf(title, sizeof title, "rtgi — %s — shadow %s, gi %s — %.1f ms/frame — H: panel", v->scene->source,
                 (const char *[]){"none", "hard", "pcf", "pcss"}[v->settings.shadow],
                 gi_techniques[v->settings.gi]->name, v->stats.frame_ms);
        glfwSetWindowTitle(l->win, title);
    }
    if (st->rmse_count != l->rmse_count) {
        l->rmse_count = st->rmse_count;
        v->ab_rmse = st->rmse;
    }
    GLuint program = view_render_take_program(l->render);
    if (program)
        ab_view_set_program(l->present, program);
    if (view_render_take(l->render, &l->image))
        l->dirty = true;
    if (st->diff_frame && st->diff_frame == l->image.frame && v->ab_auto_scale != st->diff_scale) {
        v->ab_auto_scale = st->diff_scale;
        l->dirty = true;
    }
}

/* The window: the image at the top left at its size, the panel docked
 * right of it, the busy indicator over the image; the captures of this
 * frame and the script's step; the swap. */
static void loop_draw(ViewLoop *l, const RenderOptions *o, const ViewRenderState *st)
{
    View *v = l->v;
    int fw, fh;
    glfwGetFramebufferSize(l->win, &fw, &fh);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fw, fh);
    glClearColor(0.f, 0.f, 0.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT);
    int iw = v->settings.width, ih = v->settings.height;
    if (l->image.ldr) /* a frame of another size (the window was resized, its frame is coming) is stretched */
        ab_view_draw(l->present, l->image.ldr, l->image.hdr, l->image.exposure, view_heat_scale(v), 0, fh - ih, iw,
                     ih);
    ui_frame_begin();
    view_panel_draw(v, (float)iw / l->scale, (float)fh / l->scale);
    view_busy_draw(v);
    ui_frame_end();
    view_busy_text(v, l->busy_shown, sizeof l->busy_shown);
    bool scripted_shot = o->window_out && o->frames > 0 && l->frame == o->frames - 1; /* the last frame's window */
    if (scripted_shot && !st->whole) {
        l->capture_failed = true; /* not written: see cmd_view's check after the loop */
        scripted_shot = false;
    }
    if (v->window_shot || scripted_shot) {
        /* A key's shot that fails is logged and the window goes on; the
         * scripted one is an output of the command. */
        if (!view_save_window(v, v->window_path, fw, fh) && scripted_shot)
            l->capture_failed = true;
        v->window_shot = false;
    }
    if (l->script.dir && l->sync && !view_script_step(&l->script, v, l->frame, fw, fh))
        l->sync = false; /* the script's second part: the window as a user has it */
    else if (l->script.async)
        view_script_capture(&l->script, v, fw, fh);
    glfwSwapBuffers(l->win);
    l->redraws++;
    l->redraw_at = glfwGetTime();
    l->dirty = false;
    if (l->settle > 0)
        l->settle--;
}

/* One pass: events (or the wait for them), input, the request to the
 * render thread (waited for when scripted), what it published, and the
 * window drawn again if anything changed. False when the render thread
 * failed (it logged). */
static bool loop_pass(ViewLoop *l, const RenderOptions *o)
{
    View *v = l->v;
    ViewRenderState st;
    view_render_state(l->render, &st);
    double now = glfwGetTime();
    if (l->sync)
        glfwPollEvents();
    else {
        double t = loop_timeout(l, &st, now);
        if (t < 0)
            glfwWaitEvents();
        else
            glfwWaitEventsTimeout(t);
        now = glfwGetTime();
    }
    l->passes++;
    if (l->expect_w && now > l->expect_until) /* the window manager kept its own size */
        l->expect_w = l->expect_h = 0;
    if (l->script.async) {
        view_render_state(l->render, &st);
        ViewScriptPass p = {.now = now, .redraws = l->redraws, .redraw_at = l->redraw_at, .wakeups = l->passes,
                            .state = st};
        if (!view_script_tick(&l->script, v, &p))
            glfwSetWindowShouldClose(l->win, GLFW_TRUE); /* the script is over */
        if (l->script.redraw) {
            l->script.redraw = false;
            l->dirty = true;
        }
    }
    /* The camera: movement keys held since the last pass (none the pass a
     * key goes down: a tap moves by what it was held, not by how long the
     * window slept before it). */
    bool was_moving = l->moving;
    l->moving = view_move(v, l->win, was_moving ? (float)(now - l->last) : 0.f);
    l->moving = view_anim_move_light(v, l->win, was_moving ? (float)(now - l->last) : 0.f) || l->moving;
    l->last = now;
    if (l->moving)
        l->dirty = true; /* the panel's camera follows */
    view_update_camera(v);
    if (view_anim_advance(v, now)) /* playback's time, the animation's camera, temporal's setting */
        l->dirty = true;
    if (v->quit)
        glfwSetWindowShouldClose(l->win, GLFW_TRUE);
    loop_layout(l);
    loop_live(l);

    ViewRequest req;
    memset(&req, 0, sizeof req);
    req.scene.settings = v->settings;
    req.scene.camera = v->camera;
    req.scene.time = v->time;
    req.scene.lights = v->anim.edits;
    req.force = l->sync || l->passes == 1;
    req.jobs = v->jobs;
    if (v->jobs & VIEW_JOB_SAVE) {
        snprintf(req.save_path, sizeof req.save_path, "%s", v->shot_path);
        req.half = v->half;
    }
    v->jobs = 0;
    req.diff_scale = v->ab && v->ab->mode == AB_DIFFERENCE && v->ab->diff_auto;
    req.hold_timer = l->script.dir && l->sync && l->frame < 3; /* the script's table of frames 1-2 */
    req.test_sleep_s = l->script.sleep_s;
    l->script.sleep_s = 0;
    view_render_submit(l->render, &req);
    if (l->sync)
        view_render_wait(l->render);

    view_render_state(l->render, &st);
    if (st.failed)
        return false;
    loop_absorb(l, &st, now);
    char busy[96];
    view_busy_text(v, busy, sizeof busy);
    if (strcmp(busy, l->busy_shown))
        l->dirty = true;
    if (l->sync || l->dirty || l->settle > 0 || v->window_shot) {
        bool sync = l->sync;
        loop_draw(l, o, &st);
        if (sync)
            l->frame++;
    }
    return true;
}

/* ---- The command ------------------------------------------------------------- */

int cmd_view(int argc, char **argv)
{
    RenderOptions o;
    render_options_init(&o, true);
    int rc = render_options_parse(&o, argc, argv, cmd_view_help);
    if (rc != 0)
        return rc < 0 ? 0 : rc;
    Scene scene;
    if (!render_options_load_scene(&o, &scene))
        return 1;
    GLFWwindow *render_context = NULL;
    GLFWwindow *win = view_window_open(&o, &render_context);
    if (!win) {
        scene_free(&scene);
        return 1;
    }

    ViewStatus status;
    memset(&status, 0, sizeof status);
    pthread_mutex_init(&status.lock, NULL);
    View v;
    view_init(&v, &o, &scene, &status);
    AbView present;
    ViewLoop loop;
    memset(&loop, 0, sizeof loop);
    loop.v = &v;
    loop.win = win;
    loop.present = &present;
    loop.script.dir = o.ui_test;
    loop.script.animation = o.ui_test && animation_present(&scene); /* the animation script */
    loop.sync = o.frames > 0 || o.ui_test;
    loop.panel_docked = v.show_panel;
    int ww, wh, fw, fh;
    glfwGetWindowSize(win, &ww, &wh);
    glfwGetFramebufferSize(win, &fw, &fh);
    loop.scale = ww > 0 ? (float)fw / (float)ww : 1.f;
    bool have_present;
    bool ok = view_ui_open(&loop, &o, &have_present);
    if (ok && loop.scale != 1.f) /* screen coordinates are not pixels (a HiDPI screen): the image keeps --size */
        loop_resize(&loop);
    log_set_hook(view_status_log_hook, &status);
    if (ok) {
        ViewRequest first;
        memset(&first, 0, sizeof first);
        first.scene.settings = v.settings;
        first.scene.camera = v.camera;
        first.scene.time = v.time;
        first.scene.lights = v.anim.edits;
        ViewRenderDesc d = {.context = render_context, .scene = &scene, .ab = v.ab, .status = &status,
                            .first = &first, .gl_renderer = (const char *)glGetString(GL_RENDERER),
                            .debug = o.debug};
        loop.render = view_render_start(&d);
        loop.script.render = loop.render;
        loop.script.win = win;
        ok = loop.render != NULL;
    }
    loop.last = glfwGetTime();
    while (ok && !loop.capture_failed && !glfwWindowShouldClose(win) && (o.frames == 0 || loop.frame < o.frames))
        ok = loop_pass(&loop, &o);
    ViewRenderState st;
    memset(&st, 0, sizeof st);
    if (loop.render)
        view_render_state(loop.render, &st);
    ok = ok && !loop.capture_failed && !st.failed;
    /* A scripted run (--frames N) is a command that writes images: like
     * render, it fails where a program did not build or a technique's run
     * failed, which the window itself goes on through. */
    if (ok && o.frames > 0 && !st.whole)
        ok = false;
    rc = ok ? 0 : 1;
    if (ok && o.out && o.frames > 0) {
        view_render_jobs(loop.render, VIEW_JOB_SAVE, o.out, o.half);
        view_render_wait(loop.render);
        view_render_state(loop.render, &st);
        if (!st.save_ok) {
            rc = 1;
            if (o.window_out)
                remove(o.window_out); /* all outputs or none */
        }
    }
    glfwHideWindow(win); /* gone at once, though the render thread finishes its frame */
    if (loop.render) {
        view_render_state(loop.render, &st);
        if (st.busy && glfwGetTime() - st.busy_since > 1.0) /* a compute dispatch cannot be cut short */
            log_info("view", "closing once the frame being drawn is done (%.0f s so far)",
                     glfwGetTime() - st.busy_since);
    }
    live_reference_stop(&loop.live);
    view_render_stop(loop.render);
    log_set_hook(NULL, NULL);
    if (have_present)
        ab_view_destroy(&present);
    ui_destroy();
    glfwDestroyWindow(render_context);
    glfwDestroyWindow(win);
    glfwTerminate();
    pthread_mutex_destroy(&status.lock);
    image_free(&loop.compare_file);
    scene_free(&scene);
    return rc;
}
