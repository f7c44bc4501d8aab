// tonemap.glsl — the display transform: radiance × exposure, clamped to
// [0, 1], sRGB-encoded here (srgb_encode) and written as is into the
// SRGB8_ALPHA8 final image (GL_FRAMEBUFFER_SRGB off). The tone-mapping pass
// (frame/tonemap.frag) and the forward draw that tone-maps as it shades
// (frame/forward.frag) both write it.
#ifndef TONEMAP_GLSL
#define TONEMAP_GLSL

// The sRGB transfer function (IEC 61966-2-1): 12.92·c below 0.0031308,
// else 1.055·c^(1/2.4) − 0.055, the upper branch as a minimax fit in
// c^(1/2), c^(1/4), c^(1/8) (three square roots) with a largest error of
// 0.052 of an 8-bit step (test_direct srgb_encode_matches_the_standard).
// llvmpipe's encoding for sRGB targets cost more than a millisecond of an
// 800×600 forward frame (pcf_sun.json, one thread); GPUs pay a few
// instructions.
vec3 srgb_encode(vec3 c)
{
    vec3 s1 = sqrt(c), s2 = sqrt(s1), s3 = sqrt(s2);
    vec3 hi = 0.5545159720 * s1 + 0.8999687229 * s2 - 0.4887128487 * s3 + 0.0344295102;
    return mix(12.92 * c, min(hi, vec3(1.0)), greaterThan(c, vec3(0.0031308)));
}

vec4 tonemap(vec3 radiance, float exposure) { return vec4(srgb_encode(clamp(radiance * exposure, 0.0, 1.0)), 1.0); }

#endif
