// frame/composite.frag — adds the GI technique's result to the HDR target
// (additive blend): ρ/π · E · w · indirect_scale from its irradiance image,
// and its specular radiance × indirect_scale when it has one. With GLOSSY
// (the scene has a material with F0 > 0), w is the diffuse lobe's Fresnel
// transmission for irradiance, brdf_diffuse_irradiance_weight (the same
// (1 − F) factors the direct pass and the path tracer apply); without it,
// every surface is Lambertian and w = 1.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/brdf.glsl"
#define GBUFFER_MATERIAL
#include "common/gbuffer.glsl"

layout(binding = TEX_GI) uniform sampler2D u_irradiance;
layout(binding = TEX_SPECULAR) uniform sampler2D u_specular;
layout(location = LOC_COMPOSITE_SPECULAR) uniform int u_has_specular;

out vec4 o_radiance;

void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 e = texelFetch(u_irradiance, px, 0).rgb;
    GbMaterial mat = gb_material(px);
    vec3 l = mat.diffuse / PI * e;
#ifdef GLOSSY
    vec3 x, n;
    if (any(greaterThan(mat.f0, vec3(0.0))) && gb_surface(px, x, n))
        l *= brdf_diffuse_irradiance_weight(mat.f0, dot(n, normalize(u_frame.camera.xyz - x)));
#endif
    if (u_has_specular != 0)
        l += texelFetch(u_specular, px, 0).rgb;
    o_radiance = vec4(l * u_frame.indirect_scale, 1.0);
}
