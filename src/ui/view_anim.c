/* view_anim.c — see view_anim.h. */
#include "ui/view_anim.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/animation.h"
#include "base/log.h"
#include "ui/ui.h"

/* How fast the light keys move a light: this fraction of the camera's
 * speed (a quarter of the scene's diagonal per second at first), and turn
 * a directional light (radians per second); Shift: 4× both. */
#define LIGHT_SPEED_FRACTION 0.5f
#define LIGHT_TURN_RATE 0.5f
#define LIGHT_POWER_STOPS 10.f /* the power slider: × 2^-10 .. × 2^10 */

static int light_count(const Scene *s) { return s->light_count < VIEW_MAX_LIGHTS ? s->light_count : VIEW_MAX_LIGHTS; }

void view_light_edit_apply(const ViewLightEdits *e, int i, Light *l)
{
    if (l->type == LIGHT_DIRECTIONAL) {
        float az = atan2f(l->direction[0], l->direction[2]) + e->turn[i][0];
        float el = asinf(fmaxf(-1.f, fminf(1.f, l->direction[1]))) + e->turn[i][1];
        el = fmaxf(-1.56f, fminf(1.56f, el)); /* short of straight up or down */
        if (e->turn[i][0] != 0.f || e->turn[i][1] != 0.f) {
            l->direction[0] = cosf(el) * sinf(az);
            l->direction[1] = sinf(el);
            l->direction[2] = cosf(el) * cosf(az);
        }
    } else {
        glm_vec3_add(l->position, (float *)e->move[i], l->position);
    }
    if (e->stops[i] != 0.f)
        glm_vec3_scale(l->color, exp2f(e->stops[i]), l->color);
}

/* ---- The window's thread ------------------------------------------------------ */

void view_anim_init(View *v, const Scene *s, bool temporal_given)
{
    ViewAnim *a = &v->anim;
    memset(a, 0, sizeof *a);
    a->present = animation_present(s);
    a->duration = animation_duration(s);
    a->loop = true;
    a->light_count = light_count(s);
    memcpy(a->base, s->lights, sizeof(Light) * (size_t)a->light_count);
    Camera c = v->camera;
    a->camera_tracks = animation_camera_at(s, 0.0, &c);
    a->follow_camera = a->camera_tracks;
    a->follow_yaw = v->yaw;
    a->follow_pitch = v->pitch;
    glm_vec3_copy(v->camera.position, a->follow_position);
    a->temporal_scene = s->settings.gi.frame.temporal;
    a->temporal_auto = a->present && !temporal_given;
    a->temporal_written = v->settings.set.gi.frame.temporal;
    a->shown = *s;
    memcpy(a->shown_lights, s->lights, sizeof(Light) * (size_t)a->light_count);
    a->shown.lights = a->shown_lights;
    a->shown.light_count = a->light_count;
    v->scene = &a->shown;
}

void view_anim_play(View *v, bool play, double now)
{
    ViewAnim *a = &v->anim;
    if (!a->present)
        return;
    if (play && !a->loop && v->time >= a->duration)
        v->time = 0;
    a->playing = play;
    a->play_time0 = v->time;
    a->play_wall0 = now;
    log_info("view", "animation %s at %.3f s", play ? "playing" : "paused", v->time);
}

void view_anim_scrub(View *v, double t, double now)
{
    ViewAnim *a = &v->anim;
    if (!a->present)
        return;
    v->time = fmax(0.0, fmin(t, (double)a->duration));
    a->play_time0 = v->time;
    a->play_wall0 = now;
}

void view_anim_set_stops(View *v, int i, float stops)
{
    if (i >= 0 && i < v->anim.light_count)
        v->anim.edits.stops[i] = fmaxf(-LIGHT_POWER_STOPS, fminf(LIGHT_POWER_STOPS, stops));
}

