/* view_script.h — `rtgi view --ui-test DIR`: a fixed script through the
 * panel's own actions (no clicks: Xvfb has no user), printing what it
 * measured as "ui-test: ..." lines on stdout and writing its captures to
 * DIR; tests/test_view.c reads both.
 *
 * Its first part is synchronous, one step per window frame (each frame
 * waits for its scene frame): the panel's per-pass timings table of
 * frames 1-2; the camera as scene JSON; exposure ×2 (program links and
 * renderer remakes counted); the window with and without the panel (H)
 * and the image as PNG, PFM and EXR; a resize by the user (the image
 * takes it); the G key's path into the next
 * technique (pending when slow), its confirming click and the status line
 * after it; a shader hot reload (with the shader named by
 * RTGI_UI_TEST_BREAK_SHADER broken first); with --compare, the A/B view's
 * reference, difference (its automatic scale, the panel's colour bar, its
 * RMSE), difference at a chosen scale, and split.
 *
 * Its second part runs the window as a user has it (asynchronous: the
 * window waits for events, the render thread draws when asked) and is
 * driven by time: one idle second (scene frames and window redraws
 * counted: none is due), then a slow frame (a test hook: the render
 * thread sleeps RTGI_UI_TEST_SLOW_S seconds, default 2, before drawing
 * it) started by the + key, with + pressed again while it is in flight:
 * the window's redraws during it are counted and the next scene frame
 * must carry the second key's exposure. RTGI_UI_TEST_SLOW_S=0 leaves the
 * frame its own time, and RTGI_UI_TEST_ASYNC_ONLY=1 runs the second part
 * alone: together they measure the window during a real slow frame
 * (scripts/view-responsiveness.sh).
 *
 * With --live-reference the script is the live reference's instead
 * (asynchronous, driven by time; RTGI_UI_TEST_LIVE_* tune it):
 *   the panel's box off (a line: whether it runs, the A/B view's
 *     reference: --compare's again) and on again, then
 *   converge: a line per image it publishes ("ui-test: live N spp at T s:
 *     relMSE est E, vs --compare C"), until MIN_SPP samples (default 1)
 *     and C at most TARGET (default 0.01; 0: any), or MAX_S seconds
 *     (default 120); then "live converged" with the first image that met
 *     the target and the panel's line;
 *   the A/B view in reference mode captured (live_ab_reference.png) with
 *     the image it shows (live.pfm), then split (live_split.png);
 *   a camera move: the restart count and the samples before it and at
 *     the first image after it;
 *   R (the camera home again: restarted), then BUSY_S seconds (default 2)
 *     of frames asked for without pause (exposure nudged each time): the
 *     scene frames drawn per second while the live reference converges,
 *     and where it got meanwhile (scripts/bench-live-reference.sh). */
#ifndef RTGI_VIEW_SCRIPT_H
#define RTGI_VIEW_SCRIPT_H

#include <stdbool.h>
#include <stdint.h>

typedef struct GLFWwindow GLFWwindow;

#include "ui/view_panel.h"
#include "ui/view_render.h"

typedef struct ViewScript {
    const char *dir;    /* where the captures go */
    ViewRender *render; /* the render thread: jobs and its counters */
    GLFWwindow *win;    /* the window (a user's resize) */
    int width, height;  /* the image's size before that resize */
    bool async;         /* the second part: the loop runs as a user's window */
    double deadline;    /* the second part: when its next step is due (glfwGetTime; 0: every pass) */
    double sleep_s;     /* test hook for the next request (ViewRequest.test_sleep_s) */
    int links, remakes; /* counters before the step being measured */
    /* The second part's state. */
    int phase;
    double t0, key_s, prev_redraw_at, max_gap, slow_s;
    unsigned frames0;
    int redraws0, wakeups0, slow_redraws, seen_redraws;
    float exposure1, exposure2;
    char busy[96];
    bool shot_busy;     /* capture the window at its next redraw (window_busy.png) */
    bool redraw;        /* the script changed what the window shows: the loop draws it again */
    /* The live reference's script. */
    bool live;
    int live_spp;       /* the samples of the last image reported */
    uint64_t live_restarts;
    double live_target, live_reached_s;
    int live_reached_spp;
    double live_reached_relmse;
    bool shot_live;     /* capture the window and the reference it shows at its next redraw */
    bool shot_split;    /* capture the window at its next redraw (live_split.png) */
    /* The animation script (view_script_anim.c), run instead on a scene
     * with an animation. */
    bool animation;
    double anim_time0;  /* the animation's time when playback began */
} ViewScript;

/* What the loop tells the second part each pass. */
typedef struct ViewScriptPass {
    double now;         /* glfwGetTime */
    int redraws;        /* window frames drawn so far */
    double redraw_at;   /* when the last one was */
    int wakeups;        /* loop passes so far */
    ViewRenderState state;
} ViewScriptPass;

/* First part: runs frame `frame`'s step (after the frame is drawn, before
 * the swap); false when the first part is over (the second then begins:
 * t->async). */
bool view_script_step(ViewScript *t, View *v, int frame, int fw, int fh);
/* Second part: one pass of the loop (before its request); false when the
 * script is over. */
bool view_script_tick(ViewScript *t, View *v, const ViewScriptPass *p);
/* Second part: whether the frames asked for are drawn (none in flight):
 * then the next step is due in half a second (the window's redraws after
 * them done), else the check again in a tenth. */
bool view_script_settle(ViewScript *t, const ViewScriptPass *p);
/* Second part: the counters a measured span starts from (now, scene
 * frames, redraws, loop passes), its end due in wait_s. */
void view_script_mark(ViewScript *t, const ViewScriptPass *p, double wait_s);
/* The animation script's parts (a scene with an animation; see
 * view_script_anim.c): what view_script_step and view_script_tick run
 * instead. */
bool view_script_anim_step(ViewScript *t, View *v, int frame, int fw, int fh);
bool view_script_anim_tick(ViewScript *t, View *v, const ViewScriptPass *p);
/* Second part: the window drawn this pass, before the swap (a capture
 * the script asked for). */
void view_script_capture(ViewScript *t, View *v, int fw, int fh);

#endif
