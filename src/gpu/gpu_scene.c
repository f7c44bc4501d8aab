#include "gpu/gpu_scene.h"

#include <cglm/box.h>
#include <cglm/frustum.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "gl/gl_resources.h"
#include "gl/gpu_budget.h"
#include "io/image.h"
#include "base/log.h"
#include "shared/gpu_types.h"
#include "gpu/targets.h"
#include "base/util.h"

/* ---- clusters ---------------------------------------------------------- */

/* 10 bits of each coordinate interleaved: x in bit 0, 3, 6, ... */
static uint32_t morton3(uint32_t x, uint32_t y, uint32_t z)
{
    uint32_t code = 0;
    for (int b = 0; b < 10; b++)
        code |= ((x >> b) & 1u) << (3 * b) | ((y >> b) & 1u) << (3 * b + 1) | ((z >> b) & 1u) << (3 * b + 2);
    return code;
}

typedef struct TriKey {
    uint32_t code, tri;
} TriKey;

static int trikey_cmp(const void *a, const void *b)
{
    const TriKey *x = a, *y = b;
    if (x->code != y->code)
        return x->code < y->code ? -1 : 1;
    return x->tri < y->tri ? -1 : x->tri > y->tri;
}

static void cluster_bounds(GpuCluster *c, const Scene *s, const uint32_t *idx)
{
    for (int k = 0; k < 3; k++) {
        c->bounds_min[k] = FLT_MAX;
        c->bounds_max[k] = -FLT_MAX;
    }
    for (uint32_t i = 0; i < c->index_count; i++) {
        const float *p = s->vertices[idx[c->first_index + i]].position;
        for (int k = 0; k < 3; k++) {
            c->bounds_min[k] = p[k] < c->bounds_min[k] ? p[k] : c->bounds_min[k];
            c->bounds_max[k] = p[k] > c->bounds_max[k] ? p[k] : c->bounds_max[k];
        }
    }
}

/* Writes the GPU index order into `out` (the scene's, with each large
 * submesh's triangles sorted along a Morton curve of their centroids) and
 * cuts each submesh into clusters of at most GPU_CLUSTER_TRIANGLES. */
static bool build_clusters(GpuScene *g, const Scene *s, uint32_t *out)
{
    int count = 0;
    for (int i = 0; i < s->submesh_count; i++)
        count += (int)((s->submeshes[i].index_count / 3 + GPU_CLUSTER_TRIANGLES - 1) / GPU_CLUSTER_TRIANGLES);
    g->clusters = util_calloc("gpu_scene", "clusters", (size_t)count + 1, sizeof(GpuCluster));
    if (!g->clusters)
        return false;
    memcpy(out, s->indices, sizeof(uint32_t) * s->index_count);
    for (int i = 0; i < s->submesh_count; i++) {
        const Submesh *sm = &s->submeshes[i];
        uint32_t tris = sm->index_count / 3;
        const uint32_t *src = s->indices + sm->first_index;
        if (tris > GPU_CLUSTER_TRIANGLES) {
            TriKey *keys = util_malloc("gpu_scene", "cluster sort keys", tris, sizeof(TriKey));
            if (!keys)
                return false;
            vec3 lo = {FLT_MAX, FLT_MAX, FLT_MAX}, hi = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
            for (uint32_t t = 0; t < 3 * tris; t++) {
                const float *p = s->vertices[src[t]].position;
                for (int k = 0; k < 3; k++) {
                    lo[k] = p[k] < lo[k] ? p[k] : lo[k];
                    hi[k] = p[k] > hi[k] ? p[k] : hi[k];
                }
            }
            for (uint32_t t = 0; t < tris; t++) {
                uint32_t q[3];
                for (int k = 0; k < 3; k++) {
                    float c = (s->vertices[src[3 * t]].position[k] + s->vertices[src[3 * t + 1]].position[k] +
                               s->vertices[src[3 * t + 2]].position[k]) / 3.f;
                    float extent = hi[k] - lo[k];
                    float u = extent > 0.f ? (c - lo[k]) / extent : 0.f;
                    q[k] = (uint32_t)(u * 1023.f + 0.5f);
                }
                keys[t] = (TriKey){morton3(q[0], q[1], q[2]), t};
            }
            qsort(keys, tris, sizeof(TriKey), trikey_cmp);
            uint32_t *dst = out + sm->first_index;
            for (uint32_t t = 0; t < tris; t++)
                memcpy(dst + 3 * t, src + 3 * keys[t].tri, 3 * sizeof(uint32_t));
            free(keys);
        }
        for (uint32_t t = 0; t < tris; t += GPU_CLUSTER_TRIANGLES) {
            uint32_t n = tris - t < GPU_CLUSTER_TRIANGLES ? tris - t : GPU_CLUSTER_TRIANGLES;
            GpuCluster *c = &g->clusters[g->cluster_count++];
            *c = (GpuCluster){.first_index = sm->first_index + 3 * t, .index_count = 3 * n, .submesh = i};
            cluster_bounds(c, s, out);
        }
    }
    return true;
}

