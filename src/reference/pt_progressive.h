/* pt_progressive.h — the reference path tracer converging in the
 * background, for a live ground truth in the window (issue 48): one
 * coordinator thread renders passes of samples (pt_job.h) over every pixel
 * with PtSettings.threads threads in all — 1, 2, 4, ... samples per pixel
 * up to a whole pass, then whole passes, so that an image comes soon after
 * each restart — at the lowest scheduling priority unless
 * PtSettings.ordinary_priority (SCHED_IDLE on Linux: they take only the
 * CPU time the rest of the process and the system leave, so the window's
 * frames come first), and after each complete pass publishes the image of
 * the samples so far, with their count and the relMSE estimated from the
 * per-pixel variance.
 * A restart (the camera, a light or a material changed) abandons the
 * running pass within a tile and starts again from zero samples.
 *
 * The image after n samples per pixel is the one pt_render gives for
 * spp = n with the same settings and scene, to the bit (a pixel's samples
 * depend only on seed, pixel and sample index).
 *
 * Ownership: the geometry of the Scene given to pt_progressive_create
 * (vertices, indices, submeshes, textures, and the materials' alpha
 * masks, which decide what Embree's scene filters) is borrowed and must
 * stay unchanged and alive until pt_progressive_destroy; the BVH over it
 * is built once there. Emitter quads of quad lights with a size are
 * geometry too. The camera, the lights and the materials are copied at
 * create and at each restart, so the caller may change its own freely
 * while the renderer runs. A change of geometry: destroy and create anew.
 * Thread-safe: every function may be called from any one thread (the
 * window's) while the renderer runs. */
#ifndef RTGI_PT_PROGRESSIVE_H
#define RTGI_PT_PROGRESSIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "io/image.h"
#include "reference/pathtracer.h"
#include "core/scene.h"

typedef struct PtProgressive PtProgressive;

/* Where the renderer stands (pt_progressive_status, pt_progressive_read). */
typedef struct PtProgressiveStatus {
    int spp;                /* samples per pixel of the image published last (0: none yet since the restart) */
    double relmse_estimate; /* that image's relMSE estimated from the per-pixel variance (PtStats's; 0
                               below 2 spp) */
    double seconds;         /* time from the (re)start to that image */
    uint64_t restarts;      /* pt_progressive_restart calls so far (an image read shows the state of the
                               last one: a restart withdraws the image of the state before) */
    bool done;              /* no more passes: PtSettings.spp or target_relmse reached */
    bool paused;            /* pt_progressive_pause(true) is in force */
    bool idle;              /* no pass is running (paused or done, and the last pass has ended) */
} PtProgressiveStatus;

/* Builds the BVH of `scene` and starts rendering its camera, lights and
 * materials as they are now, with `set`: size, mode, seed, sampler, depth
 * and roulette as pt_render; threads (≥ 1) in all; spp the most samples
 * per pixel to reach (then it stops: PtProgressiveStatus.done), and
 * target_relmse > 0 also stops it once the estimate is at most that (from
 * PT_TARGET_MIN_SPP on). progress, stop and time_budget are not used.
 * NULL after logging (allocation, Embree, thread). */
PtProgressive *pt_progressive_create(const Scene *scene, const PtSettings *set);

/* Starts again from zero samples with `scene`'s camera, lights and
 * materials (copied now; the geometry must be the one given to create):
 * the running pass is abandoned within a tile, and the image published so
 * far is withdrawn (status spp 0) until the first pass of the new state.
 * false after logging if the copies cannot be allocated (the renderer
 * then goes on with the previous state). */
bool pt_progressive_restart(PtProgressive *p, const Scene *scene);

/* Pauses (no new pass starts; the running one completes and is
 * published: status.idle says when it has) or resumes the rendering. */
void pt_progressive_pause(PtProgressive *p, bool paused);

/* Where it stands, without the image. */
void pt_progressive_status(PtProgressive *p, PtProgressiveStatus *st);

/* The image published last: its mean radiance into `mean`, which must be
 * allocated at PtSettings' size (image_alloc), and its status into `st`
 * (may be NULL). false, and `mean` untouched, while no pass of the
 * current state has completed. */
bool pt_progressive_read(PtProgressive *p, ImageF *mean, PtProgressiveStatus *st);

/* Stops the threads (within a tile) and frees everything; NULL is a no-op. */
void pt_progressive_destroy(PtProgressive *p);

#endif
