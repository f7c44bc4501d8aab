// gi/lpv/geometry_resolve.comp — fixed-point sums of geometry_fixed.comp →
// the geometry volume's two textures (IMG_LPV_DST + 0: xx yy zz, + 1: xy
// xz yz), (N+1)³.
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = SSBO_LPV_FIXED) readonly buffer FixedBlock { int sums[]; };
layout(binding = IMG_LPV_DST + 0, rgba32f) uniform writeonly image3D d_diag;
layout(binding = IMG_LPV_DST + 1, rgba32f) uniform writeonly image3D d_off;
layout(location = LOC_LPV_FIXED_SCALE) uniform float u_scale;

void main()
{
    ivec3 c = ivec3(gl_GlobalInvocationID);
    int size = u_lpv.size + 1;
    if (!lpv_inside(c, size))
        return;
    int base = 6 * (c.x + size * (c.y + size * c.z));
    imageStore(d_diag, c, vec4(sums[base], sums[base + 1], sums[base + 2], 0) / u_scale);
    imageStore(d_off, c, vec4(sums[base + 3], sums[base + 4], sums[base + 5], 0) / u_scale);
}
