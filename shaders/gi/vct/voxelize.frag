// gi/vct/voxelize.frag — writes the voxels of a fragment's column that its
// triangle touches: albedo, normal and a count, summed in fixed point with
// integer atomics into SSBO_VCT_VOXELS (an exact average after
// resolve.comp; the order-independent equivalent of Crassin & Green's
// moving average under imageAtomicCompSwap). Alpha-masked texels are
// skipped (material_albedo discards them).
//   conservative: the column's depth range over the pixel square (the
//     plane's slope is at most 1 per pixel along the dominant axis: ≤ 3
//     voxels) and an exact triangle–box overlap test (separating axes,
//     Akenine-Möller 2001) for each;
//   else: the one voxel at the pixel centre's depth.
#include "shared/gpu_types.h"
#include "common/material.glsl"

layout(std430, binding = SSBO_VCT_VOXELS) buffer Voxels { uint voxels[]; };
layout(location = LOC_VCT_LEVEL) uniform int u_level; // clipmap level drawn: its slab of the stack

in vec2 g_uv;
in vec3 g_normal;
flat in vec3 g_t0;
flat in vec3 g_t1;
flat in vec3 g_t2;
flat in vec4 g_bounds;
flat in int g_axis;

const float FIXED = 4096.0; // fixed-point units per 1 (albedo, normal components)

// Swizzled voxel coordinates back to (x, y, z).
ivec3 unswizzle(ivec3 s, int axis)
{
    return axis == 0 ? s.zxy : axis == 1 ? s.yzx : s;
}

// Separating-axis test of the triangle against the box centred on c with
// half extent h (all in voxel units).
bool overlaps(vec3 c, float h)
{
    vec3 v0 = g_t0 - c, v1 = g_t1 - c, v2 = g_t2 - c;
    vec3 e[3] = vec3[3](v1 - v0, v2 - v1, v0 - v2);
    vec3 fn = cross(e[0], e[1]);
    vec3 axes[13];
    axes[0] = vec3(1, 0, 0);
    axes[1] = vec3(0, 1, 0);
    axes[2] = vec3(0, 0, 1);
    axes[3] = fn;
    for (int i = 0; i < 3; i++) {
        axes[4 + 3 * i] = cross(vec3(1, 0, 0), e[i]);
        axes[5 + 3 * i] = cross(vec3(0, 1, 0), e[i]);
        axes[6 + 3 * i] = cross(vec3(0, 0, 1), e[i]);
    }
    for (int k = 0; k < 13; k++) {
        vec3 ax = axes[k];
        float r = h * (abs(ax.x) + abs(ax.y) + abs(ax.z));
        float p0 = dot(v0, ax), p1 = dot(v1, ax), p2 = dot(v2, ax);
        if (min(p0, min(p1, p2)) > r || max(p0, max(p1, p2)) < -r)
            return false;
    }
    return true;
}

void add(ivec3 s, vec3 albedo, vec3 n)
{
    int size = u_vct.size;
    ivec3 v = unswizzle(s, g_axis);
    if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, ivec3(size))))
        return;
    uint i = 8u * uint(((v.z + u_level * size) * size + v.y) * size + v.x);
    atomicAdd(voxels[i + 0u], uint(albedo.r * FIXED + 0.5));
    atomicAdd(voxels[i + 1u], uint(albedo.g * FIXED + 0.5));
    atomicAdd(voxels[i + 2u], uint(albedo.b * FIXED + 0.5));
    atomicAdd(voxels[i + 3u], uint(int(round(n.x * FIXED))));
    atomicAdd(voxels[i + 4u], uint(int(round(n.y * FIXED))));
    atomicAdd(voxels[i + 5u], uint(int(round(n.z * FIXED))));
    atomicAdd(voxels[i + 6u], 1u);
}

void main()
{
    vec2 f = gl_FragCoord.xy;
    if (u_vct.conservative != 0 && (f.x < g_bounds.x || f.y < g_bounds.y || f.x > g_bounds.z || f.y > g_bounds.w))
        return;
    vec3 albedo = clamp(material_diffuse(g_uv), 0.0, 1.0); // ρ_d: voxels reflect diffusely
    // Two-sided surfaces: the normal's sign made canonical (largest
    // component positive), so both faces of a thin wall add up.
    vec3 n = normalize(g_normal);
    vec3 an = abs(n);
    float big = an.x >= an.y && an.x >= an.z ? n.x : an.y >= an.z ? n.y : n.z;
    n = big < 0.0 ? -n : n;
    // Depth of the triangle's plane over this pixel (swizzled z).
    vec3 pn = cross(g_t1 - g_t0, g_t2 - g_t0);
    float d = dot(pn, g_t0);
    // Within the triangle's depth range, as it is exactly: rounded, the
    // plane equation of a triangle lying on a voxel boundary (a floor at
    // z = 16) gave 15.99999 on NVIDIA's division while its vertices say 16,
    // which emptied the range below and left the whole floor unvoxelized.
    float zmin = min(g_t0.z, min(g_t1.z, g_t2.z)), zmax = max(g_t0.z, max(g_t1.z, g_t2.z));
    float zc = clamp((d - pn.x * f.x - pn.y * f.y) / pn.z, zmin, zmax);
    ivec2 px = ivec2(floor(f));
    if (u_vct.conservative == 0) {
        add(ivec3(px, int(floor(zc))), albedo, n);
        return;
    }
    float dz = 0.5 * (abs(pn.x) + abs(pn.y)) / abs(pn.z);
    // zmin <= zc <= zmax, so k0 <= floor(zc) <= k1.
    int k0 = int(floor(max(zc - dz, zmin))), k1 = int(floor(min(zc + dz, zmax)));
    for (int k = k0; k <= k1; k++)
        if (overlaps(vec3(vec2(px) + 0.5, float(k) + 0.5), 0.5 + 1e-4))
            add(ivec3(px, k), albedo, n);
}
