#include "reference/pathtracer.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "camera.h"
#include "log.h"
#include "reference/pt_scene.h"
#include "reference/rng.h"
#include "reference/sampling.h"
#include "util.h"

const char *const pt_mode_names[] = {"full", "direct", "one-bounce", "one-bounce-novis", "indirect", NULL};

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
}

typedef struct Job {
    const Scene *scene;
    const PtSettings *set;
    PtScene ps;
    double *sum, *sum2;    /* per pixel RGB */
    int tiles_x, tiles_y;
    atomic_int next_tile;
    atomic_int tiles_done;
    atomic_uint_fast64_t rays;
} Job;

/* ---------------------------------------------------------------- lights */

/* Direct light from light `l` at hit h (normal n, albedo omitted): returns
 * the estimate of ∫ L cos dω (so radiance = albedo/π × this), with MIS
 * weighting for quad lights when `mis` is set. */
static void light_sample(Job *j, const Light *l, const PtHit *h, Rng *rng, bool mis, uint64_t *rays, vec3 out)
{
    const PtScene *ps = &j->ps;
    glm_vec3_zero(out);
    vec3 o, wi;
    pt_offset(ps, h->p, h->ng, o);
    float dist = 0.f;
    vec3 le = {0, 0, 0}; /* L·cos_x/pdf before visibility */
    switch (l->type) {
    case LIGHT_DIRECTIONAL: {
        glm_vec3_negate_to((float *)l->direction, wi);
        if (l->size > 0.f) {
            float a = 0.5f * l->size, cos_max = cosf(a), s = sinf(a);
            vec3 axis;
            glm_vec3_copy(wi, axis);
            sample_cone(axis, cos_max, rng_float(rng), rng_float(rng), wi);
            /* L = E/(π sin²a) so that irradiance facing the sun is E; pdf = 1/Ω. */
            float omega = 2.f * GLM_PIf * (1.f - cos_max);
            glm_vec3_scale((float *)l->color, omega / (GLM_PIf * s * s), le);
        } else {
            glm_vec3_copy((float *)l->color, le);
        }
        float c = glm_vec3_dot(wi, (float *)h->ns);
        if (c <= 0.f || glm_vec3_dot(wi, (float *)h->ng) <= 0.f)
            return;
        glm_vec3_scale(le, c, le);
        dist = 4.f * ps->diag;
        break;
    }
    case LIGHT_POINT:
    case LIGHT_SPOT: {
        vec3 lp;
        glm_vec3_copy((float *)l->position, lp);
        if (l->size > 0.f && l->type == LIGHT_POINT) {
            /* Sphere of radius r, radiance I/(πr²), sampled by solid angle. */
            float r = 0.5f * l->size;
            vec3 toc;
            glm_vec3_sub(lp, o, toc);
            float dc = glm_vec3_norm(toc);
            if (dc <= r)
                return;
            glm_vec3_scale(toc, 1.f / dc, toc);
            float sin2 = r * r / (dc * dc), cos_max = sqrtf(fmaxf(0.f, 1.f - sin2));
            sample_cone(toc, cos_max, rng_float(rng), rng_float(rng), wi);
            float c = glm_vec3_dot(wi, (float *)h->ns);
            if (c <= 0.f || glm_vec3_dot(wi, (float *)h->ng) <= 0.f)
                return;
            /* Distance to the sphere along wi. */
            float b = glm_vec3_dot(wi, toc) * dc;
            float disc = b * b - (dc * dc - r * r);
            dist = b - sqrtf(fmaxf(disc, 0.f));
            float omega = 2.f * GLM_PIf * (1.f - cos_max);
            glm_vec3_scale((float *)l->color, c * omega / (GLM_PIf * r * r), le);
            break;
        }
        if (l->size > 0.f) /* spot: disk of the given diameter facing its axis */
            sample_disk(l->position, l->direction, 0.5f * l->size, rng_float(rng), rng_float(rng), lp);
        glm_vec3_sub(lp, o, wi);
        dist = glm_vec3_norm(wi);
        glm_vec3_scale(wi, 1.f / dist, wi);
        float c = glm_vec3_dot(wi, (float *)h->ns);
        if (c <= 0.f || glm_vec3_dot(wi, (float *)h->ng) <= 0.f)
            return;
        vec3 out_dir, inten;
        glm_vec3_negate_to(wi, out_dir);
        if (l->size > 0.f && glm_vec3_dot(out_dir, (float *)l->direction) <= 0.f)
            return; /* behind the disk */
        light_intensity(l, out_dir, inten);
        glm_vec3_scale(inten, c / (dist * dist), le);
        break;
    }
    case LIGHT_QUAD: {
        vec3 lp, out_dir, n;
        glm_vec3_copy((float *)l->position, lp);
        if (l->size > 0.f) {
            float u1 = rng_float(rng) - 0.5f, u2 = rng_float(rng) - 0.5f;
            glm_vec3_muladds((float *)l->quad_u, u1 * l->size, lp);
            glm_vec3_muladds((float *)l->quad_v, u2 * l->size, lp);
        }
        glm_vec3_sub(lp, o, wi);
        dist = glm_vec3_norm(wi);
        glm_vec3_scale(wi, 1.f / dist, wi);
        float c = glm_vec3_dot(wi, (float *)h->ns);
        if (c <= 0.f || glm_vec3_dot(wi, (float *)h->ng) <= 0.f)
            return;
        glm_vec3_negate_to(wi, out_dir);
        glm_vec3_copy((float *)l->direction, n);
        float cos_l = glm_vec3_dot(out_dir, n);
        if (cos_l <= 0.f)
            return;
        vec3 inten;
        light_intensity(l, out_dir, inten); /* L·A·cos_l (power independent of size) */
        glm_vec3_scale(inten, c / (dist * dist), le);
        if (l->size > 0.f && mis) {
            float area = light_quad_area(l);
            float pdf_light = dist * dist / (cos_l * area);
            float pdf_bsdf = c / GLM_PIf;
            glm_vec3_scale(le, power_heuristic(pdf_light, pdf_bsdf), le);
        }
        break;
    }
    }
    if (le[0] <= 0.f && le[1] <= 0.f && le[2] <= 0.f)
        return;
    (*rays)++;
    if (pt_occluded(ps, o, wi, dist * (1.f - 1e-4f) - ps->eps))
        return;
    glm_vec3_copy(le, out);
}

