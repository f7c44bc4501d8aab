// gi/lpv/lookup.comp — per pixel, the accumulated light sampled trilinearly
// half a cell along the normal (no nearer the surface than the first cell
// in front of its blocking plane: lookup_cell), each light group's
// irradiance summed. The light of a cell of side s summed over the steps,
// I(ω), has radiance κ·I(ω)/s² (κ = LPV_SPEED cells a step, sh.glsl; the
// paper's faces: 1), so
//   E(n) = κ/s² ∫ I(ω) max(0, −n·ω) dω,
// with --lpv-propagation directional of I's lobe reading (never negative;
// a light group's own light travelling away from a surface gives it none),
// with faces of the 2-band SH itself, (c00·√π/2 − c1·n·√(π/3))/s².
// Cascades (see lpv.c): inside cascade k the light of its own VPLs comes
// from cascade k, that of the VPLs outside it from the coarser cascades'
// "outer" volumes; w_k fades cascade k out over the outer u_lpv.blend of
// its extent (less a cell, whose lookups read the black outside).
// Inputs: G-buffer, TEX_LPV_SUM + 3k + c, TEX_LPV_OUTER + 3(k−1) + c (the
// light groups stacked in z). Output: IMG_OUT irradiance.
#include "shared/gpu_types.h"
#if !defined(LPV_CASCADES) || !defined(LPV_GROUPS)
#error "gi/lpv/lookup.comp needs LPV_CASCADES and LPV_GROUPS, the cascade and light group counts (src/gi/lpv/lpv.c defines them)"
#endif
#include "gi/lpv/sh.glsl"
#include "common/gbuffer.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = TEX_LPV_SUM) uniform sampler3D s_all[3 * LPV_MAX_CASCADES];
layout(binding = TEX_LPV_OUTER) uniform sampler3D s_outer[3 * (LPV_MAX_CASCADES - 1)];
layout(binding = IMG_OUT, rgba32f) uniform writeonly image2D o_irradiance;

#ifdef DIRECTIONAL
// The receiver's `lobe` (receiver()): directional −n and κ/s² in w; faces
// the SH of its clamped cosine over s².
float channel(vec4 sh, vec4 lobe) { return lobe.w * lpv_lobe_toward(lpv_lobe(sh), lobe.xyz); }
vec3 convolve(vec4 r, vec4 g, vec4 b, vec4 lobe) { return vec3(channel(r, lobe), channel(g, lobe), channel(b, lobe)); }
vec4 receiver(vec3 n, float s) { return vec4(-n, LPV_SPEED / (s * s)); }
#else
vec3 convolve(vec4 r, vec4 g, vec4 b, vec4 lobe) { return max(vec3(dot(r, lobe), dot(g, lobe), dot(b, lobe)), vec3(0.0)); }
vec4 receiver(vec3 n, float s) { return sh_clamped_cos(-n) / (s * s); }
#endif

// Where the surface point p (normal n) reads cascade c (origin xyz, cell
// w), in cells: half a cell along n, but along n's dominant axis no
// nearer the surface than the centre of the first cell in front of the
// corner plane that the surface's geometry volume texels block (the
// nearest; surfel.glsl rounds to it, and its VPLs land in that cell):
// with the surface in the far half of its cell, half a cell along n
// still reads the cell behind that plane, which its light never enters.
vec3 lookup_cell(vec3 p, vec3 n, vec4 c)
{
    vec3 u = (p - c.xyz) / c.w, t = u + 0.5 * n;
    vec3 a = abs(n);
    int ax = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
    float front = round(u[ax]) + 0.5 * sign(n[ax]);
    t[ax] = n[ax] > 0.0 ? max(t[ax], front) : min(t[ax], front);
    return t;
}

// The irradiance of one volume set (the R, G, B volumes sr, sg, sb) at t
// (cells / N), summed over its light groups, each read as its own lobe
// (the groups are stacked in z; a lookup stays inside its group's layers).
vec3 groups_irradiance(sampler3D sr, sampler3D sg, sampler3D sb, vec3 t, vec4 lobe)
{
#if LPV_GROUPS == 1
    return convolve(texture(sr, t), texture(sg, t), texture(sb, t), lobe);
#else
    vec3 e = vec3(0.0);
    float h = 0.5 / float(u_lpv.size);
    for (int g = 0; g < LPV_GROUPS; g++) {
        vec3 tg = vec3(t.xy, (float(g) + clamp(t.z, h, 1.0 - h)) / float(LPV_GROUPS));
        e += convolve(texture(sr, tg), texture(sg, tg), texture(sb, tg), lobe);
    }
    return e;
#endif
}

// Irradiance from cascade k's volume (outer: its "outer" one).
vec3 cascade_irradiance(int k, bool outer, vec3 p, vec3 n)
{
    float s = u_lpv.cascade[k].w;
    vec3 t = lookup_cell(p, n, u_lpv.cascade[k]) / float(u_lpv.size);
    vec4 lobe = receiver(n, s);
    // Constant indices: arrays of samplers need dynamically uniform ones.
    if (!outer) {
        if (k == 0)
            return groups_irradiance(s_all[0], s_all[1], s_all[2], t, lobe);
        if (k == 1)
            return groups_irradiance(s_all[3], s_all[4], s_all[5], t, lobe);
        return groups_irradiance(s_all[6], s_all[7], s_all[8], t, lobe);
    }
    if (k == 1)
        return groups_irradiance(s_outer[0], s_outer[1], s_outer[2], t, lobe);
    return groups_irradiance(s_outer[3], s_outer[4], s_outer[5], t, lobe);
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
