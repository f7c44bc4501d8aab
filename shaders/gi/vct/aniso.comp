// gi/vct/aniso.comp — one level of the directional volumes (Crassin et al.
// 2011, §4.2 "anisotropic voxels"): each voxel holds what a ray travelling
// along an axis (or against it) sees through the 2×2×2 block below it: the
// two children along the axis composited front to back (c = c_front +
// (1 − α_front)·c_back, likewise α), the four pairs averaged. An axis's
// texture holds both signs (shared/gpu_types.h, GpuVctParams): slab 2k + s
// is clip level k seen along +axis (s = 0) or −axis (s = 1).
//   MODE_FIRST  the first level, from the isotropic level 0 (N deep per
//               level): every axis and sign of a voxel reads the same
//               block, so one invocation loads it once and writes all six
//               (IMG_VCT_DST, DST2, DST3: x, y, z). Per axis and sign, as
//               before, it had loaded the block six times: on llvmpipe an
//               image load is a call per lane, and this level is 7/8 of
//               the chain.
//   otherwise   a later level of axis u_axis, both signs, from the level
//               below in the same slab.
// Reads outside the source are transparent (image loads out of bounds
// return 0): past a level's N/2 voxels a slab holds 0.
#include "shared/gpu_types.h"
#include "common/math.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = IMG_VCT_SRC, rgba16f) readonly uniform image3D u_src;
layout(binding = IMG_VCT_DST, rgba16f) writeonly uniform image3D u_dst;
#ifdef MODE_FIRST
layout(binding = IMG_VCT_DST2, rgba16f) writeonly uniform image3D u_dst_y;
layout(binding = IMG_VCT_DST3, rgba16f) writeonly uniform image3D u_dst_z;
#else
layout(location = LOC_VCT_AXIS) uniform int u_axis; // 0..2: x y z
#endif

#ifdef MODE_FIRST
// The four pairs along axis `ax` (a constant) of the block whose children
// are v[dx + 2dy + 4dz], seen along it (neg false) or against it, front to
// back, averaged; in the order the later levels sum them (i across the
// first axis u, j across the second w).
vec4 composite(vec4 v[8], int ax, bool neg)
{
    int along = ax == 0 ? 1 : ax == 1 ? 2 : 4;
    int u = ax == 0 ? 2 : 1, w = ax == 2 ? 2 : 4;
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            int c0 = u * i + w * j, c1 = c0 + along;
            vec4 f = v[neg ? c1 : c0], b = v[neg ? c0 : c1];
            sum += f + (1.0 - f.a) * b;
        }
    return sum * 0.25;
}
#endif

void main()
{
    ivec3 o = ivec3(gl_GlobalInvocationID);
#ifdef MODE_FIRST
    // o.z runs over the levels' slabs of one sign: level k, depth z in it.
    ivec3 size = imageSize(u_dst);
    int depth = div_small(size.z, 2 * VCT_CLIP_LEVELS); // a slab's depth at this level
    if (any(greaterThanEqual(o, ivec3(size.xy, depth * VCT_CLIP_LEVELS))))
        return;
    int k = div_small(o.z, depth), z = o.z - k * depth;
    ivec3 pos = ivec3(o.xy, 2 * k * depth + z), neg = pos + ivec3(0, 0, depth);
    vec4 v[8];
    ivec3 first = ivec3(2 * o.xy, k * u_vct.size + 2 * z);
    for (int c = 0; c < 8; c++)
        v[c] = imageLoad(u_src, first + ivec3(c & 1, (c >> 1) & 1, c >> 2));
    // Past the level (a slab deeper than N/2): no children.
    float live = 2 * z < u_vct.size ? 1.0 : 0.0;
    imageStore(u_dst, pos, composite(v, 0, false) * live);
    imageStore(u_dst, neg, composite(v, 0, true) * live);
    imageStore(u_dst_y, pos, composite(v, 1, false) * live);
    imageStore(u_dst_y, neg, composite(v, 1, true) * live);
    imageStore(u_dst_z, pos, composite(v, 2, false) * live);
    imageStore(u_dst_z, neg, composite(v, 2, true) * live);
#else
    ivec3 size = imageSize(u_dst);
    if (any(greaterThanEqual(o, size)))
        return;
    // A slab's depth at this level, and o's slab (div_small: llvmpipe
    // divides integer vectors lane by lane).
    int depth = div_small(size.z, 2 * VCT_CLIP_LEVELS);
    int slab = div_small(o.z, depth), z = o.z - slab * depth;
    bool negative = (slab & 1) == 1;
    // The children: the same slab of the level below. The axis is a
    // uniform here, so the pairs are read by coordinates (a table indexed
    // by it would live in memory, lane by lane).
    int ax = u_axis;
    ivec3 step = ivec3(ax == 0, ax == 1, ax == 2);
    ivec3 u = ivec3(ax == 1 || ax == 2, ax == 0, 0); // the two axes across
    ivec3 w = ivec3(0, ax == 2, ax == 0 || ax == 1);
    ivec3 first = ivec3(2 * o.xy, slab * 2 * depth + 2 * z);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            ivec3 c0 = first + u * i + w * j, c1 = c0 + step;
            vec4 f = imageLoad(u_src, negative ? c1 : c0), b = imageLoad(u_src, negative ? c0 : c1);
            sum += f + (1.0 - f.a) * b;
        }
    imageStore(u_dst, o, sum * 0.25);
#endif
}
