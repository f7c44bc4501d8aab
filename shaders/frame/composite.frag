// frame/composite.frag — adds the GI technique's result to the HDR target
// (additive blend): ρ/π · E · indirect_scale from its irradiance image, and
// its specular radiance × indirect_scale when it has one.
#include "shared/gpu_types.h"
#include "common/math.glsl"

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
    if (u_has_specular != 0)
        l += texelFetch(u_specular, px, 0).rgb;
    o_radiance = vec4(l * u_frame.indirect_scale, 1.0);
}
