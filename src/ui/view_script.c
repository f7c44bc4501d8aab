/* view_script.c — see view_script.h. */
#include "ui/view_script.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "ui/view_input.h"

static void script_path(const ViewScript *t, const char *name, char *out, size_t cap)
{
    snprintf(out, cap, "%s/%s", t->dir, name);
}

/* A render-thread job done now (the script waits for it). */
static ViewRenderState script_job(ViewScript *t, unsigned jobs, const char *save_path, bool half)
{
    view_render_jobs(t->render, jobs, save_path, half);
    view_render_wait(t->render);
    ViewRenderState st;
    view_render_state(t->render, &st);
    return st;
}

static void save_image(ViewScript *t, View *v, const char *name)
{
    char path[1024];
    script_path(t, name, path, sizeof path);
    script_job(t, VIEW_JOB_SAVE, path, v->half);
}

static void save_window(ViewScript *t, View *v, const char *name, int fw, int fh)
{
    char path[1024];
    script_path(t, name, path, sizeof path);
    view_save_window(v, path, fw, fh);
}

/* A resize of the window as a user's would be (not the loop's own), waited
 * for: its framebuffer callback gives the image the new size. */
static void user_resize(ViewScript *t, int fw, int fh)
{
    glfwSetWindowSize(t->win, fw, fh); /* screen coordinates: pixels on Xvfb */
    double until = glfwGetTime() + 1.0;
    int w = 0, h = 0;
    while (glfwGetTime() < until && (glfwGetFramebufferSize(t->win, &w, &h), w != fw || h != fh))
        glfwWaitEventsTimeout(0.01);
}

/* The first part is over: the second begins (view_script_tick). */
static bool begin_async(ViewScript *t)
{
    t->async = true;
    t->phase = 0;
    t->deadline = 0;
    return false;
}

void view_script_capture(ViewScript *t, View *v, int fw, int fh)
{
    if (t->shot_live) {
        t->shot_live = false;
        save_window(t, v, "live_ab_reference.png", fw, fh);
        char path[1024];
        script_path(t, "live.pfm", path, sizeof path);
        if (!v->ab || !v->ab->reference.rgb || !image_write_pfm(path, &v->ab->reference))
            printf("ui-test: live: no reference shown to save\n");
    }
    if (t->shot_split) {
        t->shot_split = false;
        save_window(t, v, "live_split.png", fw, fh);
    }
    if (!t->shot_busy)
        return;
    t->shot_busy = false;
    save_window(t, v, "window_busy.png", fw, fh);
}

