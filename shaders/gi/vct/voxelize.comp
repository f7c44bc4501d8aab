// gi/vct/voxelize.comp — the voxelization in compute, triangle-parallel
// (as Schwarz & Seidel 2010, "Fast Parallel Surface and Solid Voxelization
// on GPUs"): no rasterizer, so it runs on every core of a GPU (an H100
// rasterizes on 4 of its 132 SMs) and on every llvmpipe thread. Each
// triangle is set up as voxelize.geom does (voxel units, its dominant axis
// swizzled to z) and writes, for every column (x, y) whose pixel square
// its projection touches, what the raster path's fragment there writes
// (gi/vct/voxelize.glsl, vct_column): the same voxels, the same sums, the
// material read at the column centre with the uv's gradient per column
// given explicitly (textureGrad: a compute shader has no derivatives).
// One dispatch per submesh (its material bound, gpu_scene_bind_material):
//   default: one invocation per triangle; a triangle of at most
//     SMALL_COLUMNS columns walks them itself, a larger one is appended to
//     its submesh's list in SSBO_VCT_WORK (its header: the indirect
//     dispatch of the tile pass);
//   VOXELIZE_TILES: per listed triangle, its columns in 8×8 tiles, one
//     invocation a column; work group (x, y) takes listed triangles x,
//     x + X, ... and their tiles y, y + Y, ... (X, Y capped).
// u_run: x the submesh's first triangle, y its triangle count, z its
// header (uint[4] at 4·z: groups x, y, z, the listed count), w where its
// list starts in SSBO_VCT_WORK.
#include "shared/gpu_types.h"
#define MATERIAL_GRADIENTS
#include "common/material.glsl"
#include "gi/vct/voxelize.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = SSBO_SCENE_VERTICES) readonly buffer Vertices { float vertex_data[]; }; // Vertex: 8 floats
layout(std430, binding = SSBO_SCENE_INDICES) readonly buffer Indices { uint indices[]; };
layout(std430, binding = SSBO_VCT_WORK) buffer Work { uint work[]; };
layout(location = LOC_VCT_LEVEL) uniform int u_level;
layout(location = LOC_VCT_RUN) uniform uvec4 u_run;

// Columns a triangle walks itself, beyond which the tile pass takes it
// (vct.c sets it per device class). A GPU's lanes walk in lock step, so a
// lane with many columns holds its warp: 16. On llvmpipe the tile pass
// costs more than it spreads: its groups per listed triangle are the
// submesh's most tiles, each group setting its triangle up in every lane
// whether or not a tile is left; 1024 (Sponza nave at 128³, compute
// voxelization 875-1010 -> 129-253 ms; at 256³ 2176-3261 -> 238-585 ms).
#ifndef SMALL_COLUMNS
#define SMALL_COLUMNS 16
#endif
// The column range is a superset of the columns the triangle–box test
// takes (its tolerance is 1e-4 voxel): that test alone decides, as in the
// raster path (voxelize.geom's VCT_COVER_MARGIN).
const float COVER_MARGIN = 1e-3;
const uint TILE_GROUPS = 64u; // most work groups per triangle (groups y)

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// A triangle set up for its columns.
struct Setup {
    VctTri t;
    VctSat sat;
    vec2 a[3];      // its projection (swizzled x, y)
    float area;     // signed twice the projection's area (never 0)
    ivec2 lo, hi;   // the columns its bounds touch, within the volume
    vec2 uv0, duv_dx, duv_dy; // uv at the first vertex's (x, y) and per column
    vec3 n0, dn_dx, dn_dy;    // interpolated normal, likewise
};

vec3 vertex_vec3(uint v, uint at) { return vec3(vertex_data[8u * v + at], vertex_data[8u * v + at + 1u], vertex_data[8u * v + at + 2u]); }

