// gi/lpv/inject_fixed.comp — light injection by compute (`--lpv-inject
// compute`): the same cell and SH lobe as inject.vert, LPV_INJECT_RUN
// consecutive VPLs per invocation (below), added with integer atomics in
// fixed point (llvmpipe has no float atomics) to
// SSBO_LPV_FIXED[(cell·3 + channel)·4 + coefficient]; a
// resolve pass (inject_resolve.comp) turns the sums into the volumes.
// u_scale (units per W/sr) leaves headroom for the scene's whole power in
// one cell. Inputs: SSBO_VPL, SSBO_COUNTERS[0] = VPL count.
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"
#include "common/vpl_record.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) readonly buffer CounterBlock { uint counters[]; };
layout(std430, binding = SSBO_LPV_FIXED) buffer FixedBlock { int sums[]; };
layout(location = LOC_LPV_CASCADE) uniform int u_cascade;
layout(location = LOC_LPV_EXCLUDE) uniform int u_exclude;
layout(location = LOC_LPV_FIXED_SCALE) uniform float u_scale;
layout(location = LOC_LPV_GROUP) uniform int u_group; // only VPLs of this light group (sh.glsl); -1: all

// Adds one cell's summed units to its 12 sums (cell index `base`; < 0:
// none), skipping zeros.
void flush(int base, ivec4 r, ivec4 g, ivec4 b)
{
    if (base < 0)
        return;
    for (int j = 0; j < 4; j++) {
        if (r[j] != 0)
            atomicAdd(sums[base + j], r[j]);
        if (g[j] != 0)
            atomicAdd(sums[base + 4 + j], g[j]);
        if (b[j] != 0)
            atomicAdd(sums[base + 8 + j], b[j]);
    }
}

// One invocation per LPV_INJECT_RUN consecutive VPLs. Neighbouring RSM texels
// come out of vpl_extract.comp together and mostly fall in one cell, so a
// run's units are summed in registers while the cell stays the same and
// added with one set of atomics per cell (each VPL's units are rounded
// alone, as before: integer sums in any order, the same volumes bit for
// bit). Each VPL's 12 atomics had been half of the pass (Cornell, 608K
// VPLs, one llvmpipe thread: 36.3 -> 16.7 ms). Each VPL is read as the
// shading loops read it (surface and flux: its normal from the surface's
// octahedral code, the value normal_xi holds).
void main()
{
    uint first = gl_GlobalInvocationID.x * uint(LPV_INJECT_RUN), count = counters[0];
    if (first >= count)
        return;
    int k = u_cascade, size = u_lpv.size, exclude = u_exclude;
    float offset = u_lpv.offset * u_lpv.cascade[k].w;
    float offset_x = exclude >= 0 ? u_lpv.offset * u_lpv.cascade[exclude].w : 0.0;
    float scale = u_scale;
    int base = -1;
    ivec4 r = ivec4(0), g = ivec4(0), b = ivec4(0);
    uint last = min(first + uint(LPV_INJECT_RUN), count);
    for (uint i = first; i < last; i++) {
        GpuVpl v = vpls[i];
        vec3 p = vpl_position(v), n = vpl_shading_normal(v);
        vec4 flux = v.flux;
        ivec3 c = lpv_cell(k, p + n * offset);
        bool take = lpv_inside(c, size) && lpv_in_group(n, u_group) &&
                    !(exclude >= 0 && lpv_inside(lpv_cell(exclude, p + n * offset_x), size));
        int at = take ? 12 * (c.x + size * (c.y + size * c.z)) : -1;
        if (at != base) {
            flush(base, r, g, b);
            base = at;
            r = g = b = ivec4(0);
        }
        vec4 lobe = sh_clamped_cos(n) / LPV_PI * scale;
        r += ivec4(round(flux.r * lobe));
        g += ivec4(round(flux.g * lobe));
        b += ivec4(round(flux.b * lobe));
    }
    flush(base, r, g, b);
}
