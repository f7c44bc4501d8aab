// gi/vct/resolve.comp — the voxelization's fixed-point sums into the voxel
// volumes: albedo = Σ albedo / count with opacity 1 where any fragment
// landed, normal = the normalized sum (sign-canonical, see voxelize.frag).
#include "shared/gpu_types.h"
#include "gi/vct/volume.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(std430, binding = SSBO_VCT_VOXELS) readonly buffer Voxels { uint voxels[]; };
// The opaque voxels, appended (vct_voxel_code) with the indirect
// dispatch of the injection over them (64 a group); past the list's
// capacity only the count grows (vct.c then injects over every voxel).
layout(std430, binding = SSBO_VCT_OPAQUE) buffer Opaque { uint opaque_count, groups_x, groups_y, groups_z; uint opaque[]; };
layout(binding = IMG_VCT_DST, rgba16f) writeonly uniform image3D u_albedo;
layout(binding = IMG_VCT_DST2, rgba16f) writeonly uniform image3D u_normal;

const float FIXED = 4096.0;

void main()
{
    ivec3 v;
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
    uint slot = atomicAdd(opaque_count, 1u);
    if (slot < uint(opaque.length())) {
        opaque[slot] = vct_voxel_code(v);
        if (slot % 64u == 0u)
            atomicMax(groups_x, slot / 64u + 1u);
    }
}