/* ---- lifetime ---------------------------------------------------------- */

/* A cluster a draw will make, with its distance for front-to-back order. */
typedef struct GpuDrawItem {
    float distance;
    int cluster;
} DrawItem;

/* GPU bytes of the scene's buffers and textures (each with its mip chain,
 * at most 4/3 of its top level). */
static uint64_t scene_bytes(const Scene *s)
{
    uint64_t bytes = sizeof(Vertex) * (uint64_t)s->vertex_count + sizeof(uint32_t) * (uint64_t)s->index_count;
    for (int i = 0; i < s->texture_count; i++)
        bytes += 8u * (uint64_t)s->textures[i].width * (uint64_t)s->textures[i].height * 4u / 3u;
    return bytes;
}

/* Versions of geometry uploaded, in the process (GpuScene.version). */
static uint64_t s_versions;

/* ---- textures ---------------------------------------------------------- */

/* The source texels [first, first + count) that texel d of a src → dst
 * resampling covers and each one's share of it: a box filter over the
 * destination texel's footprint, exact for any sizes (an odd side of 2k + 1
 * halves to k texels of 2 + 1/k source texels each), so that every level
 * keeps the mean of the one above. */
typedef struct BoxTaps {
    int first, count;
    float w[4]; /* src/dst ≤ 3: a footprint spans at most 4 texels */
} BoxTaps;

static BoxTaps box_taps(int d, int src, int dst)
{
    double r = (double)src / dst, a = d * r, b = (d + 1) * r;
    BoxTaps t = {(int)floor(a), 0, {0}};
    for (int s = t.first; s < b && t.count < 4; s++)
        t.w[t.count++] = (float)((fmin(b, s + 1.0) - fmax(a, (double)s)) / r);
    return t;
}

/* Texel k of a level: linear RGBA floats, or the RGBA8 pixels src8 decoded
 * (colour through lut, alpha /255). */
static void level_texel(const float *src, const uint8_t *src8, const float lut[256], size_t k, float out[4])
{
    for (int c = 0; c < 4; c++)
        out[c] = src8 ? (c < 3 ? lut[src8[4 * k + c]] : src8[4 * k + c] / 255.f) : src[4 * k + c];
}

/* dst (dw×dh) = the box-filtered src (sw×sh, level_texel's), in linear
 * floats. `weighted` (the texture of an alpha-masked material): the colour
 * is the alpha-weighted mean (the plain one where all alpha is 0), the
 * colour of the texels that pass the alpha test rather than of all of
 * them; alpha the plain mean (the next level's weights: the chain is the
 * alpha-weighted mean over each footprint). Sponza's leaves' transparent
 * texels are dark (a tenth of the opaque ones' mean), and the plain mean
 * darkened the leaves with distance: in the 1045 pixels of the direct
 * light (320×180, SSAA 2) where the two differ, the plain mean gave 0.84
 * of the path tracer's light, the weighted one 0.95 (the rest: shadows),
 * 0.25% of the whole image. A mean weighted by the coverage of the
 * base level's bilinear lookups (4×4 per texel) gave the same to 0.01%. */
