/* SCHED_IDLE (Linux) for the background renderer's threads (pt_job_pass). */
#define _GNU_SOURCE
#include "reference/pathtracer.h"

#include "core/brdf.h"
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#if defined(__SSE2__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif

#include "core/camera.h"
#include "base/log.h"
#include "reference/pt_job.h"
#include "reference/pt_scene.h"
#include "reference/rng.h"
#include "reference/sampler.h"
#include "reference/sampling.h"
#include "base/util.h"

const char *const pt_mode_names[] = {"full", "direct", "one-bounce", "one-bounce-novis", "indirect", NULL};
const char *const pt_sampler_names[] = {"sobol", "independent", NULL};

enum { TILE = 16, MAX_ALL_HITS = 64 };

void pt_settings_default(PtSettings *s)
{
    memset(s, 0, sizeof *s);
    s->width = s->height = 256;
    s->spp = 64;
    s->threads = 1;
    s->seed = 1;
    s->mode = PT_FULL;
    s->max_depth = 64;
    s->russian_roulette = true;
    s->rr_depth = 3;
    s->pixel_jitter = true;
    s->sampler = PT_SAMPLER_SOBOL;
}

/* What a light's sample needs that does not vary over the scene, made
 * once per pass (light_const) rather than at every vertex. */
typedef struct LightConst {
    float one_minus_cos; /* directional, size > 0: 1 − cos of the disk's angular radius */
    float li_scale;      /* directional, size > 0: the irradiance's factor to L·Ω */
    float area1;         /* quad: its area at size 1 (quad_area1) */
} LightConst;

/* pt_job.h's job. */
typedef struct PtJob {
    const Scene *scene;        /* borrowed */
    const PtSettings *set;     /* borrowed */
    PtScene ps;                /* owned: Embree's scene */
    int tiles_x, tiles_y;
    atomic_int next_tile;      /* the running pass: next tile to take */
    atomic_int tiles_done;     /* the running pass: tiles rendered */
    atomic_uint_fast64_t rays;
    double *sum, *sum2;        /* per pixel and channel: sums of the samples and their squares (owned) */
    int s0, s1;                /* the running pass: sample indices [s0, s1) */
    const atomic_int *cancel;  /* the running pass: no new tile once non-zero (may be NULL) */
    pthread_t *threads;        /* room for set->threads − 1 helpers (owned) */
    struct MatShade *mats;     /* per material, made at each pass's start (owned; NULL: none) */
    int mats_count, mats_cap;  /* materials in `mats` (0: shade_make computes every one), its room */
    LightConst *lconst;        /* per light, made at each pass's start (owned; NULL: none) */
    int lconst_cap;            /* room in `lconst` */
    CameraRayBasis cam;        /* the scene camera's rays at this size */
} Job;

/* ---------------------------------------------------------------- lights
 * One home per light type: `*_sample` draws a direction toward the light
 * from the ray origin o (already offset off the surface) from the uniform
 * pair u, and `quad_pdf` gives the density of a BSDF ray that hits the one
 * emitter that has geometry (a quad with size > 0), for MIS. Models are
 * those of the rasterizer (light_intensity in scene.c); see pathtracer.h. */

/* A direction toward a light, with what arrives along it. */
typedef struct LightSample {
    vec3 wi;     /* unit, from o toward the emitter */
    float dist;  /* shadow ray length: to the emitter (INFINITY: the sun) */
    vec3 li;     /* incident radiance / solid-angle pdf (delta lights: irradiance at normal incidence) */
    float pdf;   /* solid-angle pdf of wi if a BSDF ray can also reach this emitter (MIS), else 0 */
} LightSample;

/* wi and dist from o toward point lp. */
static void toward(const vec3 o, const vec3 lp, LightSample *ls)
{
    glm_vec3_sub((float *)lp, (float *)o, ls->wi);
    ls->dist = glm_vec3_norm(ls->wi);
    glm_vec3_scale(ls->wi, 1.f / ls->dist, ls->wi);
}

/* quad_area1 and sun_sample's constants of a sun of angular diameter
 * size > 0: with a = size/2, s = sin(a/2) and c = cos(a/2), 1 − cos a =
 * 2s² and the radiance's factor 1/c² (libm's sinf and cosf at every vertex
 * had been 1.3% of Sponza's time). */
static float quad_area1(const Light *l);
static void light_const(const Light *l, LightConst *lc)
{
    memset(lc, 0, sizeof *lc);
    if (l->type == LIGHT_DIRECTIONAL && l->size > 0.f) {
        float half = 0.5f * l->size, s = sinf(0.5f * half), c = cosf(0.5f * half);
        lc->one_minus_cos = 2.f * s * s;
        lc->li_scale = 1.f / (c * c);
    }
    if (l->type == LIGHT_QUAD)
        lc->area1 = quad_area1(l);
}

/* Directional: irradiance E on a plane facing it. With an angular diameter
 * 2a it is a disk of uniform radiance L = E / (π sin²a) (so that the
 * irradiance facing it, L·π sin²a, is E), sampled uniformly over its solid
 * angle Ω = 2π(1 − cos a) = 4π sin²(a/2); then li = L·Ω = E / cos²(a/2),
 * with no cancellation (2π(1 − cosf a) in float is 0.25% low for the real
 * sun, a = 0.0046). */
static bool sun_sample(const Light *l, const LightConst *sd, const float u[2], LightSample *ls)
{
    glm_vec3_negate_to((float *)l->direction, ls->wi);
    ls->dist = INFINITY;
    ls->pdf = 0.f;
    if (l->size <= 0.f) {
        glm_vec3_copy((float *)l->color, ls->li);
        return true;
    }
    vec3 axis;
    glm_vec3_copy(ls->wi, axis);
    sample_cone(axis, sd->one_minus_cos, u[0], u[1], ls->wi);
    glm_vec3_scale((float *)l->color, sd->li_scale, ls->li);
    return true;
}

