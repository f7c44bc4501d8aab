/* cost.c — a technique's work per frame, in gather evaluations, for
 * estimates made before it runs: the window's "slow" marking and render's
 * line before a long first frame. An evaluation is one sample (RSM texel,
 * VPL, voxel fetch or LPV cell update) at one pixel or cell; the counts are
 * upper bounds (VPL rows: every VPL slot the light stage fills, tiled rows:
 * every VPL at every pixel).
 *
 * Against wall time on llvmpipe (Cornell box, --vpls 4096 = 3163 VPLs made
 * of 4107 slots; --timings' frame_wall_ms, which also holds the direct
 * light; shared 2-core machine, load 1.5 to 3), estimate / measured:
 *   256²: vpl-all 6.7 / 2.9 s (2.3x), vpl-slc 6.7 / 0.87 s (7.7x),
 *         vpl-interleaved 0.42 / 0.19 s (2.2x), rsm 0.66 / 0.74 s (0.9x),
 *         vct 1.6 / 0.75 s (2.1x);
 *   128²: vpl-all 1.7 / 0.49 s (3.5x), vpl-clamped 1.7 / 0.12 s (14x),
 *         vpl-slc 1.7 / 0.28 s (6x), vpl-interleaved 0.10 / 0.058 s (1.8x).
 * The tiled rows' excess is the culling (vpl-slc shades about a third of
 * the VPLs at each pixel, vpl-clamped a tenth). Before (every texel of the
 * RSM cube a VPL, at 1.5e7/s) the VPL rows were 5.3 times these: 12x
 * (vpl-all) to 41x (vpl-slc) at 256². */
#include "gi/gi.h"

#include <math.h>

#include "gpu/light_stage.h"
#include "frame/renderer.h"

/* RSM texels per side for light `l`: what --vpls sets for rows that make
 * VPLs from it, else the RSM size. */
static int rsm_size(const Scene *s, const Light *l, const GiParams *p, int gi)
{
    return gi_techniques[gi]->rsm_from_vpl_count && p->vpl_count > 0 ? light_stage_rsm_size_for_vpls(s, l, p->vpl_count)
                                                                      : p->rsm_size;
}

/* Every RSM texel of every light (each face of a cube): what an exhaustive
 * gather sums and LPV injects. With `lit_only`, only the texels that can
 * hold a lit surface (light_stage_lit_layers): the VPLs the light stage
 * makes at most, about --vpls per light (the Cornell box: 4107 slots for
 * --vpls 4096, 3163 VPLs made). */
static double rsm_texels(const Scene *s, const GiParams *p, int gi, bool lit_only)
{
    double n = 0;
    for (int i = 0; i < s->light_count; i++) {
        const Light *l = &s->lights[i];
        double layers = lit_only ? light_stage_lit_layers(s, l) : shadow_frame_is_cube(l, s->bounds_min, s->bounds_max) ? 6 : 1;
        double size = rsm_size(s, l, p, gi);
        n += layers * size * size;
    }
    return n;
}

/* The LPV and VCT rows count cell updates and voxel fetches, not gather
 * samples, and were fitted to wall time at 1.5e7 of them per second
 * (595a43d: vct at 128² and 256² estimated 1-2 s, measured 0.95-1.17 s):
 * in gather evaluations at GI_COST_DEFAULT_EVALS_PER_S, each costs the
 * ratio of the two rates (the same seconds as before). */
#define VOLUME_EVAL_COST (GI_COST_DEFAULT_EVALS_PER_S / 1.5e7)

/* Samples along one cone: the step grows with the diameter (by the step
 * fraction), so the count is logarithmic in the volume's size. */
static double vct_samples_per_cone(const GiParams *p)
{
    double grow = 1.0 + (p->vct_step > 0.f ? p->vct_step : 0.5);
    return ceil(log((double)p->vct_size) / log(grow)) + 1.0;
}

double gi_cost_evaluations(int gi, const GiParams *p, const Scene *s, double px)
{
    double samples = p->exhaustive ? rsm_texels(s, p, gi, false) : p->samples;
    double vpls = rsm_texels(s, p, gi, true);
    double subsets = (double)p->interleave_n * p->interleave_m;
    switch ((GiMode)gi) {
    case GI_RSM:
    case GI_RSM_INTERLEAVED: /* per pixel: its samples (interleaving splits the pattern, not the count) */
        return px * samples;
    case GI_RSM_INTERP: /* low-res gathers plus a tenth of the pixels in full (Cornell: 5%) */
        return px * samples * (1.0 / (p->interp_factor * p->interp_factor) + 0.1);
    case GI_VPL_ALL:
        return px * vpls * p->vpl_keep;
    case GI_VPL_CLAMPED:
    case GI_VPL_SLC: /* tiles visit every VPL in the worst case */
        return px * vpls;
    case GI_VPL_INTERLEAVED:
    case GI_VPL_METALIGHTS:
        return px * vpls / subsets;
    case GI_LPV: {
        double cells = pow(p->lpv_size, 3) * p->lpv_cascades * p->lpv_groups;
        int steps = p->lpv_iterations > 0 ? p->lpv_iterations
                    : p->lpv_propagation == LPV_PROPAGATION_DIRECTIONAL ? 3 * p->lpv_size
                                                                         : p->lpv_size;
        return (cells * steps * 6 + rsm_texels(s, p, gi, false) * p->lpv_cascades + px) * VOLUME_EVAL_COST;
    }
    case GI_VCT: {
        /* Traced pixels × (diffuse cones + the specular one) × samples per
         * cone × fetches per sample (3 of the 6 directional volumes with
         * anisotropy), the injection's 3×3 shadow taps per voxel, and with a
         * second bounce two diffuse sets from each occupied voxel: about
         * 40 N² per level, from the Cornell box's bounce pass at 128³
         * (~22 s on llvmpipe, conservative walls two voxels thick, lanes
         * of empty voxels in the same SIMD chunks). */
        static const int cones[] = {6, 9, 16};
        int nc = cones[p->vct_cones >= 0 && p->vct_cones < 3 ? p->vct_cones : 0];
        double fetches = p->vct_aniso ? 3.0 : 1.0, per_cone = vct_samples_per_cone(p) * fetches;
        int scale = p->vct_trace_scale > 1 ? p->vct_trace_scale : 1;
        int levels = p->vct_levels > 1 ? p->vct_levels : 1;
        double voxels = pow(p->vct_size, 3) * levels;
        double e = px / (scale * scale) * (nc + 1) * per_cone + px + voxels * 9.0;
        if (p->vct_bounces > 1)
            e += 40.0 * p->vct_size * p->vct_size * levels * 2.0 * nc * per_cone;
        return e * VOLUME_EVAL_COST;
    }
    default:
        return 0;
    }
}

double gi_cost_seconds(int gi, const GiParams *p, const Scene *s, double px, double evals_per_s)
{
    return gi_cost_evaluations(gi, p, s, px) / evals_per_s;
}
