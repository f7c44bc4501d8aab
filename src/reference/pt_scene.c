#include "reference/pt_scene.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "io/image.h"
#include "base/log.h"

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

/* x wrapped into [0, n). */
static inline int wrap(int x, int n)
{
    x %= n;
    return x < 0 ? x + n : x;
}

static void tri_uv(const PtTri *t, float bu, float bv, float uv[2])
{
    float w = 1.f - bu - bv;
    uv[0] = w * t->uv[0][0] + bu * t->uv[1][0] + bv * t->uv[2][0];
    uv[1] = w * t->uv[0][1] + bu * t->uv[1][1] + bv * t->uv[2][1];
}

/* The record of Embree's hit (u, v) on primitive `prim` of geometry `geom`
 * of the quad scene (quads) or the triangle scene, and the barycentrics of
 * its vertices 1 and 2 there. A quad's first triangle holds u + v ≤ 1 with
 * (u, v) its own barycentrics; Embree turns the second's (u′, v′) into the
 * quad's u = 1 − u′, v = 1 − v′. */
static inline uint32_t hit_record(const PtScene *ps, bool quads, unsigned geom, unsigned prim, float u, float v,
                                  float *bu, float *bv)
{
    if (!quads) {
        *bu = u;
        *bv = v;
        return ps->tri_base[geom] + prim;
    }
    const PtQuad *q = &ps->quad[ps->quad_base[geom] + prim];
    int side = u + v > 1.f && !q->lone;
    if (side)
        u = 1.f - u, v = 1.f - v;
    /* Embree's weights of its vertices 0, 1, 2, onto the record's. */
    float w[3] = {1.f - u - v, u, v};
    int r = q->rot[side];
    *bu = w[(4 - r) % 3];
    *bv = w[(5 - r) % 3];
    return q->rec + (uint32_t)side;
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
    /* Wrapped once per axis (texel's modulo at every texel had been most
     * of the filter's time); the next texel wraps by a compare. */
    int wx0 = wrap(x0, t->width), wy0 = wrap(y0, t->height);
    int wx1 = wx0 + 1 < t->width ? wx0 + 1 : 0, wy1 = wy0 + 1 < t->height ? wy0 + 1 : 0;
    const uint8_t *r0 = t->rgba + 4 * (size_t)wy0 * t->width, *r1 = t->rgba + 4 * (size_t)wy1 * t->width;
    return ((1 - fx) * (1 - fy) * r0[4 * wx0 + 3] + fx * (1 - fy) * r0[4 * wx1 + 3] +
            (1 - fx) * fy * r1[4 * wx0 + 3] + fx * fy * r1[4 * wx1 + 3]) / 255.f;
}

/* Rejects hits on texels below the material's alpha cutoff: of the
 * triangle scene or the quad scene. */
static void alpha_filter_in(const struct RTCFilterFunctionNArguments *args, bool quads)
{
    const PtScene *ps = args->geometryUserPtr;
    for (unsigned i = 0; i < args->N; i++) {
        if (args->valid[i] != -1)
            continue;
        float bu, bv, uv[2];
        const PtTri *t = &ps->tris[hit_record(ps, quads, 1, hitn_prim(args->hit, args->N, i),
                                              hitn_u(args->hit, args->N, i), hitn_v(args->hit, args->N, i), &bu, &bv)];
        const Material *m = &ps->scene->materials[t->material];
        tri_uv(t, bu, bv, uv);
        if (m->albedo_tex >= 0 && alpha_at(&ps->scene->textures[m->albedo_tex], uv) < m->alpha_cutoff)
            args->valid[i] = 0;
    }
}

static void alpha_filter(const struct RTCFilterFunctionNArguments *args) { alpha_filter_in(args, false); }
static void alpha_filter_quads(const struct RTCFilterFunctionNArguments *args) { alpha_filter_in(args, true); }

