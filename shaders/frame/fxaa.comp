// frame/fxaa.comp — FXAA-class post-process anti-aliasing of the tone-mapped
// image, written from the published description of the algorithm (Lottes,
// "FXAA", NVIDIA white paper 2009/2011):
//  1. local contrast: skip pixels whose 4-neighbourhood luma range is below
//     a threshold relative to its brightest luma;
//  2. edge direction from 3×3 second differences (horizontal vs vertical);
//  3. the side of the edge: the neighbour across it with the larger step;
//  4. walk along the edge, on the boundary between the two pixel rows, in
//     both directions until the luma leaves the edge's average by a quarter
//     of its step (growing strides);
//  5. blend: shift the lookup across the edge by how close the pixel is to
//     the nearer end of the edge (0.5 at an end, 0 in the middle), or by a
//     sub-pixel amount from the 3×3 low-pass where that is larger, and take
//     one bilinear sample there.
// A compute pass (pass_fxaa.h), one invocation per pixel.
// Input: the tone-mapped colour (sRGB texture view, read as linear,
// bilinear). Output: the final display colour (IMG_LDR: sRGB-encoded bytes).
#include "shared/gpu_types.h"
#include "common/tonemap.glsl"

layout(local_size_x = SHADE_GROUP, local_size_y = SHADE_GROUP) in;
layout(binding = TEX_LDR) uniform sampler2D u_ldr;
layout(binding = IMG_LDR, rgba8) uniform writeonly image2D u_out;

void write_color(ivec2 px, vec3 c) { imageStore(u_out, px, vec4(srgb_encode(c), 1.0)); }

const float EDGE_THRESHOLD = 0.125;     // min contrast, relative to the local max luma
const float EDGE_THRESHOLD_MIN = 0.0312; // min contrast in dark areas
const float SUBPIXEL = 0.75;            // amount of sub-pixel smoothing
const int SEARCH_STEPS = 10;

// Perceptual luma of linear colour (gamma ≈ 2).
float luma(vec3 c) { return sqrt(dot(c, vec3(0.299, 0.587, 0.114))); }
float luma_at(vec2 uv) { return luma(textureLod(u_ldr, uv, 0.0).rgb); }

float search_stride(int i) { return i < 4 ? 1.0 : i == 4 ? 1.5 : i < 8 ? 2.0 : i == 8 ? 4.0 : 8.0; }

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, imageSize(u_out))))
        return;
    vec2 texel = 1.0 / vec2(textureSize(u_ldr, 0));
    vec2 uv = (vec2(px) + 0.5) * texel; // pixel centre
    vec3 centre = textureLod(u_ldr, uv, 0.0).rgb;
    float m = luma(centre);
    float n = luma_at(uv + vec2(0, texel.y)), s = luma_at(uv - vec2(0, texel.y));
    float e = luma_at(uv + vec2(texel.x, 0)), w = luma_at(uv - vec2(texel.x, 0));
    float lmax = max(m, max(max(n, s), max(e, w)));
    float lmin = min(m, min(min(n, s), min(e, w)));
    float range = lmax - lmin;
    // 1. Not an edge: the pixel as it is.
    if (range < max(EDGE_THRESHOLD_MIN, lmax * EDGE_THRESHOLD)) {
        write_color(px, centre);
        return;
    }
    float ne = luma_at(uv + texel), sw = luma_at(uv - texel);
    float nw = luma_at(uv + vec2(-texel.x, texel.y)), se = luma_at(uv + vec2(texel.x, -texel.y));

    // Sub-pixel aliasing: how far the centre is from its 3×3 low-pass.
    float lowpass = (2.0 * (n + s + e + w) + (ne + nw + se + sw)) / 12.0;
    float sub = clamp(abs(lowpass - m) / range, 0.0, 1.0);
    sub = smoothstep(0.0, 1.0, sub);
    sub = sub * sub * SUBPIXEL;

    // 2. Horizontal edge: luma varies along y (second differences per column).
    float vary_y = abs(nw + sw - 2.0 * w) + 2.0 * abs(n + s - 2.0 * m) + abs(ne + se - 2.0 * e);
    float vary_x = abs(nw + ne - 2.0 * n) + 2.0 * abs(w + e - 2.0 * m) + abs(sw + se - 2.0 * s);
    bool horizontal = vary_y >= vary_x;

    // 3. The side across the edge with the larger step.
    float l_neg = horizontal ? s : w, l_pos = horizontal ? n : e;
    float g_neg = abs(l_neg - m), g_pos = abs(l_pos - m);
    float across = horizontal ? texel.y : texel.x;
    float side_luma = l_pos;
    if (g_neg >= g_pos) {
        across = -across;
        side_luma = l_neg;
    }
    float edge_avg = 0.5 * (m + side_luma);
    float threshold = 0.25 * max(g_neg, g_pos);

    // 4. Walk both ways along the boundary between the pixel and that side.
    vec2 on_edge = uv + (horizontal ? vec2(0.0, 0.5 * across) : vec2(0.5 * across, 0.0));
    vec2 along = horizontal ? vec2(texel.x, 0.0) : vec2(0.0, texel.y);
    vec2 p1 = on_edge - along, p2 = on_edge + along;
    float d1 = luma_at(p1) - edge_avg, d2 = luma_at(p2) - edge_avg;
    bool done1 = abs(d1) >= threshold, done2 = abs(d2) >= threshold;
    for (int i = 1; i < SEARCH_STEPS && !(done1 && done2); i++) {
        if (!done1) {
            p1 -= along * search_stride(i);
            d1 = luma_at(p1) - edge_avg;
            done1 = abs(d1) >= threshold;
        }
        if (!done2) {
            p2 += along * search_stride(i);
            d2 = luma_at(p2) - edge_avg;
            done2 = abs(d2) >= threshold;
        }
    }

    // 5. Offset across the edge from the distance to its nearer end.
    float dist1 = horizontal ? uv.x - p1.x : uv.y - p1.y;
    float dist2 = horizontal ? p2.x - uv.x : p2.y - uv.y;
    bool nearer1 = dist1 < dist2;
    float offset = 0.5 - min(dist1, dist2) / (dist1 + dist2);
    // Only where the edge's end lies on the other side of the average than
    // the centre does (else the pixel is not on the jagged step).
    bool centre_below = m < edge_avg;
    bool end_below = (nearer1 ? d1 : d2) < 0.0;
    float edge_offset = end_below != centre_below ? offset : 0.0;
    float f = max(edge_offset, sub);
    vec2 at = uv + (horizontal ? vec2(0.0, f * across) : vec2(f * across, 0.0));
    write_color(px, textureLod(u_ldr, at, 0.0).rgb);
}
