/* probe.h — what this device sustains on work shaped like the GI gathers:
 * evaluations per second of the VPL irradiance arithmetic with 0–3 texture
 * fetches per sample, from 2D maps and from cube maps (shaders/probe/).
 * `rtgi probe` prints it; `--timings --probe FILE` states each gather's
 * evaluations per second as a fraction of the matching bound. */
#ifndef RTGI_PROBE_H
#define RTGI_PROBE_H

#include <stdbool.h>
#include <stdio.h>

/* Texture fetches per RSM gather sample (shaders/common/surfel.glsl:
 * surfel + flux): the probe kernel that bounds the gathers. */
#define PROBE_RSM_FETCHES 2

typedef struct ProbeResult {
    double evals_2d[4];   /* evaluations/s with 0..3 fetches per sample from 2D maps */
    double evals_cube[4]; /* the same from cube maps ([0] = [0] of 2D) */
    double evals_ssbo;    /* reading one GpuVpl from a storage buffer per sample, the same in every lane */
} ProbeResult;

/* The bound that matches a gather: `vpl` for VPL loops, else RSM texture
 * gathers (cube or 2D) with a fraction `from_list` of their samples read
 * from a storage-buffer list (importance weighting). */
double probe_bound(const ProbeResult *r, bool vpl, bool cube, double from_list);

/* Runs the kernels on the current GL context. false after logging. */
bool probe_run(ProbeResult *out);
/* Writes/reads the result as JSON. false after logging. */
bool probe_write_json(const char *path, const ProbeResult *r);
bool probe_read_json(const char *path, ProbeResult *r);
/* Prints "probe_<map>_fetch<N>_evals_per_s: X" lines. */
void probe_print(FILE *out, const ProbeResult *r);

#endif
