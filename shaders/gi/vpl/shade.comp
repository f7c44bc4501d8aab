// gi/vpl/shade.comp — indirect irradiance from many VPLs (SPEC §3-4), the
// visibility of each VPL by choice (GI_VISIBILITY, below), counting VPL–pixel evaluations (per work group, SSBO_EVALS;
// the second half counts candidates visited: tile-list entries for the
// tiled modes, the same as evaluations otherwise):
//   MODE_ALL          every VPL; with u_vpl.keep = q < 1 only those with
//                     ξ < q, weighted 1/q (uniform subsampling)
//   MODE_TILED        the pixel's tile list; a VPL counts inside its range
//                     r_i with falloff max(α_i, 1/d²) (SLC defined:
//                     stochastic light culling, unbiased) or 1/d² (clamped
//                     range, α = 0)
//   MODE_INTERLEAVED  sub-image k = (x mod n) + n·(y mod m) sums its VPL
//                     subset (SSBO_SUBSETS: the subsets' VPLs copied in
//                     their order, length L each), weighted by K = n·m
// GI_VISIBILITY: each evaluated term is multiplied by the VPL's visibility
// of the pixel, from its imperfect shadow map (gi/visibility/ism.glsl; map
// i is VPL i's; an interleaved subset's copy holds the VPL's index in
// normal_xi.w, src/gi/vpl/vpl.c).
// Each dispatch sums one chunk of LOOP_CHUNK entries of the pixel's list and
// adds to the image and the counters (the first chunk writes them).

#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "gi/vpl/falloff.glsl"
#include "common/gbuffer.glsl"
#include "common/packing.glsl"
#include "gi/visibility/ism.glsl"
#ifdef GI_VISIBILITY
// The term ic of VPL v (index i) at x, times its visibility there.
vec3 visible(IsmFrame vis, uint i, GpuVpl v, vec3 x, vec3 n, vec3 ic)
{
    return ic != vec3(0.0) ? ic * ism_visibility(vis, i, vpl_position(v), vpl_shading_normal(v), x, n) : ic;
}
#define VISIBLE(i, v, ic) visible(vis, i, v, x, n, ic)
#else
#define VISIBLE(i, v, ic) (ic)
#endif

layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = IMG_OUT) uniform image2D o_irradiance;
layout(location = LOC_CHUNK) uniform uint u_chunk; // this dispatch sums list entries [u_chunk, u_chunk + LOOP_CHUNK)
layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) readonly buffer CounterBlock { uint counters[]; };
layout(std430, binding = SSBO_TILES) readonly buffer TileBlock { uvec4 tiles[]; }; // VPL_TILE_LIST_BASE
layout(std430, binding = SSBO_EVALS) buffer EvalBlock { uint evals[]; };
layout(std430, binding = SSBO_SUBSETS) readonly buffer SubsetBlock { GpuVpl subsets[]; }; // K × L, zero flux: none

#if defined(MODE_TILED)
// One entry i of a tile's list, when `live` (within the list's length): its
// term if x lies within its range. The range test from the VPL itself
// rather than a load of params.comp's (α, r) per VPL (a per-lane gather on
// llvmpipe): SLC keeps a VPL while (d² + r_disk²)·α·ξ < 1, i.e. d < r, with
// α = 2π·e_max/(E·max(Φ)/π) as params.comp computes it (`limit` is
// vpl_slc_num()); the clamped range keeps d < R with α = 0 (`limit` is R²).
void tiled_term(uint i, bool live, vec3 x, vec3 n, VplFalloff fo, float limit, uint seed, IsmFrame vis,
                inout vec3 e, inout uint count)
{
    vec3 d = x - vpl_position(vpls[i]);
#ifdef SLC
    float alpha = vpl_slc_alpha(limit, vpls[i]);
    if (!live || (dot(d, d) + vpl_r2(fo, vpls[i])) * (alpha * vpl_xi_of(vpls[i].surface, seed)) >= 1.0)
        return;
#else
    const float alpha = 0.0;
    if (!live || dot(d, d) >= limit)
        return;
#endif
    float d2;
    vec3 ic = vpl_intensity_cos(vpls[i], x, n, d2);
    e += VISIBLE(i, vpls[i], ic) * max(alpha, vpl_falloff(fo, vpls[i], d2));
    count++;
}
#endif

shared uint s_evals;
shared uint s_visits;

