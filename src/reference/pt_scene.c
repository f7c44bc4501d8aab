#include "reference/pt_scene.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "image.h"
#include "log.h"

/* Embree 3's RTCHitN/RTCRayN accessors are C++ only; these read the same
 * documented structure-of-arrays layout (rtcore_ray.h) from C. */
static inline float hitn_u(const struct RTCHitN *h, unsigned n, unsigned i) { return ((const float *)h)[3 * n + i]; }
static inline float hitn_v(const struct RTCHitN *h, unsigned n, unsigned i) { return ((const float *)h)[4 * n + i]; }
static inline unsigned hitn_prim(const struct RTCHitN *h, unsigned n, unsigned i) { return ((const unsigned *)h)[5 * n + i]; }
static inline unsigned hitn_geom(const struct RTCHitN *h, unsigned n, unsigned i) { return ((const unsigned *)h)[6 * n + i]; }
static inline float rayn_tfar(const struct RTCRayN *r, unsigned n, unsigned i) { return ((const float *)r)[8 * n + i]; }

static float g_srgb_lut[256];
static pthread_once_t g_lut_once = PTHREAD_ONCE_INIT;

static void init_lut(void)
{
    for (int i = 0; i < 256; i++)
        g_srgb_lut[i] = srgb_decode((float)i / 255.f);
}

static void embree_error(void *user, enum RTCError code, const char *msg)
{
    (void)user;
    log_error("embree", "error %d: %s", (int)code, msg ? msg : "");
}

/* Texel fetch with wrap-around; row 0 of the image is v = 0. */
static const uint8_t *texel(const Texture *t, int x, int y)
{
    x %= t->width;
    y %= t->height;
    if (x < 0)
        x += t->width;
    if (y < 0)
        y += t->height;
    return t->rgba + 4 * ((size_t)y * t->width + x);
}

static void tri_uv(const Scene *s, uint32_t tri, float bu, float bv, float uv[2])
{
    const Vertex *a = &s->vertices[s->indices[3 * tri]], *b = &s->vertices[s->indices[3 * tri + 1]],
                 *c = &s->vertices[s->indices[3 * tri + 2]];
    float w = 1.f - bu - bv;
    uv[0] = w * a->uv[0] + bu * b->uv[0] + bv * c->uv[0];
    uv[1] = w * a->uv[1] + bu * b->uv[1] + bv * c->uv[1];
}

/* Alpha at uv, bilinear as the colour (texture_bilinear) and as the
 * rasterizer's sampler and glTF's LINEAR filter read it. It was the
 * nearest texel's: a mask of lone opaque texels covered 25% here and
 * (1 − ln 2)/2 = 15.3% in the rasterizer (issue 49). */
static float alpha_at(const Texture *t, const float uv[2])
{
    float x = uv[0] * t->width - 0.5f, y = uv[1] * t->height - 0.5f;
    int x0 = (int)floorf(x), y0 = (int)floorf(y);
    float fx = x - x0, fy = y - y0;
    return ((1 - fx) * (1 - fy) * texel(t, x0, y0)[3] + fx * (1 - fy) * texel(t, x0 + 1, y0)[3] +
            (1 - fx) * fy * texel(t, x0, y0 + 1)[3] + fx * fy * texel(t, x0 + 1, y0 + 1)[3]) / 255.f;
}

/* Rejects hits on texels below the material's alpha cutoff. */
static void alpha_filter(const struct RTCFilterFunctionNArguments *args)
{
    const PtScene *ps = args->geometryUserPtr;
    for (unsigned i = 0; i < args->N; i++) {
        if (args->valid[i] != -1)
            continue;
        uint32_t prim = hitn_prim(args->hit, args->N, i);
        uint32_t tri = ps->prim_tri[1][prim];
        const Material *m = &ps->scene->materials[ps->tri_material[tri]];
        float uv[2];
        tri_uv(ps->scene, tri, hitn_u(args->hit, args->N, i), hitn_v(args->hit, args->N, i), uv);
        if (m->albedo_tex >= 0 && alpha_at(&ps->scene->textures[m->albedo_tex], uv) < m->alpha_cutoff)
            args->valid[i] = 0;
    }
}

