/* cmd_view.c — `rtgi view`: the renderer in a window (GLFW), with a camera
 * and technique toggles; per-pass GPU time in the title. Same options as
 * `render`; --frames N exits after N frames and --out saves the last frame
 * (for scripted screenshots, e.g. under xvfb-run). */
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
#include "util.h"

void cmd_view_help(void)
{
    printf("usage: rtgi view [options]\n"
           "An interactive window: WASD move, Q/E down/up, Shift faster, left-drag to look,\n"
           "1-4 shadows none/hard/pcf/pcss, G/Shift-G next/previous GI technique,\n"
           "+/- exposure, F FXAA on/off, R reset camera, T print timings, P screenshot, H help, Esc quit.\n"
           "--frames N exits after N frames; --out FILE.png saves the last frame.\n");
    render_options_help();
}

typedef struct View {
    Camera camera;         /* current camera */
    Camera home;           /* the scene's camera, for R */
    float yaw, pitch;      /* radians; forward = (cos p sin y, sin p, cos p cos y) */
    float speed;           /* metres per second */
    RenderSettings settings;
    bool dirty;            /* settings changed: rebuild the renderer */
    bool dragging;
    double last_x, last_y;
    bool print_timings, screenshot;
} View;

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
    if (action != GLFW_PRESS)
        return;
    RenderSettings *s = &v->settings;
    switch (key) {
    case GLFW_KEY_ESCAPE:
        glfwSetWindowShouldClose(w, GLFW_TRUE);
        break;
    case GLFW_KEY_1: case GLFW_KEY_2: case GLFW_KEY_3: case GLFW_KEY_4:
        s->shadow = (ShadowMode)(key - GLFW_KEY_1);
        v->dirty = true;
        break;
    case GLFW_KEY_G:
        s->gi = (GiMode)((s->gi + ((mods & GLFW_MOD_SHIFT) ? GI_MODE_COUNT - 1 : 1)) % GI_MODE_COUNT);
        v->dirty = true;
        log_info("view", "GI: %s", gi_technique_names()[s->gi]);
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
    case GLFW_KEY_R:
        v->camera = v->home;
        view_set_angles(v, &v->camera);
        break;
    case GLFW_KEY_T:
        v->print_timings = true;
        break;
    case GLFW_KEY_P:
        v->screenshot = true;
        break;
    case GLFW_KEY_H:
        cmd_view_help();
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
        v->dragging = action == GLFW_PRESS;
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

static void on_glfw_error(int code, const char *msg)
{
    log_error("view", "GLFW error %d: %s", code, msg);
}

/* Continuous movement from the keys held this frame. */
static void view_move(View *v, GLFWwindow *w, float dt)
{
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

static bool save_screenshot(Renderer *r, const char *path)
{
    uint8_t *rgb = renderer_read_ldr(r);
    util_ensure_parent_dir(path);
    bool ok = image_write_png8(path, r->settings.width, r->settings.height, rgb);
    free(rgb);
    if (ok)
        log_info("view", "wrote %s", path);
    return ok;
}

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

    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        log_error("view", "cannot open a window (no display?); use 'rtgi render' for headless images");
        scene_free(&scene);
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, o.debug ? GLFW_TRUE : GLFW_FALSE);
    GLFWwindow *win = glfwCreateWindow(o.width, o.height, "rtgi", NULL, NULL);
    if (!win) {
        log_error("view", "cannot create a window with an OpenGL 4.5 core context");
        glfwTerminate();
        scene_free(&scene);
        return 1;
    }
    glfwMakeContextCurrent(win);
    glfwSwapInterval(o.frames > 0 ? 0 : 1);
    if (o.debug)
        gl_install_debug_callback();

    View v = {0};
    render_options_settings(&o, &scene, &v.settings);
    v.settings.timings = true;
    v.settings.cache = true; /* the window's common case: lights still, camera moving */
    v.settings.timing_sync = false;
    v.camera = v.home = scene.camera;
    view_set_angles(&v, &v.camera);
    v.speed = 0.25f * glm_vec3_distance(scene.bounds_min, scene.bounds_max);
    glfwSetWindowUserPointer(win, &v);
    glfwSetKeyCallback(win, on_key);
    glfwSetMouseButtonCallback(win, on_button);
    glfwSetCursorPosCallback(win, on_cursor);

    Renderer r;
    bool ok = renderer_create(&r, &scene, &v.settings);
    int frame = 0;
    double last = glfwGetTime(), title_time = last;
    while (ok && !glfwWindowShouldClose(win) && (o.frames == 0 || frame < o.frames)) {
        glfwPollEvents();
        double now = glfwGetTime();
        view_move(&v, win, (float)(now - last));
        last = now;
        view_update_camera(&v);
        int fw, fh;
        glfwGetFramebufferSize(win, &fw, &fh);
        if (fw > 0 && fh > 0 && (fw != v.settings.width || fh != v.settings.height)) {
            v.settings.width = fw;
            v.settings.height = fh;
            v.dirty = true;
        }
        if (v.dirty) {
            /* Remakes only what the change touches (nothing for exposure). */
            ok = renderer_apply(&r, &v.settings);
            v.dirty = false;
            if (!ok)
                break;
        }
        renderer_frame(&r, &v.camera);
        glBlitNamedFramebuffer(r.ldr.fbo, 0, 0, 0, r.ldr.width, r.ldr.height, 0, 0, fw, fh, GL_COLOR_BUFFER_BIT,
                               GL_NEAREST);
        glfwSwapBuffers(win);
        frame++;
        if (v.print_timings) {
            render_options_print_timings(&r, (const char *)glGetString(GL_RENDERER), 0.0);
            v.print_timings = false;
        }
        if (v.screenshot) {
            save_screenshot(&r, o.out ? o.out : "out/view.png");
            v.screenshot = false;
        }
        if (now - title_time > 0.5 && r.timer.frames > 0) {
            double total = 0;
            for (int i = 0; i < r.timer.pass_count; i++)
                total += r.timer.passes[i].gpu_ms / r.timer.frames;
            char title[768];
            snprintf(title, sizeof title, "rtgi — %s — shadow %s, gi %s — %.1f ms GPU", scene.source,
                     (const char *[]){"none", "hard", "pcf", "pcss"}[v.settings.shadow],
                     gi_technique_names()[v.settings.gi], total);
            glfwSetWindowTitle(win, title);
            gpu_timer_reset(&r.timer);
            title_time = now;
        }
    }
    rc = ok ? 0 : 1;
    if (ok && o.out && o.frames > 0 && !save_screenshot(&r, o.out))
        rc = 1;
    renderer_destroy(&r);
    glfwDestroyWindow(win);
    glfwTerminate();
    scene_free(&scene);
    return rc;
}