/* The record of triangle `tri` of the scene (material m). */
static void tri_record(const Scene *s, uint32_t tri, uint32_t m, PtTri *t)
{
    memset(t, 0, sizeof *t);
    const Vertex *v[3];
    for (int k = 0; k < 3; k++)
        v[k] = &s->vertices[s->indices[3 * tri + k]];
    glm_vec3_copy((float *)v[0]->position, t->p0);
    glm_vec3_sub((float *)v[1]->position, (float *)v[0]->position, t->e1);
    glm_vec3_sub((float *)v[2]->position, (float *)v[0]->position, t->e2);
    glm_vec3_cross(t->e1, t->e2, t->ng);
    glm_vec3_normalize(t->ng);
    for (int k = 0; k < 3; k++) {
        glm_vec3_copy((float *)v[k]->normal, t->n[k]);
        t->uv[k][0] = v[k]->uv[0];
        t->uv[k][1] = v[k]->uv[1];
    }
    t->material = m;
    /* Equal vertex normals: the interpolated normal normalised is n[0]
     * normalised, made once here (the Cornell box's every triangle). */
    if (memcmp(t->n[0], t->n[1], sizeof t->n[0]) == 0 && memcmp(t->n[0], t->n[2], sizeof t->n[0]) == 0) {
        t->flat = 1;
        glm_vec3_normalize(t->n[0]);
    }
}

/* Triangles a and b (vertex indices, one winding) as one quad q: true if
 * they share an edge, which a runs along in one direction and b in the
 * other. Then q = (v0, v1, v2, v3) with Embree's triangles (v0, v1, v3)
 * and (v2, v3, v1) being a and b rotated: Embree's vertex k of the first is
 * a[(k + rot[0]) mod 3], of the second b[(k + rot[1]) mod 3]. */
static bool quad_pair(const uint32_t a[3], const uint32_t b[3], uint32_t q[4], uint8_t rot[2])
{
    for (int r = 0; r < 3; r++) {
        uint32_t x = a[r], y = a[(r + 1) % 3], c = a[(r + 2) % 3];
        for (int k = 0; k < 3; k++)
            if (b[k] == y && b[(k + 1) % 3] == x) {
                uint32_t d = b[(k + 2) % 3];
                /* The shared edge x → y is v1 → v3: (v0, v1, v3) = (c, x, y) and (v2, v3, v1) = (d, y, x). */
                q[0] = c, q[1] = x, q[2] = d, q[3] = y;
                rot[0] = (uint8_t)((r + 2) % 3);
                rot[1] = (uint8_t)((k + 2) % 3);
                return x != y && c != x && c != y && d != x && d != y && c != d;
            }
    }
    return false;
}

/* The Embree geometry of `count` primitives of `verts` vertices each
 * (3: triangles, 4: quads), indices from idx, with the alpha filter when
 * masked; attached to scene `to` as `id`. */
static bool add_geometry(PtScene *ps, RTCScene to, unsigned id, int verts, const uint32_t *idx, uint32_t count,
                         bool masked)
{
    const Scene *s = ps->scene;
    RTCGeometry geo = rtcNewGeometry(ps->device, verts == 4 ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
    /* The scene's own vertex array; Embree reads 16 bytes per position,
     * which the following normal covers. */
    rtcSetSharedGeometryBuffer(geo, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, s->vertices, 0, sizeof(Vertex),
                               s->vertex_count);
    size_t stride = (size_t)verts * sizeof(uint32_t);
    uint32_t *ib = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_INDEX, 0, verts == 4 ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3,
                                           stride, count);
    if (!ib) {
        log_error("reference", "cannot allocate the index buffer of %u %s (%zu bytes)", count,
                  verts == 4 ? "quads" : "triangles", (size_t)count * stride);
        rtcReleaseGeometry(geo);
        return false;
    }
    memcpy(ib, idx, (size_t)count * stride);
    if (masked) {
        rtcSetGeometryUserData(geo, ps);
        rtcSetGeometryIntersectFilterFunction(geo, verts == 4 ? alpha_filter_quads : alpha_filter);
        rtcSetGeometryOccludedFilterFunction(geo, verts == 4 ? alpha_filter_quads : alpha_filter);
    }
    rtcCommitGeometry(geo);
    rtcAttachGeometryByID(to, geo, id);
    rtcReleaseGeometry(geo);
    return true;
}

