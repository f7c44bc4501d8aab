/* vct.h — hooks into a running `--gi vct` technique (its state is the
 * renderer's gi_state while GI_VCT is selected), for tests and tools: where
 * the volume lies and what its voxels hold. Not used by the frame. */
#ifndef RTGI_GI_VCT_H
#define RTGI_GI_VCT_H

#include <stdbool.h>

typedef enum VctVolume {
    VCT_VOLUME_ALBEDO,   /* rgb albedo, a opacity (0 or 1) */
    VCT_VOLUME_NORMAL,   /* xyz normal (sign-canonical) */
    VCT_VOLUME_RADIANCE, /* rgb premultiplied outgoing radiance (W/(m²·sr)), a opacity; what the cones read */
} VctVolume;

/* Voxels per side, the min corner (m) and voxel size (m) of the volume
 * (clipmap: of its finest level). */
void vct_grid(const void *state, int *n, float origin[3], float *voxel);
/* Clipmap level k's min corner (m) and voxel size (m) in the last frame. */
void vct_level(const void *state, int k, float origin[3], float *voxel);
/* Reads mip 0 of a volume of the last frame: out[((z·N + y)·N + x)·4 + c].
 * `out` holds 4·N³·L floats (L clipmap levels stacked along z). Waits for
 * the GPU. */
bool vct_read_volume(void *state, VctVolume which, float *out);
/* Reads level 0 of the directional volume of `axis` (0..2: x y z) seen
 * along it (negative false) or against it, of clipmap level k:
 * out[((z·M + y)·M + x)·4 + c] for M = N/2, 4·M³ floats. False if the
 * directional volumes are not built (--vct-aniso off). Waits for the GPU. */
bool vct_read_directional(void *state, int axis, bool negative, int k, float *out);
/* Opaque voxels of the last voxelization, and whether the injection ran
 * over their list (true) or over every voxel (the list was too short). */
unsigned vct_opaque_voxels(const void *state, bool *listed);

/* The diffuse cone set `set` (0, 1, 2: --vct-cones 6, 9, 16), in the
 * normal's frame (z = normal; the tracers turn it with basis() of
 * common/math.glsl): dirs[i] = unit direction xyz and weight w = ∫cosθ dω
 * over the cone's cell of the hemisphere (the directions' Voronoi cells),
 * tan_half[i] the tangent of the half-angle whose cone has the cell's solid
 * angle. Returns the cone count (≤ VCT_MAX_CONES). */
int vct_cone_set(int set, float dirs[][4], float *tan_half);

/* One cone to trace (vct_probe): from surface point x (m) with unit normal
 * n along unit direction d, tan_half the tangent of its half-angle. */
typedef struct VctProbe {
    float x[3], n[3], d[3];
    float tan_half;
} VctProbe;
/* Traces `count` cones through the volumes of the last frame exactly as
 * the frame's cones are traced (gi/vct/cone.glsl, vct_cone: apex offset,
 * steps, mips, directional volumes): out[i] = the radiance gathered (rgb,
 * W/(m²·sr)) and the opacity met (a). false after logging (the program did
 * not build, no memory). Waits for the GPU. */
bool vct_probe(void *state, int count, const VctProbe *probes, float (*out)[4]);

#endif
