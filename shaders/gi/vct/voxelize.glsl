// gi/vct/voxelize.glsl — what both voxelizations (the raster one,
// voxelize.geom/.frag, and the compute one, voxelize.comp) do for one
// column of voxels along a triangle's dominant axis: write the voxels of
// the column that the triangle touches, albedo, normal and a count summed
// in fixed point with integer atomics into SSBO_VCT_VOXELS (an exact
// average after resolve.comp; the order-independent equivalent of Crassin &
// Green's moving average under imageAtomicCompSwap); a voxel's first
// sample appends it to the opaque list (SSBO_VCT_OPAQUE, vct_voxel_code;
// past the list's capacity only the count grows, and gi/vct/args.comp then
// dispatches the passes over every voxel), which the resolve, the
// injection and the bounce then run over.
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
layout(std430, binding = SSBO_VCT_OPAQUE) buffer Opaque { uint opaque_count; uint opaque_pad[3]; uint opaque[]; };
// A revoxelized region (vct.c, voxelize_region): only its voxels of the
// level take samples; w 0: every voxel.
layout(location = LOC_VCT_REGION_LO) uniform ivec4 u_region_lo;
layout(location = LOC_VCT_REGION_HI) uniform ivec4 u_region_hi;

const float VCT_FIXED = 4096.0; // fixed-point units per 1 (albedo, normal components)

// The triangle–box test (separating axes, Akenine-Möller 2001) set up
// once per triangle: its 13 axes, the triangle's extent [lo, hi] along
// each and the box's half extent r along each (box half extent h =
// 0.5 + 1e-4 voxel: faces touched count). A box centred on c and the
// triangle are apart along axis a when lo − a·c > r or hi − a·c < −r.
// Axes 0–4 (x, y, and z × each edge) have no z component: they test the
// column (the pixel square against the projection); 5–12 (z, the normal,
// x × and y × each edge) each voxel of it. Also the plane over the
// columns: n·p = d.
struct VctSat {
    vec3 ax[13];
    float lo[13], hi[13], r[13];
    vec3 n;
    float d, zmin, zmax;
};

VctSat vct_sat_setup(VctTri t)
{
    VctSat s;
    vec3 e[3] = vec3[3](t.t1 - t.t0, t.t2 - t.t1, t.t0 - t.t2);
    s.ax[0] = vec3(1, 0, 0);
    s.ax[1] = vec3(0, 1, 0);
    s.ax[5] = vec3(0, 0, 1);
    s.ax[6] = cross(e[0], e[1]);
    for (int i = 0; i < 3; i++) {
        s.ax[2 + i] = vec3(-e[i].y, e[i].x, 0.0);  // z × e
        s.ax[7 + i] = vec3(0.0, -e[i].z, e[i].y);  // x × e
        s.ax[10 + i] = vec3(e[i].z, 0.0, -e[i].x); // y × e
    }
    const float h = 0.5 + 1e-4;
    for (int k = 0; k < 13; k++) {
        vec3 ax = s.ax[k];
        float p0 = dot(t.t0, ax), p1 = dot(t.t1, ax), p2 = dot(t.t2, ax);
        s.lo[k] = min(p0, min(p1, p2));
        s.hi[k] = max(p0, max(p1, p2));
        s.r[k] = h * (abs(ax.x) + abs(ax.y) + abs(ax.z));
    }
    s.n = cross(t.t1 - t.t0, t.t2 - t.t0);
    s.d = dot(s.n, t.t0);
    s.zmin = min(t.t0.z, min(t.t1.z, t.t2.z));
    s.zmax = max(t.t0.z, max(t.t1.z, t.t2.z));
    return s;
}

// Whether the triangle touches column px (its pixel square, any depth).
bool vct_column_touched(VctSat s, ivec2 px)
{
    vec2 f = vec2(px) + 0.5;
    for (int k = 0; k < 5; k++) {
        float c = dot(s.ax[k].xy, f);
        if (s.lo[k] - c > s.r[k] || s.hi[k] - c < -s.r[k])
            return false;
    }
    return true;
}

// Whether it touches voxel (px, z) of a column it touches.
bool vct_voxel_touched(VctSat s, ivec2 px, int z)
{
    vec3 centre = vec3(vec2(px) + 0.5, float(z) + 0.5);
    for (int k = 5; k < 13; k++) {
        float c = dot(s.ax[k], centre);
        if (s.lo[k] - c > s.r[k] || s.hi[k] - c < -s.r[k])
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
    if (u_region_hi.w != 0 && (any(lessThan(v, u_region_lo.xyz)) || any(greaterThanEqual(v, u_region_hi.xyz))))
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
        if (slot < uint(opaque.length()))
            opaque[slot] = vct_voxel_code(ivec3(v.xy, v.z + level * size));
    }
}

// The voxels of column `px` (its centre f = px + 0.5; conservative: one
// the triangle touches, vct_column_touched) that the triangle touches get
// albedo and the canonical normal n.
void vct_column(VctTri t, VctSat s, ivec2 px, int level, vec3 albedo, vec3 n)
{
    vec2 f = vec2(px) + 0.5;
    // Depth of the triangle's plane over this column (swizzled z), within
    // the triangle's depth range, as it is exactly: rounded, the plane
    // equation of a triangle lying on a voxel boundary (a floor at z = 16)
    // gave 15.99999 on NVIDIA's division while its vertices say 16, which
    // emptied the range below and left the whole floor unvoxelized.
    float zc = clamp((s.d - s.n.x * f.x - s.n.y * f.y) / s.n.z, s.zmin, s.zmax);
    if (u_vct.conservative == 0) {
        vct_add(ivec3(px, int(floor(zc))), t.axis, level, albedo, n);
        return;
    }
    // The plane's slope is at most 1 per column along the dominant axis.
    float dz = 0.5 * (abs(s.n.x) + abs(s.n.y)) / abs(s.n.z);
    // zmin <= zc <= zmax, so k0 <= floor(zc) <= k1.
    int k0 = int(floor(max(zc - dz, s.zmin))), k1 = int(floor(min(zc + dz, s.zmax)));
    for (int k = k0; k <= k1; k++)
        if (vct_voxel_touched(s, px, k))
            vct_add(ivec3(px, k), t.axis, level, albedo, n);
}
#endif