void main()
{
    if (gl_LocalInvocationIndex == 0u) {
        s_evals = 0u;
        s_visits = 0u;
    }
    barrier();
#if defined(MODE_INTERLEAVED)
    // A work group shades one sub-image's pixels: group (X, Y) takes subset
    // (X mod n, Y mod m) over an 8n × 8m block, every n-th pixel across and
    // m-th down (src/gi/vpl/vpl.c dispatches n·m times the blocks). A SIMD
    // row then reads one VPL per step, the same in every lane, where
    // neighbouring pixels' different subsets made every read a per-lane
    // gather; each pixel sums what it summed before, in the same order.
    const ivec2 nm = ivec2(INTERLEAVE_N, INTERLEAVE_M); // compiled in (vpl.c): constant divisors
    ivec2 wg = ivec2(gl_WorkGroupID.xy);
    ivec2 px = (wg / nm) * 8 * nm + ivec2(gl_LocalInvocationID.xy) * nm + wg % nm;
#else
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
#endif
    bool inside = all(lessThan(px, gb_size()));
    vec3 x, n;
    vec3 e = vec3(0.0);
    uint count = 0u, visits = 0u;
    if (inside && gb_surface(px, x, n)) {
        float d2;
        VplFalloff fo = vpl_falloff_params();
#ifdef GI_VISIBILITY
        IsmFrame vis = ism_frame();
#else
        IsmFrame vis; // unused
#endif
#if defined(MODE_ALL)
        float q = u_vpl.keep;
        uint nv = min(counters[0], u_chunk + uint(LOOP_CHUNK));
        for (uint i = u_chunk; i < nv; i++) {
            if (q < 1.0 && vpl_xi(vpls[i]) >= q)
                continue;
            vec3 ic = vpl_intensity_cos(vpls[i], x, n, d2);
            e += VISIBLE(i, vpls[i], ic) * vpl_falloff(fo, vpls[i], d2);
            count++;
        }
        e /= q;
#elif defined(MODE_TILED)
        uint ntiles = uint(u_vpl.tiles_x * u_vpl.tiles_y);
        uint tile = uint(px.y / VPL_TILE) * uint(u_vpl.tiles_x) + uint(px.x / VPL_TILE);
        uint cap = u_vpl.tile_capacity, nt = tiles[tile >> 2u][tile & 3u];
        uint k1 = min(nt, u_chunk + uint(LOOP_CHUNK));
        visits = k1 > u_chunk ? k1 - u_chunk : 0u;
#ifdef SLC
        float limit = vpl_slc_num();
        uint seed = counters[1]; // what the VPLs' ξ were drawn with
#else
        float limit = u_vpl.range * u_vpl.range;
        const uint seed = 0u;
#endif
        // Four list entries per load (the list and u_chunk are aligned to
        // 4, the list padded with index 0): on llvmpipe every load in a loop
        // is per lane, and one per candidate had been a third of SLC's.
        uint list = (VPL_TILE_LIST_BASE(ntiles) + tile * cap) >> 2u;
        for (uint k = u_chunk; k < k1; k += 4u) {
            uvec4 q = tiles[list + (k >> 2u)];
            tiled_term(q.x, true, x, n, fo, limit, seed, vis, e, count);
            tiled_term(q.y, k + 1u < k1, x, n, fo, limit, seed, vis, e, count);
            tiled_term(q.z, k + 2u < k1, x, n, fo, limit, seed, vis, e, count);
            tiled_term(q.w, k + 3u < k1, x, n, fo, limit, seed, vis, e, count);
        }
#elif defined(MODE_INTERLEAVED)
        uint k = uint(wg.x % nm.x + nm.x * (wg.y % nm.y)); // = px.x mod n + n·(px.y mod m)
        uint len = u_vpl.subset_len;
        uint j1 = min(len, u_chunk + uint(LOOP_CHUNK));
        for (uint j = k * len + u_chunk; j < k * len + j1; j++) {
            // The subset's own copy of its VPLs (vpl.c): two loads, no
            // index; a short subset's last entry has zero flux and adds 0.
            vec3 ic = vpl_intensity_cos(subsets[j], x, n, d2);
            e += VISIBLE(floatBitsToUint(subsets[j].normal_xi.w), subsets[j], ic) * vpl_falloff(fo, subsets[j], d2);
            count += subsets[j].flux.r + subsets[j].flux.g + subsets[j].flux.b > 0.0 ? 1u : 0u;
        }
        e *= float(u_vpl.subset_count);
#endif
    }
#if !defined(MODE_TILED)
    visits = count;
#endif
    if (inside) {
        if (u_chunk > 0u)
            e += imageLoad(o_irradiance, px).rgb;
        imageStore(o_irradiance, px, vec4(e, 1.0));
    }
    atomicAdd(s_evals, count);
    atomicAdd(s_visits, visits);
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        uint g = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
        uint gv = gl_NumWorkGroups.x * gl_NumWorkGroups.y + g;
        evals[g] = (u_chunk > 0u ? evals[g] : 0u) + s_evals;
        evals[gv] = (u_chunk > 0u ? evals[gv] : 0u) + s_visits;
    }
}
