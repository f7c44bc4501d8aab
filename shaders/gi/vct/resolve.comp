// gi/vct/resolve.comp — the voxelization's fixed-point sums into the voxel
// volumes: albedo = Σ albedo / count with opacity 1 where any sample
// landed, normal = the normalized sum (sign-canonical, see
// gi/vct/voxelize.glsl); the sums are cleared behind it for the next
// voxelization. With OPAQUE_LIST over the opaque voxels the voxelization
// listed (the volumes cleared before), else over every voxel (the list
// overflowed: empty voxels written 0); with a region (u_region_hi.w 1,
// voxelize_region) over its box of the stacked volume.
#include "shared/gpu_types.h"
#include "gi/vct/volume.glsl"

#ifdef OPAQUE_LIST
layout(local_size_x = 64) in;
#else
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#endif
layout(std430, binding = SSBO_VCT_VOXELS) buffer Voxels { uint voxels[]; };
layout(binding = IMG_VCT_DST, rgba16f) writeonly uniform image3D u_albedo;
layout(binding = IMG_VCT_DST2, rgba16f) writeonly uniform image3D u_normal;

layout(location = LOC_VCT_REGION_LO) uniform ivec4 u_region_lo;
layout(location = LOC_VCT_REGION_HI) uniform ivec4 u_region_hi;

const float FIXED = 4096.0; // as gi/vct/voxelize.glsl's VCT_FIXED

void main()
{
    ivec3 v;
#ifndef OPAQUE_LIST
    if (u_region_hi.w != 0) {
        v = ivec3(gl_GlobalInvocationID) + u_region_lo.xyz;
        if (any(greaterThanEqual(v, u_region_hi.xyz)))
            return;
    } else
#endif
    if (!vct_voxel_here(v))
        return;
    int size = u_vct.size;
    uint i = 8u * uint((v.z * size + v.y) * size + v.x);
    uint count = voxels[i + 6u];
    if (count == 0u) {
        imageStore(u_albedo, v, vec4(0.0));
        imageStore(u_normal, v, vec4(0.0));
        return;
    }
    vec3 albedo = vec3(voxels[i], voxels[i + 1u], voxels[i + 2u]) / (FIXED * float(count));
    vec3 n = vec3(int(voxels[i + 3u]), int(voxels[i + 4u]), int(voxels[i + 5u]));
    n = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 1.0, 0.0);
    imageStore(u_albedo, v, vec4(albedo, 1.0));
    imageStore(u_normal, v, vec4(n, 0.0));
    for (uint w = 0u; w < 7u; w++)
        voxels[i + w] = 0u;
}
