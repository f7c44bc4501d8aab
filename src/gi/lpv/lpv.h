/* lpv.h — hooks into a running `--gi lpv` technique (its state is the
 * renderer's gi_state while GI_LPV is selected), for tests and tools: inject
 * a given VPL list instead of the light stage's, read a grid or the
 * geometry volume back, and where its cells lie. Not used by the frame. */
#ifndef RTGI_GI_LPV_H
#define RTGI_GI_LPV_H

#include <stdbool.h>

#include "shared/gpu_types.h"

typedef enum LpvVolume {
    LPV_VOLUME_INJECTED,       /* the SH intensity injected this frame, before propagation */
    LPV_VOLUME_ACCUMULATED,    /* injected + every propagation step (what the lookup reads) */
    LPV_VOLUME_INJECTED_OUTER, /* cascade k ≥ 1: injected, only the VPLs outside cascade k − 1 */
    LPV_VOLUME_STEP,           /* the light of the last propagation step of the last volume propagated: the last
                                  cascade's, its last set's and last group's, into group 0 (the rest 0); for tests
                                  with one cascade and one group */
} LpvVolume;

/* From the next frame on, inject these `count` VPLs (copied) instead of the
 * light stage's buffer; count 0 goes back to the light stage. */
void lpv_set_vpls(void *state, const GpuVpl *vpls, int count);
/* From the next frame on, `iterations` propagation steps (volumes rebuilt). */
void lpv_set_iterations(void *state, int iterations);
/* Cells per side. */
int lpv_grid_size(const void *state);
/* Light groups (--lpv-groups): the volumes stack them in z. */
int lpv_groups(const void *state);
/* Cascade k's grid of the last frame: min corner (m) and cell size (m). */
void lpv_grid(const void *state, int cascade, float origin[3], float *cell);
/* Reads cascade k's volume: out[((c·G·N + g·N + z)·N + y)·N + x][4] for
 * colour channel c = 0..2 and light group g < G = lpv_groups, the SH
 * vec4(c00, c1x, c1y, c1z) of that cell's intensity (W/sr). `out` holds
 * 3·G·N³·4 floats. Waits for the GPU. */
bool lpv_read_volume(void *state, int cascade, LpvVolume which, float *out);
/* Reads cascade k's geometry volume, (N+1)³ texels at the cells' corners:
 * out[(((t·(N+1) + z)·(N+1) + y)·(N+1) + x)·4 + i] with t = 0 for the
 * normal tensor's xx yy zz (i = 0..2), t = 1 for xy xz yz. `out` holds
 * 8·(N+1)³ floats. Waits for the GPU. */
bool lpv_read_geometry(void *state, int cascade, float *out);

#endif
