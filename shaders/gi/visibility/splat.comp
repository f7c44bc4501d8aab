// gi/visibility/splat.comp — the scene's points into imperfect shadow
// maps (Ritschel et al. 2008): map m (work groups (·, y, z), ism.c's
// dispatch_maps) takes u_ism.far_points of the scene's points (a stride
// through the buffer, sorted by cell: spread over the whole scene) and
// u_ism.near_points of those in the 3×3×3 grid cells around its source
// (evenly through them; the far points that fall there are left out, the
// near ones stand for them), and writes each one's distance from the
// source into the texel of its direction on the source's paraboloid
// (gi/visibility/ism.glsl), keeping the nearest (an atomic minimum on the
// float's bits, which order as the distances do). A point covers as many
// texels as its share of the scene's area subtends (area·|cos| / d², its
// triangle's normal against the direction, over a texel's solid angle
// 16 / (S² (1 + ρ²)²) at radius ρ of the paraboloid),
// as a square of (2r + 1)² ≈ ISM_COVER times that, r ≤ ISM_MAX_SPLAT: the
// points land at random, so splats of their own footprint left a third of
// a surface's texels empty, and a surface behind it (a receiver's own
// points) showed through them: a wall hid half the bounce
// (test_visibility). ISM_COVER 4 leaves e⁻⁴ ≈ 2% of them empty (3:
// the wall let 1.7-2.1% through); the silhouettes it widens cost the
// Cornell box about 4% of its visible bounce. Each texel of a splat takes
// the depth of the point's plane in its direction, so that a splat does
// not stand in front of its own surface. Pull-push (pull_push.comp) fills
// what the points miss. Uniform points
// alone left a map's near field nearly empty: on Sponza a column 1 m from a
// VPL held a few of 2048 points, and the maps missed a quarter of the
// occluded light (docs/techniques.md: Visibility).
// Sources: ISM_FROM_VPLS: VPL m (none past the buffer's count);
// ISM_FROM_RSM: the representative of block m − u_ism_map_base (reps.comp).
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/packing.glsl"
#include "common/vpl_record.glsl"
#include "gi/visibility/ism.glsl"

layout(local_size_x = 64) in;

layout(r32ui, binding = IMG_OUT) uniform coherent uimage2D o_atlas;
layout(std430, binding = SSBO_ISM_POINTS) readonly buffer IsmPointBlock { uvec4 ism_points[]; }; // xyz bits, oct normal
layout(std430, binding = SSBO_ISM_CELLS) readonly buffer IsmCellBlock { uint ism_cells[]; };
#ifdef ISM_FROM_VPLS
layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) readonly buffer CounterBlock { uint counters[]; };
layout(location = LOC_ISM_MAP_BASE) uniform uint u_splat_base;
#endif

const int POINTS_PER_INVOCATION = 4;
const float ISM_PLANE = 0.02; // sine of the elevation under which a point lies on the source's own plane
const int ISM_MAX_SPLAT = 4;  // a point covers at most (2·4 + 1)² texels
const float ISM_NEAREST = 0.9; // a splat's texels lie no nearer than this times its point's distance
#ifndef ISM_COVER
#define ISM_COVER 4.0
#endif

// The 3×3×3 cells around cell c: nine runs of three cells along x, each
// contiguous in the sorted buffer; run k spans [runs[k].x, runs[k].y).
void near_runs(ivec3 c, int n, out uvec2 runs[9], out uint total)
{
    total = 0u;
    for (int k = 0; k < 9; k++) {
        ivec3 r = c + ivec3(0, k % 3 - 1, k / 3 - 1);
        bool inside = r.y >= 0 && r.y < n && r.z >= 0 && r.z < n;
        int x0 = max(r.x - 1, 0), x1 = min(r.x + 1, n - 1);
        uint row = uint((r.z * n + r.y) * n);
        runs[k] = inside ? uvec2(ism_cells[row + uint(x0)], ism_cells[row + uint(x1) + 1u]) : uvec2(0u);
        total += runs[k].y - runs[k].x;
    }
}

