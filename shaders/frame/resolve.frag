// frame/resolve.frag — supersampling resolve: the box-filtered mean of this
// pixel's N×N block of the supersampled radiance (pass_resolve.h).
#include "shared/gpu_types.h"

layout(binding = TEX_HDR) uniform sampler2D u_hdr;
layout(location = LOC_RESOLVE_FACTOR) uniform int u_factor;

out vec4 o_radiance;

void main()
{
    ivec2 base = ivec2(gl_FragCoord.xy) * u_factor;
    vec3 sum = vec3(0.0);
    for (int y = 0; y < u_factor; y++)
        for (int x = 0; x < u_factor; x++)
            sum += texelFetch(u_hdr, base + ivec2(x, y), 0).rgb;
    o_radiance = vec4(sum / float(u_factor * u_factor), 1.0);
}
