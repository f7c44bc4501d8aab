// math.glsl — constants and small helpers.
#ifndef MATH_GLSL
#define MATH_GLSL

const float PI = 3.14159265358979323846;
const float TWO_PI = 6.28318530717958647692;

// texelFetch(t, px, 0) of a NEAREST-filtered texture's level 0, through
// the sampling path: llvmpipe's texelFetch function looks up each lane's
// mip offsets and strides, textureLod's does not (the direct pass at
// 800×600 26.5 -> 25.0 ms, tone mapping 3.4 -> 2.9; the same texels).
#define FETCH_NEAREST(t, px) textureLod(t, (vec2(px) + 0.5) / vec2(textureSize(t, 0)), 0.0)

// Interleaved gradient noise (Jimenez 2014): a per-pixel value in [0,1).
float ign(vec2 pixel)
{
    return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}

// Orthonormal basis around unit n (Duff et al. 2017).
void basis(vec3 n, out vec3 t, out vec3 b)
{
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// floor(a / b) for 0 ≤ a, 1 ≤ b, a + b < 2²³ (pixel coordinates, sample
// counts), in float arithmetic: exact there, since (a + ½)/b lies ½/b
// inside (q, q + 1) and its float quotient is within (q + 1)·2⁻²⁴ < ½/b
// of it. llvmpipe has no vector integer division: `/` and `%` by a value
// it cannot see are divided lane by lane (ten of them per pixel had been
// a fifth of rsm-interleaved's gather).
int div_small(int a, int b) { return int((float(a) + 0.5) / float(b)); }
ivec2 div_small(ivec2 a, ivec2 b) { return ivec2((vec2(a) + 0.5) / vec2(b)); }

// Luminance of linear Rec. 709 RGB (src/io/image.h's luminance).
float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// hash_u32: the 32-bit integer hash C shares (shared/hash.h).
#include "shared/hash.h"

#endif