void main()
{
    uint local = gl_WorkGroupID.z * gl_NumWorkGroups.y + gl_WorkGroupID.y;
#ifdef ISM_FROM_VPLS
    uint m = u_splat_base + local;
    if (m >= min(counters[0], u_ism.maps))
        return;
    vec3 xs = vpl_position(vpls[m]), ns = vpl_shading_normal(vpls[m]);
#else
    if (local >= u_ism.maps_per_light)
        return;
    uint m = u_ism_map_base + local;
    uvec4 rep = ism_reps[m];
    if (rep.x == 0xffffffffu)
        return;
    vec3 xs = uintBitsToFloat(rep.xyz), ns = unpack_oct16(rep.w);
#endif
    int size = u_ism.size, shift = findMSB(u_ism.per_row), n = u_ism.grid_n;
    // Where the map's stride through the points starts: from its source's
    // position, not its slot (a VPL's slot is the extraction's atomic
    // append order, which varies run to run: the maps, and the images,
    // did with it).
    uvec3 xb = floatBitsToUint(xs);
    uint mask = u_ism.point_count - 1u, first = hash_u32(xb.x ^ hash_u32(xb.y ^ hash_u32(xb.z + 0x7f4a7c15u)));
    uint stride = u_ism.far_stride;
    uint far_points = u_ism.far_points, near_points = u_ism.near_points;
    float S = float(size), cell = u_ism.grid.w;
    vec3 origin = u_ism.grid.xyz;
    ivec3 c = clamp(ivec3(floor((xs - origin) / cell)), ivec3(0), ivec3(n - 1));
    uvec2 runs[9];
    uint total;
    near_runs(c, n, runs, total);
    // A near point stands for its share of the near cells' area.
    float near_area = u_ism.point_area * max(float(total) / float(max(near_points, 1u)), 1.0);
    vec3 t, b;
    basis(ns, t, b);
    ivec2 tile = ivec2(int(m & uint(u_ism.per_row - 1)), int(m >> uint(shift))) * size;
    for (int k = 0; k < POINTS_PER_INVOCATION; k++) {
        uint j = gl_GlobalInvocationID.x * uint(POINTS_PER_INVOCATION) + uint(k);
        uvec4 p;
        float area;
        if (j < far_points) {
            p = ism_points[(first + j * stride) & mask];
            ivec3 pc = ivec3(floor((uintBitsToFloat(p.xyz) - origin) / cell));
            if (total > 0u && all(lessThanEqual(abs(pc - c), ivec3(1))))
                continue; // the near points stand for it
            area = u_ism.far_area;
        } else {
            uint q = j - far_points;
            if (q >= near_points || (total <= near_points && q >= total))
                continue;
            uint at = total > near_points ? uint(float(q) * float(total) / float(near_points)) : q;
            uint index = 0u;
            for (int r = 0; r < 9; r++) {
                uint len = runs[r].y - runs[r].x;
                if (at < len) {
                    index = runs[r].x + at;
                    break;
                }
                at -= len;
            }
            p = ism_points[index];
            area = near_area;
        }
        vec3 d = uintBitsToFloat(p.xyz) - xs;
        float len2 = dot(d, d);
        if (!(len2 > 1e-12) || p.w == 0u)
            continue;
        float len = sqrt(len2);
        vec3 l = vec3(dot(d, t), dot(d, b), dot(d, ns)) / len;
        if (l.z < ISM_PLANE)
            continue; // behind the source, or on its own plane (it hides nothing in front of it)
        vec2 cc = l.xy / (1.0 + l.z); // in the unit disk
        float s = 1.0 + dot(cc, cc);
        vec3 np = unpack_oct16(p.w);
        float facing = abs(dot(np, d)) / len; // the point's surface seen from the source
        float texels = area * facing / len2 * S * S * s * s / 16.0;
        int r = min(int(0.5 * sqrt(ISM_COVER * texels)), ISM_MAX_SPLAT);
        ivec2 px = clamp(ivec2((cc * 0.5 + 0.5) * S), ivec2(0), ivec2(size - 1));
        // Texels around the point take the distance to the point's plane
        // in their own direction: a splat wider than the point lies on its
        // surface, where a flat square at the point's distance would stand
        // in front of the rest of that surface, and shadow it. Never nearer
        // than ISM_NEAREST of the point's own distance (nor farther than
        // twice it): where the plane turns toward the source (the tilted
        // planes of a column's silhouette points) it is surface the point
        // does not stand for, and had stood at up to half its distance in
        // front of what lay behind. Measured on Sponza's nave (tests/
        // vis_split, 4096 VPLs, against ray casts), the light the maps
        // hide wrongly + the light they let through wrongly, as fractions
        // of the visible bounce: 0.5 (before): 0.28 + 0.17 (net 0.90);
        // 0.8: 0.22 + 0.18; 0.9: 0.19 + 0.19 (net 1.01); 1.0: 0.18 + 0.20
        // (net 1.05). And only where that plane meets the texel's ray
        // within about the disk of ISM_COVER times the point's area around
        // it: a point of a wall 5 cm from a source on the floor covers 9×9
        // texels, and the texels whose rays ran along the wall had taken
        // twice its distance, where the ceiling lay ten times as far (the
        // Cornell box: 5% of the visible bounce hidden wrongly, vpl-slc's
        // relMSE 0.00156 -> 0.00153; Sponza vpl-slc 0.922 -> 0.951).
        vec3 pl = l * len, nl = vec3(dot(np, t), dot(np, b), dot(np, ns));
        float plane = dot(pl, nl);
        float reach2 = ISM_COVER * area * 0.5; // (1.25 × the radius of a disk of ISM_COVER × its area)²
        for (int y = -r; y <= r; y++)
            for (int x = -r; x <= r; x++) {
                ivec2 q = px + ivec2(x, y);
                if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(size))))
                    continue;
                vec2 c = (vec2(q) + 0.5) / S * 2.0 - 1.0;
                float c2 = dot(c, c);
                vec3 dir = vec3(2.0 * c, 1.0 - c2) / (1.0 + c2);
                float along = dot(dir, nl);
                if (!(along * plane > 0.0))
                    continue; // this direction does not meet the point's plane
                float at = plane / along;
                vec3 off = at * dir - pl;
                if (dot(off, off) > reach2)
                    continue; // it meets it beyond the surface the point stands for
                imageAtomicMin(o_atlas, tile + q, floatBitsToUint(clamp(at, ISM_NEAREST * len, 2.0 * len)));
            }
    }
}
