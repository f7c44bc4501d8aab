/* view.h — the state of `rtgi view` on the window's thread (the View) and
 * what changes it without drawing: the technique picker's choice and its
 * cost estimate, the status line, the camera's angles, the heat map's scale.
 * The panel (view_panel.h), the keys (view_input.h) and time and lights
 * (view_anim.h) act on it; the render thread (view_render.h) gets its
 * settings and camera as a request, and hands back its measurements
 * (ViewStats) and the status line (ViewStatus, locked).
 *
 * Slow techniques: a technique whose frame is estimated over `slow_ms` at
 * the current size is marked in the picker and needs a confirming click,
 * from the panel and from the G key alike (see view_estimate_ms). */
#ifndef RTGI_VIEW_H
#define RTGI_VIEW_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>

#include "base/log.h"
#include "core/scene.h"
#include "core/settings.h"
#include "frame/renderer.h"
#include "ui/ab_view.h"
#include "ui/live_reference.h"

/* ---- Time and lights (view_anim.h acts on them) ---- */

#define VIEW_MAX_LIGHTS 32

/* Each light's edit in the window, over its animated (or loaded) state. */
typedef struct ViewLightEdits {
    float move[VIEW_MAX_LIGHTS][3]; /* added to its position (m): spot, point, quad */
    float turn[VIEW_MAX_LIGHTS][2]; /* a directional light's direction turned: about +y, then in elevation (rad) */
    float stops[VIEW_MAX_LIGHTS];   /* its power (intensity, irradiance, radiance) × 2^stops */
} ViewLightEdits;

/* The window's side (in the View). */
typedef struct ViewAnim {
    bool present;           /* the scene has an animation */
    float duration;         /* its length (s) */
    bool playing, loop;     /* loop: playback wraps at the end (else it pauses there) */
    double play_wall0;      /* playback: View.time = play_time0 + (now - play_wall0) */
    double play_time0;
    bool camera_tracks;     /* the animation moves the camera ... */
    bool follow_camera;     /* ... and the window's camera follows it (a user's move turns it off) */
    float follow_yaw, follow_pitch; /* the camera as the animation set it */
    float follow_position[3];
    bool temporal_auto;     /* temporal follows playback (no --temporal given, not ticked in the panel) */
    bool temporal_scene;    /* the scene file's gi.temporal (kept while paused) */
    bool temporal_written;  /* what this last wrote into the settings */
    int light;              /* the light the keys and the panel edit */
    int light_count;
    Light base[VIEW_MAX_LIGHTS]; /* the scene's lights as loaded (t = 0, no edit) */
    ViewLightEdits edits;
    /* The window's scene (View.scene points here): a shallow copy of the
     * Scene made before the render thread starts, whose lights are the
     * window's own (as the next frame draws them, updated each pass) and
     * whose bounds stay as loaded; the render thread writes the Scene's. */
    Scene shown;
    Light shown_lights[VIEW_MAX_LIGHTS];
} ViewAnim;

#define VIEW_HISTORY 120

/* What the render thread measured (src/ui/view_render.c), copied into the
 * window's View each time the thread publishes new numbers. */
typedef struct ViewStats {
    double measured_ms[GI_MODE_COUNT]; /* wall ms per frame measured here, per technique ... */
    double measured_px[GI_MODE_COUNT]; /* ... at this many shading pixels (0: never measured) */
    double evals_per_s;         /* gather evaluations/s measured here (0: none yet) */
    float history[VIEW_HISTORY];/* frame wall ms, a ring buffer */
    int history_next, history_count;
    int pass_count;             /* the timings table: passes of the last interval */
    char pass_name[GPU_TIMER_MAX_PASSES][32];
    double pass_ms[GPU_TIMER_MAX_PASSES]; /* mean ms per frame: GPU, or wall when pass_wall */
    bool pass_wall;             /* the timer fences passes with glFinish (software rasterizer): wall ms */
    int timer_frames;           /* frames the table's means are over */
    double gpu_ms, frame_ms;    /* their sum; mean wall ms per frame (the render thread's frame) */
    RenderMemory memory;        /* GPU memory by owner, as of the last interval */
} ViewStats;

/* The panel's status line: the last capture, reload or error message.
 * Written by both threads (and by the log hook for every error line), so
 * behind its own lock; never held while logging. */
typedef struct ViewStatus {
    pthread_mutex_t lock;
    char text[1024];
    bool error;
    bool reloading;             /* a shader reload is under way: its errors accumulate */
} ViewStatus;

