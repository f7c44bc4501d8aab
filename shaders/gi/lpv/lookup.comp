// gi/lpv/lookup.comp — per pixel, the accumulated light sampled trilinearly
// half a cell along the normal, convolved with the cosine lobe: a cell of
// side s carrying intensity I(ω) has radiance I(ω)/s², so
//   E(n) = 1/s² ∫ I(ω) max(0, −n·ω) dω = (c00·√π/2 − c1·n·√(π/3)) / s².
// Cascades (see lpv.c): inside cascade k the light of its own VPLs comes
// from cascade k, that of the VPLs outside it from the coarser cascades'
// "outer" volumes; w_k fades cascade k out over the outer u_lpv.blend of
// its extent (less a cell, whose lookups read the black outside).
// Inputs: G-buffer, TEX_LPV_SUM + 3k + c, TEX_LPV_OUTER + 3(k−1) + c.
// Output: IMG_OUT irradiance.
#include "shared/gpu_types.h"
#ifndef LPV_CASCADES
#error "gi/lpv/lookup.comp needs LPV_CASCADES, the cascade count (src/gi/lpv/lpv.c defines it)"
#endif
#include "gi/lpv/sh.glsl"
#include "common/gbuffer.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = TEX_LPV_SUM) uniform sampler3D s_all[3 * LPV_MAX_CASCADES];
layout(binding = TEX_LPV_OUTER) uniform sampler3D s_outer[3 * (LPV_MAX_CASCADES - 1)];
layout(binding = IMG_OUT, rgba32f) uniform writeonly image2D o_irradiance;

vec3 convolve(vec4 r, vec4 g, vec4 b, vec4 lobe) { return max(vec3(dot(r, lobe), dot(g, lobe), dot(b, lobe)), vec3(0.0)); }

// Irradiance from cascade k's volume (outer: its "outer" one).
vec3 cascade_irradiance(int k, bool outer, vec3 p, vec3 n)
{
    float s = u_lpv.cascade[k].w;
    vec3 t = (p + 0.5 * s * n - u_lpv.cascade[k].xyz) / (s * float(u_lpv.size));
    vec4 lobe = sh_clamped_cos(-n) / (s * s);
    // Constant indices: arrays of samplers need dynamically uniform ones.
    if (!outer) {
        if (k == 0)
            return convolve(texture(s_all[0], t), texture(s_all[1], t), texture(s_all[2], t), lobe);
        if (k == 1)
            return convolve(texture(s_all[3], t), texture(s_all[4], t), texture(s_all[5], t), lobe);
        return convolve(texture(s_all[6], t), texture(s_all[7], t), texture(s_all[8], t), lobe);
    }
    if (k == 1)
        return convolve(texture(s_outer[0], t), texture(s_outer[1], t), texture(s_outer[2], t), lobe);
    return convolve(texture(s_outer[3], t), texture(s_outer[4], t), texture(s_outer[5], t), lobe);
}

// 1 inside cascade k, 0 outside, linear across its border band.
float cascade_weight(int k, vec3 p)
{
    vec3 u = (p - u_lpv.cascade[k].xyz) / (u_lpv.cascade[k].w * float(u_lpv.size));
    float m = min(min(u.x, min(u.y, u.z)), 1.0 - max(u.x, max(u.y, u.z))) - 1.0 / float(u_lpv.size);
    return clamp(m / u_lpv.blend, 0.0, 1.0);
}

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (px.x >= u_frame.width || px.y >= u_frame.height)
        return;
    vec3 p, n;
    vec3 e = vec3(0.0);
    if (gb_surface(px, p, n)) {
        // A constant: the loop unrolls and each call's k selects its
        // samplers at compile time. With k read from u_lpv, llvmpipe ran
        // every arm of cascade_irradiance (it runs both sides of a branch):
        // 15 fetches for one cascade's 3 (256², one thread: 14.9 -> 3.5 ms; three
        // cascades 26.2 -> 7.4 ms).
        const int last = LPV_CASCADES - 1;
        // From the coarsest: total = every VPL of the coarsest cascade;
        // rest = the VPLs outside the next finer cascade.
        vec3 total = cascade_irradiance(last, false, p, n);
        vec3 rest = last > 0 ? cascade_irradiance(last, true, p, n) : vec3(0.0);
        for (int k = last - 1; k >= 0; k--) {
            float w = cascade_weight(k, p);
            if (w > 0.0)
                total = mix(total, cascade_irradiance(k, false, p, n) + rest, w);
            if (k > 0)
                rest += cascade_irradiance(k, true, p, n);
        }
        e = total;
    }
    imageStore(o_irradiance, px, vec4(e, 1.0));
}