bool view_anim_key(View *v, int key, int mods)
{
    ViewAnim *a = &v->anim;
    switch (key) {
    case GLFW_KEY_SPACE:
        view_anim_play(v, !a->playing, glfwGetTime());
        return true;
    case GLFW_KEY_L:
        if (a->light_count > 0)
            a->light = (a->light + ((mods & GLFW_MOD_SHIFT) ? a->light_count - 1 : 1)) % a->light_count;
        return true;
    default:
        return false;
    }
}

void view_anim_light(const View *v, int i, Light *out)
{
    const ViewAnim *a = &v->anim;
    Light lights[VIEW_MAX_LIGHTS];
    memcpy(lights, a->base, sizeof(Light) * (size_t)a->light_count);
    animation_lights_at(v->scene, v->time, lights);
    *out = lights[i];
    view_light_edit_apply(&a->edits, i, out);
}

void view_anim_light_step(View *v, int key, bool fast, float dt)
{
    ViewAnim *a = &v->anim;
    int i = a->light;
    if (i < 0 || i >= a->light_count)
        return;
    float k = (fast ? 4.f : 1.f) * fminf(fmaxf(dt, 0.f), VIEW_MOVE_MAX_DT);
    float x = key == GLFW_KEY_RIGHT ? 1.f : key == GLFW_KEY_LEFT ? -1.f : 0.f;
    float z = key == GLFW_KEY_UP ? 1.f : key == GLFW_KEY_DOWN ? -1.f : 0.f;
    float y = key == GLFW_KEY_PAGE_UP ? 1.f : key == GLFW_KEY_PAGE_DOWN ? -1.f : 0.f;
    if (a->base[i].type == LIGHT_DIRECTIONAL) { /* arrows turn it; Page Up / Down as up / down */
        a->edits.turn[i][0] += x * LIGHT_TURN_RATE * k;
        a->edits.turn[i][1] += (z + y) * LIGHT_TURN_RATE * k;
        a->edits.turn[i][1] = fmaxf(-3.2f, fminf(3.2f, a->edits.turn[i][1]));
        return;
    }
    /* Across the view along the ground: the camera's forward and right
     * flattened onto the horizontal plane. */
    vec3 fwd = {v->camera.forward[0], 0.f, v->camera.forward[2]}, right;
    if (glm_vec3_norm(fwd) < 1e-4f) { /* looking straight down or up: "away" is where the camera's top points */
        glm_vec3_copy(v->camera.up, fwd);
        fwd[1] = 0.f;
    }
    if (glm_vec3_norm(fwd) < 1e-4f)
        glm_vec3_copy((vec3){0.f, 0.f, -1.f}, fwd);
    glm_vec3_normalize(fwd);
    glm_vec3_cross(fwd, (vec3){0.f, 1.f, 0.f}, right);
    float step = LIGHT_SPEED_FRACTION * v->speed * k;
    Light l;
    view_anim_light(v, i, &l);
    vec3 p;
    for (int c = 0; c < 3; c++)
        p[c] = l.position[c] + step * (x * right[c] + z * fwd[c] + (c == 1 ? y : 0.f));
    const Scene *s = v->scene;
    float margin = 0.5f * glm_vec3_distance((float *)s->bounds_min, (float *)s->bounds_max);
    for (int c = 0; c < 3; c++) {
        p[c] = fmaxf(s->bounds_min[c] - margin, fminf(s->bounds_max[c] + margin, p[c]));
        a->edits.move[i][c] += p[c] - l.position[c];
    }
}

bool view_anim_move_light(View *v, GLFWwindow *w, float dt)
{
    if (ui_wants_keyboard() || v->anim.light_count == 0)
        return false;
    static const int keys[] = {GLFW_KEY_LEFT, GLFW_KEY_RIGHT, GLFW_KEY_UP, GLFW_KEY_DOWN, GLFW_KEY_PAGE_UP,
                               GLFW_KEY_PAGE_DOWN};
    bool fast = glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    bool held = false;
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
        if (glfwGetKey(w, keys[k]) == GLFW_PRESS) {
            view_anim_light_step(v, keys[k], fast, dt);
            held = true;
        }
    return held;
}

