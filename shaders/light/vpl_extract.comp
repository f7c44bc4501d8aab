// light/vpl_extract.comp — every RSM texel that holds a surface becomes a VPL in
// SSBO_VPL (a GpuVpl, common/vpl_record.glsl: its ξ ∈ (0,1] a hash of
// the record and the seed light_stage.c leaves in counters[1], where the
// SLC loop reads it too); counters[0] counts them. The RSM is read layer by
// layer (common/rsm_layers.glsl: a 2D RSM is one layer, a cube RSM six).
#include "shared/gpu_types.h"
#include "common/rsm_texel.glsl"
#include "common/vpl_record.glsl"
#include "common/rsm_layers.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(location = LOC_VPL_STRIDE) uniform int u_stride; // keep every stride-th texel per axis (subsampling)

layout(std430, binding = SSBO_VPL) writeonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) buffer CounterBlock { uint counters[]; };

void main()
{
    ivec3 size = rsm_layers_size();
    ivec3 id = ivec3(gl_GlobalInvocationID.xy * uint(u_stride), gl_GlobalInvocationID.z);
    if (id.x >= size.x || id.y >= size.y || id.z >= size.z)
        return;
    vec3 p, n, flux;
    float area;
    uvec4 t = rsm_layer_texel(id);
    bool valid = rsm_texel_unpack(rsm_texel_frame(), t, p, n, flux, area);
    float k = float(u_stride * u_stride); // a kept texel stands for k
    if (!valid || max(flux.r, max(flux.g, flux.b)) <= 0.0)
        return;
    float xi = vpl_xi_of(uvec4(floatBitsToUint(p), t.z), counters[1]);
    uint i = atomicAdd(counters[0], 1u);
    vpls[i] = vpl_make(p, xi, t.z, flux * k, area * k); // t.z: the normal n, packed
}
