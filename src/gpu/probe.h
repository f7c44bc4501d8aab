/* probe.h — what this device sustains on work shaped like the GI gathers:
 * evaluations per second of the VPL irradiance arithmetic with 0–3 texture
 * fetches per sample, from 2D maps and from cube maps (shaders/probe/).
 * `rtgi probe` prints it; `--timings --probe FILE` states each gather's
 * evaluations per second as a fraction of the matching bound. */
#ifndef RTGI_PROBE_H
#define RTGI_PROBE_H

#include <stdbool.h>
#include <stdio.h>

/* Texture fetches per sample of the yardstick issue 11 set for the RSM
 * gathers ("two-fetch bound"). The gathers now read one packed texel per
 * sample (shaders/common/rsm_texel.glsl): the probe's `texel` kernels do
 * the same, unpacking included. */
#define PROBE_RSM_FETCHES 2

/* Side of the probe's maps unless asked otherwise, and the largest asked. */
#define PROBE_MAP_DEFAULT 512
#define PROBE_MAP_MAX 2048

typedef struct ProbeResult {
    int map_size;          /* the maps' side (texels; per cube face) */
    double evals_2d[4];    /* evaluations/s with 0..3 RGBA32F fetches per sample from 2D maps */
    double evals_cube[4];  /* the same from cube maps ([0] = [0] of 2D) */
    double evals_texel_2d; /* one packed RSM texel per sample (RGBA32UI, unpacked as the gathers do), 2D */
    double evals_texel_cube; /* the same from a cube map; both 0 in results written before they existed */
    double evals_ssbo;     /* reading one GpuVpl from a storage buffer per sample, the same in every lane */
    double lanes;          /* the fewest invocations of a kernel's timed dispatch (each grows until one
                            * lasts 4 ms: 65,536 for llvmpipe's fetch kernels, millions on a GPU); 0 if
                            * not recorded */
} ProbeResult;

/* The bound that matches a gather: `vpl` for VPL loops, else RSM texture
 * gathers (cube or 2D) with a fraction `from_list` of their samples read
 * from a storage-buffer list (importance weighting); `texel`: the packed
 * texel kernels, else the two-fetch ones. 0 where the result lacks it. */
double probe_bound(const ProbeResult *r, bool vpl, bool cube, double from_list, bool texel);

/* Runs the kernels on the current GL context with maps of map_size² texels
 * (0: PROBE_MAP_DEFAULT; clamped to [64, PROBE_MAP_MAX]). false after
 * logging. */
bool probe_run(ProbeResult *out, int map_size);
/* Writes/reads the result as JSON. false after logging. */
bool probe_write_json(const char *path, const ProbeResult *r);
bool probe_read_json(const char *path, ProbeResult *r);
/* Prints "probe_<map>_fetch<N>_evals_per_s: X" lines. */
void probe_print(FILE *out, const ProbeResult *r);

#endif
