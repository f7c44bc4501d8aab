// frame/tonemap.frag — the display transform (common/tonemap.glsl) of the
// HDR radiance. Output: display-referred colour.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/tonemap.glsl"

layout(binding = TEX_HDR) uniform sampler2D u_hdr;
layout(location = LOC_TONEMAP_EXPOSURE) uniform float u_exposure;

out vec4 o_color;

void main()
{
    o_color = tonemap(FETCH_NEAREST(u_hdr, ivec2(gl_FragCoord.xy)).rgb, u_exposure);
}
