/* sampling.h — warps of uniform numbers onto the domains the path tracer
 * samples, with their densities. */
#ifndef RTGI_SAMPLING_H
#define RTGI_SAMPLING_H

#include <cglm/cglm.h>
#include <math.h>

/* Orthonormal basis (t, b) around unit n (Duff et al. 2017). */
static inline void onb(const vec3 n, vec3 t, vec3 b)
{
    float s = n[2] >= 0.f ? 1.f : -1.f;
    float a = -1.f / (s + n[2]);
    float c = n[0] * n[1] * a;
    t[0] = 1.f + s * n[0] * n[0] * a;
    t[1] = s * c;
    t[2] = -s * n[0];
    b[0] = c;
    b[1] = s + n[1] * n[1] * a;
    b[2] = -n[1];
}

/* Local (x, y, z) around n → world. */
static inline void to_world(const vec3 n, float x, float y, float z, vec3 out)
{
    vec3 t, b;
    onb(n, t, b);
    for (int i = 0; i < 3; i++)
        out[i] = x * t[i] + y * b[i] + z * n[i];
}

/* cos and sin of 2πu for u in [0, 1), without a libm call: u's octant
 * picks the rotation, and the angle θ = 2π·frac(8u)/8 in [0, π/4] goes
 * through the Taylor series of sin to x⁹ and of cos to x¹⁰ (truncation
 * below 2e-9 on [0, π/4], under float rounding; frac(8u) and 1 − frac(8u)
 * are exact for u a multiple of 2^-24, as sampler numbers are). */
static inline void sincos_2pi(float u, float *s, float *c)
{
    float x8 = u * 8.f;
    int k = (int)x8;
    k = k < 0 ? 0 : k > 7 ? 7 : k;
    float t = x8 - (float)k;
    /* The octant's second half: α = π/4 + θ = π/2 − β with β = (1 − t)π/4. */
    float x = (k & 1 ? 1.f - t : t) * (GLM_PIf / 4.f), x2 = x * x;
    float sn = x * (1.f + x2 * (-1.f / 6 + x2 * (1.f / 120 + x2 * (-1.f / 5040 + x2 * (1.f / 362880)))));
    float cs = 1.f + x2 * (-0.5f + x2 * (1.f / 24 + x2 * (-1.f / 720 + x2 * (1.f / 40320 + x2 * (-1.f / 3628800)))));
    float ca = k & 1 ? sn : cs, sa = k & 1 ? cs : sn; /* cos and sin of the angle within the quadrant */
    switch (k >> 1) {
    case 0: *c = ca, *s = sa; break;
    case 1: *c = -sa, *s = ca; break;
    case 2: *c = -ca, *s = -sa; break;
    default: *c = sa, *s = -ca; break;
    }
}

/* Cosine-weighted hemisphere around n; pdf = cosθ/π. */
static inline void sample_cosine(const vec3 n, float u1, float u2, vec3 out)
{
    float r = sqrtf(u1), phi = 2.f * GLM_PIf * u2;
    to_world(n, r * cosf(phi), r * sinf(phi), sqrtf(fmaxf(0.f, 1.f - u1)), out);
}

/* Uniform over the cone around axis whose half-angle θmax has
 * 1 − cos θmax = one_minus_cos (pass it in a cancellation-free form, e.g.
 * 2 sin²(θmax/2): for the sun it is 1e-5, below float's resolution of
 * cos θmax); pdf = 1 / (2π · one_minus_cos). */
static inline void sample_cone(const vec3 axis, float one_minus_cos, float u1, float u2, vec3 out)
{
    float h = u1 * one_minus_cos; /* 1 − cos θ */
    float s = sqrtf(fmaxf(0.f, h * (2.f - h))), sp, cp;
    sincos_2pi(u2, &sp, &cp);
    to_world(axis, s * cp, s * sp, 1.f - h, out);
}

/* Uniform on a disk of radius r, centre c, normal n; pdf = 1/(πr²). */
static inline void sample_disk(const vec3 c, const vec3 n, float r, float u1, float u2, vec3 out)
{
    float rr = r * sqrtf(u1), sp, cp;
    sincos_2pi(u2, &sp, &cp);
    vec3 d;
    to_world(n, rr * cp, rr * sp, 0.f, d);
    glm_vec3_add((float *)c, d, out);
}

static inline float power_heuristic(float a, float b)
{
    return a * a / (a * a + b * b);
}

#endif