/* Point: intensity I in every direction. With a diameter 2r it is a sphere
 * of radiance I/(πr²) (same power), sampled uniformly over the cone it
 * subtends: sin²θmax = r²/d², 1 − cos θmax = sin²θmax / (1 + cos θmax), so
 * li = L·Ω = 2I / (d²(1 + cos θmax)). */
static bool point_sample(const Light *l, const vec3 o, const float u[2], LightSample *ls)
{
    ls->pdf = 0.f;
    if (l->size <= 0.f) {
        toward(o, l->position, ls);
        glm_vec3_scale((float *)l->color, 1.f / (ls->dist * ls->dist), ls->li);
        return true;
    }
    float r = 0.5f * l->size;
    vec3 toc;
    glm_vec3_sub((float *)l->position, (float *)o, toc);
    float dc = glm_vec3_norm(toc);
    if (dc <= r)
        return false; /* inside the emitter */
    glm_vec3_scale(toc, 1.f / dc, toc);
    float sin2 = (r / dc) * (r / dc), cos_max = sqrtf(fmaxf(0.f, 1.f - sin2));
    sample_cone(toc, sin2 / (1.f + cos_max), u[0], u[1], ls->wi);
    /* Distance to the sphere's near side along wi. */
    float b = glm_vec3_dot(ls->wi, toc) * dc;
    ls->dist = b - sqrtf(fmaxf(b * b - (dc - r) * (dc + r), 0.f));
    glm_vec3_scale((float *)l->color, 2.f / (dc * dc * (1.f + cos_max)), ls->li);
    return true;
}

/* Spot: intensity I times the cone falloff along its axis; with a diameter,
 * a disk facing the axis, sampled uniformly by area, with the same
 * intensity from each of its points (zero behind it). */
static bool spot_sample(const Light *l, const vec3 o, const float u[2], LightSample *ls)
{
    ls->pdf = 0.f;
    vec3 lp, out_dir, inten;
    glm_vec3_copy((float *)l->position, lp);
    if (l->size > 0.f)
        sample_disk(l->position, l->direction, 0.5f * l->size, u[0], u[1], lp);
    toward(o, lp, ls);
    glm_vec3_negate_to(ls->wi, out_dir);
    if (l->size > 0.f && glm_vec3_dot(out_dir, (float *)l->direction) <= 0.f)
        return false; /* behind the disk */
    light_intensity(l, out_dir, inten);
    glm_vec3_scale(inten, 1.f / (ls->dist * ls->dist), ls->li);
    return true;
}

/* |quad_u × quad_v|: quad l's area at size 1 (light_quad_area's factor),
 * inline: the direct light needs it at every vertex. */
