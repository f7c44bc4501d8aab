/* brdf.c — see brdf.h; shaders/common/brdf.glsl is the same code. */
#include "core/brdf.h"

#include "io/image.h" /* luminance */
#include "base/util.h"

#include <math.h>

/* max(x, 0) and clamp(x, 0, 1) as compares, which compile inline (fmaxf
 * and fminf are library calls without -ffinite-math-only); a NaN gives 0,
 * as fmaxf(NaN, 0) does. */
static inline float pos0(float x) { return x > 0.f ? x : 0.f; }
static inline float sat(float x) { return x > 0.f ? (x < 1.f ? x : 1.f) : 0.f; }

void brdf_surface(const vec3 base, float metallic, float roughness, float specular, BrdfSurface *out)
{
    for (int c = 0; c < 3; c++) {
        out->diffuse[c] = (1.f - metallic) * base[c];
        out->f0[c] = (1.f - metallic) * BRDF_DIELECTRIC_F0 * specular + metallic * base[c];
    }
    out->roughness = roughness;
}

float brdf_alpha(float roughness)
{
    float r = fmaxf(roughness, BRDF_MIN_ROUGHNESS);
    return r * r;
}

float brdf_f90(const vec3 f0)
{
    return fminf(1.f, 50.f * fmaxf(f0[0], fmaxf(f0[1], f0[2])));
}

void brdf_fresnel(const vec3 f0, float cos_theta, vec3 out)
{
    float f90 = brdf_f90(f0);
    float m = 1.f - sat(cos_theta);
    float m5 = m * m * m * m * m;
    for (int c = 0; c < 3; c++)
        out[c] = f0[c] + (f90 - f0[c]) * m5;
}

/* D from cos²θh and sin²θh given apart: (n·h)²(α² − 1) + 1 = cos²·α² + sin²
 * without the cancellation near the peak, where sin² ≪ 1. */
static float ggx_d_cs(float c2, float s2, float alpha)
{
    float a2 = alpha * alpha;
    float t = c2 * a2 + s2;
    return a2 / (GLM_PIf * t * t);
}

float brdf_diffuse_transmission(float fv, float fl, float f0)
{
    return f0 < 1.f - 1e-4f ? (1.f - fv) * (1.f - fl) / (1.f - f0) : 0.f;
}

void brdf_diffuse_irradiance_weight(const vec3 f0, float n_dot_v, vec3 out)
{
    vec3 fv;
    brdf_fresnel(f0, n_dot_v, fv);
    float f90 = brdf_f90(f0);
    for (int c = 0; c < 3; c++)
        out[c] = brdf_diffuse_transmission(fv[c], f0[c] + (f90 - f0[c]) / 21.f, f0[c]);
}

/* Entry (i, j) of the albedo table: n·v = i/(N − 1) (at least 1e-3),
 * roughness j/(N − 1): the grid holds both ends.
 * With Schlick's F = F0·(1 − (1 − c)⁵) + F90·(1 − c)⁵ (c = v·h) the lobe's
 * albedo is F0·A + F90·B; sampling h from the visible normals (Heitz 2018)
 * gives f_s cosθ_l / pdf = F·G2/G1(v), so A and B average G2/G1 times the
 * two Fresnel weights over BRDF_ALBEDO_SAMPLES Hammersley points. */
