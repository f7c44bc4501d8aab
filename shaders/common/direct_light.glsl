// direct_light.glsl — the radiance one light (u_light, bound by
// light_stage_bind_shadow) reflects toward the viewer, with the BRDF of
// common/brdf.glsl (Lambert + GGX; Lambertian surfaces have F0 = 0):
// f · irradiance from the light model · shadow visibility. Deferred
// (frame/shade.comp, from the G-buffer) and forward (frame/forward.frag,
// from the scene's interpolants) shading both call direct_light.
// Quad lights (u_area_light = AREA_LIGHT_EXACT and a size > 0): the diffuse
// lobe takes the polygon's exact unoccluded irradiance (Lambert's formula,
// clipped to the horizon), the specular lobe a quadrature over the
// rectangle (quad_specular); both times the shadow-map visibility toward
// the light's centre. AREA_LIGHT_POINT keeps the point at the centre with
// I(θ) = L·A·cosθ. DIRECT_DIFFUSE_ONLY (no material of the scene has
// F0 > 0, pass_direct.c) drops the GGX code.
// Needs shared/gpu_types.h, common/math.glsl, common/brdf.glsl,
// common/lights.glsl and common/shadow.glsl.
#ifndef DIRECT_LIGHT_GLSL
#define DIRECT_LIGHT_GLSL

layout(location = LOC_DIRECT_AREA_LIGHT) uniform int u_area_light;

// Specular radiance at x (normal n, view v) from quad light l of radiance
// L: the midpoint rule over QUAD_SPEC_CELLS² cells of the rectangle,
//   Σ f_s(v, ω_k) L cos θ_x cos θ_l / r² A_cell,
// with the GGX lobe widened by the angular size of a cell (α'² = α² +
// (½·cell/r)², energy kept by (α/α')², as Karis 2013 does for sphere
// lights) so that a lobe narrower than a cell is not missed between cells.
// f0, roughness as brdf_eval's.
const int QUAD_SPEC_CELLS = 8;

vec3 quad_specular(GpuLight l, vec3 radiance, vec3 x, vec3 n, vec3 v, vec3 f0, float roughness)
{
    vec3 c = l.position_type.xyz, nl = l.direction_width.xyz, u = l.quad_u.xyz, w = l.quad_v.xyz;
    float cell_area = l.quad_v.w / float(QUAD_SPEC_CELLS * QUAD_SPEC_CELLS), cell = sqrt(cell_area);
    float a = brdf_alpha(roughness), nv = dot(n, v);
    vec3 sum = vec3(0.0);
    for (int i = 0; i < QUAD_SPEC_CELLS; i++)
        for (int j = 0; j < QUAD_SPEC_CELLS; j++) {
            vec2 st = (vec2(i, j) + 0.5) / float(QUAD_SPEC_CELLS) - 0.5;
            vec3 d = c + st.x * u + st.y * w - x;
            float r2 = dot(d, d);
            vec3 ls = d * inversesqrt(r2);
            float cos_l = -dot(ls, nl), cos_x = dot(n, ls);
            if (cos_l <= 0.0 || cos_x <= 0.0)
                continue;
            float spread = 0.5 * cell * inversesqrt(r2);
            float a2 = sqrt(a * a + spread * spread);
            vec3 h = normalize(v + ls), nxh = cross(n, h);
            float nh = max(dot(n, h), 0.0);
            float dv = brdf_ggx_d_cs(nh * nh, dot(nxh, nxh), a2) * (a * a) / (a2 * a2) * brdf_smith_v(nv, cos_x, a);
            sum += brdf_fresnel(f0, max(dot(v, h), 0.0)) * dv * cos_x * cos_l / r2;
        }
    return sum * radiance * cell_area;
}

// Radiance toward v from surface point x (unit normal n facing the viewer)
// with diffuse albedo ρ_d, Schlick F0 and perceptual roughness; `pixel`
// turns the soft-shadow filters' disks.
vec3 direct_light(vec3 x, vec3 n, vec3 v, vec3 albedo, vec3 f0, float roughness, vec2 pixel)
{
    vec3 l;
    vec3 e = light_irradiance(u_light, x, n, l);
    vec3 radiance = vec3(0.0);
    bool polygon = light_type(u_light) == LIGHT_QUAD && u_area_light == AREA_LIGHT_EXACT &&
                   u_light.quad_v.w > 0.0;
#ifdef DIRECT_DIFFUSE_ONLY
    bool glossy = false;
#else
    bool glossy = max(f0.r, max(f0.g, f0.b)) > 0.0;
#endif
    if (polygon) {
        // One-sided: nothing behind the emitting plane.
        vec3 lc = u_light.position_type.xyz;
        if (dot(x - lc, u_light.direction_width.xyz) > 0.0) {
            vec3 radiance_l = u_light.color.rgb / u_light.quad_v.w; // L = (L·A) / A
            vec3 fvec = quad_vector(u_light, x, n, l);
            vec3 e_poly = radiance_l * dot(fvec, n);
            // The diffuse lobe's Fresnel transmission toward the polygon's
            // mean light direction (the vector irradiance's).
            float nl_mean = dot(n, fvec) * inversesqrt(max(dot(fvec, fvec), 1e-30));
            vec3 t = brdf_diffuse_transmission(brdf_fresnel(f0, dot(n, v)), brdf_fresnel(f0, nl_mean), f0);
            vec3 lit = t * albedo / PI * e_poly;
            if (glossy && dot(n, v) > 0.0)
                lit += quad_specular(u_light, radiance_l, x, n, v, f0, roughness);
            if (max(lit.r, max(lit.g, lit.b)) > 0.0)
                radiance = lit * shadow_visibility(x, n, l, pixel);
        }
    } else if (max(e.r, max(e.g, e.b)) > 0.0) {
        vec3 f = glossy ? brdf_eval(albedo, f0, roughness, n, v, l) : albedo / PI;
        radiance = f * e * shadow_visibility(x, n, l, pixel);
    }
    return radiance;
}

#endif