bool view_script_step(ViewScript *t, View *v, int frame, int fw, int fh)
{
    if (t->animation)
        return view_script_anim_step(t, v, frame, fw, fh);
    ViewRenderState st;
    view_render_state(t->render, &st);
    if (frame == 0 && getenv("RTGI_UI_TEST_ASYNC_ONLY")) /* the second part alone (measuring a real slow frame) */
        return begin_async(t);
    if (frame == 0 && v->live_wanted) { /* the live reference's script */
        t->live = true;
        return begin_async(t);
    }
    switch (frame) {
    case 0: /* the window shows the frame alone until the A/B steps */
        if (v->ab)
            v->ab->mode = AB_FRAME;
        v->jobs |= VIEW_JOB_RESET_TIMER; /* the timings table of frames 1-2, after the cold first one */
        break;
    case 1: { /* what "Copy as scene JSON" copies */
        char json[256];
        view_camera_json(v, json, sizeof json);
        printf("ui-test: camera {%s}\n", json);
        break;
    }
    case 2: { /* the panel's timings table; then exposure through the panel's path: live, nothing remade */
        st = script_job(t, VIEW_JOB_PASS_TABLE, NULL, false);
        const ViewStats *m = &st.stats;
        printf("ui-test: timings gi %s, %s ms, %d frames:", gi_techniques[v->settings.gi]->name,
               m->pass_wall ? "wall" : "gpu", m->timer_frames);
        for (int i = 0; i < m->pass_count; i++)
            printf(" %s=%.3f", m->pass_name[i], m->pass_ms[i]);
        printf("\n");
        t->links = st.links;
        t->remakes = st.remakes;
        v->settings.exposure *= 2.f;
        break;
    }
    case 4:
        printf("ui-test: exposure x2: program links +%d, renderer remakes +%d\n", st.links - t->links,
               st.remakes - t->remakes);
        save_window(t, v, "window_panel.png", fw, fh);
        v->show_panel = false; /* H: the window shrinks by the panel, the image keeps its size */
        break;
    case 6:
        printf("ui-test: window %dx%d without the panel, image %dx%d\n", fw, fh, v->settings.width,
               v->settings.height);
        save_window(t, v, "window_nopanel.png", fw, fh);
        save_image(t, v, "shot.png");
        save_image(t, v, "shot.pfm");
        save_image(t, v, "shot.exr");
        v->show_panel = true;
        break;
    case 7: /* the G key's path into the next technique */
        printf("ui-test: window %dx%d with the panel again, image %dx%d\n", fw, fh, v->settings.width,
               v->settings.height);
        t->remakes = st.remakes;
        view_cycle_gi(v, 1);
        printf("ui-test: G: gi %s, pending %s, estimate %.3g ms, slow above %.3g ms\n",
               gi_techniques[v->settings.gi]->name, v->pending_gi >= 0 ? gi_techniques[v->pending_gi]->name : "none",
               view_estimate_ms(v, v->pending_gi >= 0 ? v->pending_gi : (int)v->settings.gi), v->slow_ms);
        break;
    case 8: /* the user makes the window larger: the image takes it, the panel stays as wide */
        t->width = v->settings.width;
        t->height = v->settings.height;
        user_resize(t, fw + 32, fh + 16);
        break;
    case 9: { /* its confirming click ("Switch anyway") */
        printf("ui-test: user resize to %dx%d: image %dx%d\n", fw, fh, v->settings.width, v->settings.height);
        user_resize(t, t->width + (fw - v->settings.width), t->height); /* and back */
        if (v->pending_gi >= 0)
            view_select_gi(v, v->pending_gi, true);
        char status[1024];
        view_status_get(v->status, status, sizeof status, NULL);
        printf("ui-test: confirmed: gi %s, pending %s, status '%s'\n", gi_techniques[v->settings.gi]->name,
               v->pending_gi >= 0 ? gi_techniques[v->pending_gi]->name : "none", status);
        break;
    }
    case 10:
        v->show_panel = false;
        break;
    case 11: {
        printf("ui-test: technique switch: renderer remakes +%d\n", st.remakes - t->remakes);
        save_window(t, v, "before_reload.png", fw, fh);
        /* Hot reload with a shader broken on disk (the test names it): the
         * error reaches the panel and the previous program stays. */
        const char *broken = getenv("RTGI_UI_TEST_BREAK_SHADER");
        FILE *f = broken ? fopen(broken, "a") : NULL;
        if (f) {
            fputs("\n#error broken by the ui test\n", f);
            fclose(f);
        }
        view_ask_reload(v);
        break;
    }
    case 12: {
        char status[1024];
        bool error;
        view_status_get(v->status, status, sizeof status, &error);
        printf("ui-test: reload: %s: %s\n", error ? "failed" : "ok", status);
        save_window(t, v, "after_reload.png", fw, fh);
        if (!v->ab)
            return begin_async(t);
        v->ab->mode = AB_REFERENCE;
        break;
    }
    case 14:
        save_window(t, v, "ab_reference.png", fw, fh);
        v->ab->mode = AB_DIFFERENCE; /* at its automatic scale, the panel (and its colour bar) shown */
        v->show_panel = true;
        break;
    case 16: {
        save_window(t, v, "ab_difference.png", fw, fh);
        char labels[4][16];
        view_heat_labels(view_heat_scale(v), labels);
        printf("ui-test: heat scale auto %.6g (frame %u), colour bar %s %s %s %s\n", (double)v->ab_auto_scale,
               st.diff_frame, labels[0], labels[1], labels[2], labels[3]);
        st = script_job(t, VIEW_JOB_RMSE, NULL, false);
        printf("ui-test: rmse %.6g\n", st.rmse);
        v->ab->diff_auto = false; /* a chosen scale */
        v->ab->diff_scale = 0.05f;
        v->show_panel = false;
        break;
    }
    case 18:
        save_window(t, v, "ab_difference_manual.png", fw, fh);
        v->ab->mode = AB_SPLIT;
        v->ab->split = 0.5f;
        break;
    case 20:
        save_window(t, v, "ab_split.png", fw, fh);
        return begin_async(t);
    default:
        break;
    }
    fflush(stdout);
    return true;
}

