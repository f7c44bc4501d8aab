/* brdf.h — the one BRDF of rtgi (SPEC §1b), in C for the path tracer and
 * the tests; shaders/common/brdf.glsl is the same code in GLSL, and
 * tests/test_brdf.c checks that both give the same values to 1e-5.
 *
 *   f(v, l) = T·ρ_d/π + D·V·F(v·h)
 *   T   = (1 − F(n·v))(1 − F(n·l)) / (1 − F0)          (what enters the diffuse base)
 *   ρ_d = (1 − metallic)·base colour                 (diffuse albedo)
 *   F(c) = F0 + (F90 − F0)(1 − c)^5                   (Schlick)
 *   F0  = mix(0.04·specular, base colour, metallic), F90 = min(1, 50·max(F0))
 *   D   = α² / (π ((n·h)²(α² − 1) + 1)²)              (GGX / Trowbridge–Reitz)
 *   V   = G2 / (4 n·l n·v), G2 height-correlated Smith (Heitz 2014)
 *   α   = roughness², roughness clamped to ≥ BRDF_MIN_ROUGHNESS
 *
 * T is the (1 − F) of SPEC §1b taken symmetrically: with 1 − F(v·h), a
 * white dielectric reflects up to 6% more than it receives (the diffuse
 * lobe gives up less than the specular one takes, measured by test_brdf);
 * the product of the two directions' transmissions, normalised to 1 at
 * normal incidence, keeps f reciprocal and ∫ f cos ≤ 1.
 * F90 = min(1, 50·max(F0)) is Filament's rule: 1 for every real dielectric
 * (F0 = 0.04) and metal, 0 when F0 = 0, so a material with specular 0 and
 * metallic 0 (the built-in Cornell surfaces, OBJ materials) is exactly
 * Lambertian, f = ρ/π, as before glossy materials existed.
 * Vectors are unit, in any frame, with n the shading normal; f = 0 for l
 * below the surface, and the specular lobe is 0 for v below it (a shading
 * normal may face away from the viewer near silhouettes). */
#ifndef RTGI_BRDF_H
#define RTGI_BRDF_H

#include <cglm/cglm.h>
#include <stdbool.h>

#define BRDF_MIN_ROUGHNESS 0.03f /* α ≥ 9e-4: keeps D finite in float */
#define BRDF_DIELECTRIC_F0 0.04f

/* What shading needs at a surface point (the G-buffer holds the same). */
typedef struct BrdfSurface {
    vec3 diffuse;    /* ρ_d = (1 − metallic)·base colour */
    vec3 f0;         /* Fresnel reflectance at normal incidence */
    float roughness; /* perceptual (glTF); α = roughness² */
} BrdfSurface;

/* From the glTF parameters: base colour (linear), metallic, roughness, and
 * the dielectric specular weight (F0 = 0.04·specular for metallic 0). */
void brdf_surface(const vec3 base, float metallic, float roughness, float specular, BrdfSurface *out);

float brdf_alpha(float roughness);
/* The diffuse lobe's factor T from F(n·v), F(n·l) and F0 of one channel
 * (0 where F0 = 1: nothing enters). */
float brdf_diffuse_transmission(float fv, float fl, float f0);
/* What the diffuse lobe returns of irradiance E, as a factor w on ρ_d/π·E,
 * for light arriving with uniform radiance over the hemisphere:
 * w = (1 − F(n·v))(1 − F̄)/(1 − F0) per channel, F̄ = F0 + (F90 − F0)/21 the
 * cosine-weighted mean of Schlick's F(n·l) (∫(1−μ)⁵2μ dμ = 1/21); 1 where
 * F0 = 0 (Lambertian), 0 where F0 = 1. The composite weighs the GI
 * techniques' irradiance with it, as the direct pass weighs each light
 * with T. */
