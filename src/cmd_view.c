/* cmd_view.c — `rtgi view`: the renderer in a window (GLFW) with a Dear
 * ImGui panel (src/ui/view_panel.c): camera, technique and settings,
 * timings, captures, shader hot reload and the A/B view of --compare.
 * The window's render size is its framebuffer size. --frames N exits after
 * N frames and --out saves the last frame (scripted screenshots, e.g. under
 * xvfb-run); --ui-test DIR runs a fixed script through the panel's actions
 * and reports what it measured (src/ui/view_script.c; tests/test_view.c). */
#include <epoxy/gl.h> /* before GLFW, which must not pull in GL/gl.h */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "gl_context.h"
#include "log.h"
#include "render_options.h"
#include "renderer.h"
#include "shader.h"
#include "ui/ab_view.h"
#include "ui/ui.h"
#include "ui/view_panel.h"
#include "ui/view_script.h"
#include "util.h"

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
           "  H hide/show the panel, Esc quit.\n"
           "options:\n"
           "  --scene cornell|FILE.json|FILE.gltf|FILE.obj   scene (default: cornell)\n"
           "  --size WxH                    window and render size (default: 512x512)\n"
           "  --shadow none|hard|pcf|pcss   shadow technique (default: pcss)\n"
           "  --gi TECHNIQUE                indirect light (default: none), see below\n"
           "  --exposure E                  radiance multiplier before tone mapping (default: scene's)\n"
           "  --light-scale S               scale every light's emitter size (0: point lights)\n"
           "  --ssaa N                      N x N supersampling, box filter (default: 1, off)\n"
           "  --aa none|fxaa                post-process AA (default: fxaa)\n"
           "  --compare FILE                reference image for the A/B view (split, reference,\n"
           "                                difference): .pfm or .exr radiance at the window's\n"
           "                                exposure, .png shown as it is\n"
           "  --frames N                    exit after N frames (default: 0, run until closed)\n"
           "  --out FILE                    the image P saves, and with --frames the last frame:\n"
           "                                .png as shown, .pfm or .exr linear radiance\n"
           "                                (default: out/view.png)\n"
           "  --half                        .exr captures as half floats (default: float32)\n"
           "  --window-out FILE.png         what Shift-P saves: the window, panel included\n"
           "                                (default: out/window.png); with --frames, the last frame's\n"
           "  --slow-ms MS                  techniques estimated above MS per frame need a\n"
           "                                confirming click (default: 1000)\n"
           "  --no-panel                    start with the panel hidden (H shows it)\n"
           "  --ui-test DIR                 run the window test's script, write its captures to DIR\n"
           "  --shader-dir DIR              read shaders from DIR instead of the embedded copies\n"
           "  --debug                       GL debug context, KHR_debug messages logged\n"
           "  --quiet | --verbose\n");
    render_options_help_settings();
}

/* ---- Input ------------------------------------------------------------------ */

static void view_set_angles(View *v, const Camera *c)
{
    v->yaw = atan2f(c->forward[0], c->forward[2]);
    v->pitch = asinf(fmaxf(-1.f, fminf(1.f, c->forward[1])));
}

