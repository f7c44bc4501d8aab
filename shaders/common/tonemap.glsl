// tonemap.glsl — the display transform: radiance × exposure, clamped to
// [0, 1]; the sRGB render target encodes it. The tone-mapping pass
// (frame/tonemap.frag) and the forward draw that tone-maps as it shades
// (frame/forward.frag) both write it.
#ifndef TONEMAP_GLSL
#define TONEMAP_GLSL

vec4 tonemap(vec3 radiance, float exposure) { return vec4(clamp(radiance * exposure, 0.0, 1.0), 1.0); }

#endif