/* Sum over lights of direct-light estimates at h, times albedo/π. */
static void direct_light(Job *j, const PtHit *h, const vec3 albedo, Rng *rng, bool mis, uint64_t *rays, vec3 out)
{
    glm_vec3_zero(out);
    for (int i = 0; i < j->scene->light_count; i++) {
        vec3 e;
        light_sample(j, &j->scene->lights[i], h, rng, mis, rays, e);
        glm_vec3_add(out, e, out);
    }
    glm_vec3_mul(out, (float *)albedo, out);
    glm_vec3_scale(out, 1.f / GLM_PIf, out);
}

/* Emitted radiance seen at hit h coming from direction -d, MIS-weighted
 * against light sampling when it is a quad light's surface reached by a
 * BSDF sample of density pdf_bsdf (pdf_bsdf < 0: camera ray, weight 1). */
static void emitted(Job *j, const PtHit *h, const vec3 d, float pdf_bsdf, bool mis, vec3 out)
{
    const Material *m = &j->scene->materials[h->material];
    glm_vec3_zero(out);
    if (!h->front || (m->emission[0] <= 0.f && m->emission[1] <= 0.f && m->emission[2] <= 0.f))
        return;
    float w = 1.f;
    if (m->light_index >= 0 && pdf_bsdf >= 0.f) {
        if (!mis)
            return; /* light sampling alone counts this light */
        const Light *l = &j->scene->lights[m->light_index];
        float cos_l = -glm_vec3_dot((float *)d, (float *)l->direction);
        if (cos_l <= 0.f)
            return;
        float pdf_light = h->t * h->t / (cos_l * light_quad_area(l));
        w = power_heuristic(pdf_bsdf, pdf_light);
    }
    glm_vec3_scale((float *)m->emission, w, out);
}

