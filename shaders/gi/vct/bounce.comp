// gi/vct/bounce.comp — the second bounce (--vct-bounces 2): each opaque
// voxel gathers irradiance from the directly lit volume with the diffuse
// cone set, on both sides of its (two-sided) surface, and keeps the larger
// (the side that faces into the scene); its outgoing radiance gains
// ρ/π · E. Writes the new level 0 into another volume.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "gi/vct/cone.glsl"

#ifdef OPAQUE_LIST
// One invocation per listed opaque voxel (gi/vct/volume.glsl); vct.c
// copies the direct radiance for the empty ones. In a 4×4×4 group a wall
// across x had left 7 of 8 lanes of a SIMD row idle while the eighth
// marched its 12 cones.
layout(local_size_x = 64) in;
#else
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#endif
layout(binding = TEX_VCT_ALBEDO) uniform sampler3D u_albedo;
layout(binding = IMG_VCT_DST, rgba16f) writeonly uniform image3D u_dst;
// xyz: the canonical normal; w: the lit side (inject.comp), which gains the
// bounce's side here.
layout(binding = IMG_VCT_DST2, rgba16f) uniform image3D u_normal;

void main()
{
    ivec3 v;
    if (!vct_voxel_here(v))
        return;
    vec4 direct = texelFetch(u_radiance, v, 0);
    vec4 a = texelFetch(u_albedo, v, 0);
    if (a.a <= 0.0) {
        imageStore(u_dst, v, direct);
        return;
    }
    float voxel;
    vec3 x = vct_voxel_centre(v, voxel);
    vec4 canon = imageLoad(u_normal, v);
    vec3 n = canon.xyz;
    float vis;
    vec3 e_front = vct_irradiance(x, n, voxel, vis);
    vec3 e_back = vct_irradiance(x, -n, voxel, vis);
    bool front = dot(e_front, vec3(1.0)) >= dot(e_back, vec3(1.0));
    vec3 l = a.a * a.rgb / PI * (front ? e_front : e_back);
    imageStore(u_dst, v, vec4(direct.rgb + l, direct.a));
    imageStore(u_normal, v, vec4(n, canon.w + (front ? 1.0 : -1.0) * dot(l, vec3(0.2126, 0.7152, 0.0722))));
}