void brdf_diffuse_irradiance_weight(const vec3 f0, float n_dot_v, vec3 out);
/* Directional albedo of this GGX lobe, ∫ f_s cosθ dω = F0·A + F90·B (the
 * split-sum idea of Karis 2013, with our own table: his fits are for
 * another masking term and were 13–21% low for metals at roughness
 * 0.25–0.5 here). A and B for BRDF_ALBEDO_N² values of (n·v, perceptual
 * roughness) on a grid that holds both ends, computed once per process by
 * importance-sampling the lobe (brdf_albedo_table, row j = roughness);
 * brdf_specular_albedo interpolates bilinearly, as the GPU's linear filter
 * does with the table uploaded as an RG32F texture (TEX_BRDF_ALBEDO,
 * common/brdf.glsl). */
#define BRDF_ALBEDO_N 32
#define BRDF_ALBEDO_SAMPLES 256
const float (*brdf_albedo_table(void))[2];
void brdf_specular_albedo(const vec3 f0, float roughness, float n_dot_v, vec3 out);
/* Schlick's F90 for this F0: min(1, 50·max(F0)) (0 for F0 = 0: Lambertian). */
float brdf_f90(const vec3 f0);
/* Schlick Fresnel with F90 = min(1, 50·max(F0)). */
void brdf_fresnel(const vec3 f0, float cos_theta, vec3 out);
/* GGX normal distribution for cos θ_h = n·h. */
float brdf_ggx_d(float n_dot_h, float alpha);
/* Smith Λ for a direction at cos θ = c from the normal. */
float brdf_smith_lambda(float c, float alpha);
/* Smith G1 (masking of one direction). */
float brdf_smith_g1(float c, float alpha);
/* Height-correlated visibility V = G2/(4 n·l n·v). */
float brdf_smith_v(float n_dot_v, float n_dot_l, float alpha);

/* f(v, l) (without the cosine) split into its lobes; either output may be NULL. */
void brdf_eval_lobes(const BrdfSurface *s, const vec3 n, const vec3 v, const vec3 l, vec3 diffuse, vec3 specular);
/* f(v, l) = diffuse + specular lobe. */
void brdf_eval(const BrdfSurface *s, const vec3 n, const vec3 v, const vec3 l, vec3 out);

/* ---- Sampling (path tracer): local frame, z = normal ---- */

/* GGX visible normal for view wo (wo.z > 0), Heitz 2018 "Sampling the GGX
 * Distribution of Visible Normals"; the density of h is
 * brdf_vndf_pdf(wo, h) = G1(wo)·max(0, wo·h)·D(h) / wo.z. */
void brdf_sample_vndf(const vec3 wo, float alpha, float u1, float u2, vec3 h);
float brdf_vndf_pdf(const vec3 wo, const vec3 h, float alpha);
/* Solid-angle density of wi = reflect(−wo, h) under VNDF sampling:
 * vndf_pdf / (4 wo·h). */
float brdf_spec_pdf(const vec3 wo, const vec3 wi, float alpha);

/* The lobe mixture the path tracer samples: specular with probability
 * brdf_spec_prob (the luminance of F(n·v) against that of the diffuse
 * reflectance), cosine-weighted diffuse otherwise. */
float brdf_spec_prob(const BrdfSurface *s, float n_dot_v);
/* Samples wi (local frame) for wo (wo.z > 0); false if the sample falls
 * below the surface. u0 picks the lobe, (u1, u2) the direction. */
bool brdf_sample(const BrdfSurface *s, const vec3 wo, float u0, float u1, float u2, vec3 wi);
/* brdf_sample with the specular probability p = brdf_spec_prob(s, wo[2])
 * given (the path tracer computes it once per surface point). */
bool brdf_sample_p(const BrdfSurface *s, const vec3 wo, float p, float u0, float u1, float u2, vec3 wi);
/* Density of brdf_sample's wi (local frame). */
float brdf_pdf(const BrdfSurface *s, const vec3 wo, const vec3 wi);
/* brdf_eval and brdf_pdf in one (local frame, n = +z), sharing the half
 * vector and D: f(wo, wi) and the density of wi, with p =
 * brdf_spec_prob(s, wo[2]). Equal to the two apart up to rounding
 * (test_brdf). */
void brdf_eval_pdf(const BrdfSurface *s, const vec3 wo, const vec3 wi, float p, vec3 f, float *pdf);

#endif