bool pt_scene_create(PtScene *ps, const Scene *s)
{
    pthread_once(&g_lut_once, init_lut);
    memset(ps, 0, sizeof *ps);
    ps->scene = s;
    ps->device = rtcNewDevice(NULL);
    if (!ps->device) {
        log_error("embree", "cannot create an Embree device (error %d)", (int)rtcGetDeviceError(NULL));
        return false;
    }
    rtcSetDeviceErrorFunction(ps->device, embree_error, NULL);
    ps->rtc = rtcNewScene(ps->device);
    rtcSetSceneFlags(ps->rtc, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(ps->rtc, RTC_BUILD_QUALITY_HIGH);

    uint32_t ntri = s->index_count / 3;
    size_t table = sizeof(uint32_t) * ((size_t)ntri + 1);
    ps->tri_material = malloc(table);
    for (int g = 0; g < 2; g++)
        ps->prim_tri[g] = malloc(table);
    if (!ps->tri_material || !ps->prim_tri[0] || !ps->prim_tri[1]) {
        log_error("reference", "cannot allocate the triangle tables of %u triangles (3 × %zu bytes)", ntri, table);
        pt_scene_destroy(ps);
        return false;
    }
    for (int k = 0; k < s->submesh_count; k++)
        for (uint32_t t = s->submeshes[k].first_index / 3;
             t < (s->submeshes[k].first_index + s->submeshes[k].index_count) / 3; t++)
            ps->tri_material[t] = (uint32_t)s->submeshes[k].material;

    uint32_t count[2] = {0, 0};
    for (uint32_t t = 0; t < ntri; t++) {
        int g = s->materials[ps->tri_material[t]].alpha_mask ? 1 : 0;
        ps->prim_tri[g][count[g]++] = t;
    }
    for (int g = 0; g < 2; g++) {
        if (count[g] == 0)
            continue;
        RTCGeometry geo = rtcNewGeometry(ps->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        /* The scene's own vertex array; Embree reads 16 bytes per position,
         * which the following normal covers. */
        rtcSetSharedGeometryBuffer(geo, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, s->vertices, 0,
                                   sizeof(Vertex), s->vertex_count);
        uint32_t *ib = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                               3 * sizeof(uint32_t), count[g]);
        if (!ib) {
            log_error("reference", "cannot allocate the index buffer of %u triangles (%zu bytes)", count[g],
                      (size_t)count[g] * 3 * sizeof(uint32_t));
            rtcReleaseGeometry(geo);
            pt_scene_destroy(ps);
            return false;
        }
        for (uint32_t i = 0; i < count[g]; i++)
            memcpy(ib + 3 * i, s->indices + 3 * ps->prim_tri[g][i], 3 * sizeof(uint32_t));
        if (g == 1) {
            rtcSetGeometryUserData(geo, ps);
            rtcSetGeometryIntersectFilterFunction(geo, alpha_filter);
            rtcSetGeometryOccludedFilterFunction(geo, alpha_filter);
        }
        rtcCommitGeometry(geo);
        rtcAttachGeometryByID(ps->rtc, geo, (unsigned)g);
        rtcReleaseGeometry(geo);
    }
    rtcCommitScene(ps->rtc);
    ps->diag = glm_vec3_distance((float *)s->bounds_min, (float *)s->bounds_max);
    if (ps->diag <= 0.f)
        ps->diag = 1.f;
    if (rtcGetDeviceError(ps->device) != RTC_ERROR_NONE) {
        pt_scene_destroy(ps);
        return false;
    }
    return true;
}

void pt_scene_destroy(PtScene *ps)
{
    if (ps->rtc)
        rtcReleaseScene(ps->rtc);
    if (ps->device)
        rtcReleaseDevice(ps->device);
    free(ps->prim_tri[0]);
    free(ps->prim_tri[1]);
    free(ps->tri_material);
    memset(ps, 0, sizeof *ps);
}

static void init_ray(struct RTCRay *r, const vec3 o, const vec3 d, float tmax)
{
    r->org_x = o[0];
    r->org_y = o[1];
    r->org_z = o[2];
    r->dir_x = d[0];
    r->dir_y = d[1];
    r->dir_z = d[2];
    r->tnear = 0.f;
    r->tfar = tmax;
    r->time = 0.f;
    r->mask = 0xffffffffu;
    r->id = 0;
    r->flags = 0;
}

/* Fills a PtHit from Embree's geometry/primitive/barycentrics. */
static void fill_hit(const PtScene *ps, const vec3 o, const vec3 d, float t, unsigned geom, unsigned prim,
                     float bu, float bv, PtHit *h)
{
    const Scene *s = ps->scene;
    uint32_t tri = ps->prim_tri[geom][prim];
    const Vertex *a = &s->vertices[s->indices[3 * tri]], *b = &s->vertices[s->indices[3 * tri + 1]],
                 *c = &s->vertices[s->indices[3 * tri + 2]];
    h->t = t;
    (void)o;
    /* The hit point from the barycentrics rather than o + t·d: its rounding
     * error is a few ulps of the vertices' coordinates, whatever the ray's
     * length (Wächter & Binder 2019, §6.2), which pt_offset relies on. */
    vec3 e1, e2;
    glm_vec3_sub((float *)b->position, (float *)a->position, e1);
    glm_vec3_sub((float *)c->position, (float *)a->position, e2);
    for (int i = 0; i < 3; i++)
        h->p[i] = a->position[i] + bu * e1[i] + bv * e2[i];
    glm_vec3_cross(e1, e2, h->ng);
    glm_vec3_normalize(h->ng);
    float w = 1.f - bu - bv;
    for (int i = 0; i < 3; i++)
        h->ns[i] = w * a->normal[i] + bu * b->normal[i] + bv * c->normal[i];
    glm_vec3_normalize(h->ns);
    h->front = glm_vec3_dot(h->ng, (float *)d) < 0.f;
    if (!h->front)
        glm_vec3_negate(h->ng);
    if (glm_vec3_dot(h->ns, h->ng) < 0.f)
        glm_vec3_negate(h->ns);
    h->uv[0] = w * a->uv[0] + bu * b->uv[0] + bv * c->uv[0];
    h->uv[1] = w * a->uv[1] + bu * b->uv[1] + bv * c->uv[1];
    h->material = (int)ps->tri_material[tri];
}

bool pt_intersect(const PtScene *ps, const vec3 o, const vec3 d, float tmax, PtHit *h)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    init_ray(&rh.ray, o, d, tmax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(ps->rtc, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return false;
    fill_hit(ps, o, d, rh.ray.tfar, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, h);
    return true;
}

typedef struct AllHitsContext {
    struct RTCIntersectContext base; /* first member: Embree passes &base */
    const PtScene *ps;
    const float *o, *d;
    PtHit *hits;
    int max, count;
} AllHitsContext;

/* Records every (alpha-accepted) hit and rejects it, so traversal goes on. */
static void collect_filter(const struct RTCFilterFunctionNArguments *args)
{
    AllHitsContext *c = (AllHitsContext *)args->context;
    for (unsigned i = 0; i < args->N; i++) {
        if (args->valid[i] != -1)
            continue;
        if (c->count < c->max)
            fill_hit(c->ps, c->o, c->d, rayn_tfar(args->ray, args->N, i), hitn_geom(args->hit, args->N, i),
                     hitn_prim(args->hit, args->N, i), hitn_u(args->hit, args->N, i),
                     hitn_v(args->hit, args->N, i), &c->hits[c->count++]);
        args->valid[i] = 0;
    }
}

int pt_intersect_all(const PtScene *ps, const vec3 o, const vec3 d, float tmax, PtHit *hits, int max)
{
    AllHitsContext c;
    rtcInitIntersectContext(&c.base);
    c.base.filter = collect_filter;
    c.ps = ps;
    c.o = o;
    c.d = d;
    c.hits = hits;
    c.max = max;
    c.count = 0;
    struct RTCRayHit rh;
    init_ray(&rh.ray, o, d, tmax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(ps->rtc, &c.base, &rh);
    return c.count;
}

bool pt_occluded(const PtScene *ps, const vec3 o, const vec3 d, float tmax)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay r;
    init_ray(&r, o, d, tmax);
    rtcOccluded1(ps->rtc, &ctx, &r);
    return r.tfar < 0.f;
}

/* Bilinear over the base level of t at uv; colour sRGB-decoded per texel
 * unless the texture holds data (linear). */
static void texture_bilinear(const Texture *t, const float uv[2], vec3 out)
{
    float x = uv[0] * t->width - 0.5f, y = uv[1] * t->height - 0.5f;
    int x0 = (int)floorf(x), y0 = (int)floorf(y);
    float fx = x - x0, fy = y - y0;
    const uint8_t *p[4] = {texel(t, x0, y0), texel(t, x0 + 1, y0), texel(t, x0, y0 + 1), texel(t, x0 + 1, y0 + 1)};
    float wgt[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    for (int c = 0; c < 3; c++) {
        float v = 0;
        for (int k = 0; k < 4; k++)
            v += wgt[k] * (t->linear ? p[k][c] / 255.f : g_srgb_lut[p[k][c]]);
        out[c] = v;
    }
}

void pt_albedo(const PtScene *ps, const PtHit *h, vec3 out)
{
    const Material *m = &ps->scene->materials[h->material];
    glm_vec3_copy((float *)m->albedo, out);
    if (m->albedo_tex < 0)
        return;
    vec3 t;
    texture_bilinear(&ps->scene->textures[m->albedo_tex], h->uv, t);
    glm_vec3_mul(out, t, out);
}

void pt_surface(const PtScene *ps, const PtHit *h, BrdfSurface *out)
{
    const Material *m = &ps->scene->materials[h->material];
    vec3 base;
    pt_albedo(ps, h, base);
    float metallic = m->metallic, roughness = m->roughness;
    if (m->mr_tex >= 0) {
        vec3 t;
        texture_bilinear(&ps->scene->textures[m->mr_tex], h->uv, t);
        roughness *= t[1];
        metallic *= t[2];
    }
    brdf_surface(base, metallic, roughness, m->specular, out);
}

/* Wächter & Binder, "A Fast and Robust Method for Avoiding
 * Self-Intersection" (Ray Tracing Gems, ch. 6, 2019). A computed hit point
 * lies within a few ulps of the true surface, and an ulp grows with the
 * coordinate's magnitude; so each coordinate moves along the normal by a
 * fixed number of ulps of itself (OFFSET_INT · n_i, stepping the float's
 * bits as an integer), which is the same relative safety margin anywhere in
 * the scene and no more. Near zero an ulp vanishes, so coordinates below
 * OFFSET_ORIGIN move by a small absolute amount OFFSET_FLOAT · n_i instead. */
enum { OFFSET_INT = 256 };
#define OFFSET_FLOAT (1.f / 65536.f)
#define OFFSET_ORIGIN (1.f / 32.f)

static float float_step_ulps(float x, int32_t ulps)
{
    int32_t bits;
    memcpy(&bits, &x, sizeof bits);
    bits += x < 0.f ? -ulps : ulps; /* away from zero for ulps > 0 on either sign */
    memcpy(&x, &bits, sizeof x);
    return x;
}

void pt_offset(const vec3 p, const vec3 n, vec3 out)
{
    for (int i = 0; i < 3; i++) {
        int32_t of = (int32_t)(OFFSET_INT * n[i]);
        float moved = float_step_ulps(p[i], of);
        out[i] = fabsf(p[i]) < OFFSET_ORIGIN ? p[i] + OFFSET_FLOAT * n[i] : moved;
    }
}
