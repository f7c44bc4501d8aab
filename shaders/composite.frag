// composite.frag — adds indirect radiance ρ/π · E_indirect · scale to the
// HDR target (additive blend). Input: irradiance from a GI pass.
#include "common/types.glsl"
#include "common/math.glsl"

layout(binding = TEX_GB_ALBEDO) uniform sampler2D g_albedo;
layout(binding = TEX_GI) uniform sampler2D u_irradiance;

out vec4 o_radiance;

void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 e = texelFetch(u_irradiance, px, 0).rgb;
    o_radiance = vec4(texelFetch(g_albedo, px, 0).rgb / PI * e * u_gi.rsm2.w, 1.0);
}
