// gi/vct/list.comp — the opaque-voxel list after a region's
// revoxelization (vct.c, voxelize_region), as a voxelization's first
// samples make it (gi/vct/voxelize.glsl): every opaque voxel once, none
// that the region emptied.
//   LIST_FILTER: over the list before (SSBO_VCT_OPAQUE_PREV), the entries
//     outside their level's region (u_regions) kept;
//   LIST_REGION: over one level's region box (u_region_lo/hi, stacked),
//     its opaque voxels (albedo alpha > 0) appended, unless the list
//     before had overflowed (the pass over every voxel lists them);
//   else: over every voxel of the stacked levels, its opaque ones (when
//     the list before had overflowed).
// vct.c dispatches the first and the last indirectly (gi/vct/args.comp):
// the one that does not apply has no groups.
#include "shared/gpu_types.h"
#include "gi/vct/volume.glsl"

#ifdef LIST_FILTER
layout(local_size_x = 64) in;
layout(std430, binding = SSBO_VCT_OPAQUE_PREV) readonly buffer Prev { uint prev_count; uint prev_pad[3]; uint prev[]; };
layout(location = LOC_VCT_REGIONS) uniform ivec4 u_regions[2 * VCT_MAX_LEVELS];
#else
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#ifdef LIST_REGION
layout(std430, binding = SSBO_VCT_OPAQUE_PREV) readonly buffer Prev { uint prev_count; uint prev_pad[3]; uint prev[]; };
#endif
layout(binding = TEX_VCT_ALBEDO) uniform sampler3D u_albedo;
layout(location = LOC_VCT_REGION_LO) uniform ivec4 u_region_lo;
layout(location = LOC_VCT_REGION_HI) uniform ivec4 u_region_hi;
#endif
layout(std430, binding = SSBO_VCT_OPAQUE) buffer Opaque { uint opaque_count; uint opaque_pad[3]; uint opaque[]; };

void append(ivec3 v)
{
    uint slot = atomicAdd(opaque_count, 1u);
    if (slot < uint(opaque.length()))
        opaque[slot] = vct_voxel_code(v);
}

void main()
{
#if defined(LIST_FILTER)
    uint index = gl_GlobalInvocationID.x;
    if (index >= prev_count)
        return;
    ivec3 v = vct_voxel_of(prev[index]);
    int level = v.z / u_vct.size;
    ivec4 lo = u_regions[2 * level], hi = u_regions[2 * level + 1];
    if (any(lessThan(v, lo.xyz)) || any(greaterThanEqual(v, hi.xyz)))
        append(v);
#else
    ivec3 v;
#ifdef LIST_REGION
    v = ivec3(gl_GlobalInvocationID) + u_region_lo.xyz;
    if (any(greaterThanEqual(v, u_region_hi.xyz)) || prev_count > uint(prev.length()))
        return;
#else
    if (!vct_voxel_here(v))
        return;
#endif
    if (texelFetch(u_albedo, v, 0).a > 0.0)
        append(v);
#endif
}
