// ui/ab_view.frag — the window's image area: the frame, or in the A/B view
// the frame beside (or instead of) a reference image (`rtgi view --compare
// FILE`), or their difference as a heat map. Inputs: the render thread's
// presentation copies of the frame's LDR image and HDR radiance, the
// reference radiance (all bottom-up GL textures, sampled by uv so that a
// reference of another size is stretched). Output: sRGB-encoded colour for the window's
// (linear) default framebuffer.
#include "shared/gpu_types.h"

layout(binding = TEX_HDR) uniform sampler2D u_hdr;
layout(binding = TEX_LDR) uniform sampler2D u_ldr;
layout(binding = TEX_REFERENCE) uniform sampler2D u_reference;
layout(location = LOC_AB_MODE) uniform int u_mode;
layout(location = LOC_AB_SPLIT) uniform float u_split;
layout(location = LOC_AB_EXPOSURE) uniform float u_exposure;
layout(location = LOC_AB_DIFF_SCALE) uniform float u_diff_scale;
layout(location = LOC_AB_REF_DISPLAY) uniform int u_ref_display;

in vec2 v_uv;
out vec4 o_color;

vec3 srgb_encode(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

// Black → red → yellow → white as t goes 0 → 1.
vec3 heat(float t)
{
    t = clamp(t, 0.0, 1.0);
    return clamp(vec3(3.0 * t, 3.0 * t - 1.0, 3.0 * t - 2.0), 0.0, 1.0);
}

void main()
{
    // A display-referred reference (PNG) is already exposed and clamped:
    // it is compared with the frame's clamped exposed radiance. The frame
    // alone (mode 0, also the window without --compare) reads no reference.
    float ref_scale = u_ref_display != 0 ? 1.0 : u_exposure;
    if (u_mode == 3) {
        vec3 ref = texture(u_reference, v_uv).rgb * ref_scale;
        vec3 frame = texture(u_hdr, v_uv).rgb * u_exposure;
        if (u_ref_display != 0)
            frame = clamp(frame, 0.0, 1.0);
        vec3 d = abs(frame - ref);
        o_color = vec4(heat(max(d.r, max(d.g, d.b)) / u_diff_scale), 1.0);
        return;
    }
    bool show_ref = u_mode == 1 || (u_mode == 2 && v_uv.x >= u_split);
    vec3 c = show_ref ? srgb_encode(texture(u_reference, v_uv).rgb * ref_scale)
                      : srgb_encode(texture(u_ldr, v_uv).rgb); // decoded from sRGB by the texture
    if (u_mode == 2 && abs(v_uv.x - u_split) * float(textureSize(u_ldr, 0).x) < 1.0)
        c = vec3(1.0, 0.8, 0.0); // the split line
    o_color = vec4(c, 1.0);
}