static void view_update_camera(View *v)
{
    Camera *c = &v->camera;
    c->forward[0] = cosf(v->pitch) * sinf(v->yaw);
    c->forward[1] = sinf(v->pitch);
    c->forward[2] = cosf(v->pitch) * cosf(v->yaw);
    vec3 right;
    glm_vec3_cross(c->forward, (vec3){0, 1, 0}, right);
    glm_vec3_normalize(right);
    glm_vec3_cross(right, c->forward, c->up);
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    View *v = glfwGetWindowUserPointer(w);
    if (action != GLFW_PRESS || ui_wants_keyboard())
        return;
    RenderSettings *s = &v->settings;
    bool shift = (mods & GLFW_MOD_SHIFT) != 0;
    switch (key) {
    case GLFW_KEY_ESCAPE:
        glfwSetWindowShouldClose(w, GLFW_TRUE);
        break;
    case GLFW_KEY_1: case GLFW_KEY_2: case GLFW_KEY_3: case GLFW_KEY_4:
        s->shadow = (ShadowMode)(key - GLFW_KEY_1);
        v->dirty = true;
        break;
    case GLFW_KEY_G:
        view_cycle_gi(v, shift ? -1 : 1);
        break;
    case GLFW_KEY_EQUAL: case GLFW_KEY_KP_ADD:
        s->exposure *= 1.25f;
        v->dirty = true;
        break;
    case GLFW_KEY_MINUS: case GLFW_KEY_KP_SUBTRACT:
        s->exposure /= 1.25f;
        v->dirty = true;
        break;
    case GLFW_KEY_F:
        s->aa = s->aa == AA_FXAA ? AA_NONE : AA_FXAA;
        v->dirty = true;
        log_info("view", "AA: %s", s->aa == AA_FXAA ? "fxaa" : "none");
        break;
    case GLFW_KEY_C:
        if (v->ab)
            v->ab->mode = (AbMode)((v->ab->mode + 1) % AB_MODE_COUNT);
        break;
    case GLFW_KEY_R:
        v->camera = v->home;
        view_set_angles(v, &v->camera);
        break;
    case GLFW_KEY_T:
        v->print_timings = true;
        break;
    case GLFW_KEY_P:
        if (shift)
            v->window_shot = true;
        else
            v->screenshot = true;
        break;
    case GLFW_KEY_F5:
        v->reload = true;
        break;
    case GLFW_KEY_H:
        v->show_panel = !v->show_panel;
        break;
    default:
        break;
    }
}

static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    (void)mods;
    View *v = glfwGetWindowUserPointer(w);
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
        v->dragging = action == GLFW_PRESS && !ui_wants_mouse();
        glfwGetCursorPos(w, &v->last_x, &v->last_y);
    }
}

static void on_cursor(GLFWwindow *w, double x, double y)
{
    View *v = glfwGetWindowUserPointer(w);
    if (!v->dragging)
        return;
    v->yaw -= (float)(x - v->last_x) * 0.004f;
    v->pitch -= (float)(y - v->last_y) * 0.004f;
    v->pitch = fmaxf(-1.55f, fminf(1.55f, v->pitch));
    v->last_x = x;
    v->last_y = y;
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

/* Shader errors (and other errors) of the window go to the panel's status. */
static void on_log(LogLevel level, const char *tag, const char *message, void *user)
{
    View *v = user;
    if (level < LOG_ERROR)
        return;
    size_t len = strlen(v->status);
    if (v->reloading && v->status_error && len + 4 < sizeof v->status) /* a reload's errors, first one first */
        snprintf(v->status + len, sizeof v->status - len, " | [%s] %s", tag, message);
    else
        snprintf(v->status, sizeof v->status, "[%s] %s", tag, message);
    v->status_error = true;
}

/* Continuous movement from the keys held this frame. */
static void view_move(View *v, GLFWwindow *w, float dt)
{
    if (ui_wants_keyboard())
        return;
    float step = v->speed * dt * (glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ? 4.f : 1.f);
    vec3 right;
    glm_vec3_cross(v->camera.forward, v->camera.up, right);
    struct { int key; float *axis; float sign; } moves[] = {
        {GLFW_KEY_W, v->camera.forward, 1}, {GLFW_KEY_S, v->camera.forward, -1}, {GLFW_KEY_D, right, 1},
        {GLFW_KEY_A, right, -1},            {GLFW_KEY_E, (vec3){0, 1, 0}, 1},    {GLFW_KEY_Q, (vec3){0, 1, 0}, -1},
    };
    for (size_t i = 0; i < sizeof moves / sizeof moves[0]; i++)
        if (glfwGetKey(w, moves[i].key) == GLFW_PRESS)
            glm_vec3_muladds(moves[i].axis, moves[i].sign * step, v->camera.position);
}

/* ---- The window -------------------------------------------------------------- */

/* GLFW, and a window of --size with an OpenGL 4.5 core context made
 * current; NULL after logging why (GLFW is terminated then). */
static GLFWwindow *view_window_open(const RenderOptions *o)
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
    GLFWwindow *win = glfwCreateWindow(o->width, o->height, "rtgi", NULL, NULL);
    if (!win) {
        log_error("view", "cannot create a window with an OpenGL 4.5 core context%s%s", s_glfw_error[0] ? ": " : "",
                  s_glfw_error);
        glfwTerminate();
        return NULL;
    }
    s_glfw_window_up = true;
    glfwMakeContextCurrent(win);
    glfwSwapInterval(o->frames > 0 || o->ui_test ? 0 : 1);
    if (o->debug)
        gl_install_debug_callback();
    return win;
}