/* The camera at the current time, when it follows the animation. */
static void follow_camera(View *v)
{
    ViewAnim *a = &v->anim;
    Camera c = v->camera;
    if (!animation_camera_at(v->scene, v->time, &c))
        return;
    v->camera = c;
    view_set_angles(v, &c);
    a->follow_yaw = v->yaw;
    a->follow_pitch = v->pitch;
    glm_vec3_copy(c.position, a->follow_position);
}

bool view_anim_advance(View *v, double now)
{
    ViewAnim *a = &v->anim;
    bool changed = false;
    if (a->present && a->playing) {
        double t = a->play_time0 + (now - a->play_wall0);
        if (t > a->duration) {
            if (a->loop && a->duration > 0) {
                t = fmod(t, (double)a->duration);
                a->play_time0 = t;
                a->play_wall0 = now;
            } else {
                t = a->duration;
                a->playing = false;
            }
        }
        changed = t != v->time;
        v->time = t;
    }
    if (a->follow_camera) {
        /* A move of the user's (keys, drag, R) takes the camera over. */
        if (v->yaw != a->follow_yaw || v->pitch != a->follow_pitch ||
            memcmp(v->camera.position, a->follow_position, sizeof a->follow_position) != 0)
            a->follow_camera = false;
        else
            follow_camera(v);
    }
    for (int i = 0; i < a->light_count; i++) /* the window's scene: the lights the next frame draws */
        view_anim_light(v, i, &a->shown_lights[i]);
    if (a->temporal_auto) {
        if (v->edit.gi.frame.temporal != a->temporal_written) { /* ticked in the panel: the user's choice from now on */
            a->temporal_auto = false;
        } else {
            bool want = a->temporal_scene || a->playing;
            if (want != a->temporal_written) {
                v->settings.set.gi.frame.temporal = v->edit.gi.frame.temporal = a->temporal_written = want;
                changed = true;
            }
        }
    }
    return changed;
}

/* ---- The panel ------------------------------------------------------------------- */

static void animation_section(View *v)
{
    ViewAnim *a = &v->anim;
    double now = glfwGetTime();
    if (ui_button(a->playing ? "Pause (Space)" : "Play (Space)"))
        view_anim_play(v, !a->playing, now);
    ui_same_line();
    ui_checkbox("loop", &a->loop);
    ui_same_line();
    ui_text("%.2f / %.2f s", v->time, (double)a->duration);
    float t = (float)v->time;
    if (ui_slider_float("time (s)", &t, 0.f, a->duration, false, "%.3f"))
        view_anim_scrub(v, t, now);
    ui_tooltip("drag to scrub; the frame at a paused time is `rtgi render --time T`'s");
    if (a->camera_tracks) {
        bool follow = a->follow_camera;
        if (ui_checkbox("camera follows the animation", &follow)) {
            a->follow_camera = follow;
            if (follow)
                follow_camera(v);
        }
        ui_tooltip("moving the camera (WASD, drag, R) stops following; tick to follow again");
    }
    bool on = v->settings.set.gi.frame.temporal;
    ui_text("temporal accumulation %s (%s)", on ? "on" : "off",
            a->temporal_auto ? "on while playing" : "chosen: --temporal or the settings");
}

