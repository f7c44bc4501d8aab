// vpl.glsl — irradiance at x (normal n) from a diffuse virtual point light
// of flux Φ at xp (normal np), SPEC §3 / Dachsbacher & Stamminger 2005:
//   E = Φ · max(0, np·(x − xp)) · max(0, n·(xp − x)) / (π ‖x − xp‖⁴)
// (unnormalised vectors, hence the 4th power). Visibility is ignored.
// Requires PI (common/math.glsl).
#ifndef VPL_GLSL
#define VPL_GLSL
vec3 vpl_irradiance(vec3 x, vec3 n, vec3 xp, vec3 np, vec3 flux)
{
    vec3 d = x - xp;
    float d2 = max(dot(d, d), 1e-12);
    return flux * (max(0.0, dot(np, d)) * max(0.0, -dot(n, d)) / (PI * d2 * d2));
}

// The same for a VPL that stands for the surface patch of its RSM texel,
// area A, seen as a disk on its axis (gi/vpl/falloff.glsl): 1/d² becomes
// 1/(d² + r2) with r2 = A/π, bounded next to the patch and within
// A/(πd²) of the point's beyond; r2 = 0 is vpl_irradiance. Here r2 is
// given as a fraction r2_num / r2_den (r2_den > 0), so that a caller whose
// area is itself a quotient (an RSM texel's, common/rsm_texel.glsl) pays
// for one division: E = Φ·cos·cos·r2_den / (π d² (d² r2_den + r2_num)).
vec3 vpl_irradiance_disk_fraction(vec3 x, vec3 n, vec3 xp, vec3 np, vec3 flux, float r2_num, float r2_den)
{
    vec3 d = x - xp;
    float d2 = max(dot(d, d), 1e-12);
    return flux * (max(0.0, dot(np, d)) * max(0.0, -dot(n, d)) * r2_den / (PI * d2 * (d2 * r2_den + r2_num)));
}

vec3 vpl_irradiance_disk(vec3 x, vec3 n, vec3 xp, vec3 np, vec3 flux, float r2)
{
    return vpl_irradiance_disk_fraction(x, n, xp, np, flux, r2, 1.0);
}

#endif
