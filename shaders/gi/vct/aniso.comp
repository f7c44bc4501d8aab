// gi/vct/aniso.comp — one level of the directional volumes of one axis
// (Crassin et al. 2011, §4.2 "anisotropic voxels"): each voxel holds what a
// ray travelling along the axis (or against it) sees through the 2×2×2
// block below it: the two children along the axis composited front to back
// (c = c_front + (1 − α_front)·c_back, likewise α), the four pairs
// averaged. The axis's texture holds both signs (shared/gpu_types.h,
// GpuVctParams): slab 2k + s is clip level k seen along +axis (s = 0) or
// −axis (s = 1). The first level reads the isotropic level 0 (N deep per
// level), later ones the level below in the same slab. Reads outside the
// source are transparent (image loads out of bounds return 0): past a
// level's N/2 voxels a slab holds 0.
#include "shared/gpu_types.h"
#include "common/math.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = IMG_VCT_SRC, rgba16f) readonly uniform image3D u_src;
layout(binding = IMG_VCT_DST, rgba16f) writeonly uniform image3D u_dst;
layout(location = LOC_VCT_AXIS) uniform int u_axis;   // 0..2: x y z
layout(location = LOC_VCT_FIRST) uniform int u_first; // 1: u_src is the isotropic level 0

void main()
{
    ivec3 o = ivec3(gl_GlobalInvocationID);
    ivec3 size = imageSize(u_dst);
    if (any(greaterThanEqual(o, size)))
        return;
    // A slab's depth at this level, and o's slab (div_small: llvmpipe
    // divides integer vectors lane by lane).
    int depth = div_small(size.z, 2 * u_vct.clip_levels);
    int slab = div_small(o.z, depth), z = o.z - slab * depth;
    bool negative = (slab & 1) == 1;
    // The children's slab: level k of the isotropic volume, or the same slab.
    int base = u_first != 0 ? (slab >> 1) * u_vct.size : slab * 2 * depth;
    if (u_first != 0 && 2 * z >= u_vct.size) {
        imageStore(u_dst, o, vec4(0.0)); // past the level: no children
        return;
    }
    int ax = u_axis;
    ivec3 step = ivec3(ax == 0, ax == 1, ax == 2);
    ivec3 u = ivec3(ax == 1 || ax == 2, ax == 0, 0); // the two axes across
    ivec3 w = ivec3(0, ax == 2, ax == 0 || ax == 1);
    ivec3 first = ivec3(2 * o.xy, base + 2 * z);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            ivec3 c0 = first + u * i + w * j, c1 = c0 + step;
            vec4 f = imageLoad(u_src, negative ? c1 : c0), b = imageLoad(u_src, negative ? c0 : c1);
            sum += f + (1.0 - f.a) * b;
        }
    imageStore(u_dst, o, sum * 0.25);
}