static void albedo_entry(int i, int j, float ab[2])
{
    float mu = fmaxf((float)i / (BRDF_ALBEDO_N - 1), 1e-3f), alpha = brdf_alpha((float)j / (BRDF_ALBEDO_N - 1));
    vec3 v = {sqrtf(1.f - mu * mu), 0.f, mu};
    double a = 0, b = 0;
    float lv = brdf_smith_lambda(mu, alpha);
    for (uint32_t k = 0; k < BRDF_ALBEDO_SAMPLES; k++) {
        vec3 h, l; /* u2: the van der Corput radical inverse of k */
        brdf_sample_vndf(v, alpha, ((float)k + 0.5f) / BRDF_ALBEDO_SAMPLES,
                         (float)util_reverse_bits(k) * 2.3283064365386963e-10f, h);
        float c = glm_vec3_dot(v, h);
        for (int d = 0; d < 3; d++)
            l[d] = 2.f * c * h[d] - v[d];
        if (l[2] <= 0.f)
            continue;
        double g = (1.0 + lv) / (1.0 + lv + brdf_smith_lambda(l[2], alpha));
        double m = 1.0 - fminf(fmaxf(c, 0.f), 1.f), m5 = m * m * m * m * m;
        a += g * (1.0 - m5);
        b += g * m5;
    }
    ab[0] = (float)(a / BRDF_ALBEDO_SAMPLES);
    ab[1] = (float)(b / BRDF_ALBEDO_SAMPLES);
}

const float (*brdf_albedo_table(void))[2]
{
    static float table[BRDF_ALBEDO_N * BRDF_ALBEDO_N][2];
    static bool made;
    if (!made) {
        for (int j = 0; j < BRDF_ALBEDO_N; j++)
            for (int i = 0; i < BRDF_ALBEDO_N; i++)
                albedo_entry(i, j, table[j * BRDF_ALBEDO_N + i]);
        made = true;
    }
    return (const float(*)[2])table;
}

void brdf_specular_albedo(const vec3 f0, float roughness, float n_dot_v, vec3 out)
{
    /* Bilinear between the entries: what the GPU's linear filter does with
     * the table as a texture read at (x·(N − 1) + ½)/N (brdf.glsl). */
    const float(*t)[2] = brdf_albedo_table();
    float x = fminf(fmaxf(n_dot_v, 0.f), 1.f) * (BRDF_ALBEDO_N - 1);
    float y = fminf(fmaxf(roughness, 0.f), 1.f) * (BRDF_ALBEDO_N - 1);
    int x0 = (int)x, y0 = (int)y, x1 = x0 + 1 < BRDF_ALBEDO_N ? x0 + 1 : x0, y1 = y0 + 1 < BRDF_ALBEDO_N ? y0 + 1 : y0;
    float fx = x - (float)x0, fy = y - (float)y0, ab[2];
    for (int k = 0; k < 2; k++) {
        float top = t[y0 * BRDF_ALBEDO_N + x0][k] * (1.f - fx) + t[y0 * BRDF_ALBEDO_N + x1][k] * fx;
        float bot = t[y1 * BRDF_ALBEDO_N + x0][k] * (1.f - fx) + t[y1 * BRDF_ALBEDO_N + x1][k] * fx;
        ab[k] = top * (1.f - fy) + bot * fy;
    }
    float f90 = brdf_f90(f0);
    for (int c = 0; c < 3; c++)
        out[c] = f0[c] * ab[0] + f90 * ab[1];
}

float brdf_ggx_d(float n_dot_h, float alpha)
{
    return ggx_d_cs(n_dot_h * n_dot_h, pos0(1.f - n_dot_h * n_dot_h), alpha);
}

float brdf_smith_lambda(float c, float alpha)
{
    float c2 = c * c;
    return 0.5f * (-1.f + sqrtf(c2 + alpha * alpha * (1.f - c2)) / c);
}

float brdf_smith_g1(float c, float alpha)
{
    if (c <= 0.f)
        return 0.f;
    return 1.f / (1.f + brdf_smith_lambda(c, alpha));
}

float brdf_smith_v(float nv, float nl, float alpha)
{
    float a2 = alpha * alpha;
    float gv = nl * sqrtf(nv * nv * (1.f - a2) + a2);
    float gl = nv * sqrtf(nl * nl * (1.f - a2) + a2);
    return 0.5f / (gv + gl);
}

