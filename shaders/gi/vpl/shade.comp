// gi/vpl/shade.comp — indirect irradiance from many VPLs (SPEC §3-4), no
// visibility, counting VPL–pixel evaluations (per work group, SSBO_EVALS;
// the second half counts candidates visited: tile-list entries for the
// tiled modes, the same as evaluations otherwise):
//   MODE_ALL          every VPL; with u_vpl.keep = q < 1 only those with
//                     ξ < q, weighted 1/q (uniform subsampling)
//   MODE_TILED        the pixel's tile list; a VPL counts inside its range
//                     r_i with falloff max(α_i, 1/d²) (SLC defined:
//                     stochastic light culling, unbiased) or 1/d² (clamped
//                     range, α = 0)
//   MODE_INTERLEAVED  sub-image k = (x mod n) + n·(y mod m) sums its VPL
//                     subset (SSBO_SUBSETS, length L each), weighted by K = n·m
// Each dispatch sums one chunk of LOOP_CHUNK entries of the pixel's list and
// adds to the image and the counters (the first chunk writes them).
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "gi/vpl/falloff.glsl"
#include "common/gbuffer.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = IMG_OUT) uniform image2D o_irradiance;
layout(location = LOC_CHUNK) uniform uint u_chunk; // this dispatch sums list entries [u_chunk, u_chunk + LOOP_CHUNK)
layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) readonly buffer CounterBlock { uint counters[]; };
layout(std430, binding = SSBO_TILES) readonly buffer TileBlock { uint tiles[]; };
layout(std430, binding = SSBO_EVALS) buffer EvalBlock { uint evals[]; };
layout(std430, binding = SSBO_SUBSETS) readonly buffer SubsetBlock { uint subsets[]; };

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
    ivec2 nm = ivec2(u_vpl.interleave_n, u_vpl.interleave_m);
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
#if defined(MODE_ALL)
        float q = u_vpl.keep;
        uint nv = min(counters[0], u_chunk + uint(LOOP_CHUNK));
        for (uint i = u_chunk; i < nv; i++) {
            if (q < 1.0 && vpl_xi(vpls[i]) >= q)
                continue;
            vec3 ic = vpl_intensity_cos(vpls[i], x, n, d2);
            e += ic * vpl_falloff(fo, vpls[i], d2);
            count++;
        }
        e /= q;
#elif defined(MODE_TILED)
        uint ntiles = uint(u_vpl.tiles_x * u_vpl.tiles_y);
        uint tile = uint(px.y / VPL_TILE) * uint(u_vpl.tiles_x) + uint(px.x / VPL_TILE);
        uint cap = u_vpl.tile_capacity, nt = tiles[tile];
        uint k1 = min(nt, u_chunk + uint(LOOP_CHUNK));
        visits = k1 > u_chunk ? k1 - u_chunk : 0u;
        // The range test from the VPL itself rather than a load of
        // params.comp's (α, r) per VPL (a per-lane gather on llvmpipe):
        // SLC keeps a VPL while (d² + r_disk²)·α·ξ < 1, i.e. d < r, with
        // α = 2π·e_max/(E·max(Φ)/π) as params.comp computes it; the
        // clamped range keeps d < R with α = 0.
#ifdef SLC
        float alpha_num = vpl_slc_num();
        uint seed = counters[1]; // what the VPLs' ξ were drawn with
#else
        float range2 = u_vpl.clamp_range * u_vpl.clamp_range;
#endif
        for (uint k = u_chunk; k < k1; k++) {
            uint i = tiles[ntiles + 1u + tile * cap + k];
            vec3 d = x - vpl_position(vpls[i]);
#ifdef SLC
            float alpha = vpl_slc_alpha(alpha_num, vpls[i]);
            if ((dot(d, d) + vpl_r2(fo, vpls[i])) * (alpha * vpl_xi_of(vpls[i].surface, seed)) >= 1.0)
                continue;
#else
            const float alpha = 0.0;
            if (dot(d, d) >= range2)
                continue;
#endif
            vec3 ic = vpl_intensity_cos(vpls[i], x, n, d2);
            e += ic * max(alpha, vpl_falloff(fo, vpls[i], d2));
            count++;
        }
#elif defined(MODE_INTERLEAVED)
        uint k = uint(wg.x % nm.x + nm.x * (wg.y % nm.y)); // = px.x mod n + n·(px.y mod m)
        uint len = u_vpl.subset_len;
        uint j1 = min(len, u_chunk + uint(LOOP_CHUNK));
        for (uint j = k * len + u_chunk; j < k * len + j1; j++) {
            uint i = subsets[j];
            if (i == 0xffffffffu)
                continue;
            vec3 ic = vpl_intensity_cos(vpls[i], x, n, d2);
            e += ic * vpl_falloff(fo, vpls[i], d2);
            count++;
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