// False for a degenerate triangle or one wholly outside the volume's columns.
bool setup(uint tri, out Setup s)
{
    uint v[3] = uint[3](indices[3u * tri], indices[3u * tri + 1u], indices[3u * tri + 2u]);
    vec3 p[3];
    for (int i = 0; i < 3; i++)
        p[i] = (vertex_vec3(v[i], 0u) - u_vct.level[u_level].xyz) / u_vct.level[u_level].w;
    vec3 n = cross(p[1] - p[0], p[2] - p[0]);
    vec3 an = abs(n);
    s.t.axis = vct_dominant_axis(n);
    s.t.t0 = vct_swizzle(p[0], s.t.axis);
    s.t.t1 = vct_swizzle(p[1], s.t.axis);
    s.t.t2 = vct_swizzle(p[2], s.t.axis);
    s.sat = vct_sat_setup(s.t);
    s.a = vec2[3](s.t.t0.xy, s.t.t1.xy, s.t.t2.xy);
    vec2 e1 = s.a[1] - s.a[0], e2 = s.a[2] - s.a[0];
    s.area = cross2(e1, e2);
    // Pixel squares [x, x + 1] that reach the bounds [min, max] (with the margin).
    vec2 lo = min(s.a[0], min(s.a[1], s.a[2])), hi = max(s.a[0], max(s.a[1], s.a[2]));
    s.lo = max(ivec2(ceil(lo - 1.0 - COVER_MARGIN)), ivec2(0));
    s.hi = min(ivec2(floor(hi + COVER_MARGIN)), ivec2(u_vct.size - 1));
    // Barycentrics of a point q: b1 = cross2(q − a0, e2) / area, b2 = cross2(e1, q − a0) / area.
    vec2 uv[3] = vec2[3](vec2(vertex_data[8u * v[0] + 6u], vertex_data[8u * v[0] + 7u]),
                         vec2(vertex_data[8u * v[1] + 6u], vertex_data[8u * v[1] + 7u]),
                         vec2(vertex_data[8u * v[2] + 6u], vertex_data[8u * v[2] + 7u]));
    vec3 nv[3] = vec3[3](vertex_vec3(v[0], 3u), vertex_vec3(v[1], 3u), vertex_vec3(v[2], 3u));
    vec2 db1 = vec2(e2.y, -e2.x) / s.area, db2 = vec2(-e1.y, e1.x) / s.area;
    s.uv0 = uv[0];
    s.duv_dx = (uv[1] - uv[0]) * db1.x + (uv[2] - uv[0]) * db2.x;
    s.duv_dy = (uv[1] - uv[0]) * db1.y + (uv[2] - uv[0]) * db2.y;
    s.n0 = nv[0];
    s.dn_dx = (nv[1] - nv[0]) * db1.x + (nv[2] - nv[0]) * db2.x;
    s.dn_dy = (nv[1] - nv[0]) * db1.y + (nv[2] - nv[0]) * db2.y;
    return max(an.x, max(an.y, an.z)) > 0.0 && s.area != 0.0 && all(lessThanEqual(s.lo, s.hi));
}

// Whether column px is the raster path's fragment: with the conservative
// voxelization one the triangle touches (vct_column_touched), else one
// whose centre lies inside (a centre on an edge shared by two triangles
// counts for one of them: the top-left rule).
bool covered(Setup s, ivec2 px)
{
    if (u_vct.conservative != 0)
        return vct_column_touched(s.sat, px);
    vec2 f = vec2(px) + 0.5;
    float sgn = s.area > 0.0 ? 1.0 : -1.0;
    for (int i = 0; i < 3; i++) {
        vec2 d = sgn * (s.a[(i + 1) % 3] - s.a[i]); // counter-clockwise edges: inside on the left
        vec2 from = sgn > 0.0 ? s.a[i] : s.a[(i + 1) % 3];
        float e = cross2(d, f - from);
        if (e < 0.0 || (e == 0.0 && !(d.y < 0.0 || (d.y == 0.0 && d.x < 0.0))))
            return false;
    }
    return true;
}

void column(Setup s, ivec2 px)
{
    if (!covered(s, px))
        return;
    vec2 q = vec2(px) + 0.5 - s.a[0];
    vec2 uv = s.uv0 + s.duv_dx * q.x + s.duv_dy * q.y;
    material_dx = s.duv_dx;
    material_dy = s.duv_dy;
    material_masked = false;
    vec3 albedo = clamp(material_diffuse(uv), 0.0, 1.0); // ρ_d: voxels reflect diffusely
    if (material_masked)
        return;
    vct_column(s.t, s.sat, px, u_level, albedo, vct_canonical_normal(s.n0 + s.dn_dx * q.x + s.dn_dy * q.y));
}

void main()
{
    Setup s;
#ifdef VOXELIZE_TILES
    uint header = 4u * u_run.z, count = work[header + 3u];
    for (uint i = gl_WorkGroupID.x; i < count; i += gl_NumWorkGroups.x) {
        setup(work[u_run.w + i], s);
        ivec2 tiles = (s.hi - s.lo + 8) / 8;
        uint n = uint(tiles.x * tiles.y);
        ivec2 in_tile = ivec2(gl_LocalInvocationID.x % 8u, gl_LocalInvocationID.x / 8u);
        for (uint t = gl_WorkGroupID.y; t < n; t += gl_NumWorkGroups.y) {
            ivec2 px = s.lo + 8 * ivec2(int(t) % tiles.x, int(t) / tiles.x) + in_tile;
            if (all(lessThanEqual(px, s.hi)))
                column(s, px);
        }
    }
#else
    uint local = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (local >= u_run.y)
        return;
    uint tri = u_run.x + local;
    if (!setup(tri, s))
        return;
    ivec2 size = s.hi - s.lo + 1;
    if (size.x * size.y > SMALL_COLUMNS) {
        uint header = 4u * u_run.z;
        uint slot = atomicAdd(work[header + 3u], 1u);
        work[u_run.w + slot] = tri;
        atomicMax(work[header], min(slot + 1u, 65535u));
        ivec2 tiles = (size + 7) / 8;
        atomicMax(work[header + 1u], min(uint(tiles.x * tiles.y), TILE_GROUPS));
        return;
    }
    for (int y = s.lo.y; y <= s.hi.y; y++)
        for (int x = s.lo.x; x <= s.hi.x; x++)
            column(s, ivec2(x, y));
#endif
}
