/* view_input.c — see view_input.h. */
#include "ui/view_input.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>

#include "base/log.h"
#include "ui/ui.h"
#include "ui/view_anim.h"
#include "ui/view_panel.h"
#include "ui/view_render.h"



void view_key(View *v, int key, int mods)
{
    RenderSettings *s = &v->settings;
    bool shift = (mods & GLFW_MOD_SHIFT) != 0;
    switch (key) {
    case GLFW_KEY_ESCAPE:
        v->quit = true;
        break;
    case GLFW_KEY_1: case GLFW_KEY_2: case GLFW_KEY_3: case GLFW_KEY_4:
        s->shadow = (ShadowMode)(key - GLFW_KEY_1);
        break;
    case GLFW_KEY_G:
        view_cycle_gi(v, shift ? -1 : 1);
        break;
    case GLFW_KEY_EQUAL: case GLFW_KEY_KP_ADD:
        s->exposure *= 1.25f;
        break;
    case GLFW_KEY_MINUS: case GLFW_KEY_KP_SUBTRACT:
        s->exposure /= 1.25f;
        break;
    case GLFW_KEY_F:
        s->aa = s->aa == AA_FXAA ? AA_NONE : AA_FXAA;
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
        v->jobs |= VIEW_JOB_PRINT_TIMINGS;
        break;
    case GLFW_KEY_P:
        if (shift)
            v->window_shot = true;
        else
            v->jobs |= VIEW_JOB_SAVE;
        break;
    case GLFW_KEY_F5:
        view_ask_reload(v);
        break;
    case GLFW_KEY_H:
        v->show_panel = !v->show_panel;
        break;
    default:
        view_anim_key(v, key, mods); /* Space, L: src/ui/view_anim.c */
        break;
    }
}

bool view_move(View *v, GLFWwindow *w, float dt)
{
    if (ui_wants_keyboard())
        return false;
    float step = v->speed * fminf(fmaxf(dt, 0.f), VIEW_MOVE_MAX_DT) *
                 (glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ? 4.f : 1.f);
    vec3 right;
    glm_vec3_cross(v->camera.forward, v->camera.up, right);
    struct { int key; float *axis; float sign; } moves[] = {
        {GLFW_KEY_W, v->camera.forward, 1}, {GLFW_KEY_S, v->camera.forward, -1}, {GLFW_KEY_D, right, 1},
        {GLFW_KEY_A, right, -1},            {GLFW_KEY_E, (vec3){0, 1, 0}, 1},    {GLFW_KEY_Q, (vec3){0, 1, 0}, -1},
    };
    bool held = false;
    for (size_t i = 0; i < sizeof moves / sizeof moves[0]; i++)
        if (glfwGetKey(w, moves[i].key) == GLFW_PRESS) {
            glm_vec3_muladds(moves[i].axis, moves[i].sign * step, v->camera.position);
            held = true;
        }
    return held;
}
