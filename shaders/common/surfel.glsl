// surfel.glsl — a surface point packed in one RGBA32UI texel: the world
// position (xyz: the float bits, exact) and a unit normal in w (octahedral
// map, Cigolle et al. 2014, 15 bits per coordinate: error < 1e-4 rad; bit
// 31 marks a texel that holds a surface): the G-buffer's surface texel
// (the camera-facing normal, common/gbuffer.glsl). RSM texels are packed
// tighter, flux included (common/rsm_texel.glsl).
#ifndef SURFEL_GLSL
#define SURFEL_GLSL

#include "common/packing.glsl"

uvec4 surfel_pack(vec3 position, vec3 normal)
{
    uvec2 q = uvec2(round(clamp(oct_encode(normal) * 0.5 + 0.5, 0.0, 1.0) * 32767.0));
    return uvec4(floatBitsToUint(position), 0x80000000u | (q.y << 15) | q.x);
}

bool surfel_valid(uvec4 s) { return (s.w & 0x80000000u) != 0u; }
vec3 surfel_unpack_position(uvec4 s) { return uintBitsToFloat(s.xyz); }
vec3 surfel_unpack_normal(uvec4 s)
{
    vec2 e = vec2(uvec2(s.w, s.w >> 15) & 0x7fffu) * (1.0 / 32767.0);
    return oct_decode(e * 2.0 - 1.0);
}

#endif