static void mip_downsample(const float *src, const uint8_t *src8, const float lut[256], int sw, int sh,
                           float *dst, int dw, int dh, bool weighted)
{
    for (int y = 0; y < dh; y++) {
        BoxTaps ty = box_taps(y, sh, dh);
        for (int x = 0; x < dw; x++) {
            BoxTaps tx = box_taps(x, sw, dw);
            float plain[4] = {0, 0, 0, 0}, premul[3] = {0, 0, 0}, alpha_sum = 0.f;
            for (int j = 0; j < ty.count; j++)
                for (int i = 0; i < tx.count; i++) {
                    float px[4], w = ty.w[j] * tx.w[i];
                    level_texel(src, src8, lut, (size_t)(ty.first + j) * sw + (size_t)(tx.first + i), px);
                    for (int c = 0; c < 4; c++)
                        plain[c] += w * px[c];
                    for (int c = 0; c < 3; c++)
                        premul[c] += w * px[3] * px[c];
                    alpha_sum += w * px[3];
                }
            float *o = dst + 4 * ((size_t)y * dw + x);
            for (int c = 0; c < 3; c++)
                o[c] = weighted && alpha_sum > 0.f ? premul[c] / alpha_sum : plain[c];
            o[3] = plain[3];
        }
    }
}

/* Uploads t into `tex` (RGBA16F, gl_mip_levels levels): level 0 its pixels
 * decoded exactly (sRGB colour through the same table as the path
 * tracer's, data /255), each further level the box filter of the one above
 * in linear space (mip_downsample, kept in float from level to level).
 * Colour textures had been SRGB8_ALPHA8 with glGenerateMipmap, which left
 * both conversions to the driver: Mesa's llvmpipe decodes sRGB texels by
 * an approximation (−1.7% at code 32, +0.7% at 96, +2.5% at 5: in a shader,
 * texelFetch against the formula) and re-encodes generated levels with one
 * that rounds up by 0.3 of a step around codes 60-120, each level from the
 * rounded one above (Sponza's textures up to 3.5% off their mean at level
 * 9): the rasterizer's direct blue on Sponza was 2.1% above the path
 * tracer's (issue 49). Half floats keep every texel within 2^-11 (0.05%) of its
 * value, whatever the driver. `weighted`: alpha-weighted colour levels for
 * textures of alpha-masked materials (mip_downsample). */
static bool upload_texture(GLuint tex, const Texture *t, bool weighted)
{
    float lut[256];
    for (int i = 0; i < 256; i++)
        lut[i] = t->linear ? i / 255.f : srgb_decode(i / 255.f);
    /* Level 0 in bands of rows; levels 1.. in two buffers in turn (level 2
     * and its successors fit in the second, level 3 and its in the first). */
    enum { BAND_ROWS = 64 };
    int w1 = t->width > 1 ? t->width / 2 : 1, h1 = t->height > 1 ? t->height / 2 : 1;
    int w2 = w1 > 1 ? w1 / 2 : 1, h2 = h1 > 1 ? h1 / 2 : 1;
    size_t band = (size_t)t->width * (t->height < BAND_ROWS ? t->height : BAND_ROWS);
    size_t n1 = (size_t)w1 * h1 > band ? (size_t)w1 * h1 : band;
    float *buf[2] = {util_malloc("gpu_scene", "a texture level", n1, 4 * sizeof(float)),
                     util_malloc("gpu_scene", "a texture level", (size_t)w2 * h2, 4 * sizeof(float))};
    bool ok = buf[0] && buf[1];
    for (int y0 = 0; ok && y0 < t->height; y0 += BAND_ROWS) {
        int rows = t->height - y0 < BAND_ROWS ? t->height - y0 : BAND_ROWS;
        for (size_t k = 0; k < (size_t)t->width * rows; k++)
            level_texel(NULL, t->rgba + 4 * (size_t)y0 * t->width, lut, k, buf[0] + 4 * k);
        glTextureSubImage2D(tex, 0, 0, y0, t->width, rows, GL_RGBA, GL_FLOAT, buf[0]);
    }
    int levels = gl_mip_levels(t->width, t->height, 1), sw = t->width, sh = t->height;
    for (int level = 1; ok && level < levels; level++) {
        int dw = sw > 1 ? sw / 2 : 1, dh = sh > 1 ? sh / 2 : 1;
        float *dst = buf[(level - 1) & 1];
        mip_downsample(buf[level & 1], level == 1 ? t->rgba : NULL, lut, sw, sh, dst, dw, dh, weighted);
        glTextureSubImage2D(tex, level, 0, 0, dw, dh, GL_RGBA, GL_FLOAT, dst);
        sw = dw;
        sh = dh;
    }
    free(buf[0]);
    free(buf[1]);
    return ok;
}

