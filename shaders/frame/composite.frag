// frame/composite.frag — adds the GI technique's result to the HDR target
// (additive blend): ρ/π · E · w · indirect_scale from its irradiance image,
// and its specular radiance × indirect_scale when it has one. With GLOSSY
// (the scene has a material with F0 > 0), w is the diffuse lobe's Fresnel
// transmission for irradiance, brdf_diffuse_irradiance_weight (the same
// (1 − F) factors the direct pass and the path tracer apply); without it,
// every surface is Lambertian and w = 1.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#ifdef GLOSSY
#include "common/brdf.glsl"
layout(binding = TEX_GB_POSITION) uniform sampler2D g_position;
layout(binding = TEX_GB_NORMAL) uniform sampler2D g_normal;
layout(binding = TEX_GB_SPECULAR) uniform sampler2D g_specular;
#endif

layout(binding = TEX_GB_ALBEDO) uniform sampler2D g_albedo;
layout(binding = TEX_GI) uniform sampler2D u_irradiance;
layout(binding = TEX_SPECULAR) uniform sampler2D u_specular;
layout(location = LOC_COMPOSITE_SPECULAR) uniform int u_has_specular;

out vec4 o_radiance;

void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 e = texelFetch(u_irradiance, px, 0).rgb;
    vec3 l = texelFetch(g_albedo, px, 0).rgb / PI * e;
#ifdef GLOSSY
    vec3 f0 = texelFetch(g_specular, px, 0).rgb;
    if (any(greaterThan(f0, vec3(0.0)))) {
        vec3 x = texelFetch(g_position, px, 0).xyz;
        vec3 n = texelFetch(g_normal, px, 0).xyz;
        l *= brdf_diffuse_irradiance_weight(f0, dot(n, normalize(u_frame.camera.xyz - x)));
    }
#endif
    if (u_has_specular != 0)
        l += texelFetch(u_specular, px, 0).rgb;
    o_radiance = vec4(l * u_frame.indirect_scale, 1.0);
}
