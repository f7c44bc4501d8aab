// gi/lpv/lookup.comp — per pixel, the accumulated light of the finest
// cascade that holds the pixel (blended into the next one across the outer
// u_lpv.blend of a cascade), sampled trilinearly half a cell along the
// normal, convolved with the cosine lobe: a cell of side s carrying
// intensity I(ω) has radiance I(ω)/s², so
//   E(n) = 1/s² ∫ I(ω) max(0, −n·ω) dω = (c00·√π/2 − c1·n·√(π/3)) / s².
// Inputs: G-buffer, TEX_LPV_SUM + 3k + channel. Output: IMG_OUT irradiance.
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = TEX_GB_POSITION) uniform sampler2D g_position;
layout(binding = TEX_GB_NORMAL) uniform sampler2D g_normal;
layout(binding = TEX_LPV_SUM + 0) uniform sampler3D s_sum[3 * LPV_MAX_CASCADES];
layout(binding = IMG_OUT, rgba32f) uniform writeonly image2D o_irradiance;

vec3 cascade_irradiance(int k, vec3 p, vec3 n)
{
    float s = u_lpv.cascade[k].w;
    vec3 t = (p + 0.5 * s * n - u_lpv.cascade[k].xyz) / (s * float(u_lpv.size));
    vec4 lobe = sh_clamped_cos(-n) / (s * s);
    vec3 e;
    // Indexed with constants: arrays of samplers need dynamically uniform indices.
    if (k == 0)
        e = vec3(dot(texture(s_sum[0], t), lobe), dot(texture(s_sum[1], t), lobe), dot(texture(s_sum[2], t), lobe));
#if LPV_MAX_CASCADES > 1
    else if (k == 1)
        e = vec3(dot(texture(s_sum[3], t), lobe), dot(texture(s_sum[4], t), lobe), dot(texture(s_sum[5], t), lobe));
#endif
#if LPV_MAX_CASCADES > 2
    else
        e = vec3(dot(texture(s_sum[6], t), lobe), dot(texture(s_sum[7], t), lobe), dot(texture(s_sum[8], t), lobe));
#endif
    return max(e, vec3(0.0));
}

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (px.x >= u_frame.width || px.y >= u_frame.height)
        return;
    vec4 p = texelFetch(g_position, px, 0);
    vec3 e = vec3(0.0);
    if (p.w != 0.0) {
        vec3 n = normalize(texelFetch(g_normal, px, 0).xyz);
        float left = 1.0;
        for (int k = 0; k < u_lpv.cascades && left > 0.0; k++) {
            // Distance to the cascade's border as a fraction of its extent,
            // less a cell (the border cells read the black outside).
            vec3 u = (p.xyz - u_lpv.cascade[k].xyz) / (u_lpv.cascade[k].w * float(u_lpv.size));
            float m = min(min(u.x, min(u.y, u.z)), 1.0 - max(u.x, max(u.y, u.z))) - 1.0 / float(u_lpv.size);
            float w = k == u_lpv.cascades - 1 ? 1.0 : clamp(m / u_lpv.blend, 0.0, 1.0);
            if (w > 0.0)
                e += left * w * cascade_irradiance(k, p.xyz, n);
            left *= 1.0 - w;
        }
    }
    imageStore(o_irradiance, px, vec4(e, 1.0));
}
