// frame/direct.frag — deferred direct shading of one light: Lambert f = ρ/π,
// irradiance from the light model, shadow visibility; plus emitted
// radiance when u_add_emission is set (once per frame). Additive blend.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/lights.glsl"
#include "common/shadow.glsl"

layout(binding = TEX_GB_POSITION) uniform sampler2D g_position;
layout(binding = TEX_GB_NORMAL) uniform sampler2D g_normal;
layout(binding = TEX_GB_ALBEDO) uniform sampler2D g_albedo;
layout(binding = TEX_GB_EMISSION) uniform sampler2D g_emission;
layout(location = LOC_DIRECT_EMISSION) uniform int u_add_emission;

out vec4 o_radiance;

void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 p = texelFetch(g_position, px, 0);
    if (p.w == 0.0)
        discard;
    vec3 x = p.xyz;
    vec3 n = texelFetch(g_normal, px, 0).xyz;
    vec3 albedo = texelFetch(g_albedo, px, 0).rgb;
    vec3 l;
    vec3 e = light_irradiance(u_light, x, n, l);
    vec3 radiance = vec3(0.0);
    if (max(e.r, max(e.g, e.b)) > 0.0)
        radiance = albedo / PI * e * shadow_visibility(x, n, l, gl_FragCoord.xy);
    if (u_add_emission != 0)
        radiance += texelFetch(g_emission, px, 0).rgb;
    o_radiance = vec4(radiance, 1.0);
}
