/* timings.h — the --timings report of a renderer's frames (render's and
 * the window's): per-pass times, memory, GI counters (each technique row's
 * own lines), the gather's evaluations/s and, with a probe, its fractions
 * of the device's bound (issue 11). */
#ifndef RTGI_TIMINGS_H
#define RTGI_TIMINGS_H

#include <stdbool.h>

#include "frame/renderer.h"
#include "gpu/probe.h"

/* The probe the report compares with: --probe's path ("run" or a file) and
 * the file's result when it names one (NULL path: none). */
void timings_use_probe(const char *path, const ProbeResult *file);
/* Prints frame_cold_ms (the timed frames of the report, which draw every
 * light product), frame_steady_ms and steady_<pass>_ms lines for frames
 * that keep the light products (r's timer holds only steady frames). */
void timings_print_steady(const Renderer *r, double cold_ms, double steady_ms);
/* A gather's evaluations/s in the --timings report: of all its passes
 * and of each (RenderStats.gather_passes); 0 without a gather. */
typedef struct GatherRates {
    double total;
    double pass[GI_GATHER_PASSES];
} GatherRates;
/* Whether the report measures the RSM gather's reads-only twin (with
 * --probe, when the timings report gave the gather's evaluations/s): the
 * same passes with GiParams.rsm.reads_only, which read every sample and
 * evaluate none. */
bool timings_reads_twin(const RenderSettings *rs, const GatherRates *gather);
/* Prints the twin's evaluations/s (r runs it: its timer holds only the
 * twin's frames) and the gather's fraction of it, in all and per pass: how
 * near the gather is to the limit of its own reads on this device. */
void timings_print_reads_twin(Renderer *r, const GatherRates *gather);
/* Prints the --timings report (per-pass times, GI counters, the gather's
 * evaluations/s, in all and per gather pass, and, with the probe, their
 * fractions of the probe's bound). Returns the gather's rates. */
GatherRates timings_print(Renderer *r, const char *gl_renderer, double frame_ms);

#endif