static void lights_section(View *v)
{
    ViewAnim *a = &v->anim;
    static const char *const types[] = {"directional", "spot", "point", "quad"};
    char labels[VIEW_MAX_LIGHTS][32];
    const char *items[VIEW_MAX_LIGHTS];
    for (int i = 0; i < a->light_count; i++) {
        int ty = (int)a->base[i].type;
        snprintf(labels[i], sizeof labels[i], "%d: %s", i, ty >= 0 && ty < 4 ? types[ty] : "?");
        items[i] = labels[i];
    }
    ui_combo("light (L)", &a->light, items, a->light_count);
    int i = a->light;
    Light l;
    view_anim_light(v, i, &l);
    if (l.type == LIGHT_DIRECTIONAL)
        ui_text("direction %.3f %.3f %.3f", (double)l.direction[0], (double)l.direction[1], (double)l.direction[2]);
    else
        ui_text("position %.3f %.3f %.3f", (double)l.position[0], (double)l.position[1], (double)l.position[2]);
    const char *power = l.type == LIGHT_DIRECTIONAL ? "irradiance" : l.type == LIGHT_QUAD ? "radiance" : "intensity";
    ui_text("%s %.4g %.4g %.4g", power, (double)l.color[0], (double)l.color[1], (double)l.color[2]);
    float scale = exp2f(a->edits.stops[i]);
    char label[48];
    snprintf(label, sizeof label, "%s x", power);
    if (ui_slider_float(label, &scale, exp2f(-LIGHT_POWER_STOPS), exp2f(LIGHT_POWER_STOPS), true, "%.3g"))
        view_anim_set_stops(v, i, log2f(fmaxf(scale, 1e-30f)));
    ui_tooltip("multiplies the light's power as loaded (or as the animation has it)");
    if (ui_button("Reset light")) {
        memset(a->edits.move[i], 0, sizeof a->edits.move[i]);
        memset(a->edits.turn[i], 0, sizeof a->edits.turn[i]);
        a->edits.stops[i] = 0.f;
    }
    ui_text_wrapped(l.type == LIGHT_DIRECTIONAL
                        ? "Arrows turn it (left/right about the vertical, up/down in elevation), Shift faster; "
                          "L / Shift-L pick the light."
                        : "Arrows move it across the view along the ground, Page Up / Page Down raise and lower it, "
                          "Shift faster; L / Shift-L pick the light.");
}

void view_anim_panel(View *v)
{
    if (v->anim.present && ui_header("Animation (Space plays)", true))
        animation_section(v);
    if (v->anim.light_count > 0 && ui_header("Lights (arrows move)", false))
        lights_section(v);
}

/* ---- The render thread --------------------------------------------------------- */

bool view_anim_apply(ViewAnimApplied *ap, Scene *s, Renderer *r, double time, const ViewLightEdits *e)
{
    int n = light_count(s);
    if (!ap->made) { /* the scene as loaded: t = 0, no edit */
        memcpy(ap->base, s->lights, sizeof(Light) * (size_t)n);
        ap->time = 0.0;
        memset(&ap->edits, 0, sizeof ap->edits);
        ap->made = true;
    }
    if (ap->time == time && !memcmp(&ap->edits, e, sizeof *e))
        return true;
    Light before[VIEW_MAX_LIGHTS], plain[VIEW_MAX_LIGHTS];
    memcpy(before, s->lights, sizeof(Light) * (size_t)n);
    /* The lights as loaded, then the animation at `time` over them (its
     * lights, camera and objects), then the edits over what it left. */
    memcpy(s->lights, ap->base, sizeof(Light) * (size_t)n);
    SceneChange c;
    animation_apply(s, time, &c);
    memcpy(plain, s->lights, sizeof(Light) * (size_t)n);
    c.what &= ~(unsigned)SCENE_CHANGED_LIGHTS;
    for (int i = 0; i < n; i++) {
        view_light_edit_apply(e, i, &s->lights[i]);
        if (memcmp(&before[i], &s->lights[i], sizeof(Light)) != 0)
            c.what |= SCENE_CHANGED_LIGHTS;
        /* A quad light's emitter stands where animation_apply put it (the
         * animated light, where that differs from the loaded one), else
         * where it was: it follows the edited light. */
        const Light *at = memcmp(&ap->base[i], &plain[i], sizeof(Light)) ? &plain[i] : &before[i];
        if (memcmp(at, &s->lights[i], sizeof(Light)) != 0)
            animation_place_emitter(s, i, &c);
    }
    ap->time = time;
    ap->edits = *e;
    if (!c.what)
        return true;
    ap->changes++;
    return renderer_scene_changed(r, &c);
}
