// vpl.glsl — irradiance at x (normal n) from a diffuse virtual point light
// of flux Φ at xp (normal np), SPEC §3 / Dachsbacher & Stamminger 2005:
//   E = Φ · max(0, np·(x − xp)) · max(0, n·(xp − x)) / (π ‖x − xp‖⁴)
// (unnormalised vectors, hence the 4th power). Visibility is ignored.
vec3 vpl_irradiance(vec3 x, vec3 n, vec3 xp, vec3 np, vec3 flux)
{
    vec3 d = x - xp;
    float d2 = max(dot(d, d), 1e-12);
    return flux * (max(0.0, dot(np, d)) * max(0.0, -dot(n, d)) / (PI * d2 * d2));
}

// The same for a VPL that stands for the surface patch of its RSM texel,
// area A, seen as a disk on its axis (gi/vpl/falloff.glsl): 1/d² becomes
// 1/(d² + r2) with r2 = A/π, bounded next to the patch and within
// A/(πd²) of the point's beyond; r2 = 0 is vpl_irradiance.
vec3 vpl_irradiance_disk(vec3 x, vec3 n, vec3 xp, vec3 np, vec3 flux, float r2)
{
    vec3 d = x - xp;
    float d2 = max(dot(d, d), 1e-12);
    return flux * (max(0.0, dot(np, d)) * max(0.0, -dot(n, d)) / (PI * d2 * (d2 + r2)));
}
