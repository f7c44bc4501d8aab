// gi/vct/voxelize.glsl — what both voxelizations (the raster one,
// voxelize.geom/.frag, and the compute one, voxelize.comp) do for one
// column of voxels along a triangle's dominant axis: write the voxels of
// the column that the triangle touches, albedo, normal and a count summed
// in fixed point with integer atomics into SSBO_VCT_VOXELS (an exact
// average after resolve.comp; the order-independent equivalent of Crassin &
// Green's moving average under imageAtomicCompSwap); a voxel's first
// sample appends it to the opaque list (SSBO_VCT_OPAQUE, vct_voxel_code,
// with the indirect dispatch of 64 a group over it; past the list's
// capacity only the count grows and vct.c resolves every voxel), which the
// resolve, the injection and the bounce then run over.
//   conservative: the column's depth range over the pixel square (the
//     plane's slope is at most 1 per pixel along the dominant axis: ≤ 3
//     voxels) and an exact triangle–box overlap test (separating axes,
//     Akenine-Möller 2001) for each;
//   else: the one voxel at the column centre's depth.
// Coordinates are voxel units, p = (world − origin) / voxel, swizzled so
// that the dominant axis is z (vct_swizzle): a column is an (x, y) pixel.
// With VCT_SETUP_ONLY (the geometry shader) only the coordinate helpers.

// A triangle in swizzled voxel coordinates and its dominant axis 0..2.
struct VctTri {
    vec3 t0, t1, t2;
    int axis;
};

// Voxel coordinates with `axis` moved to z.
vec3 vct_swizzle(vec3 p, int axis)
{
    return axis == 0 ? p.yzx : axis == 1 ? p.zxy : p;
}

// Swizzled voxel coordinates back to (x, y, z).
ivec3 vct_unswizzle(ivec3 s, int axis)
{
    return axis == 0 ? s.zxy : axis == 1 ? s.yzx : s;
}

// The dominant axis of a normal: its largest component's.
int vct_dominant_axis(vec3 n)
{
    vec3 an = abs(n);
    return an.x >= an.y && an.x >= an.z ? 0 : an.y >= an.z ? 1 : 2;
}

// Two-sided surfaces: the normal's sign made canonical (largest component
// positive), so both faces of a thin wall add up.
vec3 vct_canonical_normal(vec3 n)
{
    n = normalize(n);
    vec3 an = abs(n);
    float big = an.x >= an.y && an.x >= an.z ? n.x : an.y >= an.z ? n.y : n.z;
    return big < 0.0 ? -n : n;
}

#ifndef VCT_SETUP_ONLY
#include "gi/vct/volume.glsl"

layout(std430, binding = SSBO_VCT_VOXELS) buffer Voxels { uint voxels[]; };
layout(std430, binding = SSBO_VCT_OPAQUE) buffer Opaque { uint opaque_count, groups_x, groups_y, groups_z; uint opaque[]; };

const float VCT_FIXED = 4096.0; // fixed-point units per 1 (albedo, normal components)

// Separating-axis test of the triangle against the box centred on c with
// half extent h (all in voxel units).
bool vct_overlaps(VctTri t, vec3 c, float h)
{
    vec3 v0 = t.t0 - c, v1 = t.t1 - c, v2 = t.t2 - c;
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

// Adds one sample to voxel s (swizzled) of clipmap level `level`.
void vct_add(ivec3 s, int axis, int level, vec3 albedo, vec3 n)
{
    int size = u_vct.size;
    ivec3 v = vct_unswizzle(s, axis);
    if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, ivec3(size))))
        return;
    uint i = 8u * uint(((v.z + level * size) * size + v.y) * size + v.x);
    atomicAdd(voxels[i + 0u], uint(albedo.r * VCT_FIXED + 0.5));
    atomicAdd(voxels[i + 1u], uint(albedo.g * VCT_FIXED + 0.5));
    atomicAdd(voxels[i + 2u], uint(albedo.b * VCT_FIXED + 0.5));
    atomicAdd(voxels[i + 3u], uint(int(round(n.x * VCT_FIXED))));
    atomicAdd(voxels[i + 4u], uint(int(round(n.y * VCT_FIXED))));
    atomicAdd(voxels[i + 5u], uint(int(round(n.z * VCT_FIXED))));
    if (atomicAdd(voxels[i + 6u], 1u) == 0u) {
        uint slot = atomicAdd(opaque_count, 1u);
        if (slot < uint(opaque.length())) {
            opaque[slot] = vct_voxel_code(ivec3(v.xy, v.z + level * size));
            if (slot % 64u == 0u)
                atomicMax(groups_x, slot / 64u + 1u);
        }
    }
}

// The voxels of column `px` (its centre f = px + 0.5) that triangle t
// touches get albedo and the canonical normal n.
void vct_column(VctTri t, ivec2 px, int level, vec3 albedo, vec3 n)
{
    vec2 f = vec2(px) + 0.5;
    // Depth of the triangle's plane over this column (swizzled z).
    vec3 pn = cross(t.t1 - t.t0, t.t2 - t.t0);
    float d = dot(pn, t.t0);
    // Within the triangle's depth range, as it is exactly: rounded, the
    // plane equation of a triangle lying on a voxel boundary (a floor at
    // z = 16) gave 15.99999 on NVIDIA's division while its vertices say 16,
    // which emptied the range below and left the whole floor unvoxelized.
    float zmin = min(t.t0.z, min(t.t1.z, t.t2.z)), zmax = max(t.t0.z, max(t.t1.z, t.t2.z));
    float zc = clamp((d - pn.x * f.x - pn.y * f.y) / pn.z, zmin, zmax);
    if (u_vct.conservative == 0) {
        vct_add(ivec3(px, int(floor(zc))), t.axis, level, albedo, n);
        return;
    }
    float dz = 0.5 * (abs(pn.x) + abs(pn.y)) / abs(pn.z);
    // zmin <= zc <= zmax, so k0 <= floor(zc) <= k1.
    int k0 = int(floor(max(zc - dz, zmin))), k1 = int(floor(min(zc + dz, zmax)));
    for (int k = k0; k <= k1; k++)
        if (vct_overlaps(t, vec3(f, float(k) + 0.5), 0.5 + 1e-4))
            vct_add(ivec3(px, k), t.axis, level, albedo, n);
}
#endif
