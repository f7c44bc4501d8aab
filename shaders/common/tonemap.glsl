// tonemap.glsl — the display transform: radiance × exposure, clamped to
// [0, 1] (tonemap), then sRGB-encoded by srgb_encode. Every pass that
// writes the display image encodes in the shader: the compute passes
// (frame/shade.comp, frame/finish.comp, frame/fxaa.comp), whose image
// stores take no sRGB format, and the forward draw that tone-maps as it
// shades (frame/forward.frag), where the target's conversion cost llvmpipe
// 0.8 ms more than srgb_encode (13.4 against 12.6 ms, pcf_sun.json
// 800×600, one thread). GPUs pay a few instructions either way.
#ifndef TONEMAP_GLSL
#define TONEMAP_GLSL

// The sRGB transfer function (IEC 61966-2-1): 12.92·c below 0.0031308,
// else 1.055·c^(1/2.4) − 0.055, the upper branch as a minimax fit in
// c^(1/2), c^(1/4), c^(1/8) (three square roots) with a largest error of
// 0.052 of an 8-bit step (test_direct srgb_encode_matches_the_standard).
vec3 srgb_encode(vec3 c)
{
    vec3 s1 = sqrt(c), s2 = sqrt(s1), s3 = sqrt(s2);
    vec3 hi = 0.5545159720 * s1 + 0.8999687229 * s2 - 0.4887128487 * s3 + 0.0344295102;
    return mix(12.92 * c, min(hi, vec3(1.0)), greaterThan(c, vec3(0.0031308)));
}

// Display-referred linear colour, alpha 1.
vec4 tonemap(vec3 radiance, float exposure) { return vec4(clamp(radiance * exposure, 0.0, 1.0), 1.0); }

#endif
