// frame/tonemap.frag — radiance × exposure, clamped, sRGB-encoded by the sRGB
// render target. Input: HDR radiance. Output: display-referred colour.
#include "shared/gpu_types.h"
#include "common/math.glsl"

layout(binding = TEX_HDR) uniform sampler2D u_hdr;
layout(location = LOC_TONEMAP_EXPOSURE) uniform float u_exposure;

out vec4 o_color;

void main()
{
    vec3 c = FETCH_NEAREST(u_hdr, ivec2(gl_FragCoord.xy)).rgb * u_exposure;
    o_color = vec4(clamp(c, 0.0, 1.0), 1.0);
}
