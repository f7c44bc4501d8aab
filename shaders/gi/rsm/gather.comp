// gi/rsm/gather.comp — one bounce from the RSM into an irradiance image, in
// one of four layouts chosen by a define:
//   MODE_FULL         every full-resolution pixel
//   MODE_LOWRES       one pixel per interp_factor² block (screen-space interpolation, step 1)
//   MODE_LIST         the pixels listed by interp.comp (step 3: full gathers)
//   MODE_INTERLEAVED  the de-interleaved G-buffer (bound at TEX_GB_SURFACE);
//                     sub-image k uses the disjoint
//                     sample subset k, k + n·m, k + 2·n·m, ...
// The weighting is compiled in (WEIGHTING, an RSM_WEIGHT_*); with
// EXHAUSTIVE the sum runs over every VPL of SSBO_VPL instead, one dispatch
// per LOOP_CHUNK of them (the later ones accumulate). Compiled, not read
// from uniforms: llvmpipe runs the code under an `if` whether or not a lane
// takes it, and the untaken paths' set-up had been two thirds of
// rsm-interleaved's work per pixel. u_accumulate adds to the image (one
// dispatch per light). READS_ONLY: the twin of `--probe run` that reads
// the samples and evaluates nothing (gi/rsm/sampling.glsl).
#include "shared/gpu_types.h"
#ifndef WEIGHTING
#error "gi/rsm/gather.comp needs WEIGHTING (an RSM_WEIGHT_*), as src/gi/rsm/rsm.c defines it"
#endif
#include "common/math.glsl"
#include "common/vpl.glsl"
#include "common/packing.glsl"
#include "gi/visibility/ism.glsl" // GI_VISIBILITY: the visibility of the bounce (src/gi/visibility/ism.c)
#include "gi/rsm/sampling.glsl"
#include "common/gbuffer.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = IMG_OUT) uniform image2D o_irradiance;
layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) readonly buffer CounterBlock { uint counters[]; };
#ifdef MODE_LIST
layout(std430, binding = SSBO_PIXEL_LIST) readonly buffer PixelList { uint list_count; uint groups_x, groups_y, groups_z; uint list[]; };
#endif
layout(location = LOC_GATHER_ACCUMULATE) uniform int u_accumulate;
layout(location = LOC_CHUNK) uniform uint u_chunk; // exhaustive: this dispatch sums VPLs [u_chunk, u_chunk + LOOP_CHUNK)

// A pixel's set of the importance sample list: a hash, so that neighbours
// take independent ones (RSM_LIST_SETS is a power of two: a mask).
uint list_set(ivec2 px)
{
    uint h = uint(px.x) * 0x8da6b343u ^ uint(px.y) * 0xd8163841u;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    h ^= h >> 12;
    return h % uint(RSM_LIST_SETS);
}

vec3 gather(vec3 x, vec3 n, ivec2 px, int first, int stride, int count)
{
#if defined(EXHAUSTIVE)
    vec3 e = vec3(0.0);
    float r2_per_area = u_gi.disk_r2_per_area; // read once (see RsmFrame)
    uint nv = min(counters[0], u_chunk + uint(LOOP_CHUNK));
#ifdef GI_VISIBILITY
    IsmFrame vis = ism_frame(); // one map per VPL
#endif
    for (uint i = u_chunk; i < nv; i++) {
#ifdef READS_ONLY
        e += rsm_reads_fold_vpl(vpls[i].surface, vpls[i].flux);
#else
        vec3 xp = vpl_position(vpls[i]), np = vpl_shading_normal(vpls[i]);
        vec3 ei = vpl_irradiance_disk(x, n, xp, np, vpls[i].flux.rgb, vpls[i].flux.w * r2_per_area);
#ifdef GI_VISIBILITY
        if (ei != vec3(0.0))
            ei *= ism_visibility(vis, i, xp, np, x, n);
#endif
        e += ei;
#endif
    }
    return e;
#elif WEIGHTING == RSM_WEIGHT_IMPORTANCE
    return rsm_gather_importance(x, n, list_set(px), first, stride, count);
#else
    return rsm_gather(rsm_frame(x), x, n, first, stride, count, WEIGHTING == RSM_WEIGHT_UNBIASED, u_gi.rsm_samples);
#endif
}

void store(ivec2 at, vec3 e)
{
    if (u_accumulate != 0)
        e += imageLoad(o_irradiance, at).rgb;
    imageStore(o_irradiance, at, vec4(e, 1.0));
}

void main()
{
    ivec2 gid = ivec2(gl_GlobalInvocationID.xy);
    int N = u_gi.rsm_samples;
#if defined(MODE_FULL)
    if (any(greaterThanEqual(gid, ivec2(u_frame.width, u_frame.height))))
        return;
    ivec2 px = gid, at = gid;
    int first = 0, stride = 1, count = N;
#elif defined(MODE_LOWRES)
    if (any(greaterThanEqual(gid, ivec2(u_gi.low_width, u_gi.low_height))))
        return;
    int f = u_gi.rsm_interp_factor;
    ivec2 px = min(gid * f + f / 2, ivec2(u_frame.width, u_frame.height) - 1), at = gid;
    int first = 0, stride = 1, count = N;
#elif defined(MODE_LIST)
    // Dispatched indirectly (interp.comp): 64 consecutive entries per group.
    uint index = gl_WorkGroupID.x * 64u + gl_LocalInvocationIndex;
    if (index >= list_count)
        return;
    uint code = list[index];
    ivec2 px = ivec2(code & 0xffffu, code >> 16), at = px;
    int first = 0, stride = 1, count = N;
#elif defined(MODE_INTERLEAVED)
    int n = u_gi.interleave_pattern_n, m = u_gi.interleave_pattern_m;
    ivec2 sub = ivec2(u_gi.sub_width, u_gi.sub_height);
    ivec2 k2 = div_small(gid, sub);
    if (k2.x >= n || k2.y >= m)
        return;
    // The surface texels are the de-interleaved copies here (gi/interleave.comp).
    ivec2 px = gid, at = gid;
    if (any(greaterThanEqual((gid - k2 * sub) * ivec2(n, m) + k2, ivec2(u_frame.width, u_frame.height))))
        return; // padding texel of a sub-image: no pixel maps here
    int first = k2.x + n * k2.y, stride = n * m, count = max(div_small(N, n * m), 1);
#if WEIGHTING != RSM_WEIGHT_IMPORTANCE // the pattern's subset (importance: its two parts')
    ivec2 part = rsm_subset(N, first, stride);
    first = part.x;
    count = part.y;
#endif
#endif
    vec3 x, nrm;
    if (!gb_surface(px, x, nrm)) {
        if (u_accumulate == 0)
            imageStore(o_irradiance, at, vec4(0.0));
        return;
    }
    store(at, gather(x, nrm, px, first, stride, count));
}