void brdf_eval_lobes(const BrdfSurface *s, const vec3 n, const vec3 v, const vec3 l, vec3 diffuse, vec3 specular)
{
    float nv = glm_vec3_dot((float *)n, (float *)v), nl = glm_vec3_dot((float *)n, (float *)l);
    if (nl <= 0.f) {
        if (diffuse)
            glm_vec3_zero(diffuse);
        if (specular)
            glm_vec3_zero(specular);
        return;
    }
    vec3 h, f, nxh;
    glm_vec3_add((float *)v, (float *)l, h);
    glm_vec3_normalize(h);
    glm_vec3_cross((float *)n, h, nxh);
    float nh = pos0(glm_vec3_dot((float *)n, h)), vh = pos0(glm_vec3_dot((float *)v, h));
    brdf_fresnel(s->f0, vh, f);
    float a = brdf_alpha(s->roughness);
    /* A view below the shading normal's horizon (interpolated normals near
     * silhouettes) sees the diffuse lobe only. */
    float dv = nv > 0.f ? ggx_d_cs(nh * nh, glm_vec3_dot(nxh, nxh), a) * brdf_smith_v(nv, nl, a) : 0.f;
    vec3 fv, fl;
    brdf_fresnel(s->f0, nv, fv);
    brdf_fresnel(s->f0, nl, fl);
    for (int c = 0; c < 3; c++) {
        if (diffuse)
            diffuse[c] = brdf_diffuse_transmission(fv[c], fl[c], s->f0[c]) * s->diffuse[c] / GLM_PIf;
        if (specular)
            specular[c] = f[c] * dv;
    }
}

void brdf_eval(const BrdfSurface *s, const vec3 n, const vec3 v, const vec3 l, vec3 out)
{
    vec3 d, sp;
    brdf_eval_lobes(s, n, v, l, d, sp);
    glm_vec3_add(d, sp, out);
}

/* ---- Sampling ---- */

void brdf_sample_vndf(const vec3 wo, float alpha, float u1, float u2, vec3 h)
{
    /* Stretch the view to the hemisphere configuration. */
    vec3 vh = {alpha * wo[0], alpha * wo[1], wo[2]};
    glm_vec3_normalize(vh);
    /* Orthonormal basis around vh. */
    float lensq = vh[0] * vh[0] + vh[1] * vh[1];
    vec3 t1 = {1.f, 0.f, 0.f}, t2;
    if (lensq > 0.f) {
        float inv = 1.f / sqrtf(lensq);
        t1[0] = -vh[1] * inv;
        t1[1] = vh[0] * inv;
        t1[2] = 0.f;
    }
    glm_vec3_cross(vh, t1, t2);
    /* Uniform point on the disk, warped to the projected visible half. */
    float r = sqrtf(u1), phi = 2.f * GLM_PIf * u2;
    float p1 = r * cosf(phi), p2 = r * sinf(phi);
    float sh = 0.5f * (1.f + vh[2]);
    p2 = (1.f - sh) * sqrtf(fmaxf(0.f, 1.f - p1 * p1)) + sh * p2;
    float pz = sqrtf(fmaxf(0.f, 1.f - p1 * p1 - p2 * p2));
    vec3 nh;
    for (int k = 0; k < 3; k++)
        nh[k] = p1 * t1[k] + p2 * t2[k] + pz * vh[k];
    /* Unstretch. */
    h[0] = alpha * nh[0];
    h[1] = alpha * nh[1];
    h[2] = fmaxf(0.f, nh[2]);
    glm_vec3_normalize(h);
}

float brdf_vndf_pdf(const vec3 wo, const vec3 h, float alpha)
{
    float oh = glm_vec3_dot((float *)wo, (float *)h);
    if (wo[2] <= 0.f || h[2] <= 0.f || oh <= 0.f)
        return 0.f;
    return brdf_smith_g1(wo[2], alpha) * oh * ggx_d_cs(h[2] * h[2], h[0] * h[0] + h[1] * h[1], alpha) / wo[2];
}

float brdf_spec_pdf(const vec3 wo, const vec3 wi, float alpha)
{
    vec3 h;
    glm_vec3_add((float *)wo, (float *)wi, h);
    float len = glm_vec3_norm(h);
    if (!(len > 0.f))
        return 0.f;
    glm_vec3_scale(h, 1.f / len, h);
    float oh = glm_vec3_dot((float *)wo, h);
    if (oh <= 0.f)
        return 0.f;
    return brdf_vndf_pdf(wo, h, alpha) / (4.f * oh);
}

