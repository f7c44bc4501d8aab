// gi/lpv/geometry_fixed.comp — geometry-volume injection by compute (the
// default `--lpv-inject compute`): one invocation per surfel (surfel.glsl),
// its normal tensor A/s² · n nᵀ added with integer atomics in fixed point
// (LOC_LPV_FIXED_SCALE units per 1) to SSBO_LPV_FIXED[6·cell + j], j = xx,
// yy, zz, xy, xz, yz; geometry_resolve.comp writes the two textures.
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"
#include "gi/lpv/surfel.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = SSBO_LPV_FIXED) buffer FixedBlock { int sums[]; };
layout(location = LOC_LPV_CASCADE) uniform int u_cascade;
layout(location = LOC_LPV_SURFEL_AREA) uniform float u_max_area;
layout(location = LOC_LPV_FIXED_SCALE) uniform float u_scale;

void main()
{
    ivec3 q = ivec3(gl_GlobalInvocationID);
    ivec3 size = surfel_size();
    if (any(greaterThanEqual(q, size)))
        return;
    vec3 p, n;
    float area, w;
    if (!lpv_surfel(q, u_max_area, p, n, area))
        return;
    ivec3 c = lpv_surfel_cell(u_cascade, p, area, w);
    int size_gv = u_lpv.size + 1;
    if (!lpv_inside(c, size_gv))
        return;
    int base = 6 * (c.x + size_gv * (c.y + size_gv * c.z));
    float t[6] = float[6](n.x * n.x, n.y * n.y, n.z * n.z, n.x * n.y, n.x * n.z, n.y * n.z);
    for (int j = 0; j < 6; j++) {
        int v = int(round(w * t[j] * u_scale));
        if (v != 0)
            atomicAdd(sums[base + j], v);
    }
}
