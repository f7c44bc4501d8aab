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