enum { SETTLE, IDLE_START, IDLE_END, SLOW_KEY, SLOW_WAIT };

/* The largest gap between the window's redraws while the slow frame is
 * the one in flight (from the key that started it). */
static void track_redraws(ViewScript *t, const ViewScriptPass *p)
{
    if (p->redraws == t->seen_redraws || p->state.frames != t->frames0)
        return;
    if (p->redraw_at - t->prev_redraw_at > t->max_gap)
        t->max_gap = p->redraw_at - t->prev_redraw_at;
    t->prev_redraw_at = p->redraw_at;
    t->seen_redraws = p->redraws;
}

bool view_script_settle(ViewScript *t, const ViewScriptPass *p)
{
    if (p->state.busy || p->state.frames == 0) {
        t->deadline = p->now + 0.1;
        return false;
    }
    t->deadline = p->now + 0.5;
    return true;
}

void view_script_mark(ViewScript *t, const ViewScriptPass *p, double wait_s)
{
    t->t0 = p->now;
    t->frames0 = p->state.frames;
    t->redraws0 = p->redraws;
    t->wakeups0 = p->wakeups;
    t->deadline = p->now + wait_s;
}

static double env_or(const char *name, double fallback)
{
    const char *s = getenv(name);
    return s && *s ? atof(s) : fallback;
}

enum { LIVE_OFF, LIVE_ON, LIVE_CONVERGE, LIVE_SHOT, LIVE_SHOT_WAIT, LIVE_SPLIT, LIVE_SPLIT_SHOT, LIVE_MOVE, LIVE_MOVED,
       LIVE_BUSY };

/* A line for each image the live reference published since the last. */
static void live_report(ViewScript *t, const View *v, double now)
{
    const LiveStatus *s = &v->live;
    if (s->spp <= 0 || s->spp == t->live_spp)
        return;
    t->live_spp = s->spp;
    printf("ui-test: live %d spp at %.3f s: relMSE est %.6g, vs --compare %.6g (window %.2f s)\n", s->spp, s->seconds,
           s->relmse_estimate, s->relmse_compare, now - t->t0);
    if (t->live_reached_s < 0 && s->relmse_compare >= 0 && s->relmse_compare <= t->live_target) {
        t->live_reached_s = s->seconds;
        t->live_reached_spp = s->spp;
        t->live_reached_relmse = s->relmse_compare;
    }
}

/* The A/B view in `mode`, drawn at this pass; the script goes on to `next`. */
static void live_mode(ViewScript *t, View *v, AbMode mode, int next)
{
    if (v->ab)
        v->ab->mode = mode;
    t->redraw = true;
    t->phase = next;
}

