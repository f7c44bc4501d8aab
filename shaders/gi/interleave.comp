// gi/interleave.comp — interleaved sampling (Keller & Heidrich 2001;
// Segovia et al. 2006) around the shading in gi/rsm/gather.comp and gi/vpl/shade.comp:
//   MODE_SPLIT  G-buffer → n×m de-interleaved sub-images (pixel (x, y) goes
//               to sub-image (x mod n, y mod m) at (x / n, y / m))
//   MODE_MERGE  the shaded sub-images back to the interleaved layout
//   MODE_BLUR   geometry-aware blur over the n×m window: neighbours whose
//               normal and position agree (thresholds of the interpolation);
//               with DEINTERLEAVED_INPUT it reads the shaded sub-images
//               where MODE_MERGE would have put them (merge and blur in
//               one pass)
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

const int n = INTERLEAVE_N, m = INTERLEAVE_M;

// Where pixel px lies in the de-interleaved layout (sub-images of size sub).
ivec2 di_of(ivec2 px, ivec2 sub) { return (px % ivec2(n, m)) * sub + px / ivec2(n, m); }

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, ivec2(u_frame.width, u_frame.height))))
        return;
    ivec2 sub = ivec2(u_gi.sub_width, u_gi.sub_height);
    ivec2 di = di_of(px, sub);
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
    // The thresholds and the image's size read once: in a loop every
    // uniform read is a per-lane gather on llvmpipe. Each tap is selected,
    // not branched on: a lane's untaken branch runs anyway.
    float max_dist = u_gi.rsm_interp_dist * distance(p, u_frame.camera.xyz);
    float min_cos = u_gi.rsm_interp_normal;
    ivec2 size = ivec2(u_frame.width, u_frame.height);
    vec3 sum = vec3(0.0);
    float count = 0.0;
    for (int dy = -m / 2; dy < m - m / 2; dy++)
        for (int dx = -n / 2; dx < n - n / 2; dx++) {
            ivec2 q = px + ivec2(dx, dy);
            bool inside = all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size));
            q = clamp(q, ivec2(0), size - 1);
            vec3 qp, qn;
            bool ok = gb_surface(q, qp, qn);
            float w = inside && ok && dot(nrm, qn) >= min_cos && distance(qp, p) <= max_dist ? 1.0 : 0.0;
#ifdef DEINTERLEAVED_INPUT
            sum += w * FETCH_NEAREST(u_input, di_of(q, sub)).rgb;
#else
            sum += w * FETCH_NEAREST(u_input, q).rgb;
#endif
            count += w;
        }
    imageStore(o_irradiance, px, vec4(count > 0.0 ? sum / count : vec3(0.0), 1.0));
#endif
}