/* ---------------------------------------------------------------- paths */

static void radiance(Job *j, const vec3 o0, const vec3 d0, Rng *rng, uint64_t *rays, vec3 L)
{
    const PtSettings *s = j->set;
    const PtScene *ps = &j->ps;
    int min_direct = s->mode == PT_INDIRECT ? 2 : 1;
    int max_direct = s->mode == PT_DIRECT ? 1 : (s->mode == PT_ONE_BOUNCE || s->mode == PT_ONE_BOUNCE_NOVIS) ? 2 : s->max_depth;
    bool novis = s->mode == PT_ONE_BOUNCE_NOVIS;
    bool mis = !novis;
    vec3 o, d, thr = {1, 1, 1};
    glm_vec3_copy((float *)o0, o);
    glm_vec3_copy((float *)d0, d);
    glm_vec3_zero(L);
    float pdf_prev = -1.f;
    for (int depth = 1; depth <= s->max_depth; depth++) {
        PtHit h;
        (*rays)++;
        if (!pt_intersect(ps, o, d, INFINITY, &h))
            break;
        /* Emission reaching the previous vertex is part of its direct light. */
        int owner = depth == 1 ? 1 : depth - 1;
        if (owner >= min_direct && owner <= max_direct) {
            vec3 e;
            emitted(j, &h, d, depth == 1 ? -1.f : pdf_prev, mis, e);
            glm_vec3_muladd(thr, e, L);
        }
        if (depth > max_direct)
            break;
        vec3 albedo;
        pt_albedo(ps, &h, albedo);
        if (depth >= min_direct) {
            vec3 e;
            direct_light(j, &h, albedo, rng, mis, rays, e);
            glm_vec3_muladd(thr, e, L);
        }
        if (novis) {
            /* One bounce without visibility on x1 → x2: every surface along
             * the cosine-sampled ray contributes its direct light. */
            vec3 dir, o1, t1;
            sample_cosine(h.ns, rng_float(rng), rng_float(rng), dir);
            if (glm_vec3_dot(dir, h.ng) <= 0.f)
                break;
            pt_offset(ps, h.p, h.ng, o1);
            glm_vec3_mul(thr, albedo, t1);
            PtHit hits[MAX_ALL_HITS];
            (*rays)++;
            int n = pt_intersect_all(ps, o1, dir, INFINITY, hits, MAX_ALL_HITS);
            for (int k = 0; k < n; k++) {
                vec3 a2, e;
                pt_albedo(ps, &hits[k], a2);
                direct_light(j, &hits[k], a2, rng, false, rays, e);
                glm_vec3_muladd(t1, e, L);
            }
            break;
        }
        if (s->russian_roulette && depth > s->rr_depth) {
            float p = fminf(fmaxf(thr[0], fmaxf(thr[1], thr[2])), 0.95f);
            if (rng_float(rng) >= p)
                break;
            glm_vec3_scale(thr, 1.f / p, thr);
        }
        sample_cosine(h.ns, rng_float(rng), rng_float(rng), d);
        float c = glm_vec3_dot(d, h.ns);
        if (c <= 0.f || glm_vec3_dot(d, h.ng) <= 0.f)
            break;
        pdf_prev = c / GLM_PIf;
        glm_vec3_mul(thr, albedo, thr); /* f·cos/pdf = (ρ/π)·cos/(cos/π) = ρ */
        pt_offset(ps, h.p, h.ng, o);
        if (thr[0] <= 0.f && thr[1] <= 0.f && thr[2] <= 0.f)
            break;
    }
}