/* The live reference's script (view_script.h). */
static bool live_tick(ViewScript *t, View *v, const ViewScriptPass *p)
{
    const LiveStatus *s = &v->live;
    const ViewRenderState *st = &p->state;
    if (t->phase != LIVE_BUSY)
        t->deadline = p->now + 0.05;
    switch (t->phase) {
    case LIVE_OFF: /* the panel's box off, then on: converging from its first image on */
        if (s->spp <= 0 && p->now - t->t0 < 60)
            break;
        v->live_wanted = false;
        t->phase = LIVE_ON;
        break;
    case LIVE_ON:
        printf("ui-test: live off: running %d, A/B reference %dx%d\n", s->running,
               v->ab ? v->ab->reference.width : 0, v->ab ? v->ab->reference.height : 0);
        v->live_wanted = true;
        t->phase = LIVE_CONVERGE;
        t->t0 = 0;
        break;
    case LIVE_CONVERGE: {
        if (t->t0 == 0) {
            t->t0 = p->now;
            t->live_target = env_or("RTGI_UI_TEST_LIVE_TARGET", 0.01);
            t->live_reached_s = -1;
        }
        live_report(t, v, p->now);
        bool met = s->spp >= (int)env_or("RTGI_UI_TEST_LIVE_MIN_SPP", 1) &&
                   (t->live_target <= 0 || t->live_reached_s >= 0);
        if (!met && !s->done && p->now - t->t0 < env_or("RTGI_UI_TEST_LIVE_MAX_S", 120))
            break;
        if (t->live_reached_s >= 0)
            printf("ui-test: live converged: relMSE vs --compare %.6g <= %.3g at %d spp, %.3f s after the start\n",
                   t->live_reached_relmse, t->live_target, t->live_reached_spp, t->live_reached_s);
        else
            printf("ui-test: live converged: not to %.3g in %.1f s (%d spp, vs --compare %.6g)\n", t->live_target,
                   p->now - t->t0, s->spp, s->relmse_compare);
        char line[160];
        view_live_text(v, line, sizeof line);
        printf("ui-test: live panel '%s'\n", line);
        t->phase = LIVE_SHOT;
        break;
    }
    case LIVE_SHOT: /* the A/B view shows the live reference alone */
        live_mode(t, v, AB_REFERENCE, LIVE_SHOT_WAIT);
        break;
    case LIVE_SHOT_WAIT:
        t->shot_live = true; /* at this pass's redraw: the window and the reference it shows, together */
        t->redraw = true;
        t->phase = LIVE_SPLIT;
        break;
    case LIVE_SPLIT:
        live_mode(t, v, AB_SPLIT, LIVE_SPLIT_SHOT);
        break;
    case LIVE_SPLIT_SHOT:
        t->shot_split = true;
        t->redraw = true;
        t->phase = LIVE_MOVE;
        break;
    case LIVE_MOVE:
        t->live_restarts = s->restarts;
        t->frames0 = (unsigned)s->spp;
        v->yaw += 0.2f; /* the loop's camera follows: a restart */
        t->phase = LIVE_MOVED;
        t->t0 = p->now;
        break;
    case LIVE_MOVED:
        if ((s->restarts == t->live_restarts || s->spp <= 0) && p->now - t->t0 < 60)
            break;
        printf("ui-test: live camera moved: restarts %llu -> %llu, %u spp before, %d at the first image after\n",
               (unsigned long long)t->live_restarts, (unsigned long long)s->restarts, t->frames0, s->spp);
        view_key(v, GLFW_KEY_R, 0); /* home again: a restart where --compare is the converged image */
        t->phase = LIVE_BUSY;
        t->t0 = p->now;
        t->frames0 = st->frames;
        t->live_spp = 0;
        t->live_reached_s = -1;
        t->live_restarts = s->restarts;
        t->deadline = p->now + 0.005;
        break;
    case LIVE_BUSY: {
        /* Frames without pause: each pass asks for one (the newest request wins). */
        v->settings.exposure *= (st->frames & 1u) ? 1.001f : 1.f / 1.001f;
        t->deadline = p->now + 0.005;
        if (s->restarts != t->live_restarts)
            live_report(t, v, p->now);
        double busy_s = env_or("RTGI_UI_TEST_LIVE_BUSY_S", 2.0);
        if (p->now - t->t0 < busy_s)
            break;
        unsigned frames = st->frames - t->frames0;
        printf("ui-test: live busy %.2f s: scene frames %u (%.2f per second), live %d spp, vs --compare %.6g, "
               "relMSE %.3g reached %s",
               p->now - t->t0, frames, frames / (p->now - t->t0), s->spp, s->relmse_compare, t->live_target,
               t->live_reached_s >= 0 ? "at" : "not");
        if (t->live_reached_s >= 0)
            printf(" %.3f s (%d spp)", t->live_reached_s, t->live_reached_spp);
        printf("\n");
        fflush(stdout);
        return false;
    }
    }
    fflush(stdout);
    return true;
}

