// gi/lpv/inject_resolve.comp — fixed-point sums of inject_fixed.comp →
// the injected volumes (IMG_LPV_DST + channel, RGBA32F), into the layers of
// light group LOC_LPV_GROUP.
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = SSBO_LPV_FIXED) readonly buffer FixedBlock { int sums[]; };
layout(binding = IMG_LPV_DST + 0, rgba32f) uniform writeonly image3D d_r;
layout(binding = IMG_LPV_DST + 1, rgba32f) uniform writeonly image3D d_g;
layout(binding = IMG_LPV_DST + 2, rgba32f) uniform writeonly image3D d_b;
layout(location = LOC_LPV_FIXED_SCALE) uniform float u_scale;
layout(location = LOC_LPV_GROUP) uniform int u_group;

void main()
{
    ivec3 c = ivec3(gl_GlobalInvocationID);
    int size = u_lpv.size;
    if (!lpv_inside(c, size))
        return;
    int base = 12 * (c.x + size * (c.y + size * c.z));
    vec4 v[3];
    for (int ch = 0; ch < 3; ch++)
        v[ch] = vec4(sums[base + 4 * ch], sums[base + 4 * ch + 1], sums[base + 4 * ch + 2], sums[base + 4 * ch + 3]) / u_scale;
    ivec3 at = c + ivec3(0, 0, lpv_group_layer(u_group, size));
    imageStore(d_r, at, v[0]);
    imageStore(d_g, at, v[1]);
    imageStore(d_b, at, v[2]);
}