typedef struct View {
    const Scene *scene;         /* borrowed */
    RenderSettings settings;    /* wanted: the render thread draws the next frame with them */
    Settings edit;              /* the panel's working copy of the settings-table values */
    Camera camera;              /* current camera */
    Camera home;                /* the scene's camera (R) */
    double time;                /* animation time in seconds: each frame is drawn at the time it
                                   was asked for (view_anim.h plays, pauses and scrubs it) */
    ViewAnim anim;              /* playback and the lights' edits (view_anim.h) */
    float yaw, pitch;           /* radians; forward = (cos p sin y, sin p, cos p cos y) */
    float speed;                /* metres per second */
    bool dragging;
    double last_x, last_y;
    bool show_panel;            /* H */
    bool window_shot;           /* Shift-P: save the window as shown (panel included) */
    bool quit;                  /* Esc */
    unsigned jobs;              /* ViewJob bits for the render thread (P, T, F5, RMSE), sent once */
    double slow_ms;             /* techniques estimated above this per frame need a confirmation */
    int pending_gi;             /* a slow technique waiting for its confirming click, or -1 */
    bool status_pending;        /* the status line is pending_gi's confirm text (cleared with it) */
    ViewStats stats;            /* the render thread's measurements, as last published */
    ViewStatus *status;         /* shared with the render thread */
    bool busy;                  /* a scene frame is being drawn ... */
    double busy_s;              /* ... for this long (the busy indicator) */
    char shot_path[256];        /* P: .png (as shown), .pfm/.exr (radiance) */
    bool half;                  /* --half: .exr captures as half floats */
    char window_path[256];      /* Shift-P: .png of the window */
    AbView *ab;                 /* --compare or the live reference, or NULL */
    bool live_wanted;           /* the live reference is on (--live-reference, the panel's box) */
    LiveStatus live;            /* where it stands (the window's loop copies it each pass) */
    double ab_rmse;             /* last measured RMSE against it (-1: not measured / sizes differ) */
    float ab_auto_scale;        /* the heat map's automatic scale for the image shown (0: none yet) */
} View;

/* Estimated ms per frame of technique `gi` at the current size and settings:
 * the frame time measured here for it (scaled by pixels) if it ran in this
 * window, else a cost model: the direct-light frame time plus gather
 * evaluations (pixels × samples or VPLs per pixel, VPL counts from the RSM
 * sizes: every texel lit, an upper bound) over the device's measured
 * evaluations/s (GI_COST_DEFAULT_EVALS_PER_S until one is measured; src/gi/cost.c). */
double view_estimate_ms(const View *v, int gi);
bool view_gi_is_slow(const View *v, int gi);
/* Switches to technique `gi`, or leaves it pending when it is slow and not
 * `confirmed` (its confirm text then on the status line until it is
 * switched to or cancelled). Returns true if switched. */
bool view_select_gi(View *v, int gi, bool confirmed);
/* "Cancel": no technique pending, its confirm text cleared. */
void view_cancel_gi(View *v);
/* The G key: the next (step 1) or previous (-1) technique after the pending
 * one or the current one; slow ones become pending instead. */
void view_cycle_gi(View *v, int step);
/* The camera as the scene file's "camera" object. */
void view_camera_json(const View *v, char *out, size_t cap);
/* The heat map's full scale as drawn: the automatic one of the image
 * shown, or the chosen one; and its colour bar's labels (0, 1/3, 2/3, 1). */
float view_heat_scale(const View *v);
void view_heat_labels(float scale, char labels[4][16]);
/* The busy indicator's text while a scene frame is being drawn ("" when
 * none is, or for less than a quarter second). */
void view_busy_text(const View *v, char *out, size_t cap);

/* Sets the status line (and logs it). Either thread. */
void view_status(ViewStatus *s, bool error, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* The log hook of the window: error lines go to the status line (during
 * a reload they accumulate, first one first). `user` is the ViewStatus. */
void view_status_log_hook(LogLevel level, const char *tag, const char *message, void *user);
/* A copy of the status line. */
void view_status_get(ViewStatus *s, char *out, size_t cap, bool *error);

/* The most a movement step may cover: a window that waited (a slow
 * event, a stall) moves the camera no further than this many seconds of
 * a held key (a frame of over ten seconds had thrown it across Sponza). */
#define VIEW_MOVE_MAX_DT 0.1f
/* The camera's angles from its forward vector, and back. */
void view_set_angles(View *v, const Camera *c);
void view_update_camera(View *v);

#endif
