/* view_panel.h — the state of `rtgi view` and its Dear ImGui panel:
 * technique and shadow pickers, every row of the settings table as a
 * widget with its range, exposure (live: renderer_apply remakes nothing for
 * it), per-pass GPU ms with a history plot, the camera with "copy as scene
 * JSON", captures, shader hot reload and the A/B view of --compare.
 *
 * Slow techniques: a technique whose frame is estimated over `slow_ms` at
 * the current size is marked in the picker and needs a confirming click,
 * from the panel and from the G key alike (see view_estimate_ms). */
#ifndef RTGI_VIEW_PANEL_H
#define RTGI_VIEW_PANEL_H

#include <stdbool.h>
#include <stddef.h>

#include "renderer.h"
#include "scene.h"
#include "settings.h"
#include "ui/ab_view.h"

#define VIEW_HISTORY 120

typedef struct View {
    const Scene *scene;         /* borrowed */
    Renderer *renderer;         /* borrowed: the window's */
    RenderSettings settings;    /* wanted; the loop applies them when dirty */
    Settings edit;              /* the panel's working copy of the settings-table values */
    bool dirty;                 /* settings changed since the last renderer_apply */
    Camera camera;              /* current camera */
    Camera home;                /* the scene's camera (R) */
    float yaw, pitch;           /* radians; forward = (cos p sin y, sin p, cos p cos y) */
    float speed;                /* metres per second */
    bool dragging;
    double last_x, last_y;
    bool show_panel;            /* H */
    bool print_timings;         /* T: print the timings table on stdout */
    bool screenshot;            /* P: save the rendered image to shot_path */
    bool window_shot;           /* Shift-P: save the window as shown (panel included) */
    bool reload;                /* F5: rebuild every program from the shader files */
    double slow_ms;             /* techniques estimated above this per frame need a confirmation */
    int pending_gi;             /* a slow technique waiting for its confirming click, or -1 */
    double measured_ms[GI_MODE_COUNT]; /* wall ms per frame measured here, per technique ... */
    double measured_px[GI_MODE_COUNT]; /* ... at this many shading pixels (0: never measured) */
    double evals_per_s;         /* gather evaluations/s measured here (0: none yet) */
    float history[VIEW_HISTORY];/* frame wall ms, a ring buffer */
    int history_next, history_count;
    int pass_count;             /* the timings table: passes of the last interval */
    char pass_name[GPU_TIMER_MAX_PASSES][32];
    double pass_ms[GPU_TIMER_MAX_PASSES]; /* mean ms per frame: GPU, or wall when pass_wall */
    bool pass_wall;             /* the timer fences passes with glFinish (software rasterizer): wall ms */
    double gpu_ms, frame_ms;    /* their sum; mean wall ms per frame */
    RenderMemory memory;        /* GPU memory by owner, as of the last interval */
    char status[1024];          /* the last capture / reload message */
    bool status_error;
    bool reloading;             /* a shader reload is under way: its errors accumulate in status */
    char shot_path[256];        /* P: .png (as shown), .pfm/.exr (radiance) */
    bool half;                  /* --half: .exr captures as half floats */
    char window_path[256];      /* Shift-P: .png of the window */
    AbView *ab;                 /* --compare, or NULL */
    double ab_rmse;             /* last measured RMSE against it (-1: not measured / sizes differ) */
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
 * `confirmed`. Returns true if switched. */
bool view_select_gi(View *v, int gi, bool confirmed);
/* The G key: the next (step 1) or previous (-1) technique after the pending
 * one or the current one; slow ones become pending instead. */
void view_cycle_gi(View *v, int step);
/* The camera as the scene file's "camera" object. */
void view_camera_json(const View *v, char *out, size_t cap);
/* Records the last interval's timings (the renderer's timer, means per
 * frame) and, if `is_cost` (no remake, reload or first frame in it), the
 * measured cost of the current technique and the gather rate. */
void view_record_timings(View *v, double frame_ms, bool is_cost);
/* Fills the timings table (pass_name, pass_ms, gpu_ms) from the renderer's
 * timer, means over the frames since its last reset: GPU ms per pass, or on
 * a software rasterizer (the timer's `sync`) the wall ms that `render
 * --timings` reports, since timestamps there miss compute passes. */
void view_take_pass_table(View *v);
/* Sets the status line (and logs it). */
void view_status(View *v, bool error, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* Saves the rendered image: .png as shown (tone-mapped, after FXAA), any
 * other extension through image_write as linear radiance. The outcome goes
 * to the status line; false on failure. */
bool view_save_image(View *v, const char *path);
/* Saves the window's back buffer as shown, panel included (call before the
 * swap), as PNG. */
bool view_save_window(View *v, const char *path, int fw, int fh);
/* Hot reload: every program rebuilt from the shader files (--shader-dir,
 * else the source tree's shaders/); one that fails keeps its previous build
 * and its error shows in the panel's status. */
void view_reload_shaders(View *v);
/* The panel's width (pixels, from its left edge at 6) in a window fw wide. */
float view_panel_width(int fw);
/* Draws the panel for this frame (between ui_frame_begin and ui_frame_end). */
void view_panel_draw(View *v, int fw, int fh);

#endif