static float quad_area1(const Light *l)
{
    const float *u = l->quad_u, *v = l->quad_v;
    vec3 n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* Solid-angle pdf of light-sampling a point at distance dist on quad l's
 * emitter (area at size 1: a1), seen at cosine cos_l from its normal: area
 * pdf 1/A converted. */
static float quad_pdf(const Light *l, float a1, float dist, float cos_l)
{
    return dist * dist / (cos_l * a1 * l->size * l->size);
}

/* Quad: one-sided radiance L; intensity L·A·cos θ at size 0 (a point at
 * its centre); with a size, the real quad (emitter geometry that BSDF rays
 * hit), sampled uniformly by area, power independent of size. */
static bool quad_sample(const Light *l, const LightConst *lc, const vec3 o, const float u[2], LightSample *ls)
{
    ls->pdf = 0.f;
    vec3 lp;
    glm_vec3_copy((float *)l->position, lp);
    if (l->size > 0.f) {
        glm_vec3_muladds((float *)l->quad_u, (u[0] - 0.5f) * l->size, lp);
        glm_vec3_muladds((float *)l->quad_v, (u[1] - 0.5f) * l->size, lp);
    }
    toward(o, lp, ls);
    float cos_l = -glm_vec3_dot(ls->wi, (float *)l->direction);
    if (cos_l <= 0.f)
        return false;
    /* light_intensity's L·A·cos_l at size 1, over dist². */
    float a1 = lc->area1, inv_d2 = 1.f / (ls->dist * ls->dist);
    glm_vec3_scale((float *)l->color, a1 * cos_l * inv_d2, ls->li);
    if (l->size > 0.f)
        ls->pdf = quad_pdf(l, a1, ls->dist, cos_l);
    return true;
}

/* lc: l's light_const (NULL: made here). */
static bool light_sample(const Light *l, const LightConst *lc, const vec3 o, const float u[2], LightSample *ls)
{
    LightConst own;
    if (!lc) {
        light_const(l, &own);
        lc = &own;
    }
    switch (l->type) {
    case LIGHT_DIRECTIONAL:
        return sun_sample(l, lc, u, ls);
    case LIGHT_POINT:
        return point_sample(l, o, u, ls);
    case LIGHT_SPOT:
        return spot_sample(l, o, u, ls);
    case LIGHT_QUAD:
        return quad_sample(l, lc, o, u, ls);
    }
    return false;
}

/* A surface point as one path vertex sees it: the BRDF, the shading frame
 * and the view direction in it, made once per vertex for its light samples
 * and its bounce. */
typedef struct Shade {
    BrdfSurface surf;
    vec3 t, b, n;     /* the shading frame (onb of the shading normal n: to_world's) */
    vec3 wo;          /* toward the viewer, in that frame */
    float spec_prob;  /* brdf_spec_prob at wo: how often the bounce samples the specular lobe */
    bool lambert;     /* F0 = 0: f = ρ/π and pdf = cos/π exactly (brdf.h), with no Fresnel to evaluate */
    vec3 rho_pi;      /* lambert: ρ/π */
} Shade;

static float dot3(const vec3 a, const vec3 b) { return glm_vec3_dot((float *)a, (float *)b); }

/* A material's BRDF where it does not vary over the surface (no texture):
 * made once per pass rather than at every vertex. */
typedef struct MatShade {
    BrdfSurface surf;
    bool constant;    /* no albedo or metallicRoughness texture: surf holds everywhere */
} MatShade;

/* The job's MatShade of every material of the scene as it is now (the
 * progressive renderer changes materials between passes); with no room for
 * them, none (shade_make then computes each). */
static void materials_refresh(Job *j)
{
    int n = j->scene->material_count;
    if (n > j->mats_cap) {
        MatShade *m = realloc(j->mats, (size_t)n * sizeof *m);
        if (!m) {
            j->mats_count = 0;
            return;
        }
        j->mats = m;
        j->mats_cap = n;
    }
    for (int i = 0; i < n; i++) {
        const Material *m = &j->scene->materials[i];
        MatShade *c = &j->mats[i];
        c->constant = m->albedo_tex < 0 && m->mr_tex < 0;
        brdf_surface(m->albedo, m->metallic, m->roughness, m->specular, &c->surf);
    }
    j->mats_count = n;
}

/* The job's LightConst of every light as it is now (lights change between
 * passes too); with no room for them, none (light_sample then makes each). */
static void lights_refresh(Job *j)
{
    int n = j->scene->light_count;
    if (n > j->lconst_cap) {
        LightConst *c = realloc(j->lconst, (size_t)n * sizeof *c);
        if (!c) {
            free(j->lconst);
            j->lconst = NULL;
            j->lconst_cap = 0;
            return;
        }
        j->lconst = c;
        j->lconst_cap = n;
    }
    for (int i = 0; i < n; i++)
        light_const(&j->scene->lights[i], &j->lconst[i]);
}

static void shade_make(const Job *j, const PtHit *h, const vec3 wo, Shade *sh)
{
    if (h->material < j->mats_count && j->mats[h->material].constant)
        sh->surf = j->mats[h->material].surf;
    else
        pt_surface(&j->ps, h, &sh->surf);
    glm_vec3_copy((float *)h->ns, sh->n);
    onb(sh->n, sh->t, sh->b);
    sh->wo[0] = dot3(wo, sh->t);
    sh->wo[1] = dot3(wo, sh->b);
    sh->wo[2] = dot3(wo, sh->n);
    const float *f0 = sh->surf.f0;
    sh->lambert = f0[0] <= 0.f && f0[1] <= 0.f && f0[2] <= 0.f;
    sh->spec_prob = sh->lambert ? 0.f : brdf_spec_prob(&sh->surf, sh->wo[2]);
    glm_vec3_scale(sh->surf.diffuse, 1.f / GLM_PIf, sh->rho_pi);
}

/* f and the BSDF-sampling density of world direction wi, at cosine c =
 * wi·n > 0 with the shading normal. */
static void shade_eval(const Shade *sh, const vec3 wi, float c, vec3 f, float *pdf)
{
    if (sh->lambert) {
        glm_vec3_copy((float *)sh->rho_pi, f);
        *pdf = c / GLM_PIf;
        return;
    }
    vec3 l = {dot3(wi, sh->t), dot3(wi, sh->b), c};
    brdf_eval_pdf(&sh->surf, sh->wo, l, sh->spec_prob, f, pdf);
}

/* Direct light at hit h (shade: its vertex; o: its point moved off the
 * surface, pt_offset): one sample of every light, times the BRDF (brdf.h)
 * and the cosine, with MIS against the BSDF sample for emitters BSDF rays
 * can hit (when `mis`). */
static void direct_light(Job *j, const PtHit *h, const Shade *sh, const vec3 o, Sampler *smp, bool mis,
                         uint64_t *rays, vec3 out)
{
    glm_vec3_zero(out);
    for (int i = 0; i < j->scene->light_count; i++) {
        float u[2];
        sampler_2d(smp, u);
        LightSample ls;
        if (!light_sample(&j->scene->lights[i], j->lconst ? &j->lconst[i] : NULL, o, u, &ls))
            continue;
        float c = dot3(ls.wi, sh->n);
        if (c <= 0.f || dot3(ls.wi, h->ng) <= 0.f)
            continue;
        vec3 e, f;
        float pdf_bsdf;
        shade_eval(sh, ls.wi, c, f, &pdf_bsdf);
        glm_vec3_scale(ls.li, c, e);
        glm_vec3_mul(e, f, e);
        if (mis && ls.pdf > 0.f)
            glm_vec3_scale(e, power_heuristic(ls.pdf, pdf_bsdf), e);
        if (e[0] <= 0.f && e[1] <= 0.f && e[2] <= 0.f)
            continue;
        (*rays)++;
        /* Stop short of the emitter's own surface. */
        if (pt_occluded(&j->ps, o, ls.wi, ls.dist * (1.f - 1e-4f)))
            continue;
        glm_vec3_add(out, e, out);
    }
}

/* Samples the BSDF at hit h (shade: its vertex): the direction `wi`, its
 * density and the weight f·cos/pdf. The lobe choice takes a number only
 * when both lobes may be picked, so a Lambertian surface draws the same
 * numbers as plain cosine sampling. false if the sample is unusable.
 * Always inline: its weight then stays in registers (through memory, the
 * caller's 8-byte load of its 4-byte stores missed store forwarding: 11%
 * of the Cornell box's path loop). */
static inline __attribute__((always_inline)) bool bsdf_sample(const PtHit *h, const Shade *sh, Sampler *smp, vec3 wi,
                                                              float *pdf, vec3 weight)
{
    float p = sh->spec_prob;
    float u[2];
    vec3 l;
    if (sh->lambert) {
        /* brdf_sample_p's cosine lobe, inline, its cos and sin without libm. */
        sampler_2d(smp, u);
        float r = sqrtf(u[0]), cphi, sphi;
        sincos_2pi(u[1], &sphi, &cphi);
        l[0] = r * cphi;
        l[1] = r * sphi;
        l[2] = sqrtf(1.f - u[0] > 0.f ? 1.f - u[0] : 0.f);
        if (!(l[2] > 0.f))
            return false;
    } else {
        float u0 = p <= 0.f ? 1.f : p >= 1.f ? 0.f : sampler_1d(smp);
        sampler_2d(smp, u);
        if (!brdf_sample_p(&sh->surf, sh->wo, p, u0, u[0], u[1], l))
            return false;
    }
    for (int i = 0; i < 3; i++)
        wi[i] = l[0] * sh->t[i] + l[1] * sh->b[i] + l[2] * sh->n[i];
    /* The cosine lobe's l is unit to a few ulps (r² + z² = 1) and so is the
     * frame: only the specular lobe's reflection needs normalising. */
    if (!sh->lambert)
        glm_vec3_normalize(wi);
    float c = dot3(wi, sh->n);
    if (c <= 0.f || dot3(wi, h->ng) <= 0.f)
        return false;
    if (sh->lambert) {
        /* f·cos/pdf = ρ/π · c / (c/π) */
        *pdf = c / GLM_PIf;
        glm_vec3_copy((float *)sh->surf.diffuse, weight);
        return true;
    }
    vec3 f;
    shade_eval(sh, wi, c, f, pdf);
    if (!(*pdf > 0.f))
        return false;
    glm_vec3_scale(f, c / *pdf, weight);
    return true;
}

/* Emitted radiance seen at hit h coming from direction -d, MIS-weighted
 * against light sampling when it is a quad light's surface reached by a
 * BSDF sample of density pdf_bsdf (pdf_bsdf < 0: camera ray, weight 1). */
static void emitted(Job *j, const PtHit *h, const vec3 d, float pdf_bsdf, bool mis, vec3 out)
{
    const Material *m = &j->scene->materials[h->material];
    glm_vec3_zero(out);
    if (!h->front)
        return;
    /* A quad light's emitter shines with its light's radiance, taken from
     * the light (scene_emitter_radiance) rather than from the emitter's
     * material: the light sample and the BSDF hit then see one light even
     * where the material is rewritten later (the window's render thread
     * places an edited light's emitter only at its next frame, while the
     * live reference has restarted with the edited light already). */
    const Light *l = m->light_index >= 0 ? &j->scene->lights[m->light_index] : NULL;
    vec3 le;
    if (l)
        scene_emitter_radiance(l, le);
    else
        glm_vec3_copy((float *)m->emission, le);
    if (le[0] <= 0.f && le[1] <= 0.f && le[2] <= 0.f)
        return;
    float w = 1.f;
    if (l && pdf_bsdf >= 0.f) {
        if (!mis)
            return; /* light sampling alone counts this light */
        float cos_l = -glm_vec3_dot((float *)d, (float *)l->direction);
        if (cos_l <= 0.f)
            return;
        float a1 = j->lconst ? j->lconst[m->light_index].area1 : quad_area1(l);
        w = power_heuristic(pdf_bsdf, quad_pdf(l, a1, h->t, cos_l));
    }
    glm_vec3_scale(le, w, out);
}

/* ---------------------------------------------------------------- paths */

/* One path of a pixel's sample, as the tile's paths advance together one
 * vertex at a time (render_tile): where it is, what it carries, what it
 * has gathered. */
typedef struct Path {
    vec3 o, d;        /* the ray to trace next: origin (moved off the surface) and direction */
    vec3 thr;         /* throughput: the product of the BSDF weights so far */
    vec3 L;           /* radiance gathered */
    float pdf_prev;   /* the BSDF density of d (-1: a camera ray) */
    bool alive;       /* has a hit at this depth to shade */
    PtRawHit raw;     /* Embree's hit of the ray just traced */
    PtHit hit;        /* its hit record */
} Path;

/* What the mode asks of every vertex. */
typedef struct PathMode {
    int min_direct, max_direct; /* vertices whose direct light counts */
    bool novis, mis;
} PathMode;

static PathMode path_mode(const PtSettings *s)
{
    PathMode m;
    m.min_direct = s->mode == PT_INDIRECT ? 2 : 1;
    m.max_direct = s->mode == PT_DIRECT ? 1 : (s->mode == PT_ONE_BOUNCE || s->mode == PT_ONE_BOUNCE_NOVIS) ? 2 : s->max_depth;
    m.novis = s->mode == PT_ONE_BOUNCE_NOVIS;
    m.mis = !m.novis;
    return m;
}

/* Vertex `depth` of path p, at its hit p->hit reached along p->d: the
 * emission it sees, its direct light, Russian roulette and the BSDF sample
 * that sets the next ray (p->o, p->d); false when the path ends here. */
static bool path_vertex(Job *j, const PathMode *pm, Path *p, int depth, Sampler *smp, uint64_t *rays)
{
    const PtSettings *s = j->set;
    const PtScene *ps = &j->ps;
    const PtHit *h = &p->hit;
    /* Emission reaching the previous vertex is part of its direct light. */
    int owner = depth == 1 ? 1 : depth - 1;
    if (owner >= pm->min_direct && owner <= pm->max_direct) {
        vec3 e;
        emitted(j, h, p->d, depth == 1 ? -1.f : p->pdf_prev, pm->mis, e);
        glm_vec3_muladd(p->thr, e, p->L);
    }
    if (depth > pm->max_direct)
        return false;
    vec3 wo;
    glm_vec3_negate_to(p->d, wo);
    Shade sh;
    shade_make(j, h, wo, &sh);
    pt_offset(h->p, h->ng, p->o); /* where this vertex's shadow rays and bounce start */
    if (depth >= pm->min_direct) {
        vec3 e;
        direct_light(j, h, &sh, p->o, smp, pm->mis, rays, e);
        glm_vec3_muladd(p->thr, e, p->L);
    }
    if (pm->novis) {
        /* One bounce without visibility on x1 → x2: every surface along
         * the BSDF-sampled ray contributes its direct light. */
        vec3 dir, t1, w;
        float pdf;
        if (!bsdf_sample(h, &sh, smp, dir, &pdf, w))
            return false;
        glm_vec3_mul(p->thr, w, t1);
        vec3 wo2;
        glm_vec3_negate_to(dir, wo2);
        PtHit hits[MAX_ALL_HITS];
        (*rays)++;
        int n = pt_intersect_all(ps, p->o, dir, INFINITY, hits, MAX_ALL_HITS);
        for (int k = 0; k < n; k++) {
            Shade s2;
            vec3 e, o2;
            shade_make(j, &hits[k], wo2, &s2);
            pt_offset(hits[k].p, hits[k].ng, o2);
            direct_light(j, &hits[k], &s2, o2, smp, false, rays, e);
            glm_vec3_muladd(t1, e, p->L);
        }
        return false;
    }
    /* The throughput in a local (registers) rather than p->thr through
     * the calls: 9% of the Cornell box's time went to reloading it. */
    float t0 = p->thr[0], t1 = p->thr[1], t2 = p->thr[2];
    if (s->russian_roulette && depth > s->rr_depth) {
        float q = t0 > t1 ? t0 : t1;
        q = q > t2 ? q : t2;
        q = q < 0.95f ? q : 0.95f;
        if (sampler_1d(smp) >= q)
            return false;
        float r = 1.f / q;
        t0 *= r, t1 *= r, t2 *= r;
    }
    vec3 w;
    if (!bsdf_sample(h, &sh, smp, p->d, &p->pdf_prev, w))
        return false;
    /* f·cos/pdf; Lambertian: ρ */
    p->thr[0] = t0 * w[0];
    p->thr[1] = t1 * w[1];
    p->thr[2] = t2 * w[2];
    return !(p->thr[0] <= 0.f && p->thr[1] <= 0.f && p->thr[2] <= 0.f);
}

/* The paths of one sample index of a tile's row, from their camera rays'
 * hits (a packet) on, each until it ends, all advanced one vertex at a
 * time: every path's ray is traced before any is shaded, so that the
 * memory reads of their hits (records, texels: cache misses on a large
 * scene) are asked for together rather than one after another. A path's
 * numbers, and so its radiance, are those it would draw alone. */
static void trace_paths(Job *j, const PathMode *pm, Path *path, int n, Sampler *smp, uint64_t *rays)
{
    const PtScene *ps = &j->ps;
    bool prefetch = ps->memory_bound; /* else the texels are in the caches already */
    for (int i = 0; i < n; i++)
        if (path[i].alive && prefetch)
            pt_prefetch_surface(ps, &path[i].hit);
    for (int depth = 1;; depth++) {
        bool any = false;
        for (int i = 0; i < n; i++)
            if (path[i].alive)
                any |= path[i].alive = path_vertex(j, pm, &path[i], depth, &smp[i], rays);
        if (!any || depth >= j->set->max_depth)
            return;
        for (int i = 0; i < n; i++)
            if (path[i].alive) {
                (*rays)++;
                path[i].alive = pt_trace(ps, path[i].o, path[i].d, INFINITY, &path[i].raw);
            }
        for (int i = 0; i < n; i++)
            if (path[i].alive) {
                pt_hit(ps, path[i].d, &path[i].raw, &path[i].hit);
                if (prefetch)
                    pt_prefetch_surface(ps, &path[i].hit);
            }
    }
}

/* Samples [s0, s1) of every pixel of one tile, added to the job's sums:
 * row by row, each sample index of a row's pixels at once, their camera
 * rays traced as one packet (pt_intersect_packet) and their paths together
 * (trace_paths). A pixel's samples are added in index order, so the sums
 * do not depend on the tiling. */
static void render_tile(Job *j, int tile, uint64_t *rays)
{
    _Static_assert((int)TILE <= (int)PT_PACKET, "a tile's row is one packet");
    const PtSettings *s = j->set;
    PathMode pm = path_mode(s);
    int tx = tile % j->tiles_x, ty = tile / j->tiles_x;
    int x0 = tx * TILE, x1 = x0 + TILE < s->width ? x0 + TILE : s->width;
    const float *cam = j->scene->camera.position;
    Sampler smp[TILE];
    vec3 d[TILE];
    PtHit hits[TILE];
    bool hit[TILE];
    Path path[TILE];
    for (int y = ty * TILE; y < (ty + 1) * TILE && y < s->height; y++) {
        size_t row = (size_t)y * s->width;
        for (int x = x0; x < x1; x++)
            smp[x - x0] = sampler_make(s->sampler, s->seed, row + x);
        for (int k = j->s0; k < j->s1; k++) {
            for (int x = x0; x < x1; x++) {
                Sampler *sm = &smp[x - x0];
                sampler_start(sm, (uint32_t)k);
                float jit[2] = {0.5f, 0.5f};
                if (s->pixel_jitter)
                    sampler_2d(sm, jit);
                else
                    sampler_skip_2d(sm); /* the light's sample and the bounce keep their blocks */
                camera_ray_dir(&j->cam, x + jit[0], y + jit[1], d[x - x0]);
            }
            pt_intersect_packet(&j->ps, cam, (const vec3 *)d, x1 - x0, hits, hit);
            for (int i = 0; i < x1 - x0; i++) {
                Path *p = &path[i];
                glm_vec3_copy((float *)cam, p->o);
                glm_vec3_copy(d[i], p->d);
                glm_vec3_one(p->thr);
                glm_vec3_zero(p->L);
                p->pdf_prev = -1.f;
                p->alive = hit[i];
                if (hit[i])
                    p->hit = hits[i];
            }
            *rays += (uint64_t)(x1 - x0); /* the camera rays */
            /* Together where the scene's records and texels overflow the
             * caches; one by one where they fit (lock step costs the
             * Cornell box 5%: the loops' bookkeeping). */
            int group = s->path_group > 0 ? s->path_group : j->ps.memory_bound ? x1 - x0 : 1;
            for (int i = 0; i < x1 - x0; i += group)
                trace_paths(j, &pm, path + i, group < x1 - x0 - i ? group : x1 - x0 - i, smp + i, rays);
            for (int x = x0; x < x1; x++) {
                const float *L = path[x - x0].L;
                double *sum = j->sum + 3 * (row + x), *sum2 = j->sum2 + 3 * (row + x);
                for (int c = 0; c < 3; c++) {
                    float v = isfinite(L[c]) ? L[c] : 0.f;
                    sum[c] += v;
                    sum2[c] += (double)v * v;
                }
            }
        }
    }
}

/* Renders tiles of the running pass until none is left or the pass is
 * cancelled; the calling thread calls tick(ctx) between tiles if given. */
static void work_tiles(Job *j, void (*tick)(void *), void *ctx)
{
    /* Denormals flushed to zero, as Embree asks of every thread that traces
     * (its kernels slow down severely on denormal operands); this thread's
     * mode is restored on return (the caller's thread works too). */
#if defined(__SSE2__)
    unsigned int csr = _mm_getcsr();
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
    int n = j->tiles_x * j->tiles_y;
    for (int t; !(j->cancel && atomic_load(j->cancel)) && (t = atomic_fetch_add(&j->next_tile, 1)) < n;) {
        uint64_t rays = 0;
        render_tile(j, t, &rays);
        atomic_fetch_add(&j->rays, rays);
        atomic_fetch_add(&j->tiles_done, 1);
        if (tick)
            tick(ctx);
    }
#if defined(__SSE2__)
    _mm_setcsr(csr);
#endif
}

static void *worker(void *arg)
{
    work_tiles(arg, NULL, NULL);
    return NULL;
}

bool pt_thread_start(pthread_t *t, void *(*fn)(void *), void *arg, bool background)
{
    if (pthread_create(t, NULL, fn, arg) != 0)
        return false;
#if defined(SCHED_IDLE)
    /* Set on the running thread: glibc's pthread_attr_setschedpolicy takes
     * only SCHED_OTHER, FIFO and RR (EINVAL for SCHED_IDLE), so the
     * attribute had silently given every thread the ordinary policy. A
     * system that refuses the policy keeps an ordinary thread. */
    if (background) {
        struct sched_param prio = {0};
        pthread_setschedparam(*t, SCHED_IDLE, &prio);
    }
#else
    (void)background;
#endif
    return true;
}

Job *pt_job_create(const Scene *scene, const PtSettings *set)
{
    sampler_init();
    Job *j = calloc(1, sizeof *j);
    size_t npix = (size_t)set->width * (size_t)set->height;
    int helpers = set->threads > 1 ? set->threads - 1 : 0;
    if (j) {
        j->sum = calloc(npix * 3, sizeof(double));
        j->sum2 = calloc(npix * 3, sizeof(double));
        j->threads = calloc((size_t)helpers + 1, sizeof(pthread_t));
    }
    if (!j || !j->sum || !j->sum2 || !j->threads) {
        log_error("reference", "cannot allocate the %dx%d sums (%.2f GiB)", set->width, set->height,
                  (double)(npix * 6 * sizeof(double)) / (1u << 30));
    } else if (pt_scene_create(&j->ps, scene)) { /* logs */
        j->scene = scene;
        j->set = set;
        camera_ray_basis(&scene->camera, set->width, set->height, &j->cam);
        j->tiles_x = (set->width + TILE - 1) / TILE;
        j->tiles_y = (set->height + TILE - 1) / TILE;
        atomic_init(&j->rays, 0);
        return j;
    }
    if (j)
        free(j->sum), free(j->sum2), free(j->threads);
    free(j);
    return NULL;
}

void pt_job_destroy(Job *j)
{
    if (!j)
        return;
    free(j->sum);
    free(j->sum2);
    free(j->threads);
    free(j->mats);
    free(j->lconst);
    pt_scene_destroy(&j->ps);
    free(j);
}

void pt_job_clear(Job *j)
{
    size_t n = 3 * (size_t)j->set->width * (size_t)j->set->height;
    memset(j->sum, 0, n * sizeof(double));
    memset(j->sum2, 0, n * sizeof(double));
    atomic_store(&j->rays, 0);
    camera_ray_basis(&j->scene->camera, j->set->width, j->set->height, &j->cam);
}

/* Passes of about 2^18 samples: short enough that a stop request or a
 * time budget ends a render within a second or so, long enough that the
 * threads stay busy. The schedule depends on the size only. */
int pt_job_pass_spp(const Job *j)
{
    size_t npix = (size_t)j->set->width * (size_t)j->set->height;
    int pass_spp = (int)((((size_t)1 << 18) + npix - 1) / npix);
    return pass_spp < 1 ? 1 : pass_spp;
}

bool pt_job_pass(Job *j, int s0, int s1, int nthreads, bool background, const atomic_int *cancel,
                 void (*tick)(void *), void *ctx)
{
    j->s0 = s0;
    j->s1 = s1;
    j->cancel = cancel;
    atomic_store(&j->next_tile, 0);
    atomic_store(&j->tiles_done, 0);
    materials_refresh(j);
    lights_refresh(j);
    int helpers = nthreads - 1, max = j->set->threads > 1 ? j->set->threads - 1 : 0;
    helpers = helpers < 0 ? 0 : helpers > max ? max : helpers;
    int started = 0;
    for (; started < helpers; started++)
        if (!pt_thread_start(&j->threads[started], worker, j, background))
            break; /* the threads started do the work */
    work_tiles(j, tick, ctx);
    for (int i = 0; i < started; i++)
        pthread_join(j->threads[i], NULL);
    return atomic_load(&j->tiles_done) == j->tiles_x * j->tiles_y;
}

int pt_job_tiles_done(const Job *j, int *total)
{
    *total = j->tiles_x * j->tiles_y;
    return atomic_load(&j->tiles_done);
}

double pt_job_relmse_estimate(const Job *j, int spp)
{
    if (spp < 2)
        return 0.0;
    size_t n = 3 * (size_t)j->set->width * (size_t)j->set->height;
    double acc = 0.0;
    for (size_t i = 0; i < n; i++) {
        double m = j->sum[i] / spp, var = (j->sum2[i] - spp * m * m) / (spp - 1);
        acc += fmax(var, 0.0) / spp / (m * m + 0.01);
    }
    return acc / (double)n;
}

void pt_job_resolve(const Job *j, int spp, ImageF *mean, ImageF *variance)
{
    for (size_t i = 0; i < 3 * (size_t)j->set->width * (size_t)j->set->height; i++) {
        double m = spp > 0 ? j->sum[i] / spp : 0.0;
        mean->rgb[i] = (float)m;
        if (variance) {
            double var = spp > 1 ? (j->sum2[i] - spp * m * m) / (spp - 1) : 0.0;
            variance->rgb[i] = (float)(fmax(var, 0.0) / spp);
        }
    }
}

uint64_t pt_job_rays(const Job *j)
{
    return atomic_load(&j->rays);
}

/* ---------------------------------------------------------------- pt_render */

/* What pt_render's progress needs between tiles. */
typedef struct Progress {
    Job *job;
    double t0;          /* when the render started (util_seconds) */
    double printed_at;  /* when the last line was printed (s since t0) */
    double drawn_at;    /* when the bar was last drawn (s since t0) */
    int spp_goal;       /* the samples per pixel the render expects to stop at */
} Progress;

/* Progress on stderr: a bar redrawn in place on a terminal, else one line
 * every 5 s (logs; RTGI_PROGRESS_S sets the interval, log_progress_seconds)
 * and a last one; with the samples reached, rays/s and the time left. */
static void draw_progress(Progress *p, int spp, double frac, bool last)
{
    double elapsed = util_seconds() - p->t0;
    bool tty = isatty(STDERR_FILENO);
    double every = log_progress_seconds(5.0);
    /* Off a terminal a render shorter than the interval prints nothing (the
     * final line only closes earlier ones; with an interval of 0, always). */
    if (!tty && (last ? p->printed_at <= 0 && every > 0 : elapsed - p->printed_at < every))
        return;
    p->printed_at = elapsed;
    double rps = elapsed > 0 ? (double)pt_job_rays(p->job) / elapsed : 0.0;
    /* The time left is unknown until a pass has finished: "ETA ?" then. */
    char eta[32] = "?";
    if (frac > 0)
        snprintf(eta, sizeof eta, "%.1f s", elapsed * (1.0 - frac) / frac);
    char bar[41];
    int filled = (int)(frac * 40);
    for (int i = 0; i < 40; i++)
        bar[i] = i < filled ? '#' : ' ';
    bar[40] = 0;
    fprintf(stderr, "%sreference [%s] %3d%%  %d/%d spp  %.1f s  %.2f Mrays/s  ETA %s%s", tty ? "\r" : "", bar,
            (int)(100 * frac), spp, p->spp_goal, elapsed, rps / 1e6, eta, tty && !last ? "" : "\n");
    fflush(stderr);
}

/* Between tiles: the bar, at most every 0.2 s. */
static void progress_tick(void *ctx)
{
    Progress *p = ctx;
    double now = util_seconds() - p->t0;
    if (now - p->drawn_at < 0.2)
        return;
    p->drawn_at = now;
    int total, done = pt_job_tiles_done(p->job, &total);
    double spp_done = p->job->s0 + (double)done / total * (p->job->s1 - p->job->s0);
    draw_progress(p, p->job->s0, fmin(1.0, spp_done / p->spp_goal), false);
}

/* The line before a long render, after its first pass (`spp` samples per
 * pixel in `secs` seconds): what the rest will take. */
static void log_forecast(const PtSettings *set, Job *j, int spp, double secs, int *goal)
{
    double per_spp = secs / spp;
    if (set->target_relmse > 0.0) {
        /* relMSE ∝ 1/spp: the samples that bring the estimate to the target. */
        double est = pt_job_relmse_estimate(j, spp);
        double need = est > 0.0 ? ceil(spp * est / set->target_relmse) : spp;
        need = fmax(need, PT_TARGET_MIN_SPP);
        *goal = need < set->spp ? (int)need : set->spp;
        log_info("reference", "estimated relMSE %.3g at %d spp; the target %g needs about %d spp: about %.1f s "
                 "(%.3f s per spp)", est, spp, set->target_relmse, *goal, per_spp * *goal, per_spp);
    } else if (set->time_budget > 0.0 && per_spp * set->spp > set->time_budget) {
        *goal = (int)fmax(spp, set->time_budget / per_spp);
        log_info("reference", "time budget %.1f s: about %d of %d spp (%.3f s per spp)", set->time_budget, *goal,
                 set->spp, per_spp);
    } else {
        log_info("reference", "%d spp: about %.1f s (%.3f s per spp, from the first %d)", set->spp,
                 per_spp * set->spp, per_spp, spp);
    }
}

/* Every pass until the samples are done, set->stop is raised, the
 * estimated relMSE reaches set->target_relmse or the next pass would end
 * past set->time_budget; the samples per pixel reached. */
static int run_passes(Job *j, const PtSettings *set, Progress *p, PtStop *why)
{
    int pass_spp = pt_job_pass_spp(j), nthreads = set->threads < 1 ? 1 : set->threads;
    int spp = 0;
    *why = PT_STOP_SPP;
    for (int pass = 0; spp < set->spp; pass++) {
        int s1 = spp + pass_spp < set->spp ? spp + pass_spp : set->spp;
        double started = util_seconds();
        pt_job_pass(j, spp, s1, nthreads, false, NULL, set->progress ? progress_tick : NULL, p);
        double now = util_seconds(), took = now - started;
        spp = s1;
        if (spp >= set->spp)
            break;
        if (pass == 0 && set->progress)
            log_forecast(set, j, spp, now - p->t0, &p->spp_goal);
        if (set->stop && *set->stop) {
            *why = PT_STOP_INTERRUPTED;
            break;
        }
        if (set->target_relmse > 0.0 && spp >= PT_TARGET_MIN_SPP &&
            pt_job_relmse_estimate(j, spp) <= set->target_relmse) {
            *why = PT_STOP_TARGET;
            break;
        }
        /* The next pass is about as long as this one. */
        if (set->time_budget > 0.0 && now + took - p->t0 > set->time_budget) {
            *why = PT_STOP_TIME;
            break;
        }
    }
    return spp;
}

bool pt_render(const Scene *scene, const PtSettings *set, ImageF *mean, ImageF *variance, PtStats *stats)
{
    memset(mean, 0, sizeof *mean);
    if (variance)
        memset(variance, 0, sizeof *variance);
    /* The outputs first: a size that cannot be held fails before the BVH
     * build and the render. */
    if (!image_alloc(mean, set->width, set->height)) /* logs */
        return false;
    if (variance && !image_alloc(variance, set->width, set->height)) {
        image_free(mean);
        return false;
    }
    Job *j = pt_job_create(scene, set);
    if (!j) {
        image_free(mean);
        if (variance)
            image_free(variance);
        return false;
    }
    Progress p = {.job = j, .t0 = util_seconds(), .spp_goal = set->spp};
    PtStop why;
    int spp = run_passes(j, set, &p, &why);
    if (set->progress)
        draw_progress(&p, spp, fmin(1.0, (double)spp / p.spp_goal), true);
    pt_job_resolve(j, spp, mean, variance);
    if (stats) {
        stats->seconds = util_seconds() - p.t0;
        stats->rays = pt_job_rays(j);
        stats->spp = spp;
        stats->stopped = why;
        stats->relmse_estimate = pt_job_relmse_estimate(j, spp);
    }
    pt_job_destroy(j);
    return true;
}

bool pt_emitter_mask(const Scene *scene, int w, int h, uint8_t *mask)
{
    PtScene ps;
    if (!pt_scene_create(&ps, scene))
        return false;
    uint8_t *sees = calloc((size_t)w * h, 1);
    if (!sees) {
        log_error("reference", "cannot allocate a %dx%d emitter mask", w, h);
        pt_scene_destroy(&ps);
        return false;
    }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            vec3 d;
            PtHit hit;
            camera_ray(&scene->camera, w, h, (float)x + 0.5f, (float)y + 0.5f, d);
            if (!pt_intersect(&ps, scene->camera.position, d, INFINITY, &hit))
                continue;
            const Material *m = &scene->materials[hit.material];
            sees[(size_t)y * w + x] = hit.front && (m->emission[0] > 0.f || m->emission[1] > 0.f || m->emission[2] > 0.f);
        }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            bool near = false;
            for (int dy = -1; dy <= 1 && !near; dy++)
                for (int dx = -1; dx <= 1 && !near; dx++) {
                    int u = x + dx, v = y + dy;
                    near = u >= 0 && v >= 0 && u < w && v < h && sees[(size_t)v * w + u];
                }
            mask[(size_t)y * w + x] = near ? 0 : 255;
        }
    free(sees);
    pt_scene_destroy(&ps);
    return true;
}