float brdf_spec_prob(const BrdfSurface *s, float n_dot_v)
{
    vec3 f, d;
    brdf_fresnel(s->f0, n_dot_v, f);
    for (int c = 0; c < 3; c++)
        d[c] = (1.f - f[c]) * s->diffuse[c];
    float ls = luminance(f), ld = luminance(d);
    return n_dot_v > 0.f && ls + ld > 0.f ? ls / (ls + ld) : 0.f;
}

bool brdf_sample(const BrdfSurface *s, const vec3 wo, float u0, float u1, float u2, vec3 wi)
{
    return brdf_sample_p(s, wo, brdf_spec_prob(s, wo[2]), u0, u1, u2, wi);
}

bool brdf_sample_p(const BrdfSurface *s, const vec3 wo, float p, float u0, float u1, float u2, vec3 wi)
{
    if (u0 < p) {
        vec3 h;
        brdf_sample_vndf(wo, brdf_alpha(s->roughness), u1, u2, h);
        float oh = glm_vec3_dot((float *)wo, h);
        for (int k = 0; k < 3; k++)
            wi[k] = 2.f * oh * h[k] - wo[k];
    } else {
        float r = sqrtf(u1), phi = 2.f * GLM_PIf * u2;
        wi[0] = r * cosf(phi);
        wi[1] = r * sinf(phi);
        wi[2] = sqrtf(pos0(1.f - u1));
    }
    return wi[2] > 0.f;
}

float brdf_pdf(const BrdfSurface *s, const vec3 wo, const vec3 wi)
{
    if (wi[2] <= 0.f)
        return 0.f;
    float p = brdf_spec_prob(s, wo[2]); /* 0 for wo below the horizon */
    float pdf = (1.f - p) * wi[2] / GLM_PIf;
    if (p > 0.f)
        pdf += p * brdf_spec_pdf(wo, wi, brdf_alpha(s->roughness));
    return pdf;
}

void brdf_eval_pdf(const BrdfSurface *s, const vec3 wo, const vec3 wi, float p, vec3 f, float *pdf)
{
    float nv = wo[2], nl = wi[2];
    glm_vec3_zero(f);
    *pdf = 0.f;
    if (nl <= 0.f)
        return;
    /* One half vector for both: brdf_eval_lobes' h and brdf_spec_pdf's. */
    vec3 h;
    glm_vec3_add((float *)wo, (float *)wi, h);
    float len = glm_vec3_norm(h);
    if (len > 0.f)
        glm_vec3_scale(h, 1.f / len, h);
    float a = brdf_alpha(s->roughness);
    float oh = glm_vec3_dot((float *)wo, h);
    float d = ggx_d_cs(h[2] * h[2], h[0] * h[0] + h[1] * h[1], a);
    vec3 fh, fv, fl;
    brdf_fresnel(s->f0, pos0(oh), fh);
    brdf_fresnel(s->f0, nv, fv);
    brdf_fresnel(s->f0, nl, fl);
    float dv = nv > 0.f && len > 0.f ? d * brdf_smith_v(nv, nl, a) : 0.f;
    for (int c = 0; c < 3; c++)
        f[c] = brdf_diffuse_transmission(fv[c], fl[c], s->f0[c]) * s->diffuse[c] / GLM_PIf + fh[c] * dv;
    /* brdf_pdf: (1 − p) cos/π + p · VNDF density / (4 wo·h), where the VNDF
     * density is G1(wo)·(wo·h)·D / wo.z. */
    *pdf = (1.f - p) * nl / GLM_PIf;
    if (p > 0.f && len > 0.f && nv > 0.f && h[2] > 0.f && oh > 0.f)
        *pdf += p * brdf_smith_g1(nv, a) * d / (4.f * nv);
}
