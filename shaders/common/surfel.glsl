// surfel.glsl — a surface point packed in one RGBA32UI texel: the world
// position (xyz: the float bits, exact) and a unit normal in w (octahedral
// map, Cigolle et al. 2014, 15 bits per coordinate: error < 1e-4 rad; bit
// 31 marks a texel that holds a surface). The RSM's texel (the lit side's
// normal, beside its RGBA32F flux texel: two fetches per gather sample,
// issue 11) and the G-buffer's surface texel (the camera-facing normal,
// common/gbuffer.glsl) are both one.
#ifndef SURFEL_GLSL
#define SURFEL_GLSL

vec2 oct_encode(vec3 n)
{
    vec2 p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if (n.z < 0.0)
        p = (1.0 - abs(p.yx)) * vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
    return p;
}

vec3 oct_decode(vec2 e)
{
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    float t = max(-n.z, 0.0);
    n.xy -= vec2(n.x >= 0.0 ? t : -t, n.y >= 0.0 ? t : -t);
    return n * inversesqrt(dot(n, n));
}

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
