// rsm_surfel.glsl — the packed RSM texel, so a gather sample costs two
// fetches (issue 11): an RGBA32UI "surfel" texel holding the world position
// (xyz: the float bits, exact) and the normal of the lit side in w
// (octahedral map, Cigolle et al. 2014, 15 bits per coordinate: error
// < 1e-4 rad; bit 31 marks a texel that holds a surface), beside the
// RGBA32F flux texel (Φ rgb, a = the surface area the texel stands for).
#ifndef RSM_SURFEL_GLSL
#define RSM_SURFEL_GLSL

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
    return normalize(n);
}

uvec4 rsm_surfel_pack(vec3 position, vec3 normal)
{
    uvec2 q = uvec2(round(clamp(oct_encode(normal) * 0.5 + 0.5, 0.0, 1.0) * 32767.0));
    return uvec4(floatBitsToUint(position), 0x80000000u | (q.y << 15) | q.x);
}

bool rsm_surfel_valid(uvec4 s) { return (s.w & 0x80000000u) != 0u; }
vec3 rsm_surfel_position(uvec4 s) { return uintBitsToFloat(s.xyz); }
vec3 rsm_surfel_normal(uvec4 s)
{
    vec2 e = vec2(uvec2(s.w, s.w >> 15) & 0x7fffu) / 32767.0;
    return oct_decode(e * 2.0 - 1.0);
}

#endif