static void render_tile(Job *j, int tile, uint64_t *rays)
{
    const PtSettings *s = j->set;
    int tx = tile % j->tiles_x, ty = tile / j->tiles_x;
    for (int y = ty * TILE; y < (ty + 1) * TILE && y < s->height; y++)
        for (int x = tx * TILE; x < (tx + 1) * TILE && x < s->width; x++) {
            size_t pix = (size_t)y * s->width + x;
            Rng rng = rng_make(s->seed, pix);
            double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
            for (int k = 0; k < s->spp; k++) {
                float jx = s->pixel_jitter ? rng_float(&rng) : 0.5f;
                float jy = s->pixel_jitter ? rng_float(&rng) : 0.5f;
                vec3 d, L;
                camera_ray(&j->scene->camera, s->width, s->height, x + jx, y + jy, d);
                radiance(j, j->scene->camera.position, d, &rng, rays, L);
                for (int c = 0; c < 3; c++) {
                    float v = isfinite(L[c]) ? L[c] : 0.f;
                    sum[c] += v;
                    sum2[c] += (double)v * v;
                }
            }
            memcpy(j->sum + 3 * pix, sum, sizeof sum);
            memcpy(j->sum2 + 3 * pix, sum2, sizeof sum2);
        }
}

static void *worker(void *arg)
{
    Job *j = arg;
    uint64_t rays = 0;
    int n = j->tiles_x * j->tiles_y;
    for (int t; (t = atomic_fetch_add(&j->next_tile, 1)) < n;) {
        render_tile(j, t, &rays);
        atomic_fetch_add(&j->tiles_done, 1);
    }
    atomic_fetch_add(&j->rays, rays);
    return NULL;
}

static void draw_progress(int done, int total, double elapsed)
{
    int width = 40, filled = total ? done * width / total : width;
    fprintf(stderr, "\rreference [");
    for (int i = 0; i < width; i++)
        fputc(i < filled ? '#' : ' ', stderr);
    fprintf(stderr, "] %3d%%  %.1fs", total ? 100 * done / total : 100, elapsed);
    fflush(stderr);
}

bool pt_render(const Scene *scene, const PtSettings *set, ImageF *mean, ImageF *variance, PtStats *stats)
{
    Job *j = calloc(1, sizeof *j);
    j->scene = scene;
    j->set = set;
    if (!pt_scene_create(&j->ps, scene)) {
        free(j);
        return false;
    }
    size_t npix = (size_t)set->width * set->height;
    j->sum = calloc(npix * 3, sizeof(double));
    j->sum2 = calloc(npix * 3, sizeof(double));
    j->tiles_x = (set->width + TILE - 1) / TILE;
    j->tiles_y = (set->height + TILE - 1) / TILE;
    atomic_init(&j->next_tile, 0);
    atomic_init(&j->tiles_done, 0);
    atomic_init(&j->rays, 0);

    double t0 = util_seconds();
    int nthreads = set->threads < 1 ? 1 : set->threads;
    pthread_t *th = calloc((size_t)nthreads, sizeof(pthread_t));
    for (int i = 0; i < nthreads; i++)
        pthread_create(&th[i], NULL, worker, j);
    int total = j->tiles_x * j->tiles_y;
    if (set->progress) {
        while (atomic_load(&j->tiles_done) < total) {
            draw_progress(atomic_load(&j->tiles_done), total, util_seconds() - t0);
            nanosleep(&(struct timespec){0, 200000000L}, NULL);
        }
        draw_progress(total, total, util_seconds() - t0);
        fputc('\n', stderr);
    }
    for (int i = 0; i < nthreads; i++)
        pthread_join(th[i], NULL);
    free(th);
    double secs = util_seconds() - t0;

    bool ok = image_alloc(mean, set->width, set->height);
    if (ok && variance)
        ok = image_alloc(variance, set->width, set->height);
    for (size_t i = 0; ok && i < npix * 3; i++) {
        double m = j->sum[i] / set->spp;
        mean->rgb[i] = (float)m;
        if (variance) {
            double var = set->spp > 1 ? (j->sum2[i] - set->spp * m * m) / (set->spp - 1) : 0.0;
            variance->rgb[i] = (float)(fmax(var, 0.0) / set->spp);
        }
    }
    if (stats) {
        stats->seconds = secs;
        stats->rays = atomic_load(&j->rays);
    }
    free(j->sum);
    free(j->sum2);
    pt_scene_destroy(&j->ps);
    free(j);
    return ok;
}
