// light/vpl_extract.comp — every RSM texel that holds a surface becomes a VPL in
// SSBO_VPL {position, fixed random ξ ∈ (0,1], normal, flux}; counters[0]
// counts them. The RSM layers are read through 2D-array views (a 2D RSM is
// one layer, a cube RSM six).
#include "shared/gpu_types.h"
#include "common/rsm_texel.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(binding = TEX_RSM) uniform usampler2DArray r_texel;
layout(location = LOC_VPL_STRIDE) uniform int u_stride; // keep every stride-th texel per axis (subsampling)
layout(location = LOC_VPL_SEED) uniform uint u_seed; // seed of the VPLs' random ξ

layout(std430, binding = SSBO_VPL) writeonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) buffer CounterBlock { uint counters[]; };

uint hash_u32(uint x)
{
    x ^= x >> 16; x *= 0x7feb352du;
    x ^= x >> 15; x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

void main()
{
    ivec3 size = textureSize(r_texel, 0);
    ivec3 id = ivec3(gl_GlobalInvocationID.xy * uint(u_stride), gl_GlobalInvocationID.z);
    if (id.x >= size.x || id.y >= size.y || id.z >= size.z)
        return;
    vec3 p, n, flux;
    float area;
    bool valid = rsm_texel_unpack(rsm_texel_frame(), texelFetch(r_texel, id, 0), p, n, flux, area);
    float k = float(u_stride * u_stride); // a kept texel stands for k
    if (!valid || max(flux.r, max(flux.g, flux.b)) <= 0.0)
        return;
    uint texel = uint(id.x + size.x * (id.y + size.y * id.z));
    float xi = (float(hash_u32(texel ^ hash_u32(u_seed + 0x9e3779b9u)) >> 8) + 1.0) / 16777216.0;
    uint i = atomicAdd(counters[0], 1u);
    vpls[i].position_xi = vec4(p, xi);
    vpls[i].normal = vec4(n, 0.0);
    vpls[i].flux = vec4(flux * k, area * k);
}
