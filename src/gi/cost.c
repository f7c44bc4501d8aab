/* cost.c — a technique's work per frame, in gather evaluations, for
 * estimates made before it runs: the window's "slow" marking and render's
 * warning before a long first frame. Counts are upper bounds (every RSM
 * texel lit); an evaluation is one sample (RSM texel, VPL, voxel fetch or
 * LPV cell update) at one pixel or cell. */
#include "gi/gi.h"

#include <math.h>

#include "light_stage.h"
#include "renderer.h"

/* VPLs the light stage would make (every RSM texel lit: an upper bound). */
static double vpl_upper_bound(const Scene *s, const GiParams *p, int gi)
{
    double n = 0;
    for (int i = 0; i < s->light_count; i++) {
        const Light *l = &s->lights[i];
        int faces = (l->type == LIGHT_POINT || l->type == LIGHT_QUAD) ? 6 : 1;
        int size = gi_techniques[gi]->rsm_from_vpl_count && p->vpl_count > 0
                       ? light_stage_rsm_size_for_vpls(l, p->vpl_count)
                       : p->rsm_size;
        n += (double)faces * size * size;
    }
    return n;
}

/* Samples along one cone: the step grows with the diameter (by the step
 * fraction), so the count is logarithmic in the volume's size. */
static double vct_samples_per_cone(const GiParams *p)
{
    double grow = 1.0 + (p->vct_step > 0.f ? p->vct_step : 0.5);
    return ceil(log((double)p->vct_size) / log(grow)) + 1.0;
}

double gi_cost_evaluations(int gi, const GiParams *p, const Scene *s, double px)
{
    double samples = p->exhaustive ? vpl_upper_bound(s, p, gi) : p->samples;
    double subsets = (double)p->interleave_n * p->interleave_m;
    switch ((GiMode)gi) {
    case GI_RSM:
    case GI_RSM_INTERLEAVED: /* per pixel: its samples (interleaving splits the pattern, not the count) */
        return px * samples;
    case GI_RSM_INTERP: /* low-res gathers plus a tenth of the pixels in full (Cornell: 5%) */
        return px * samples * (1.0 / (p->interp_factor * p->interp_factor) + 0.1);
    case GI_VPL_ALL:
        return px * vpl_upper_bound(s, p, gi) * p->vpl_keep;
    case GI_VPL_CLAMPED:
    case GI_VPL_SLC: /* tiles visit every VPL in the worst case */
        return px * vpl_upper_bound(s, p, gi);
    case GI_VPL_INTERLEAVED:
    case GI_VPL_METALIGHTS:
        return px * vpl_upper_bound(s, p, gi) / subsets;
    case GI_LPV: {
        double cells = pow(p->lpv_size, 3) * p->lpv_cascades;
        int steps = p->lpv_iterations > 0 ? p->lpv_iterations : p->lpv_size;
        return cells * steps * 6 + vpl_upper_bound(s, p, gi) * p->lpv_cascades + px;
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
        return e;
    }
    default:
        return 0;
    }
}
