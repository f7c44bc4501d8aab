// gi/vpl/metalight_signature.comp — Metalights (Faure & Chang 2010): each VPL's
// contribution to a low-resolution grid of G-buffer samples (u_vpl.signature_w
// × ... pixels spread over the screen), summarised as the contribution-
// weighted screen centroid and the total (luminance of irradiance). The CPU
// groups VPLs with similar signatures into metalights.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "gi/vpl/falloff.glsl"
#include "common/gbuffer.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) readonly buffer CounterBlock { uint counters[]; };
layout(std430, binding = SSBO_SUBSETS) writeonly buffer SignatureBlock { vec4 signatures[]; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= counters[0])
        return;
    ivec2 size = gb_size();
    ivec2 grid = ivec2(u_vpl.signature_w, u_vpl.signature_h);
    vec2 mean_uv = vec2(0.0);
    float total = 0.0;
    VplFalloff fo = vpl_falloff_params();
    for (int sy = 0; sy < grid.y; sy++)
        for (int sx = 0; sx < grid.x; sx++) {
            vec2 uv = (vec2(sx, sy) + 0.5) / vec2(grid);
            ivec2 px = ivec2(uv * vec2(size));
            vec3 p, n;
            if (!gb_surface(px, p, n))
                continue;
            float d2;
            vec3 ic = vpl_intensity_cos(vpls[i], p, n, d2);
            float c = luminance(ic * vpl_falloff(fo, vpls[i], d2));
            mean_uv += c * uv;
            total += c;
        }
    signatures[i] = vec4(total > 0.0 ? mean_uv / total : vec2(2.0), total, 0.0);
}