/* The view's state from the options and the scene (needs the context:
 * the timer's mode depends on the GL renderer). */
static void view_init(View *v, const RenderOptions *o, const Scene *scene, Renderer *r)
{
    memset(v, 0, sizeof *v);
    v->scene = scene;
    v->renderer = r;
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
    v->edit.shadow = v->settings.shadow_params;
    v->edit.gi = v->settings.gi_params;
    v->camera = v->home = scene->camera;
    view_set_angles(v, &v->camera);
    v->speed = 0.25f * glm_vec3_distance((float *)scene->bounds_min, (float *)scene->bounds_max);
}

/* The window's input callbacks, ImGui and, with --compare, the A/B view
 * (*have_ab: `ab` was made and needs ab_view_destroy). False after a
 * failure (it logged). */
static bool view_ui_open(GLFWwindow *win, View *v, const RenderOptions *o, AbView *ab, bool *have_ab)
{
    glfwSetWindowUserPointer(win, v);
    /* Ours first: ImGui's callbacks chain to them. */
    glfwSetKeyCallback(win, on_key);
    glfwSetMouseButtonCallback(win, on_button);
    glfwSetCursorPosCallback(win, on_cursor);
    *have_ab = false;
    if (!ui_create(win))
        return false;
    if (!o->compare)
        return true;
    *have_ab = ab_view_create(ab, o->compare);
    v->ab = *have_ab ? ab : NULL;
    if (*have_ab && v->show_panel) /* the split starts mid-way across the image beside the panel */
        ab->split = 0.5f + (6.f + view_panel_width(o->width)) / (2.f * (float)o->width);
    return *have_ab;
}

/* ---- The loop ------------------------------------------------------------------ */

/* What the loop carries from one frame to the next. */
typedef struct ViewLoop {
    GLFWwindow *win;
    ViewScript script;      /* --ui-test: its state (dir NULL: none) */
    int frame;              /* frames drawn */
    int interval_frames;    /* frames in the timing interval */
    bool interval_clean;    /* no remake, reload or first frame in the interval: its time is a cost */
    double last;            /* when the last frame began (glfwGetTime) */
    double interval_start;  /* when the interval began */
    bool capture_failed;    /* the scripted --window-out capture failed: the command fails */
} ViewLoop;

/* The window's size, a shader reload and changed settings, applied
 * before a frame. False when the renderer could not take them (it logged). */
static bool view_apply_changes(View *v, ViewLoop *l, int fw, int fh)
{
    Renderer *r = v->renderer;
    if (fw > 0 && fh > 0 && (fw != v->settings.width || fh != v->settings.height)) {
        v->settings.width = fw;
        v->settings.height = fh;
        v->dirty = true;
    }
    if (v->reload) {
        view_reload_shaders(v);
        v->reload = false;
        l->interval_clean = false;
    }
    if (v->dirty) {
        l->interval_clean = false;
        const RenderSettings *was = &r->settings, *want = &v->settings;
        if (memcmp(&was->gi_params, &want->gi_params, sizeof was->gi_params) ||
            memcmp(&was->shadow_params, &want->shadow_params, sizeof was->shadow_params) ||
            was->shadow != want->shadow || was->ssaa != want->ssaa || was->aa != want->aa)
            memset(v->measured_px, 0, sizeof v->measured_px); /* the measured costs were for other settings */
        /* Remakes only what the change touches (nothing for exposure). */
        bool applied = renderer_apply(r, &v->settings);
        v->dirty = false;
        if (!applied)
            return false;
    }
    /* The window shows the final image; the A/B view reads the radiance. */
    v->settings.display_only = v->ab == NULL;
    return r->settings.display_only == v->settings.display_only || renderer_apply(r, &v->settings);
}

/* One frame: input and camera, the changes applied, the image (or the A/B
 * view), the panel, the captures, the script's step, the swap. False when
 * the changes could not be applied (it logged): the frame was abandoned. */
