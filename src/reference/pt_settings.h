/* pt_settings.h — what a path-traced render is asked (PtSettings) and
 * what it reports (PtStats): the types pathtracer.h's functions take, and
 * which its core (pt_job.h) and its sampler (sampler.h) read, apart from
 * those functions so that neither includes pathtracer.h. */
#ifndef RTGI_PT_SETTINGS_H
#define RTGI_PT_SETTINGS_H

#include <stdbool.h>
#include <stdint.h>

typedef enum PtMode {
    PT_FULL = 0,           /* all bounces */
    PT_DIRECT,             /* emission + direct light */
    PT_ONE_BOUNCE,         /* direct + exactly one indirect bounce */
    PT_ONE_BOUNCE_NOVIS,   /* one-bounce with the bounce segment unoccluded (what RSM computes) */
    PT_INDIRECT,           /* full minus direct */
} PtMode;

/* Where a path's random numbers come from. */
typedef enum PtSampler {
    PT_SAMPLER_SOBOL = 0,    /* Owen-scrambled Sobol' pairs, shuffled per pixel (Burley 2020) */
    PT_SAMPLER_INDEPENDENT,  /* independent uniform numbers from PCG32 per pixel */
} PtSampler;

typedef struct PtSettings {
    int width, height;
    int spp;               /* samples per pixel, ≥ 1 */
    int threads;           /* ≥ 1 */
    uint64_t seed;
    PtMode mode;
    int max_depth;         /* path vertices at most */
    bool russian_roulette;
    int rr_depth;          /* bounces before roulette starts */
    bool pixel_jitter;     /* false: every sample through the pixel centre */
    bool progress;         /* progress on stderr: a bar on a terminal, else a line every few seconds */
    const volatile int *stop; /* may be NULL; when it becomes non-zero (e.g. from a SIGINT handler) the
                                 render finishes its current pass and stops there (PtStats.spp) */
    PtSampler sampler;     /* default: PT_SAMPLER_SOBOL */
    double target_relmse;  /* > 0: stop after the pass at which the relMSE estimated from the per-pixel
                              variance is at most this (from PT_TARGET_MIN_SPP samples on) */
    double time_budget;    /* > 0: seconds; stop before a pass that would end past it (the first pass
                              always runs) */
    int path_group;        /* paths of a tile row traced in lock step (render_tile): 0 (default) the whole
                              row where the scene overflows the caches, else 1; n ≥ 1: up to n (the same
                              image whatever it is: test_reference_exact checks) */
    bool ordinary_priority;/* pt_progressive: its threads at the ordinary scheduling priority, not the
                              lowest (SCHED_IDLE), which on a machine busy with other work leaves them
                              almost nothing */
} PtSettings;

/* The samples a target relMSE needs before its estimate is trusted (the
 * variance of few samples is itself noisy). */
enum { PT_TARGET_MIN_SPP = 16 };

/* Why a render stopped. */
typedef enum PtStop {
    PT_STOP_SPP = 0,       /* PtSettings.spp reached */
    PT_STOP_TARGET,        /* the estimated relMSE reached PtSettings.target_relmse */
    PT_STOP_TIME,          /* the next pass would have ended past PtSettings.time_budget */
    PT_STOP_INTERRUPTED,   /* PtSettings.stop was raised */
} PtStop;

typedef struct PtStats {
    double seconds;
    uint64_t rays;         /* closest-hit, all-hit and shadow rays */
    int spp;               /* samples per pixel reached: PtSettings.spp unless stopped early */
    PtStop stopped;        /* why it stopped */
    double relmse_estimate;/* the relMSE of the mean estimated from the per-pixel variance (0 below 2 spp):
                              exact in expectation for independent samples, an overestimate for Sobol'
                              ones (pt_job.h) */
} PtStats;

#endif
