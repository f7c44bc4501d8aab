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
    float s = sqrtf(fmaxf(0.f, h * (2.f - h))), phi = 2.f * GLM_PIf * u2;
    to_world(axis, s * cosf(phi), s * sinf(phi), 1.f - h, out);
}

/* Uniform on a disk of radius r, centre c, normal n; pdf = 1/(πr²). */
static inline void sample_disk(const vec3 c, const vec3 n, float r, float u1, float u2, vec3 out)
{
    float rr = r * sqrtf(u1), phi = 2.f * GLM_PIf * u2;
    vec3 d;
    to_world(n, rr * cosf(phi), rr * sinf(phi), 0.f, d);
    glm_vec3_add((float *)c, d, out);
}

static inline float power_heuristic(float a, float b)
{
    return a * a / (a * a + b * b);
}

#endif
