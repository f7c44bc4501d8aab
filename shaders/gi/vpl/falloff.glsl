// gi/vpl/falloff.glsl — the distance falloff of a VPL. A VPL stands for the
// surface patch of its RSM texel (area A, GpuVpl.flux.w). As a point it
// falls off as 1/d², unbounded next to it (bright lines where surfaces
// meet); with u_vpl.disk (the default) as the disk of that area seen on its
// axis, 1/(d² + A/π): bounded by π/A next to the VPL, within A/(π d²) of
// 1/d² beyond — the exact irradiance of such a disk, so no energy is lost
// far away. The notes' near clamp 1/max(·, c) (u_vpl.near_clamp = c, 0 =
// off) can be added; it removes hot spots but loses energy (measured 3.9%).
// The falloff's parameters, read from u_vpl once per invocation and
// passed into the loops: on llvmpipe a uniform read inside a loop is a
// per-lane gather under the loop's mask (with the RSM gathers' hoisting:
// vpl-all -3.4% of a cold 128² frame's shader instructions, callgrind).
#include "common/vpl_record.glsl"

struct VplFalloff {
    float r2_per_area; // r² = A · this: 1/π with u_vpl.disk, else 0
    float near;        // the near clamp, at least 1e-12
};

VplFalloff vpl_falloff_params()
{
    return VplFalloff(u_vpl.disk != 0 ? 1.0 / PI : 0.0, max(u_vpl.near_clamp, 1e-12));
}

float vpl_r2(VplFalloff f, GpuVpl v)
{
    return v.flux.w * f.r2_per_area;
}

float vpl_falloff(VplFalloff f, GpuVpl v, float d2)
{
    return 1.0 / max(d2 + vpl_r2(f, v), f.near);
}

// Stochastic light culling's α_i = 2π·e_max / (E·max I_i) with
// max I_i = max(Φ)/π for a diffuse VPL (Tokuyoshi & Harada 2016); `num`
// is vpl_slc_num(), 2π·e_max/E, read once outside the loops. params.comp's
// ranges and shade.comp's in-loop range test take the same α.
float vpl_slc_num() { return TWO_PI * u_vpl.slc_emax / u_vpl.slc_exposure; }

float vpl_slc_alpha(float num, GpuVpl v)
{
    vec3 phi = v.flux.rgb;
    return num / max(max(phi.r, max(phi.g, phi.b)) / PI, 1e-30);
}

// Φ/π · cosθ_p · cosθ_x (the VPL's radiant intensity toward x times the
// receiver cosine), and the squared distance.
vec3 vpl_intensity_cos(GpuVpl v, vec3 x, vec3 n, out float d2)
{
    vec3 d = x - vpl_position(v);
    d2 = max(dot(d, d), 1e-12);
    float inv = inversesqrt(d2);
    float c = max(0.0, dot(vpl_shading_normal(v), d) * inv) * max(0.0, -dot(n, d) * inv);
    return v.flux.rgb * (c / PI);
}