static bool view_frame_step(View *v, ViewLoop *l, const RenderOptions *o)
{
    Renderer *r = v->renderer;
    glfwPollEvents();
    double now = glfwGetTime();
    view_move(v, l->win, (float)(now - l->last));
    l->last = now;
    view_update_camera(v);
    int fw, fh;
    glfwGetFramebufferSize(l->win, &fw, &fh);
    if (!view_apply_changes(v, l, fw, fh))
        return false;
    renderer_frame(r, &v->camera);
    if (v->ab)
        ab_view_draw(v->ab, r, fw, fh);
    else
        glBlitNamedFramebuffer(r->ldr.fbo, 0, 0, 0, r->ldr.width, r->ldr.height, 0, 0, fw, fh, GL_COLOR_BUFFER_BIT,
                               GL_NEAREST);
    ui_frame_begin();
    view_panel_draw(v, fw, fh);
    ui_frame_end();
    bool scripted_shot = o->window_out && o->frames > 0 && l->frame == o->frames - 1; /* the last frame's window */
    if (scripted_shot && !renderer_frames_whole(r)) {
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
    if (v->screenshot) {
        view_save_image(v, v->shot_path);
        v->screenshot = false;
    }
    if (l->script.dir && !view_script_step(&l->script, v, l->frame, fw, fh))
        glfwSetWindowShouldClose(l->win, GLFW_TRUE);
    glfwSwapBuffers(l->win);
    l->frame++;
    l->interval_frames++;
    return true;
}

/* After a frame: the timings table on T, and every half second (or 30
 * frames) the interval's timings recorded and the window's title. */
static void view_interval_update(View *v, ViewLoop *l)
{
    Renderer *r = v->renderer;
    double end = glfwGetTime();
    if (v->print_timings) {
        /* Before the first interval is measured: this frame's wall time. */
        render_options_print_timings(r, (const char *)glGetString(GL_RENDERER),
                                     v->frame_ms > 0 ? v->frame_ms : 1e3 * (end - l->last));
        v->print_timings = false;
    }
    bool script_timing = l->script.dir && l->frame < 3; /* the script's table holds frames 1-2 */
    if ((end - l->interval_start > 0.5 || l->interval_frames >= 30) && r->timer.frames > 0 && !script_timing) {
        view_record_timings(v, 1e3 * (end - l->interval_start) / l->interval_frames, l->interval_clean);
        char title[768];
        snprintf(title, sizeof title, "rtgi — %s — shadow %s, gi %s — %.1f ms/frame — H: panel", v->scene->source,
                 (const char *[]){"none", "hard", "pcf", "pcss"}[v->settings.shadow],
                 gi_techniques[v->settings.gi]->name, v->frame_ms);
        glfwSetWindowTitle(l->win, title);
        gpu_timer_reset(&r->timer);
        l->interval_start = end;
        l->interval_frames = 0;
        l->interval_clean = true;
    }
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
    GLFWwindow *win = view_window_open(&o);
    if (!win) {
        scene_free(&scene);
        return 1;
    }

    Renderer r;
    View v;
    view_init(&v, &o, &scene, &r);
    AbView ab;
    bool have_ab;
    bool ok = view_ui_open(win, &v, &o, &ab, &have_ab);
    bool have_renderer = ok; /* a failed create is destroyed too */
    if (ok)
        ok = renderer_create(&r, &scene, &v.settings);
    log_set_hook(on_log, &v);
    ViewLoop loop = {.win = win, .script = {.dir = o.ui_test}};
    loop.last = loop.interval_start = glfwGetTime();
    while (ok && !loop.capture_failed && !glfwWindowShouldClose(win) && (o.frames == 0 || loop.frame < o.frames)) {
        ok = view_frame_step(&v, &loop, &o);
        if (ok)
            view_interval_update(&v, &loop);
    }
    log_set_hook(NULL, NULL);
    ok = ok && !loop.capture_failed;
    /* A scripted run (--frames N) is a command that writes images: like
     * render, it fails where a program did not build or a technique's run
     * failed, which the window itself goes on through. */
    if (ok && o.frames > 0 && !renderer_frames_whole(&r))
        ok = false;
    rc = ok ? 0 : 1;
    if (ok && o.out && o.frames > 0 && !view_save_image(&v, o.out)) {
        rc = 1;
        if (o.window_out)
            remove(o.window_out); /* all outputs or none */
    }
    if (have_renderer)
        renderer_destroy(&r);
    if (have_ab)
        ab_view_destroy(&ab);
    ui_destroy();
    glfwDestroyWindow(win);
    glfwTerminate();
    scene_free(&scene);
    return rc;
}
