// temporal/accumulate.comp — temporal accumulation of the indirect
// irradiance (src/frame/pass_temporal.c, `--temporal on`). Per pixel with
// a surface:
//   1. its world position (the G-buffer's, exact) projected by the last
//      frame's camera: where it was on screen (the motion vector);
//   2. the last frame's accumulated irradiance there, bilinear over the
//      four texels around it, each kept only where the last frame's
//      G-buffer held the same surface: its position on this pixel's
//      tangent plane (within u_params.z of the distance to the camera:
//      depth) and its normal within ~25° (disocclusion rejection; a moved
//      object's pixels find no match and start again);
//   3. that history clamped to this frame's 3×3 neighbourhood, mean ± γσ
//      within its min and max (variance clipping): a light that moved
//      changes the neighbourhood, and the history cannot lag behind it by
//      more than the noise (u_params.w = γ; 0: no clamp, for measuring:
//      --temporal-clamp off);
//   4. blended with this frame's value by α = max(1 / (frames + 1), α_min)
//      (a running mean while it builds up, then an exponential one).
// Out (IMG_OUT): rgb the accumulated irradiance, a the frames it holds.
#include "shared/gpu_types.h"
#include "common/gbuffer.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = TEX_GI) uniform sampler2D u_current;
layout(binding = TEX_TEMPORAL_HISTORY) uniform sampler2D u_history;
layout(binding = TEX_TEMPORAL_SURFACE) uniform usampler2D u_prev_surface;
layout(binding = IMG_OUT, rgba32f) uniform writeonly image2D o_out;
layout(location = LOC_TEMPORAL_PREV_VIEW_PROJ) uniform mat4 u_prev_view_proj;
layout(location = LOC_TEMPORAL_PARAMS) uniform vec4 u_params;

void main()
{
    ivec2 size = gb_size(), px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, size)))
        return;
    vec3 cur = FETCH_NEAREST(u_current, px).rgb;
    vec3 x, n;
    if (!gb_surface(px, x, n)) {
        imageStore(o_out, px, vec4(cur, 0.0));
        return;
    }
    // This frame's neighbourhood: surfaces only (the background holds no light).
    vec3 m1 = vec3(0.0), m2 = vec3(0.0), lo = cur, hi = cur;
    float count = 0.0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            ivec2 q = clamp(px + ivec2(dx, dy), ivec2(0), size - 1);
            vec3 y;
            if (!gb_position(q, y))
                continue;
            vec3 c = FETCH_NEAREST(u_current, q).rgb;
            m1 += c;
            m2 += c * c;
            lo = min(lo, c);
            hi = max(hi, c);
            count += 1.0;
        }
    vec3 mean = m1 / count, sigma = sqrt(max(m2 / count - mean * mean, vec3(0.0)));
    vec3 box_lo = max(lo, mean - u_params.w * sigma), box_hi = min(hi, mean + u_params.w * sigma);

    vec4 out_value = vec4(cur, 1.0);
    vec4 clip = u_prev_view_proj * vec4(x, 1.0);
    if (u_params.y > 0.5 && clip.w > 0.0) {
        vec2 p = (clip.xy / clip.w * 0.5 + 0.5) * vec2(size) - 0.5;
        ivec2 base = ivec2(floor(p));
        vec2 f = p - vec2(base);
        float tolerance = u_params.z * distance(u_frame.camera.xyz, x);
        vec4 sum = vec4(0.0);
        float weight = 0.0;
        for (int k = 0; k < 4; k++) {
            ivec2 o = ivec2(k & 1, k >> 1), q = base + o;
            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)))
                continue;
            uvec4 s = FETCH_NEAREST(u_prev_surface, q);
            if (!surfel_valid(s))
                continue;
            vec3 xp = surfel_unpack_position(s), np = surfel_unpack_normal(s);
            if (abs(dot(xp - x, n)) > tolerance || dot(np, n) < 0.9)
                continue;
            vec2 b = mix(vec2(1.0) - f, f, vec2(o));
            float w = b.x * b.y;
            sum += w * FETCH_NEAREST(u_history, q);
            weight += w;
        }
        if (weight > 1e-3) {
            vec4 h = sum / weight;
            float frames = h.a;
            float alpha = max(1.0 / (frames + 1.0), u_params.x);
            vec3 hist = u_params.w > 0.0 ? clamp(h.rgb, box_lo, box_hi) : h.rgb;
            out_value = vec4(mix(hist, cur, alpha), min(frames + 1.0, 1.0 / u_params.x));
        }
    }
    imageStore(o_out, px, out_value);
}
