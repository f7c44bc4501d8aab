/* view_script_anim.c — `rtgi view --ui-test DIR` on a scene with an
 * animation: the window test's script for time and lights (issue 50,
 * item 4), through the panel's and the keys' own paths; tests/test_view.c
 * reads its "ui-test: ..." lines and its captures.
 *
 * First part (one step per window frame, each waiting for its scene
 * frame): the frame at t = 0 (anim_t0.pfm); the time slider to T
 * (RTGI_UI_TEST_TIME, default 1.3 s) and its frame (anim_t.pfm, against
 * `render --time T`); the selected light moved with the arrow and Page
 * Down keys as if held (anim_moved.pfm, the light's state printed for a
 * still scene with it); its power ×2 in the panel (anim_bright.pfm).
 *
 * Second part (the window as a user has it): Space plays for two seconds
 * (scene frames, the time reached and temporal accumulation's setting and
 * passes counted), Space pauses, and one idle second after the pause's
 * frame (scene frames and window redraws counted: none is due). */
#include "ui/view_script.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "ui/view_anim.h"
#include "ui/view_input.h"

static void anim_save(ViewScript *t, const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", t->dir, name);
    view_render_jobs(t->render, VIEW_JOB_SAVE, path, false);
    view_render_wait(t->render);
}

/* The light as the window draws it, as a scene file's light would give it. */
static void print_light(const View *v, const char *what)
{
    int i = v->anim.light;
    Light l;
    view_anim_light(v, i, &l);
    printf("ui-test: %s: light %d type %d position %.9g %.9g %.9g direction %.9g %.9g %.9g power %.9g %.9g %.9g\n",
           what, i, (int)l.type, (double)l.position[0], (double)l.position[1], (double)l.position[2],
           (double)l.direction[0], (double)l.direction[1], (double)l.direction[2], (double)l.color[0],
           (double)l.color[1], (double)l.color[2]);
}

bool view_script_anim_step(ViewScript *t, View *v, int frame, int fw, int fh)
{
    (void)fw;
    (void)fh;
    switch (frame) {
    case 0: {
        printf("ui-test: animation %.4g s, %d lights, time %.4g, temporal %s (%s)\n", (double)v->anim.duration,
               v->anim.light_count, v->time, v->settings.set.gi.frame.temporal ? "on" : "off",
               v->anim.temporal_auto ? "auto" : "chosen");
        anim_save(t, "anim_t0.pfm");
        const char *at = getenv("RTGI_UI_TEST_TIME");
        view_anim_scrub(v, at ? atof(at) : 1.3, glfwGetTime()); /* the time slider's path */
        break;
    }
    case 1:
        anim_save(t, "anim_t.pfm");
        printf("ui-test: scrubbed to %.9g s: temporal %s, playing %d\n", v->time,
               v->settings.set.gi.frame.temporal ? "on" : "off", (int)v->anim.playing);
        print_light(v, "at the time");
        /* Keys held: Shift-Right for 0.3 s, Shift-Page Down for 0.2 s (in
         * the steps of a window's passes). */
        for (int k = 0; k < 3; k++)
            view_anim_light_step(v, GLFW_KEY_RIGHT, true, 0.1f);
        for (int k = 0; k < 2; k++)
            view_anim_light_step(v, GLFW_KEY_PAGE_DOWN, true, 0.1f);
        break;
    case 2:
        anim_save(t, "anim_moved.pfm");
        print_light(v, "moved");
        view_anim_set_stops(v, v->anim.light, 1.f); /* the panel's power slider at x2 */
        break;
    case 3:
        anim_save(t, "anim_bright.pfm");
        print_light(v, "power x2");
        t->async = true;
        t->phase = 0;
        t->deadline = 0;
        fflush(stdout);
        return false;
    default:
        break;
    }
    fflush(stdout);
    return true;
}

enum { SETTLE, PLAY, PLAYED, PAUSE_SETTLE, IDLE_START, IDLE_END };

/* The pass names of the last published timings, into out. */
static void pass_names(const ViewStats *m, char *out, size_t cap)
{
    size_t n = 0;
    out[0] = 0;
    for (int i = 0; i < m->pass_count && n + 2 < cap; i++)
        n += (size_t)snprintf(out + n, cap - n, "%s%s", i ? "," : "", m->pass_name[i]);
}

bool view_script_anim_tick(ViewScript *t, View *v, const ViewScriptPass *p)
{
    if (p->now < t->deadline)
        return true;
    const ViewRenderState *st = &p->state;
    switch (t->phase) {
    case SETTLE:
    case PAUSE_SETTLE: /* the last frames drawn and shown */
        if (view_script_settle(t, p))
            t->phase = t->phase == SETTLE ? PLAY : IDLE_START;
        break;
    case PLAY:
        view_key(v, GLFW_KEY_SPACE, 0);
        t->anim_time0 = v->time;
        view_script_mark(t, p, 2.0);
        t->phase = PLAYED;
        break;
    case PLAYED: {
        char passes[512];
        pass_names(&st->stats, passes, sizeof passes);
        printf("ui-test: played %.2f s: scene frames +%u, time %.4g to %.4g, temporal %s, passes %s\n",
               p->now - t->t0, st->frames - t->frames0, t->anim_time0, v->time,
               v->settings.set.gi.frame.temporal ? "on" : "off", passes);
        view_key(v, GLFW_KEY_SPACE, 0);
        t->deadline = p->now + 0.2;
        t->phase = PAUSE_SETTLE;
        break;
    }
    case IDLE_START:
        view_script_mark(t, p, 1.0);
        t->phase = IDLE_END;
        break;
    case IDLE_END:
        printf("ui-test: paused at %.4g s, idle %.2f s: scene frames +%u, window redraws +%d, loop passes +%d, "
               "temporal %s, playing %d\n",
               v->time, p->now - t->t0, st->frames - t->frames0, p->redraws - t->redraws0, p->wakeups - t->wakeups0,
               v->settings.set.gi.frame.temporal ? "on" : "off", (int)v->anim.playing);
        fflush(stdout);
        return false;
    }
    fflush(stdout);
    return true;
}
