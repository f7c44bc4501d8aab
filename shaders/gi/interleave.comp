// gi/interleave.comp — interleaved sampling (Keller & Heidrich 2001;
// Segovia et al. 2006) around the shading in gi/rsm/gather.comp and gi/vpl/shade.comp:
//   MODE_SPLIT  G-buffer → n×m de-interleaved sub-images (pixel (x, y) goes
//               to sub-image (x mod n, y mod m) at (x / n, y / m))
//   MODE_MERGE  the shaded sub-images back to the interleaved layout
//   MODE_BLUR   geometry-aware blur over the n×m window: neighbours whose
//               normal and position agree (thresholds of the interpolation)
#include "shared/gpu_types.h"
#include "common/gbuffer.glsl"
// The n × m pattern, compiled in (src/gi/interleave.c): llvmpipe divides
// by a value it cannot see lane by lane, and runs a window of a constant
// size unrolled.
#ifndef INTERLEAVE_N
#error "gi/interleave.comp needs INTERLEAVE_N and INTERLEAVE_M (src/gi/interleave.c)"
#endif

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = TEX_INPUT) uniform sampler2D u_input; // MERGE: de-interleaved irradiance; BLUR: merged
#if defined(MODE_SPLIT)
layout(rgba32ui, binding = IMG_OUT) uniform writeonly uimage2D o_surface;
#else
layout(rgba32f, binding = IMG_OUT) uniform writeonly image2D o_irradiance;
#endif

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, ivec2(u_frame.width, u_frame.height))))
        return;
    const int n = INTERLEAVE_N, m = INTERLEAVE_M;
    ivec2 sub = ivec2(u_gi.sub_width, u_gi.sub_height);
    ivec2 di = (px % ivec2(n, m)) * sub + px / ivec2(n, m);
#if defined(MODE_SPLIT)
    imageStore(o_surface, di, texelFetch(g_surface, px, 0));
#elif defined(MODE_MERGE)
    imageStore(o_irradiance, px, texelFetch(u_input, di, 0));
#else
    vec3 p, nrm;
    if (!gb_surface(px, p, nrm)) {
        imageStore(o_irradiance, px, vec4(0.0));
        return;
    }
    float max_dist = u_gi.interp_dist * distance(p, u_frame.camera.xyz);
    vec3 sum = vec3(0.0);
    float count = 0.0;
    for (int dy = -m / 2; dy < m - m / 2; dy++)
        for (int dx = -n / 2; dx < n - n / 2; dx++) {
            ivec2 q = px + ivec2(dx, dy);
            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(u_frame.width, u_frame.height))))
                continue;
            vec3 qp, qn;
            if (!gb_surface(q, qp, qn) || dot(nrm, qn) < u_gi.interp_normal || distance(qp, p) > max_dist)
                continue;
            sum += texelFetch(u_input, q, 0).rgb;
            count += 1.0;
        }
    imageStore(o_irradiance, px, vec4(count > 0.0 ? sum / count : vec3(0.0), 1.0));
#endif
}
