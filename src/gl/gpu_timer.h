/* gpu_timer.h — per-pass GPU and CPU timings.
 * Each pass is bracketed by gpu_timer_begin/end: GL timestamp queries give
 * GPU time; when `sync` is set the CPU waits for the GPU at both ends
 * (glFinish) and the wall time is recorded too, which is the meaningful
 * number on software rasterizers such as llvmpipe. Times accumulate by pass
 * name over frames until gpu_timer_reset.
 *
 * Every begin/end pair also pushes/pops a debug group (GL 4.3 / KHR_debug)
 * named after the pass, whether timing is enabled or not, so RenderDoc and
 * apitrace captures show the frame as its passes. A disabled timer creates
 * no queries, never waits on the GPU and reads nothing back. Passes do not
 * nest: end the open one before the next begin.
 *
 * A one-time pass (gpu_timer_begin_once: setup work such as vct_voxelize,
 * which runs in the first, untimed warm-up frame) is kept apart: its times
 * are those of its last run, not summed over frames, kept across
 * gpu_timer_reset, left out of `passes` and of the total, and printed after
 * the total as a row marked "once". gpu_timer_forget_once drops them (the
 * technique that ran them is gone). */
#ifndef RTGI_GPU_TIMER_H
#define RTGI_GPU_TIMER_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdio.h>

#define GPU_TIMER_MAX_PASSES 32
#define GPU_TIMER_MAX_ONCE 4
#define GPU_TIMER_MAX_QUERIES 256

typedef struct GpuTimerPass {
    char name[32];
    double gpu_ms; /* summed over frames (a one-time pass: its last run) */
    double cpu_ms; /* summed over frames (sync only; a one-time pass: its last run) */
    double frame_gpu_ms, frame_cpu_ms; /* the frame in progress */
    double min_gpu_ms, min_cpu_ms;     /* the fastest frame that ran the pass (0: none yet) */
} GpuTimerPass;

typedef struct GpuTimer {
    bool enabled;
    bool sync;
    bool exact;  /* a hardware driver's timestamps bound each pass's own work (not a software
                  * rasterizer's, see gl_renderer_is_software): rates take them, not wall time */
    GLuint queries[GPU_TIMER_MAX_QUERIES]; /* owned */
    int query_pass[GPU_TIMER_MAX_QUERIES / 2]; /* index into passes, or GPU_TIMER_MAX_PASSES + index into once */
    int query_count;                       /* pairs in flight ×2 */
    double cpu_begin;
    int open_pass;                         /* pass between begin/end or -1 */
    int debug_groups;                      /* debug groups pushed and not yet popped */
    GpuTimerPass passes[GPU_TIMER_MAX_PASSES];
    int pass_count;
    int frames;
    GpuTimerPass once[GPU_TIMER_MAX_ONCE]; /* one-time passes, kept across gpu_timer_reset */
    int once_count;
} GpuTimer;

void gpu_timer_create(GpuTimer *t, bool enabled, bool sync);
void gpu_timer_destroy(GpuTimer *t);
/* Opens pass `pass`: pushes its debug group, and when enabled starts its
 * timestamp (after a glFinish when `sync`). */
void gpu_timer_begin(GpuTimer *t, const char *pass);
/* The same for a one-time pass (see the top). */
void gpu_timer_begin_once(GpuTimer *t, const char *pass);
/* Closes the open pass: ends its timestamp and pops its debug group. */
void gpu_timer_end(GpuTimer *t);
/* The time a rate divides by: the timer queries where they are exact, else
 * (a software rasterizer) wall time when synchronised. */
static inline bool gpu_timer_rates_use_wall(const GpuTimer *t) { return t->sync && !t->exact; }
/* Collects this frame's queries (waits for them). */
void gpu_timer_end_frame(GpuTimer *t);
/* Forgets the per-frame passes (not the one-time ones). */
void gpu_timer_reset(GpuTimer *t);
/* Forgets the one-time passes. */
void gpu_timer_forget_once(GpuTimer *t);
/* Mean per frame of a pass, or -1 if it never ran. */
double gpu_timer_mean_ms(const GpuTimer *t, const char *pass, bool cpu);
/* The pass's time in the fastest frame that ran it (GPU or, with sync,
 * wall), or −1: what a device sustains when nothing else competes for it,
 * the statistic rtgi probe reports for its kernels too. */
double gpu_timer_min_ms(const GpuTimer *t, const char *pass, bool cpu);
/* Prints "pass  gpu_ms  cpu_ms" lines and a total, means per frame, then
 * the one-time passes' rows with "once" after them. */
void gpu_timer_print(const GpuTimer *t, FILE *f);

#endif
