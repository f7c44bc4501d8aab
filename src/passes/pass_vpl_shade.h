/* pass_vpl_shade.h — indirect light from many VPLs (SPEC §4):
 *   all          brute force: every pixel sums every VPL (or a uniform
 *                random fraction q of them, weighted 1/q)
 *   clamped      each VPL cut at a fixed range R: the biased baseline
 *   slc          stochastic light culling (Tokuyoshi & Harada 2016): per VPL
 *                α_i = 2π·e_max/(E·max I_i), range r_i = 1/√(α_i ξ_i), falloff
 *                max(α_i, 1/d²) inside it — unbiased over ξ
 *   interleaved  n×m interleaved shading with random disjoint VPL subsets
 *   metalights   the same with subsets dealt from metalights (Faure & Chang
 *                2010): VPLs ordered by their contribution to a low-res grid
 *                of G-buffer samples and grouped n·m at a time; each
 *                sub-image gets one member of every metalight. Regrouped
 *                whenever a light, the camera or the VPLs change.
 * clamped and slc bin VPL spheres into 16×16 screen tiles (a per-tile world
 * box from the G-buffer) in a culling pass before shading.
 * Inputs: GBuffer, VplBuffer, parameters. Output: an irradiance image.
 * Owns: its programs, the range, tile, evaluation and subset buffers. */
#ifndef RTGI_PASS_VPL_SHADE_H
#define RTGI_PASS_VPL_SHADE_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>

#include "gpu_types.h"
#include "passes/pass_vpl.h"
#include "scene.h"
#include "targets.h"

typedef enum VplMethod { VPL_ALL, VPL_CLAMPED, VPL_SLC, VPL_INTERLEAVED, VPL_METALIGHTS } VplMethod;

typedef struct PassVplShade {
    GLuint params_slc, params_clamped, cull;
    GLuint shade_all, shade_tiled, shade_interleaved;
    GLuint signature;
    GLuint ubo;           /* GpuVplParams */
    GLuint ranges;        /* vec2 per VPL */
    GLuint tiles;         /* counts[tiles], overflow, lists[tiles × capacity] */
    GLuint evals;         /* uint per shading work group */
    GLuint subsets;       /* K × L VPL indices; also the signatures (vec4 per VPL) */
    uint32_t vpl_capacity;
    uint32_t tile_capacity;   /* list entries per tile */
    int tiles_x, tiles_y;
    int width, height;
    int groups;           /* shading work groups */
    uint64_t grouping_key;/* what the metalight grouping was computed for */
    int regroups;         /* how many times the grouping was (re)computed */
    uint32_t subset_len;  /* L */
    GpuVplParams params;  /* as last uploaded */
} PassVplShade;

bool pass_vpl_shade_create(PassVplShade *p, int width, int height, uint32_t vpl_capacity);
void pass_vpl_shade_destroy(PassVplShade *p);

/* Uploads the parameters: exposure E for SLC, clamped range in metres. */
void pass_vpl_shade_set_params(PassVplShade *p, const GiParams *gp, float exposure, float range);
/* Per-VPL ranges and tiled culling (clamped and slc). */
void pass_vpl_cull_run(PassVplShade *p, VplMethod method, const GBuffer *gb, const VplBuffer *vb);
/* true if the metalight grouping was made for `key` and still holds: the
 * caller must then keep the VPL buffer as it is, since the grouping refers
 * to VPLs by their place in it (and the GPU appends them in no fixed order). */
bool pass_vpl_grouping_current(const PassVplShade *p, VplMethod method, uint64_t key);
/* Builds the interleaved subsets: random (interleaved) or from metalights
 * (recomputed only when `key` differs from the last grouping's). */
void pass_vpl_subsets_run(PassVplShade *p, VplMethod method, uint64_t key, const GiParams *gp, const GBuffer *gb,
                          const VplBuffer *vb);
void pass_vpl_shade_run(PassVplShade *p, VplMethod method, const GBuffer *gb, const VplBuffer *vb, GLuint out);
/* VPL–pixel evaluations of the last shading run (waits for the GPU);
 * `candidates` (may be NULL) receives the VPL–pixel pairs visited, which
 * for the tiled modes includes tile-list entries out of the pixel's range. */
uint64_t pass_vpl_shade_evaluations(const PassVplShade *p, uint64_t *candidates);
/* Tile-list entries dropped for lack of room in the last culling run. */
uint32_t pass_vpl_cull_overflow(const PassVplShade *p);

#endif
