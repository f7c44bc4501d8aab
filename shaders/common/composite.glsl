// composite.glsl — what a surface returns of the GI technique's result,
// × indirect_scale: the irradiance E in the technique's image, plus its
// specular radiance when it has one. Lambertian surfaces (every surface of
// a scene without GLOSSY) return ρ_d/π · E. Glossy ones (F0 > 0) are shaded
// as if the indirect light arrived evenly over the hemisphere (radiance
// E/π): the diffuse lobe returns ρ_d/π · E · w, w its Fresnel transmission
// for such light (brdf_diffuse_irradiance_weight: the (1 − F) factors the
// direct light and the path tracer apply), and, for techniques without a
// specular image of their own (all but vct), the GGX lobe returns E/π
// times its directional albedo (brdf_specular_albedo), the glossy
// reflection of the bounce light that the reference has too. On Sponza
// 320×180 against one-bounce-novis: rsm relMSE / FLIP / indirect mean
// 0.00304 / 0.0687 / 0.956 with ρ_d/π alone, 0.00308 / 0.0775 / 0.939 with
// w alone, 0.00292 / 0.0608 / 0.971 with both.
// Needs shared/gpu_types.h, common/math.glsl, common/brdf.glsl and
// common/gbuffer.glsl with GBUFFER_MATERIAL.
#ifndef COMPOSITE_GLSL
#define COMPOSITE_GLSL

layout(binding = TEX_GI) uniform sampler2D u_irradiance;
layout(binding = TEX_SPECULAR) uniform sampler2D u_specular;
layout(location = LOC_COMPOSITE_SPECULAR) uniform int u_has_specular;

// The indirect radiance toward the camera at pixel px (material mat; x, n
// its surfel, valid where `surface`).
vec3 composite_indirect(ivec2 px, GbMaterial mat, bool surface, vec3 x, vec3 n)
{
    vec3 e = FETCH_NEAREST(u_irradiance, px).rgb;
    vec3 l = mat.diffuse / PI * e;
#ifdef GLOSSY
    if (any(greaterThan(mat.f0, vec3(0.0))) && surface) {
        float nv = clamp(dot(n, normalize(u_frame.camera.xyz - x)), 0.0, 1.0);
        l *= brdf_diffuse_irradiance_weight(mat.f0, nv);
        if (u_has_specular == 0)
            l += brdf_specular_albedo(mat.f0, mat.roughness, nv) / PI * e;
    }
#endif
    if (u_has_specular != 0)
        l += FETCH_NEAREST(u_specular, px).rgb;
    return l * u_frame.indirect_scale;
}

#endif
