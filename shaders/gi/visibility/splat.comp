// gi/visibility/splat.comp — the scene's points into imperfect shadow
// maps (Ritschel et al. 2008): map m (work groups (·, y, z), ism.c's
// dispatch_maps) takes u_ism.points of the scene's points, from an offset
// hashed from m, and writes each one's distance from the map's source into
// the texel of its direction on the source's paraboloid (gi/visibility/
// ism.glsl), keeping the nearest (an atomic minimum on the float's bits,
// which order as the distances do). A point far from the source covers
// less than a texel; a near one a square of up to 5×5 texels, as many as
// its share of the scene's area subtends (point_area / d², over a texel's
// solid angle 16 / (S² (1 + ρ²)²) at radius ρ of the paraboloid), and
// pull-push (pull_push.comp) fills what the points miss.
// Sources: ISM_FROM_VPLS: VPL m (none past the buffer's count);
// ISM_FROM_RSM: the representative of block m - u_ism_map_base (reps.comp).
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/packing.glsl"
#include "common/vpl_record.glsl"
#include "gi/visibility/ism.glsl"

layout(local_size_x = 64) in;

layout(r32ui, binding = IMG_OUT) uniform coherent uimage2D o_atlas;
layout(std430, binding = SSBO_ISM_POINTS) readonly buffer IsmPointBlock { vec4 ism_points[]; };
#ifdef ISM_FROM_VPLS
layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) readonly buffer CounterBlock { uint counters[]; };
layout(location = LOC_ISM_MAP_BASE) uniform uint u_splat_base;
#endif

const int POINTS_PER_INVOCATION = 4;
const float ISM_PLANE = 0.02; // sine of the elevation under which a point lies on the source's own plane

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
    int size = u_ism.size, shift = findMSB(u_ism.per_row);
    uint mask = u_ism.point_count - 1u, first = hash_u32(m * 0x9e3779b9u + 0x7f4a7c15u);
    float area = u_ism.point_area, S = float(size);
    vec3 t, b;
    basis(ns, t, b);
    ivec2 tile = ivec2(int(m & uint(u_ism.per_row - 1)), int(m >> uint(shift))) * size;
    for (int k = 0; k < POINTS_PER_INVOCATION; k++) {
        uint j = gl_GlobalInvocationID.x * uint(POINTS_PER_INVOCATION) + uint(k);
        if (j >= u_ism.points)
            break;
        vec4 p = ism_points[(first + j) & mask];
        vec3 d = p.xyz - xs;
        float len2 = dot(d, d);
        if (!(len2 > 1e-12) || p.w == 0.0)
            continue;
        float len = sqrt(len2);
        vec3 l = vec3(dot(d, t), dot(d, b), dot(d, ns)) / len;
        if (l.z < ISM_PLANE)
            continue; // behind the source, or on its own plane (it hides nothing in front of it)
        vec2 c = l.xy / (1.0 + l.z); // in the unit disk
        float rho2 = dot(c, c), s = 1.0 + rho2;
        float texels = area / len2 * S * S * s * s / 16.0;
        int r = min(int(0.5 * sqrt(texels) - 0.5), 2);
        ivec2 at = clamp(ivec2((c * 0.5 + 0.5) * S), ivec2(0), ivec2(size - 1));
        uint depth = floatBitsToUint(len);
        for (int y = -r; y <= r; y++)
            for (int x = -r; x <= r; x++) {
                ivec2 q = at + ivec2(x, y);
                if (all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, ivec2(size))))
                    imageAtomicMin(o_atlas, tile + q, depth);
            }
    }
}