static RTCScene new_scene(RTCDevice device)
{
    RTCScene sc = rtcNewScene(device);
    rtcSetSceneFlags(sc, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    /* Spatial splits: Sponza's long thin triangles overlap less, a ray
     * visits fewer nodes (its rays 13-30% faster in Embree, for 0.3 CPU s
     * more of build; the Cornell box's the same). */
    rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
    return sc;
}

/* The quad scene (PtScene.quads) of the records' triangles (prim_tri:
 * record → Scene triangle; tri_material per Scene triangle): each Scene
 * triangle with the next one where both have one material and share an
 * edge (quad_pair: two records in a row, as a submesh's triangles are),
 * else alone. */
static bool build_quads(PtScene *ps, const uint32_t *prim_tri, const uint32_t *tri_material, uint32_t ntri)
{
    const Scene *s = ps->scene;
    uint32_t *rec = malloc(sizeof(uint32_t) * ((size_t)ntri + 1)), *idx = malloc(4 * sizeof(uint32_t) * ((size_t)ntri + 1));
    ps->quad = malloc(sizeof(PtQuad) * ((size_t)ntri + 1));
    bool ok = rec && idx && ps->quad;
    if (!ok)
        log_error("reference", "cannot allocate the quads of %u triangles", ntri);
    for (uint32_t i = 0; ok && i < ntri; i++)
        rec[prim_tri[i]] = i; /* Scene triangle → record */
    uint32_t n = 0;
    for (int g = 0; g < 2 && ok; g++) {
        ps->quad_base[g] = n;
        for (uint32_t t = 0; t < ntri; t++) {
            if (rec[t] < ps->tri_base[g] || (g == 0 && rec[t] >= ps->tri_base[1]))
                continue; /* another geometry's */
            PtQuad *q = &ps->quad[n];
            uint32_t *v = idx + 4 * (size_t)n++;
            memset(q, 0, sizeof *q);
            q->rec = rec[t];
            bool pair = t + 1 < ntri && tri_material[t + 1] == tri_material[t] && rec[t + 1] == rec[t] + 1 &&
                        quad_pair(s->indices + 3 * (size_t)t, s->indices + 3 * (size_t)(t + 1), v, q->rot);
            if (!pair) {
                memcpy(v, s->indices + 3 * (size_t)t, 3 * sizeof(uint32_t));
                v[3] = v[2];
                q->rot[0] = q->rot[1] = 0;
                q->lone = 1;
            }
            t += pair;
        }
        uint32_t count = n - ps->quad_base[g];
        if (count > 0)
            ok = add_geometry(ps, ps->quads, (unsigned)g, 4, idx + 4 * (size_t)ps->quad_base[g], count, g == 1);
    }
    free(rec);
    free(idx);
    return ok;
}

/* PtScene.tiny from the records of a scene of ntri ≤ PT_TINY_MAX
 * triangles. false after logging. */
static bool build_tiny(PtScene *ps, uint32_t ntri)
{
    ps->tiny = calloc(1, sizeof *ps->tiny);
    if (!ps->tiny) {
        log_error("reference", "cannot allocate the small scene's arrays");
        return false;
    }
    for (uint32_t i = 0; i < ntri; i++)
        for (int c = 0; c < 3; c++) {
            ps->tiny->p0[c][i] = ps->tris[i].p0[c];
            ps->tiny->e1[c][i] = ps->tris[i].e1[c];
            ps->tiny->e2[c][i] = ps->tris[i].e2[c];
        }
    ps->tiny->n = (ntri + 7) & ~7u; /* the padding lanes stay zero: degenerate */
    return true;
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
    ps->rtc = new_scene(ps->device);

    uint32_t ntri = s->index_count / 3;
    size_t table = sizeof(uint32_t) * ((size_t)ntri + 1);
    size_t records = sizeof(PtTri) * ((size_t)ntri + 1);
    uint32_t *tri_material = malloc(table), *prim_tri = malloc(table);
    ps->tris = aligned_alloc(128, records);
    if (!tri_material || !prim_tri || !ps->tris) {
        log_error("reference", "cannot allocate the triangle records of %u triangles (%zu bytes)", ntri,
                  records + 2 * table);
        free(tri_material);
        free(prim_tri);
        pt_scene_destroy(ps);
        return false;
    }
    for (int k = 0; k < s->submesh_count; k++)
        for (uint32_t t = s->submeshes[k].first_index / 3;
             t < (s->submeshes[k].first_index + s->submeshes[k].index_count) / 3; t++)
            tri_material[t] = (uint32_t)s->submeshes[k].material;

    /* Opaque triangles first (geometry 0), then alpha-masked (geometry 1):
     * prim_tri maps a record to its scene triangle. */
    uint32_t count[2] = {0, 0};
    for (uint32_t t = 0; t < ntri; t++)
        count[s->materials[tri_material[t]].alpha_mask ? 1 : 0]++;
    ps->tri_base[0] = 0;
    ps->tri_base[1] = count[0];
    uint32_t fill[2] = {0, count[0]};
    for (uint32_t t = 0; t < ntri; t++) {
        uint32_t i = fill[s->materials[tri_material[t]].alpha_mask ? 1 : 0]++;
        prim_tri[i] = t;
        tri_record(s, t, tri_material[t], &ps->tris[i]);
    }
    size_t bytes = records;
    for (int i = 0; i < s->texture_count; i++)
        bytes += 4 * (size_t)s->textures[i].width * (size_t)s->textures[i].height;
    ps->memory_bound = bytes > PT_CACHE_BYTES;
    uint32_t *idx = malloc(3 * table);
    bool ok = idx != NULL;
    if (!ok)
        log_error("reference", "cannot allocate the index copy of %u triangles", ntri);
    for (uint32_t i = 0; ok && i < ntri; i++)
        memcpy(idx + 3 * (size_t)i, s->indices + 3 * (size_t)prim_tri[i], 3 * sizeof(uint32_t));
    for (int g = 0; g < 2 && ok; g++)
        if (count[g] > 0)
            ok = add_geometry(ps, ps->rtc, (unsigned)g, 3, idx + 3 * (size_t)ps->tri_base[g], count[g], g == 1);
    free(idx);
    if (ok && count[1] == 0 && ntri <= PT_TINY_MAX)
        ok = build_tiny(ps, ntri);
    if (ok && !ps->memory_bound && !ps->tiny) {
        ps->quads = new_scene(ps->device);
        ok = build_quads(ps, prim_tri, tri_material, ntri);
        if (ok)
            rtcCommitScene(ps->quads);
    }
    free(tri_material);
    free(prim_tri);
    if (!ok) {
        pt_scene_destroy(ps);
        return false;
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
    if (ps->quads)
        rtcReleaseScene(ps->quads);
    free(ps->quad);
    free(ps->tiny);
    if (ps->device)
        rtcReleaseDevice(ps->device);
    free(ps->tris);
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

/* Fills a PtHit from a hit at distance t on record `rec` at barycentrics
 * (bu, bv). */
static void fill_hit(const PtScene *ps, const vec3 d, float t, uint32_t rec, float bu, float bv, PtHit *h)
{
    const PtTri *tr = &ps->tris[rec];
    h->t = t;
    /* The hit point from the barycentrics rather than o + t·d: its rounding
     * error is a few ulps of the vertices' coordinates, whatever the ray's
     * length (Wächter & Binder 2019, §6.2), which pt_offset relies on. */
    for (int i = 0; i < 3; i++)
        h->p[i] = tr->p0[i] + bu * tr->e1[i] + bv * tr->e2[i];
    glm_vec3_copy((float *)tr->ng, h->ng);
    float w = 1.f - bu - bv;
    if (tr->flat) {
        glm_vec3_copy((float *)tr->n[0], h->ns);
    } else {
        for (int i = 0; i < 3; i++)
            h->ns[i] = w * tr->n[0][i] + bu * tr->n[1][i] + bv * tr->n[2][i];
        glm_vec3_normalize(h->ns);
    }
    h->front = glm_vec3_dot(h->ng, (float *)d) < 0.f;
    if (!h->front)
        glm_vec3_negate(h->ng);
    if (glm_vec3_dot(h->ns, h->ng) < 0.f)
        glm_vec3_negate(h->ns);
    tri_uv(tr, bu, bv, h->uv);
    h->material = (int)tr->material;
}

/* Asks for the cache line at p ahead of its read. An asm statement on
 * x86 rather than __builtin_prefetch: GCC 12 takes a function whose only
 * effect is __builtin_prefetch for pure and drops its calls (-O3 had made
 * pt_prefetch_surface an empty function). */
static inline void prefetch(const void *p)
{
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
    __asm__ volatile("prefetcht0 %0" : : "m"(*(const char *)p));
#else
    __builtin_prefetch(p);
#endif
}

/* The texels a bilinear lookup of t at uv reads (texture_bilinear's two
 * rows at x0 and x1), asked of the memory ahead of the read. */
static void texture_prefetch(const Texture *t, const float uv[2])
{
    float x = uv[0] * t->width - 0.5f, y = uv[1] * t->height - 0.5f;
    int x0 = wrap((int)floorf(x), t->width), y0 = wrap((int)floorf(y), t->height);
    int x1 = x0 + 1 < t->width ? x0 + 1 : 0, y1 = y0 + 1 < t->height ? y0 + 1 : 0;
    const uint8_t *r0 = t->rgba + 4 * (size_t)y0 * t->width, *r1 = t->rgba + 4 * (size_t)y1 * t->width;
    prefetch(r0 + 4 * x0);
    prefetch(r1 + 4 * x0);
    prefetch(r0 + 4 * x1);
    prefetch(r1 + 4 * x1);
}

/* The closest hit in scene `sc` (the quads or the triangles). */
static bool trace_in(const PtScene *ps, RTCScene sc, const vec3 o, const vec3 d, float tmax, PtRawHit *r)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    init_ray(&rh.ray, o, d, tmax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(sc, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return false;
    r->t = rh.ray.tfar;
    r->rec = hit_record(ps, sc == ps->quads, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, &r->u, &r->v);
    const char *rec = (const char *)&ps->tris[r->rec];
    prefetch(rec);
    prefetch(rec + 64);
    return true;
}

/* Eight lanes of floats or of their masks (GCC's vector extensions: SSE
 * pairs by default, AVX where tiny_hit's clone for it runs). */
typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));

/* Every triangle of a small scene (PtTiny) against o + t·d, t in (0,
 * tmax) (Möller & Trumbore), eight at a time: the closest hit into r, or
 * with `any` whether there is one (r unused). */
__attribute__((target_clones("avx2", "default"))) static bool tiny_hit(const PtTiny *k, const vec3 o, const vec3 d,
                                                                        float tmax, bool any, PtRawHit *r)
{
    const v8f ox = {o[0], o[0], o[0], o[0], o[0], o[0], o[0], o[0]}, oy = ox * 0.f + o[1], oz = ox * 0.f + o[2];
    const v8f dx = ox * 0.f + d[0], dy = ox * 0.f + d[1], dz = ox * 0.f + d[2];
    const v8f zero = ox * 0.f, one = zero + 1.f, far = zero + tmax;
    v8f best_t = zero + INFINITY;
    v8i best_i = (v8i){0} - 1, lane = {0, 1, 2, 3, 4, 5, 6, 7};
    for (uint32_t i = 0; i < k->n; i += 8, lane += 8) {
        v8f e1x, e1y, e1z, e2x, e2y, e2z, tx, ty, tz;
        memcpy(&e1x, &k->e1[0][i], sizeof e1x);
        memcpy(&e1y, &k->e1[1][i], sizeof e1y);
        memcpy(&e1z, &k->e1[2][i], sizeof e1z);
        memcpy(&e2x, &k->e2[0][i], sizeof e2x);
        memcpy(&e2y, &k->e2[1][i], sizeof e2y);
        memcpy(&e2z, &k->e2[2][i], sizeof e2z);
        memcpy(&tx, &k->p0[0][i], sizeof tx);
        memcpy(&ty, &k->p0[1][i], sizeof ty);
        memcpy(&tz, &k->p0[2][i], sizeof tz);
        tx = ox - tx, ty = oy - ty, tz = oz - tz;
        v8f px = dy * e2z - dz * e2y, py = dz * e2x - dx * e2z, pz = dx * e2y - dy * e2x;
        v8f inv = one / (e1x * px + e1y * py + e1z * pz); /* inf on a degenerate lane: NaNs, no hit */
        v8f u = (tx * px + ty * py + tz * pz) * inv;
        v8f qx = ty * e1z - tz * e1y, qy = tz * e1x - tx * e1z, qz = tx * e1y - ty * e1x;
        v8f v = (dx * qx + dy * qy + dz * qz) * inv;
        v8f t = (e2x * qx + e2y * qy + e2z * qz) * inv;
        v8i hit = (u >= zero) & (v >= zero) & (u + v <= one) & (t > zero) & (t < far) & (t < best_t);
        if (any) {
            int32_t found = 0;
            for (int l = 0; l < 8; l++)
                found |= hit[l];
            if (found)
                return true;
            continue;
        }
        best_t = (v8f)((hit & (v8i)t) | (~hit & (v8i)best_t));
        best_i = (hit & lane) | (~hit & best_i);
    }
    if (any)
        return false;
    int b = -1;
    for (int l = 0; l < 8; l++)
        if (best_i[l] >= 0 && (b < 0 || best_t[l] < best_t[b]))
            b = l;
    if (b < 0)
        return false;
    /* The winner's barycentrics again, alone (kept in lanes they cost the
     * loop two blends and its registers). */
    uint32_t i = (uint32_t)best_i[b];
    float e1[3] = {k->e1[0][i], k->e1[1][i], k->e1[2][i]}, e2[3] = {k->e2[0][i], k->e2[1][i], k->e2[2][i]};
    float tv[3] = {o[0] - k->p0[0][i], o[1] - k->p0[1][i], o[2] - k->p0[2][i]}, p[3], q[3];
    glm_vec3_cross((float *)d, e2, p);
    glm_vec3_cross(tv, e1, q);
    float inv = 1.f / glm_vec3_dot(e1, p);
    r->t = best_t[b];
    r->u = glm_vec3_dot(tv, p) * inv;
    r->v = glm_vec3_dot((float *)d, q) * inv;
    r->rec = i;
    return true;
}

bool pt_trace(const PtScene *ps, const vec3 o, const vec3 d, float tmax, PtRawHit *r)
{
    if (ps->tiny) /* its records are in the caches: nothing to prefetch */
        return tiny_hit(ps->tiny, o, d, tmax, false, r);
    return trace_in(ps, ps->quads ? ps->quads : ps->rtc, o, d, tmax, r);
}

void pt_hit(const PtScene *ps, const vec3 d, const PtRawHit *r, PtHit *h)
{
    fill_hit(ps, d, r->t, r->rec, r->u, r->v, h);
}

void pt_prefetch_surface(const PtScene *ps, const PtHit *h)
{
    const Material *m = &ps->scene->materials[h->material];
    if (m->albedo_tex >= 0)
        texture_prefetch(&ps->scene->textures[m->albedo_tex], h->uv);
    if (m->mr_tex >= 0)
        texture_prefetch(&ps->scene->textures[m->mr_tex], h->uv);
}

bool pt_intersect(const PtScene *ps, const vec3 o, const vec3 d, float tmax, PtHit *h)
{
    PtRawHit r;
    if (!trace_in(ps, ps->rtc, o, d, tmax, &r))
        return false;
    pt_hit(ps, d, &r, h);
    return true;
}

void pt_intersect_packet(const PtScene *ps, const vec3 o, const vec3 *d, int n, PtHit *h, bool *hit)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    struct RTCRayHit16 rh;
    _Alignas(64) int valid[PT_PACKET]; /* Embree reads the mask with aligned loads */
    for (int i = 0; i < PT_PACKET; i++) {
        int k = i < n ? i : 0; /* inactive lanes: a copy of ray 0, masked off */
        valid[i] = i < n ? -1 : 0;
        rh.ray.org_x[i] = o[0];
        rh.ray.org_y[i] = o[1];
        rh.ray.org_z[i] = o[2];
        rh.ray.dir_x[i] = d[k][0];
        rh.ray.dir_y[i] = d[k][1];
        rh.ray.dir_z[i] = d[k][2];
        rh.ray.tnear[i] = 0.f;
        rh.ray.tfar[i] = INFINITY;
        rh.ray.time[i] = 0.f;
        rh.ray.mask[i] = 0xffffffffu;
        rh.ray.id[i] = (unsigned)i;
        rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, ps->rtc, &ctx, &rh);
    for (int i = 0; i < n; i++) {
        hit[i] = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
        if (hit[i])
            fill_hit(ps, d[i], rh.ray.tfar[i], ps->tri_base[rh.hit.geomID[i]] + rh.hit.primID[i], rh.hit.u[i],
                     rh.hit.v[i], &h[i]);
    }
}

typedef struct AllHitsContext {
    struct RTCIntersectContext base; /* first member: Embree passes &base */
    const PtScene *ps;
    const float *d;
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
            fill_hit(c->ps, c->d, rayn_tfar(args->ray, args->N, i),
                     c->ps->tri_base[hitn_geom(args->hit, args->N, i)] + hitn_prim(args->hit, args->N, i),
                     hitn_u(args->hit, args->N, i), hitn_v(args->hit, args->N, i), &c->hits[c->count++]);
        args->valid[i] = 0;
    }
}

