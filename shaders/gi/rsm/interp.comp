// gi/rsm/interp.comp — screen-space interpolation (Dachsbacher & Stamminger
// 2005, §4): each full-resolution pixel looks at its four surrounding
// low-resolution samples; a sample is usable if its normal and world
// position agree with the pixel's. With three or four usable samples the
// pixel takes their bilinear-weighted mean; otherwise it is appended to the
// list of pixels that get a full gather (SSBO_PIXEL_LIST).
#include "shared/gpu_types.h"
#include "common/gbuffer.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = TEX_INPUT) uniform sampler2D u_lowres;
layout(rgba32f, binding = IMG_OUT) uniform image2D o_irradiance;
// The list: its count, then the arguments of the indirect dispatch of the
// full gathers (one 64-lane group per 64 entries), then the entries. Each
// listed pixel takes the next entry with one atomic: the lanes of a SIMD
// group (a row of 8 pixels of the tile) take theirs in lane order, so
// neighbouring lanes of the full gather still shade neighbouring pixels,
// without the tile's barriers (on llvmpipe three barriers per tile cost a
// fifth of this pass: 960×540, 31 -> 25 ms). The lane whose entry opens a
// group of 64 raises the dispatch's group count.
layout(std430, binding = SSBO_PIXEL_LIST) buffer PixelList { uint list_count; uint groups_x, groups_y, groups_z; uint list[]; };

// Interpolated irradiance of pixel px, or false if it needs a full gather.
bool interpolate(ivec2 px, out vec4 result)
{
    result = vec4(0.0);
    vec3 p, n;
    if (!gb_surface(px, p, n))
        return true;
    int f = u_gi.rsm_interp_factor;
    float max_dist = u_gi.rsm_interp_dist * distance(p, u_frame.camera.xyz);
    vec2 u = (vec2(px) + 0.5) / float(f) - 0.5;
    ivec2 i0 = ivec2(floor(u));
    vec2 t = u - vec2(i0);
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    int usable = 0;
    for (int k = 0; k < 4; k++) {
        ivec2 o = ivec2(k & 1, k >> 1);
        ivec2 s = clamp(i0 + o, ivec2(0), ivec2(u_gi.low_width, u_gi.low_height) - 1);
        ivec2 sp = min(s * f + f / 2, ivec2(u_frame.width, u_frame.height) - 1);
        vec3 q, qn;
        if (!gb_surface(sp, q, qn) || dot(n, qn) < u_gi.rsm_interp_normal || distance(p, q) > max_dist)
            continue;
        float w = (o.x == 1 ? t.x : 1.0 - t.x) * (o.y == 1 ? t.y : 1.0 - t.y) + 1e-4;
        sum += w * texelFetch(u_lowres, s, 0).rgb;
        wsum += w;
        usable++;
    }
    result = vec4(sum / max(wsum, 1e-30), 1.0);
    return usable >= 3;
}

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, ivec2(u_frame.width, u_frame.height))))
        return;
    vec4 e;
    if (interpolate(px, e)) {
        imageStore(o_irradiance, px, e);
        return;
    }
    uint slot = atomicAdd(list_count, 1u);
    if (slot % 64u == 0u)
        atomicMax(groups_x, slot / 64u + 1u);
    list[slot] = uint(px.x) | (uint(px.y) << 16);
}
