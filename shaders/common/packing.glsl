// packing.glsl — compact encodings shared by the packed texels (the
// G-buffer's, common/gbuffer.glsl and common/surfel.glsl; the RSM's,
// common/rsm_texel.glsl).
//   octahedral unit vectors (Cigolle et al. 2014): oct_encode maps a unit
//     vector to [-1, 1]², oct_decode maps back; the texels quantize it;
//     pack_oct16/unpack_oct16 at 16 bits per coordinate in one uint
//     (error < 5e-5 rad: the RSM texel's and the VPL's normal)
//   RGB9E5 (EXT_texture_shared_exponent, GL 4.5 §8.5.2: 9-bit mantissas,
//     one exponent, bias 15): non-negative colours from 2^-15 (full
//     precision; down to 2^-24 with fewer bits) to 65408, every channel
//     within 2^-9 of the largest
#ifndef PACKING_GLSL
#define PACKING_GLSL

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

uint pack_oct16(vec3 n)
{
    uvec2 o = uvec2(round(clamp(oct_encode(n) * 0.5 + 0.5, 0.0, 1.0) * 65535.0));
    return o.x | (o.y << 16);
}

vec3 unpack_oct16(uint o)
{
    return oct_decode(vec2(uvec2(o, o >> 16) & 0xffffu) * (2.0 / 65535.0) - 1.0);
}

const float RGB9E5_MAX = 65408.0; // (2⁹ − 1)/2⁹ · 2¹⁶

// The shared exponent e (bias 15, plus 1) is floor(log2(max channel)) + 16,
// read from the float's exponent bits (no log2/exp2 per texel); each
// channel is round(c / 2^(e − 24)), and e rises by one where the largest
// rounds up to 512.
uint pack_rgb9e5(vec3 c)
{
    c = clamp(c, 0.0, RGB9E5_MAX);
    float m = max(c.r, max(c.g, c.b));
    int e = max(int(floatBitsToUint(m) >> 23) - 127, -16) + 16;
    float scale = uintBitsToFloat(uint(127 + 24 - e) << 23); // 2^(24 − e)
    if (floor(m * scale + 0.5) >= 512.0) {
        e++;
        scale *= 0.5;
    }
    uvec3 q = uvec3(floor(c * scale + 0.5));
    return q.r | (q.g << 9) | (q.b << 18) | (uint(e) << 27);
}

vec3 unpack_rgb9e5(uint p)
{
    // 2^(e − 24) built from its exponent bits (e − 24 + 127), not exp2
    return vec3(uvec3(p, p >> 9, p >> 18) & 0x1ffu) * uintBitsToFloat(((p >> 27) + 103u) << 23);
}

#endif
