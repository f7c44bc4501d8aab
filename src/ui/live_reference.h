/* live_reference.h — the window's ground truth converging live (`rtgi view
 * --live-reference`, the panel's "live reference" box; issue 48): the
 * reference path tracer (pt_progressive.h: its threads at the lowest
 * scheduling priority, so the window's frames come first) renders the
 * window's camera and the scene's lights and materials at the window's
 * image size, and the window's loop polls it for each newer image, which
 * the A/B view shows (split, reference, difference) as it converges.
 *
 * A change of what the path tracer sees restarts it from zero samples:
 * the camera, the lights, the animation time (View.time) or the image
 * size. A new size, or moved geometry (an animated object, a quad light's
 * emitter), makes the renderer anew: its BVH is built again, on a thread
 * of its own (Sponza's takes seconds, which the window's thread would have
 * stood still for); changes meanwhile restart it, or make it anew again,
 * once it is made. Exposure,
 * the GI and shadow techniques and their settings change only the
 * real-time frame, not the ground truth, and restart nothing.
 *
 * Used by the window's thread only. */
#ifndef RTGI_LIVE_REFERENCE_H
#define RTGI_LIVE_REFERENCE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "io/image.h"
#include "reference/pathtracer.h"
#include "reference/pt_progressive.h"
#include "core/scene.h"

/* Where the live reference stands (the panel's line, the ui-test). */
typedef struct LiveStatus {
    bool running;            /* a renderer exists or is being made */
    bool building;           /* it is being made (its BVH built) */
    int width, height;       /* its image size */
    int threads;             /* its threads */
    int spp;                 /* samples per pixel of the image read last (0: none since the restart) */
    double relmse_estimate;  /* that image's relMSE estimated from its per-pixel variance */
    double seconds;          /* from the restart to that image */
    bool done;               /* the spp cap reached: no more passes */
    uint64_t restarts;       /* restarts and remakes since it was started (the first start is 0) */
    double relmse_compare;   /* its measured relMSE against the --compare radiance (metric_relmse), -1: none
                                (no file, a display-referred one, or another size) */
} LiveStatus;

typedef struct LiveMake LiveMake;

typedef struct LiveReference {
    PtSettings set;          /* threads and the spp cap; the size is the window's */
    PtProgressive *pt;       /* owned; NULL: stopped or being made */
    Vertex *geom;            /* owned: the vertices pt borrows (NULL: the scene's, which cannot move) */
    Vertex *pending;         /* owned: vertices of a newer state, for a renderer made once the make in
                                flight ends (NULL: none) */
    LiveMake *make;          /* owned: the renderer being made on a thread, or NULL */
    bool failed;             /* the last make failed (it logged) */
    bool stale;              /* the state changed while it was made: restart it once made */
    const Scene *scene;      /* borrowed: the scene of the last update */
    Camera camera;           /* the state it renders: */
    double time;
    Light *lights;           /* a copy, owned */
    int light_count;
    ImageF image;            /* the image read last (status.spp samples) */
    uint64_t read_restarts;  /* the renderer's restart count when it was read */
    const ImageF *compare;   /* borrowed, may be NULL: relmse_compare's reference */
    LiveStatus status;
} LiveReference;

/* A stopped live reference: `threads` (≥ 1) threads and at most `spp`
 * samples per pixel once started; `compare` (borrowed, may be NULL) is the
 * radiance its relMSE is measured against; `ordinary_priority`: its
 * threads at the ordinary priority, not SCHED_IDLE. */
void live_reference_init(LiveReference *l, int threads, int spp, bool ordinary_priority, const ImageF *compare);

/* Starts it, or brings it to `scene`'s lights and materials seen through
 * `camera` at `time` and w×h: 0 when nothing changed, 1 when it (re)started
 * (the image read so far belongs to another state: status.spp is 0 until
 * the first pass of this one), -1 after logging when it could not start
 * (it is then stopped). `scene`'s indices, submeshes, materials and
 * textures must be the same at every call and outlive the renderer. Its
 * vertices may move under it (the render thread applies the animation):
 * where objects or quad-light emitters can move (animation_geometry_moves),
 * the renderer borrows vertices of its own, made at `time` with `scene`'s
 * lights (animation_vertices_at), and a state whose vertices differ makes
 * the renderer anew (its BVH built again, on its thread, as for a new
 * size). */
int live_reference_update(LiveReference *l, const Scene *scene, const Camera *camera, double time, int w, int h);

/* Whether the renderer published an image newer than the one read last:
 * then l->image is it and l->status says its samples. Updates l->status
 * either way. */
bool live_reference_poll(LiveReference *l);

/* Stops the threads and frees the renderer and its images (init state
 * kept: it may be started again). */
void live_reference_stop(LiveReference *l);

/* The panel's line: "48 spp in 4.1 s, relMSE ~0.00423 (est.)", or what it
 * waits for. */
void live_reference_text(const LiveStatus *st, char *out, size_t cap);

#endif
