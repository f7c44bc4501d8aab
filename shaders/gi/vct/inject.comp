// gi/vct/inject.comp — light injection (Crassin et al. 2011, §4.1): each
// opaque voxel's outgoing diffuse radiance from the light bound to
// UBO_LIGHT, L = ρ/π · E · V, in W/(m²·sr) like every other technique
// (SPEC §1), stored premultiplied by the voxel's opacity. E is the light
// model's irradiance on the voxel's surface (two-sided: the normal turned
// toward the light); V is the shadow map's verdict averaged over a 3×3 grid
// across the voxel, half a voxel diagonal off the surface toward the light,
// with a depth bias of one voxel. Lights after the first add to the level.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/lights.glsl"
#include "common/shadow.glsl"
#include "gi/vct/volume.glsl"

#ifdef OPAQUE_LIST
// One invocation per listed opaque voxel (gi/vct/volume.glsl): an empty
// voxel would cost its shadow taps all the same (llvmpipe runs the code
// under a branch whether or not a lane takes it).
layout(local_size_x = 64) in;
#else
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#endif
layout(binding = TEX_VCT_ALBEDO) uniform sampler3D u_albedo;
layout(binding = IMG_VCT_DST, rgba16f) uniform image3D u_radiance;
// xyz: the canonical normal (resolve.comp); w written here: the lit side.
layout(binding = IMG_VCT_DST2, rgba16f) uniform image3D u_normal;
layout(location = LOC_VCT_ACCUMULATE) uniform int u_accumulate;

float visibility(vec3 x, vec3 n, float voxel)
{
    vec3 t, b;
    basis(n, t, b);
    float lit = 0.0;
    for (int i = -1; i <= 1; i++)
        for (int j = -1; j <= 1; j++) {
            vec3 q = x + n * (0.87 * voxel) + (t * float(i) + b * float(j)) * (0.33 * voxel);
            ShadowCoord sc = shadow_coord(q);
            lit += sc.d - voxel <= shadow_fetch(sc, vec2(0.0)) ? 1.0 : 0.0;
        }
    return lit / 9.0;
}

void main()
{
    ivec3 v;
    if (!vct_voxel_here(v))
        return;
    vec4 a = texelFetch(u_albedo, v, 0);
    vec3 l = vec3(0.0);
    float side = 1.0; // the lit side: the canonical normal's (1) or the other (−1)
    vec4 canon = vec4(0.0);
    if (a.a > 0.0) {
        float voxel;
        vec3 x = vct_voxel_centre(v, voxel);
        canon = imageLoad(u_normal, v);
        vec3 n = canon.xyz;
        vec3 to_light = light_type(u_light) == LIGHT_DIRECTIONAL ? -u_light.direction_width.xyz
                                                                  : normalize(u_light.position_type.xyz - x);
        if (dot(n, to_light) < 0.0) {
            n = -n;
            side = -1.0;
        }
        vec3 dir;
        vec3 e = light_irradiance(u_light, x, n, dir);
        if (max(e.r, max(e.g, e.b)) > 0.0)
            l = a.rgb / PI * e * visibility(x, n, voxel);
    }
    vec4 r = vec4(l * a.a, a.a);
    // The lit side, for the directional volumes (aniso.comp): w sums each
    // light's luminance signed by the side it lights.
    float lit = side * dot(l, vec3(0.2126, 0.7152, 0.0722));
    if (u_accumulate != 0) {
        r.rgb += imageLoad(u_radiance, v).rgb;
        lit += canon.w;
    }
    imageStore(u_radiance, v, r);
    if (a.a > 0.0)
        imageStore(u_normal, v, vec4(canon.xyz, lit));
}