bool view_script_tick(ViewScript *t, View *v, const ViewScriptPass *p)
{
    if (t->animation)
        return view_script_anim_tick(t, v, p);
    if (t->live) {
        if (p->now < t->deadline)
            return true;
        return live_tick(t, v, p);
    }
    if (t->phase == SLOW_KEY || t->phase == SLOW_WAIT)
        track_redraws(t, p);
    if (p->now < t->deadline)
        return true;
    const ViewRenderState *st = &p->state;
    switch (t->phase) {
    case SETTLE: /* the first part's last frames shown, the window's redraws after them done */
        if (view_script_settle(t, p))
            t->phase = IDLE_START;
        break;
    case IDLE_START:
        view_script_mark(t, p, 1.0);
        t->phase = IDLE_END;
        break;
    case IDLE_END: {
        printf("ui-test: idle %.2f s: scene frames +%u, window redraws +%d, loop passes +%d\n", p->now - t->t0,
               st->frames - t->frames0, p->redraws - t->redraws0, p->wakeups - t->wakeups0);
        /* A slow frame, started by a key. */
        const char *slow = getenv("RTGI_UI_TEST_SLOW_S");
        t->sleep_s = slow ? atof(slow) : 2.0;
        view_key(v, GLFW_KEY_EQUAL, 0);
        t->exposure1 = v->settings.exposure;
        t->t0 = p->now;
        t->frames0 = st->frames;
        t->redraws0 = t->seen_redraws = p->redraws;
        t->prev_redraw_at = p->now;
        t->max_gap = 0;
        t->slow_redraws = -1;
        t->deadline = p->now + fmax(0.3 * t->sleep_s, 0.5);
        t->phase = SLOW_KEY;
        break;
    }
    case SLOW_KEY: /* during it, once it is in flight: the key again */
        if (!st->busy && st->frames == t->frames0 && p->now - t->t0 < 60) {
            t->deadline = p->now + 0.05;
            break;
        }
        view_busy_text(v, t->busy, sizeof t->busy);
        t->shot_busy = true; /* the window as it shows the slow frame's indicator (view_script_capture) */
        view_key(v, GLFW_KEY_EQUAL, 0);
        t->exposure2 = v->settings.exposure;
        t->key_s = p->now - st->busy_since;
        t->deadline = 0;
        t->phase = SLOW_WAIT;
        break;
    case SLOW_WAIT:
        if (st->frames >= t->frames0 + 1 && t->slow_redraws < 0) {
            t->slow_redraws = p->redraws - t->redraws0;
            t->slow_s = p->now - t->t0;
        }
        if ((st->frames < t->frames0 + 2 || st->busy) && p->now - t->t0 < 60)
            break;
        printf("ui-test: slow frame: window redraws %d during it (largest gap %.2f s), busy '%s'; key at %.2f s "
               "into it: exposure %.6g then %.6g, scene frames +%u, the last drawn at %.6g; it took %.2f s\n",
               t->slow_redraws, t->max_gap, t->busy, t->key_s, (double)t->exposure1, (double)t->exposure2,
               st->frames - t->frames0, (double)st->last_exposure, t->slow_s);
        fflush(stdout);
        return false;
    }
    fflush(stdout);
    return true;
}