bool pt_surface_map(const Scene *scene, int w, int h, int32_t *ids)
{
    PtScene ps;
    if (!pt_scene_create(&ps, scene))
        return false;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            vec3 d;
            PtHit hit;
            camera_ray(&scene->camera, w, h, (float)x + 0.5f, (float)y + 0.5f, d);
            int32_t *id = &ids[(size_t)y * w + x];
            *id = -1;
            if (!pt_intersect(&ps, scene->camera.position, d, INFINITY, &hit))
                continue;
            int axis = 0; /* the dominant axis of the normal that faces the camera */
            for (int k = 1; k < 3; k++)
                if (fabsf(hit.ng[k]) > fabsf(hit.ng[axis]))
                    axis = k;
            *id = hit.material * 6 + 2 * axis + (hit.ng[axis] < 0.f);
        }
    pt_scene_destroy(&ps);
    return true;
}

bool pt_write_emitter_mask(const Scene *scene, int w, int h, const char *path)
{
    uint8_t *mask = malloc((size_t)w * h), *rgb = malloc((size_t)w * h * 3);
    bool ok = mask && rgb;
    if (!ok)
        log_error("reference", "cannot allocate a %dx%d emitter mask", w, h);
    ok = ok && pt_emitter_mask(scene, w, h, mask);
    for (size_t i = 0; ok && i < (size_t)w * h; i++)
        rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = mask[i];
    ok = ok && image_write_png8(path, w, h, rgb);
    free(mask);
    free(rgb);
    return ok;
}
