// brdf.glsl — the one BRDF of rtgi, identical to src/core/brdf.c (see brdf.h for
// the formulas); tests/test_brdf.c checks both agree to 1e-5. Needs
// common/math.glsl.
//   f(v, l) = T·ρ_d/π + D·V·F(v·h), T = (1 − F(n·v))(1 − F(n·l)) / (1 − F0),
//   F Schlick with F90 = min(1, 50·max(F0)),
//   D GGX, V height-correlated Smith, α = max(roughness, 0.03)².
// The G-buffer's specular attachment holds F0 (rgb) and the perceptual
// roughness (a); its albedo attachment holds ρ_d = (1 − metallic)·base.

const float BRDF_MIN_ROUGHNESS = 0.03;
const float BRDF_DIELECTRIC_F0 = 0.04;

// Perceptual (glTF) roughness → GGX α.
float brdf_alpha(float roughness)
{
    float r = max(roughness, BRDF_MIN_ROUGHNESS);
    return r * r;
}

// ρ_d and F0 from the glTF parameters (specular: dielectric weight, F0 = 0.04·specular).
void brdf_surface(vec3 base, float metallic, float specular, out vec3 diffuse, out vec3 f0)
{
    diffuse = (1.0 - metallic) * base;
    f0 = (1.0 - metallic) * BRDF_DIELECTRIC_F0 * specular + metallic * base;
}

// Schlick's F90 for this F0: min(1, 50·max(F0)) (brdf.h).
float brdf_f90(vec3 f0) { return min(1.0, 50.0 * max(f0.r, max(f0.g, f0.b))); }

// Schlick Fresnel, F90 = min(1, 50·max(F0)).
vec3 brdf_fresnel(vec3 f0, float cos_theta)
{
    float f90 = brdf_f90(f0);
    float m = 1.0 - clamp(cos_theta, 0.0, 1.0);
    float m5 = m * m * m * m * m;
    return f0 + (vec3(f90) - f0) * m5;
}

// GGX D from cos²θh and sin²θh given apart (no cancellation near the peak).
float brdf_ggx_d_cs(float c2, float s2, float alpha)
{
    float a2 = alpha * alpha;
    float t = c2 * a2 + s2;
    return a2 / (PI * t * t);
}

// The diffuse lobe's T = (1 − F(n·v))(1 − F(n·l)) / (1 − F0) per channel (0 where F0 = 1).
vec3 brdf_diffuse_transmission(vec3 fv, vec3 fl, vec3 f0)
{
    vec3 t;
    for (int c = 0; c < 3; c++)
        t[c] = f0[c] < 1.0 - 1e-4 ? (1.0 - fv[c]) * (1.0 - fl[c]) / (1.0 - f0[c]) : 0.0;
    return t;
}

// What the diffuse lobe returns of irradiance E as a factor on ρ_d/π·E, for
// uniform incident radiance: (1 − F(n·v))(1 − F̄)/(1 − F0), F̄ = F0 + (F90 − F0)/21
// (brdf.h); 1 where F0 = 0.
vec3 brdf_diffuse_irradiance_weight(vec3 f0, float n_dot_v)
{
    float f90 = brdf_f90(f0);
    return brdf_diffuse_transmission(brdf_fresnel(f0, n_dot_v), f0 + (vec3(f90) - f0) / 21.0, f0);
}

// Directional albedo of the GGX lobe, ∫ f_s cosθ dω = F0·A + F90·B: what
// the lobe returns of light that arrives evenly from the hemisphere. A and
// B from the table src/core/brdf.c computes for this BRDF (brdf_albedo_table,
// bound at TEX_BRDF_ALBEDO by the passes that use it: x = n·v, y =
// perceptual roughness on a grid holding both ends: texel centre i is
// i/(N − 1); linear filtering).
layout(binding = TEX_BRDF_ALBEDO) uniform sampler2D u_brdf_albedo;

vec3 brdf_specular_albedo(vec3 f0, float roughness, float n_dot_v)
{
    vec2 n = vec2(textureSize(u_brdf_albedo, 0));
    vec2 uv = (clamp(vec2(n_dot_v, roughness), 0.0, 1.0) * (n - 1.0) + 0.5) / n;
    vec2 ab = textureLod(u_brdf_albedo, uv, 0.0).rg;
    float f90 = brdf_f90(f0);
    return f0 * ab.x + vec3(f90 * ab.y);
}

float brdf_ggx_d(float n_dot_h, float alpha)
{
    return brdf_ggx_d_cs(n_dot_h * n_dot_h, max(0.0, 1.0 - n_dot_h * n_dot_h), alpha);
}

// Height-correlated Smith visibility G2 / (4 n·l n·v).
float brdf_smith_v(float nv, float nl, float alpha)
{
    float a2 = alpha * alpha;
    float gv = nl * sqrt(nv * nv * (1.0 - a2) + a2);
    float gl = nv * sqrt(nl * nl * (1.0 - a2) + a2);
    return 0.5 / (gv + gl);
}

// f(v, l) split into its lobes (without the cosine); zero for l below the
// surface, no specular lobe for v below it.
void brdf_eval_lobes(vec3 diffuse_albedo, vec3 f0, float roughness, vec3 n, vec3 v, vec3 l,
                     out vec3 diffuse, out vec3 specular)
{
    float nv = dot(n, v), nl = dot(n, l);
    diffuse = vec3(0.0);
    specular = vec3(0.0);
    if (nl <= 0.0)
        return;
    vec3 h = normalize(v + l);
    float nh = max(dot(n, h), 0.0), vh = max(dot(v, h), 0.0);
    vec3 f = brdf_fresnel(f0, vh);
    float a = brdf_alpha(roughness);
    vec3 nxh = cross(n, h);
    float dv = nv > 0.0 ? brdf_ggx_d_cs(nh * nh, dot(nxh, nxh), a) * brdf_smith_v(nv, nl, a) : 0.0;
    diffuse = brdf_diffuse_transmission(brdf_fresnel(f0, nv), brdf_fresnel(f0, nl), f0) * diffuse_albedo / PI;
    specular = f * dv;
}

vec3 brdf_eval(vec3 diffuse_albedo, vec3 f0, float roughness, vec3 n, vec3 v, vec3 l)
{
    vec3 d, s;
    brdf_eval_lobes(diffuse_albedo, f0, roughness, n, v, l, d, s);
    return d + s;
}
