/* pass_rsm_gather.h — one-bounce gathering from reflective shadow maps
 * (Dachsbacher & Stamminger 2005) and its two accelerations:
 *   full          N samples per pixel on the paper's polar pattern (or all VPLs)
 *   interpolated  gather at 1/f resolution, interpolate where 3-4 of the 4
 *                 surrounding low-res samples agree in normal and position,
 *                 full gather for the rest (the paper's screen-space scheme)
 *   interleaved   n×m de-interleaved sub-images with disjoint sample subsets
 *                 (Keller & Heidrich 2001, Segovia et al. 2006), reassembled,
 *                 then a geometry-aware blur
 * Inputs: GBuffer, RsmMap(s), VplBuffer (exhaustive mode and pixel list),
 * GI parameters (UBO_GI). Output: an irradiance image (RGBA32F).
 * Owns: its programs, the sample pattern, the low-res and de-interleaved
 * textures. */
#ifndef RTGI_PASS_RSM_GATHER_H
#define RTGI_PASS_RSM_GATHER_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "passes/pass_rsm.h"
#include "passes/pass_vpl.h"
#include "scene.h"
#include "targets.h"

typedef enum GatherLayout { GATHER_FULL, GATHER_LOWRES, GATHER_LIST, GATHER_INTERLEAVED, GATHER_LAYOUTS } GatherLayout;

typedef struct PassRsmGather {
    GLuint gather[GATHER_LAYOUTS][2]; /* [layout][cube] */
    GLuint interp;                    /* rsm_interp.comp */
    GLuint split, merge, blur;        /* gi_interleave.comp */
    GLuint pattern;                   /* SSBO: vec4 per sample */
    GLuint light_ubo;
    int width, height;                /* full resolution */
    int low_w, low_h;                 /* low resolution */
    int sub_w, sub_h;                 /* interleaved sub-image size */
    int di_w, di_h;                   /* de-interleaved layout: n·sub_w × m·sub_h */
    GLuint lowres;                    /* RGBA32F low_w × low_h */
    GLuint di_position, di_normal;    /* de-interleaved G-buffer */
    GLuint di_irradiance;             /* de-interleaved result */
    GLuint merged;                    /* reassembled, before the blur */
} PassRsmGather;

/* The N-sample pattern: ξ1 = (i + ½)/N, ξ2 = radical inverse of i (a
 * Hammersley set), as vec4(ξ1·sin 2πξ2, ξ1·cos 2πξ2, ξ1, ξ2). */
void rsm_pattern(int n, float (*out)[4]);
/* Texels in the sampling disk: π·(r_max·resolution)². */
float rsm_disk_texels(const GiParams *gp);

bool pass_rsm_gather_create(PassRsmGather *p, const GiParams *gp, int width, int height);
void pass_rsm_gather_destroy(PassRsmGather *p);

/* Gathers light `m` into `out` (accumulating when `accumulate`) in the
 * given layout. GATHER_LOWRES writes the pass's low-res texture and
 * GATHER_INTERLEAVED its de-interleaved texture; FULL and LIST write `out`. */
void pass_rsm_gather_run(PassRsmGather *p, GatherLayout layout, const RsmMap *m, bool exhaustive, bool accumulate,
                         const GBuffer *gb, const VplBuffer *vb, GLuint out);
/* Interpolates the low-res result into `out`, listing pixels for a full gather. */
void pass_rsm_interp_run(PassRsmGather *p, const GBuffer *gb, const VplBuffer *vb, GLuint out);
void pass_interleave_split(PassRsmGather *p, const GBuffer *gb);
/* Reassembles the sub-images into `out`, then blurs (if `blur`) in place via the merged texture. */
void pass_interleave_merge(PassRsmGather *p, const GBuffer *gb, bool blur, GLuint out);
/* Geometry-aware blur over the n×m window of `in` into `out` (in ≠ out). */
void pass_interleave_blur(PassRsmGather *p, const GBuffer *gb, GLuint in, GLuint out);

#endif