int pt_intersect_all(const PtScene *ps, const vec3 o, const vec3 d, float tmax, PtHit *hits, int max)
{
    AllHitsContext c;
    rtcInitIntersectContext(&c.base);
    c.base.filter = collect_filter;
    c.ps = ps;
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
    if (ps->tiny)
        return tiny_hit(ps->tiny, o, d, tmax, true, NULL);
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay r;
    init_ray(&r, o, d, tmax);
    rtcOccluded1(ps->quads ? ps->quads : ps->rtc, &ctx, &r);
    return r.tfar < 0.f;
}

/* Bilinear over the base level of t at uv; colour sRGB-decoded per texel
 * unless the texture holds data (linear). */
static void texture_bilinear(const Texture *t, const float uv[2], vec3 out)
{
    float x = uv[0] * t->width - 0.5f, y = uv[1] * t->height - 0.5f;
    float fx0 = floorf(x), fy0 = floorf(y);
    float fx = x - fx0, fy = y - fy0;
    /* Wrapped once per axis; the next texel wraps by a compare. */
    int x0 = wrap((int)fx0, t->width), y0 = wrap((int)fy0, t->height);
    int x1 = x0 + 1 < t->width ? x0 + 1 : 0, y1 = y0 + 1 < t->height ? y0 + 1 : 0;
    const uint8_t *r0 = t->rgba + 4 * (size_t)y0 * t->width, *r1 = t->rgba + 4 * (size_t)y1 * t->width;
    const uint8_t *p[4] = {r0 + 4 * x0, r0 + 4 * x1, r1 + 4 * x0, r1 + 4 * x1};
    float wgt[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    for (int c = 0; c < 3; c++) {
        float v = 0;
        if (t->linear)
            for (int k = 0; k < 4; k++)
                v += wgt[k] * (p[k][c] / 255.f);
        else
            for (int k = 0; k < 4; k++)
                v += wgt[k] * g_srgb_lut[p[k][c]];
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