bool gpu_scene_create(GpuScene *g, const Scene *s)
{
    *g = (GpuScene){0};
    char what[600];
    snprintf(what, sizeof what, "%s (%u triangles, %d textures)", s->source, (unsigned)(s->index_count / 3), s->texture_count);
    if (!gpu_budget_check(scene_bytes(s), what))
        return false;
    uint32_t *indices = util_malloc("gpu_scene", "index buffer", s->index_count + 1, sizeof(uint32_t));
    if (!indices || !build_clusters(g, s, indices) ||
        !(g->draw_items = util_malloc("gpu_scene", "draw list", (size_t)g->cluster_count + 1, sizeof(DrawItem)))) {
        free(indices);
        free(g->clusters);
        *g = (GpuScene){0};
        return false;
    }
    /* An empty scene still gets a (1-byte, undefined) buffer of each. */
    uint64_t vb = sizeof(Vertex) * (uint64_t)s->vertex_count, ib = sizeof(uint32_t) * (uint64_t)s->index_count;
    /* Vertices are updatable: animated objects move (gpu_scene_update_vertices). */
    g->vbo = gl_buffer_make(vb ? vb : 1, vb ? s->vertices : NULL, GL_DYNAMIC_STORAGE_BIT, "scene.vertices");
    g->ibo = gl_buffer_make(ib ? ib : 1, ib ? indices : NULL, 0, "scene.indices");
    g->cluster_indices = indices;
    g->version = ++s_versions;
    g->textures = calloc((size_t)s->texture_count + 1, sizeof(GLuint));
    if (!g->vbo || !g->ibo || !g->textures) { /* gl_buffer_make logs its failure */
        if (!g->textures)
            log_error("gpu_scene", "out of memory for %d texture names", s->texture_count);
        gpu_scene_destroy(g);
        return false;
    }

    glCreateVertexArrays(1, &g->vao);
    glVertexArrayVertexBuffer(g->vao, 0, g->vbo, 0, sizeof(Vertex));
    glVertexArrayElementBuffer(g->vao, g->ibo);
    const GLuint offs[3] = {offsetof(Vertex, position), offsetof(Vertex, normal), offsetof(Vertex, uv)};
    const GLint comps[3] = {3, 3, 2};
    for (GLuint a = 0; a < 3; a++) {
        glEnableVertexArrayAttrib(g->vao, a);
        glVertexArrayAttribFormat(g->vao, a, comps[a], GL_FLOAT, GL_FALSE, offs[a]);
        glVertexArrayAttribBinding(g->vao, a, 0);
    }

    g->texture_count = s->texture_count;
    for (int i = 0; i < s->texture_count; i++) {
        const Texture *t = &s->textures[i];
        bool masked = false; /* the texture of an alpha-masked material: alpha-weighted levels */
        for (int m = 0; m < s->material_count; m++)
            masked |= s->materials[m].alpha_mask && s->materials[m].albedo_tex == i;
        g->textures[i] = gl_texture_make_levels(GL_TEXTURE_2D, GL_RGBA16F, t->width, t->height, 1, 0, t->name);
        if (!g->textures[i] || !upload_texture(g->textures[i], t, masked)) { /* logged */
            gpu_scene_destroy(g);
            return false;
        }
        glTextureParameteri(g->textures[i], GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTextureParameteri(g->textures[i], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(g->textures[i], GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTextureParameteri(g->textures[i], GL_TEXTURE_WRAP_T, GL_REPEAT);
    }
    return true;
}

void gpu_scene_update_vertices(GpuScene *g, const Scene *s, uint32_t first, uint32_t count)
{
    if (count == 0 || first >= s->vertex_count)
        return;
    if (count > s->vertex_count - first)
        count = s->vertex_count - first;
    glNamedBufferSubData(g->vbo, (GLintptr)(sizeof(Vertex) * first), (GLsizeiptr)(sizeof(Vertex) * count),
                         s->vertices + first);
    GpuSceneMove *m = &g->moves[g->move_count++ % GPU_SCENE_MOVES];
    for (int k = 0; k < 3; k++) {
        m->min[k] = FLT_MAX;
        m->max[k] = -FLT_MAX;
    }
    for (int i = 0; i < g->cluster_count; i++) {
        GpuCluster *c = &g->clusters[i];
        bool moved = false; /* a triangle of it uses a moved vertex: its bounds before and after join the box */
        for (uint32_t j = 0; j < c->index_count && !moved; j++)
            moved = g->cluster_indices[c->first_index + j] - first < count;
        for (int pass = 0; pass < 2; pass++) {
            if (pass)
                cluster_bounds(c, s, g->cluster_indices);
            for (int k = 0; k < 3 && moved; k++) {
                m->min[k] = fminf(m->min[k], c->bounds_min[k]);
                m->max[k] = fmaxf(m->max[k], c->bounds_max[k]);
            }
        }
    }
    m->from = g->version;
    g->version = m->to = ++s_versions;
}

bool gpu_scene_moved_since(const GpuScene *g, uint64_t version, float min[3], float max[3])
{
    for (int k = 0; k < 3; k++) {
        min[k] = FLT_MAX;
        max[k] = -FLT_MAX;
    }
    uint64_t at = g->version;
    uint32_t kept = g->move_count < GPU_SCENE_MOVES ? g->move_count : GPU_SCENE_MOVES;
    for (uint32_t i = 0; at != version; i++) { /* newest first, back along the chain */
        if (i == kept)
            return false;
        const GpuSceneMove *m = &g->moves[(g->move_count - 1 - i) % GPU_SCENE_MOVES];
        if (m->to != at)
            return false;
        for (int k = 0; k < 3; k++) {
            min[k] = fminf(min[k], m->min[k]);
            max[k] = fmaxf(max[k], m->max[k]);
        }
        at = m->from;
    }
    return true;
}

uint64_t gpu_scene_bytes(const GpuScene *g)
{
    const GLuint bufs[2] = {g->vbo, g->ibo};
    return gl_buffers_bytes(bufs, 2) + gl_textures_bytes(g->textures, g->texture_count);
}

void gpu_scene_destroy(GpuScene *g)
{
    if (g->texture_count)
        glDeleteTextures(g->texture_count, g->textures);
    free(g->textures);
    free(g->clusters);
    free(g->draw_items);
    free(g->cluster_indices);
    glDeleteVertexArrays(1, &g->vao);
    glDeleteBuffers(1, &g->vbo);
    glDeleteBuffers(1, &g->ibo);
    *g = (GpuScene){0};
}

/* ---- drawing ----------------------------------------------------------- */

void gpu_scene_draw(const GpuScene *g, const Scene *s, GLuint program, DrawFlags flags)
{
    gpu_scene_draw_view(g, s, &(DrawPrograms){program, program, 0}, flags, NULL);
}

void gpu_scene_draw_split(const GpuScene *g, const Scene *s, GLuint opaque, GLuint masked, DrawFlags flags)
{
    gpu_scene_draw_view(g, s, &(DrawPrograms){opaque, masked, 0}, flags, NULL);
}

static int drawitem_cmp(const void *a, const void *b)
{
    const DrawItem *x = a, *y = b;
    if (x->distance != y->distance)
        return x->distance < y->distance ? -1 : 1;
    return x->cluster - y->cluster; /* stable: equal distances keep scene order */
}

void gpu_scene_bind_material(const GpuScene *g, const Material *m, GLuint program)
{
    glProgramUniform3fv(program, LOC_MATERIAL_ALBEDO, 1, m->albedo);
    glProgramUniform1i(program, LOC_MATERIAL_HAS_TEX, m->albedo_tex >= 0);
    glProgramUniform1f(program, LOC_MATERIAL_CUTOFF, m->alpha_mask ? m->alpha_cutoff : -1.f);
    glProgramUniform3fv(program, LOC_MATERIAL_EMISSION, 1, m->emission);
    glProgramUniform4f(program, LOC_MATERIAL_PBR, m->metallic, m->roughness, m->specular, m->mr_tex >= 0 ? 1.f : 0.f);
    if (m->albedo_tex >= 0)
        glBindTextureUnit(TEX_ALBEDO, g->textures[m->albedo_tex]);
    if (m->mr_tex >= 0)
        glBindTextureUnit(TEX_MATERIAL_MR, g->textures[m->mr_tex]);
}

static bool untextured(const Material *m) { return m->albedo_tex < 0 && m->mr_tex < 0 && !m->alpha_mask; }

void gpu_scene_draw_view(const GpuScene *g, const Scene *s, const DrawPrograms *programs, DrawFlags flags,
                         const DrawView *view)
{
    GLuint opaque = programs->opaque, masked = programs->masked;
    /* The visible clusters, in scene order or nearest first (the scratch
     * list the scene owns: no allocation per draw). */
    DrawItem *items = g->draw_items;
    int n = 0, culled = 0;
    vec4 planes[6];
    bool cull = view && view->view_proj;
    if (cull)
        glm_frustum_planes((vec4 *)view->view_proj, planes);
    for (int i = 0; i < g->cluster_count; i++) {
        const GpuCluster *c = &g->clusters[i];
        if (cull) {
            vec3 box[2] = {{c->bounds_min[0], c->bounds_min[1], c->bounds_min[2]},
                           {c->bounds_max[0], c->bounds_max[1], c->bounds_max[2]}};
            if (!glm_aabb_frustum(box, planes)) {
                culled++;
                continue;
            }
        }
        float d2 = view && view->eye ? scene_box_dist2(view->eye, c->bounds_min, c->bounds_max) : 0.f;
        items[n++] = (DrawItem){d2, i};
    }
    if (view && view->eye)
        qsort(items, (size_t)n, sizeof(DrawItem), drawitem_cmp);
    if (view && view->culled)
        *view->culled = culled;

    glBindVertexArray(g->vao);
    /* Opaque first (they fill depth that masked draws are then tested
     * against), masked after; one pass when both programs are the same. */
    for (int pass = 0; pass < (opaque == masked ? 1 : 2); pass++) {
        GLuint in_use = 0;
        int bound = -1; /* the material whose uniforms are set in the program in use */
        for (int k = 0; k < n; k++) {
            const GpuCluster *c = &g->clusters[items[k].cluster];
            int mi = s->submeshes[c->submesh].material;
            const Material *m = &s->materials[mi];
            if ((flags & DRAW_SKIP_EMITTERS) && m->light_index >= 0)
                continue;
            if (opaque != masked && m->alpha_mask != (pass == 1))
                continue;
            GLuint program = pass == 1 ? masked : programs->untextured && untextured(m) ? programs->untextured : opaque;
            if (program != in_use) {
                glUseProgram(program);
                in_use = program;
                bound = -1;
            }
            if (mi != bound)
                gpu_scene_bind_material(g, m, program);
            bound = mi;
            if (view && view->draw_ids)
                glProgramUniform1ui(program, LOC_VBUFFER_DRAW, (GLuint)items[k].cluster);
            glDrawElements(GL_TRIANGLES, (GLsizei)c->index_count, GL_UNSIGNED_INT,
                           (const void *)(sizeof(uint32_t) * c->first_index));
        }
    }
    glBindVertexArray(0);
}
