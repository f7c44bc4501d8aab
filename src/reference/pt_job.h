/* pt_job.h — the path tracer's core for its two drivers: pt_render
 * (pathtracer.c: one image, `rtgi reference`) and the progressive renderer
 * (pt_progressive.c: an image that keeps converging in the background).
 * A job holds the Embree scene and an image's per-pixel sums of samples
 * and squared samples, and renders them in passes: samples [s0, s1) of
 * every pixel, over 16×16 tiles shared by threads. A pixel's samples
 * depend only on (seed, pixel, sample index), so the sums after samples
 * [0, n) are the same whatever the passes and threads were. Not for use
 * outside src/reference/. */
#ifndef RTGI_PT_JOB_H
#define RTGI_PT_JOB_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

#include "io/image.h"
#include "reference/pt_settings.h"
#include "core/scene.h"

typedef struct PtJob PtJob;

/* A job for `set` over `scene` (both borrowed until pt_job_destroy; the
 * render reads the scene's camera, lights and materials as they are when a
 * pass runs, and set->threads threads at most); NULL after logging. */
PtJob *pt_job_create(const Scene *scene, const PtSettings *set);
void pt_job_destroy(PtJob *j);

/* Forgets every sample (sums and ray count) and takes the scene's camera
 * anew: for a restart, between passes. */
void pt_job_clear(PtJob *j);

/* Samples per pixel of one pass: about 2^18 samples, at least 1. */
int pt_job_pass_spp(const PtJob *j);

/* Samples [s0, s1) of every pixel, added to the sums, on `nthreads`
 * threads: the calling one and nthreads − 1 started here (all of them at
 * the lowest scheduling priority, SCHED_IDLE, when `background`: they then
 * run only on cores nothing else wants). Between two tiles the calling
 * thread calls tick(ctx) when tick is not NULL. When *cancel (may be NULL)
 * becomes non-zero the threads take no new tile and this returns false: the
 * pass is incomplete and the sums are partial (pt_job_clear them); true
 * when every tile was rendered. */
bool pt_job_pass(PtJob *j, int s0, int s1, int nthreads, bool background, const atomic_int *cancel,
                 void (*tick)(void *ctx), void *ctx);

/* Starts thread *t running fn(arg), at the lowest scheduling priority
 * (SCHED_IDLE) when `background` and the system allows it, else an
 * ordinary one; false if no thread could be started. */
bool pt_thread_start(pthread_t *t, void *(*fn)(void *), void *arg, bool background);

/* The tiles of the running pass rendered so far, of `total`. */
int pt_job_tiles_done(const PtJob *j, int *total);

/* The relMSE that the mean of `spp` samples (the sums of samples [0, spp))
 * is expected to have against the converged image, from each pixel's
 * sample variance: the mean over pixels and channels of
 * (variance of the mean) / (mean² + 0.01), metric_relmse's normalisation.
 * Exact in expectation for independent samples; Owen-scrambled Sobol'
 * samples converge faster than the sample variance says, so it is then an
 * overestimate (about ×2 on the Cornell box at 64 spp: the measured error
 * was 0.45–0.58 of it, test_reference_exact).
 * 0 below 2 samples. */
double pt_job_relmse_estimate(const PtJob *j, int spp);

/* The mean of `spp` samples per pixel into `mean`, and the variance of
 * that mean into `variance` (may be NULL); both allocated by the caller at
 * the job's size. */
void pt_job_resolve(const PtJob *j, int spp, ImageF *mean, ImageF *variance);

/* Rays traced since the job was made or cleared. */
uint64_t pt_job_rays(const PtJob *j);

#endif
