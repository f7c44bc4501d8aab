/* cost.c — what the technique rows' cost models share (each model is its
 * row's `cost`, in the technique's file): a technique's work per frame, in
 * gather evaluations, for estimates made before it runs: the window's "slow" marking and render's
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

/* RSM texels per side for light `l`: what --vpls sets for rows that make
 * VPLs from it, else the RSM size. */
static int rsm_size(const GiCostQuery *q, const Light *l)
{
    const GiParams *p = q->params;
    return q->row->rsm_from_vpl_count && p->vpl.count > 0 ? light_stage_rsm_size_for_vpls(q->scene, l, p->vpl.count)
                                                          : p->rsm.size;
}

/* The Cornell box: 4107 slots for --vpls 4096, 3163 VPLs made. */
double gi_cost_rsm_texels(const GiCostQuery *q, bool lit_only)
{
    const Scene *s = q->scene;
    double n = 0;
    for (int i = 0; i < s->light_count; i++) {
        const Light *l = &s->lights[i];
        double layers = lit_only ? light_stage_lit_layers(s, l) : shadow_frame_is_cube(l, s->bounds_min, s->bounds_max) ? 6 : 1;
        double size = rsm_size(q, l);
        n += layers * size * size;
    }
    return n;
}

double gi_cost_evaluations(int gi, const GiParams *p, const Scene *s, double px)
{
    const GiTechnique *row = gi >= 0 && gi < GI_MODE_COUNT ? gi_techniques[gi] : NULL;
    if (!row || !row->cost)
        return 0;
    return row->cost(&(GiCostQuery){row, p, s, px});
}

double gi_cost_seconds(int gi, const GiParams *p, const Scene *s, double px, double evals_per_s)
{
    return gi_cost_evaluations(gi, p, s, px) / evals_per_s;
}
