// gi/lpv/inject_fixed.comp — light injection by compute (`--lpv-inject
// compute`): the same cell and SH lobe as inject.vert, one invocation per
// VPL, added with integer atomics in fixed point (llvmpipe has no float
// atomics) to SSBO_LPV_FIXED[(cell·3 + channel)·4 + coefficient]; a
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

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= counters[0])
        return;
    GpuVpl v = vpls[i];
    vec3 n = vpl_normal(v);
    int k = u_cascade, size = u_lpv.size;
    ivec3 c = lpv_cell(k, vpl_position(v) + n * (u_lpv.inject_offset * u_lpv.cascade[k].w));
    if (!lpv_inside(c, size))
        return;
    if (u_exclude >= 0 &&
        lpv_inside(lpv_cell(u_exclude, vpl_position(v) + n * (u_lpv.inject_offset * u_lpv.cascade[u_exclude].w)), size))
        return;
    vec4 lobe = sh_clamped_cos(n) / LPV_PI * u_scale;
    int base = 12 * (c.x + size * (c.y + size * c.z));
    for (int ch = 0; ch < 3; ch++) {
        ivec4 q = ivec4(round(v.flux[ch] * lobe));
        for (int j = 0; j < 4; j++)
            if (q[j] != 0)
                atomicAdd(sums[base + 4 * ch + j], q[j]);
    }
}
