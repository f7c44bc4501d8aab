// gi/vct/aniso.comp — one level of the directional volumes (Crassin et al.
// 2011, §4.2 "anisotropic voxels"): each voxel holds what a ray travelling
// along an axis (or against it) sees through the 2×2×2 block below it: the
// two children along the axis composited front to back, the four pairs
// averaged. An axis's texture holds both signs (shared/gpu_types.h,
// GpuVctParams): slab 2k + s is clip level k seen along +axis (s = 0) or
// −axis (s = 1).
// The volumes hold occupancy density β (optical depth β·VCT_OPTICAL_DEPTH
// per level-0 voxel of path) and radiance × β (shared/gpu_types.h), so the
// compositing works in transmittance: children of 2^l level-0 voxels pass
// t = e^(−β·k), k = VCT_OPTICAL_DEPTH·2^l, a pair t_f·t_b, and the block
// the mean t of its four pairs, which gives back β = −ln t / 2k; the
// radiance is composited front to back as opacity-weighted colour (c_f
// + t_f·c_b, c = L·(1 − t)) and divided back. Before, the block averaged
// opacities of children that had been composited as opacities: a wall one
// voxel thick let 17-42% of a cone through (at 0-50° from its normal,
// mips 0-3), now under 2% (tests/test_vct.c, thin_wall_stops_cones).
//   MODE_FIRST  the first level, from the isotropic level 0 (N deep per
//               level): every axis and sign of a voxel reads the same
//               block, so one invocation loads it once and writes all six
//               (IMG_VCT_DST, DST2, DST3: x, y, z). Per axis and sign, as
//               before, it had loaded the block six times: on llvmpipe an
//               image load is a call per lane, and this level is 7/8 of
//               the chain.
//   otherwise   level u_mip of axis u_axis, both signs, from the level
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
layout(binding = TEX_VCT_NORMAL) uniform sampler3D u_normal; // w: the lit side (inject.comp)
#else
layout(location = LOC_VCT_AXIS) uniform int u_axis; // 0..2: x y z
layout(location = LOC_VCT_MIP) uniform int u_mip;   // the level written: children of 2^u_mip level-0 voxels
#endif

// Opacity over density, (1 − e^(−βk)) / β, for a child of transmittance
// t = e^(−βk) (its limit k as β → 0).
float opacity_per_density(float beta, float t, float k) { return beta > 1e-6 ? (1.0 - t) / beta : k; }

// A pair of children, f in front of b: its transmittance, and in `c` the
// radiance it sends out through f, weighted by opacity.
float pair(vec4 f, vec4 b, float k, out vec3 c)
{
    float tf = exp(-f.a * k), tb = exp(-b.a * k);
    c = f.rgb * opacity_per_density(f.a, tf, k) + tf * b.rgb * opacity_per_density(b.a, tb, k);
    return tf * tb;
}

// The block from the sums over its four pairs of transmittance and
// weighted radiance: density over its depth 2k, radiance × density.
vec4 block(float t_sum, vec3 c_sum, float k)
{
    float t = max(0.25 * t_sum, 1e-30), alpha = 1.0 - t;
    float beta = -log(t) / (2.0 * k);
    return vec4(alpha > 0.0 ? 0.25 * c_sum * (beta / alpha) : vec3(0.0), beta);
}

#ifdef MODE_FIRST
// What a level-0 voxel sends along travel direction `dir` (an axis, either
// sign): a surface's lit side faces the way the normal volume's w says
// (inject.comp: the canonical normal's side, signed, weighted by each
// light's luminance, over the voxel's luminance: lit = n·σ, σ in [−1, 1]).
// Seen from its lit side or edge-on (dot(lit, −dir) ≥ 0) a voxel sends
// its radiance, from behind (≤ −½) none, in between a ramp; its opacity
// is the same from every side. Before, every voxel sent its
// radiance every way: the top faces of the Cornell blocks (the brightest
// surfaces under the light) lit the floor beside them and the wall behind
// them through their own edges (Cornell 256², with the cones of an
// earlier clearance: floor 2.6×, the short block's top 2.1× the
// reference's bounce, where this read 1.0 and 0.9; scripts/gi-regions.sh).
vec4 seen_along(vec4 v, vec4 n, vec3 dir)
{
    float lum = dot(v.rgb, vec3(0.2126, 0.7152, 0.0722));
    float sigma = lum > 0.0 ? clamp(n.w / lum, -1.0, 1.0) : 0.0;
    return vec4(v.rgb * clamp(1.0 + 2.0 * dot(n.xyz * sigma, -dir), 0.0, 1.0), v.a);
}

// The four pairs along axis `ax` (a constant) of the block whose children
// are v[dx + 2dy + 4dz] (normals n), seen along it (neg false) or against
// it, front to back, averaged; in the order the later levels sum them (i
// across the first axis u, j across the second w).
vec4 composite(vec4 v[8], vec4 n[8], int ax, bool neg)
{
    vec3 dir = vec3(ax == 0, ax == 1, ax == 2) * (neg ? -1.0 : 1.0);
    int along = ax == 0 ? 1 : ax == 1 ? 2 : 4;
    int u = ax == 0 ? 2 : 1, w = ax == 2 ? 2 : 4;
    float t = 0.0;
    vec3 c = vec3(0.0);
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            int c0 = u * i + w * j, c1 = c0 + along;
            int f = neg ? c1 : c0, b = neg ? c0 : c1;
            vec3 pc;
            t += pair(seen_along(v[f], n[f], dir), seen_along(v[b], n[b], dir), VCT_OPTICAL_DEPTH, pc);
            c += pc;
        }
    return block(t, c, VCT_OPTICAL_DEPTH);
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
    vec4 v[8], n[8];
    ivec3 first = ivec3(2 * o.xy, k * u_vct.size + 2 * z);
    for (int c = 0; c < 8; c++) {
        ivec3 at = first + ivec3(c & 1, (c >> 1) & 1, c >> 2);
        v[c] = imageLoad(u_src, at);
        n[c] = texelFetch(u_normal, at, 0);
    }
    // Past the level (a slab deeper than N/2): no children.
    float live = 2 * z < u_vct.size ? 1.0 : 0.0;
    imageStore(u_dst, pos, composite(v, n, 0, false) * live);
    imageStore(u_dst, neg, composite(v, n, 0, true) * live);
    imageStore(u_dst_y, pos, composite(v, n, 1, false) * live);
    imageStore(u_dst_y, neg, composite(v, n, 1, true) * live);
    imageStore(u_dst_z, pos, composite(v, n, 2, false) * live);
    imageStore(u_dst_z, neg, composite(v, n, 2, true) * live);
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
    float k = VCT_OPTICAL_DEPTH * float(1 << u_mip), t = 0.0;
    vec3 c = vec3(0.0);
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            ivec3 c0 = first + u * i + w * j, c1 = c0 + step;
            vec3 pc;
            t += pair(imageLoad(u_src, negative ? c1 : c0), imageLoad(u_src, negative ? c0 : c1), k, pc);
            c += pc;
        }
    imageStore(u_dst, o, block(t, c, k));
#endif
}
