/* vpl.c — indirect light from many VPLs (SPEC §4); five rows of the
 * technique table over the light stage's VPL buffer:
 *   vpl-all          brute force: every pixel sums every VPL (or a uniform
 *                    random fraction q of them, weighted 1/q)
 *   vpl-clamped      each VPL cut at a fixed range R: the biased baseline
 *   vpl-slc          stochastic light culling (Tokuyoshi & Harada 2016): per
 *                    VPL α_i = 2π·e_max/(E·max I_i), range r_i = 1/√(α_i ξ_i),
 *                    falloff max(α_i, 1/d²) inside it — unbiased over ξ
 *   vpl-interleaved  n×m interleaved shading with random disjoint VPL subsets
 *   vpl-metalights   the same with subsets dealt from metalights (Faure &
 *                    Chang 2010): VPLs ordered by their contribution to a
 *                    low-res grid of G-buffer samples and grouped n·m at a
 *                    time; each sub-image gets one member of every
 *                    metalight. Regrouped whenever a light, the camera or a
 *                    setting changes.
 * clamped and slc bin VPL spheres into 16×16 screen tiles (a per-tile world
 * box from the G-buffer) in a culling pass before shading.
 * With --gi-visibility on, each evaluated VPL's term is multiplied by its
 * visibility of the pixel from its imperfect shadow map (gi/visibility/
 * ism.h, one map per VPL); culling, ranges and grouping are unchanged.
 * Inputs: G-buffer, VPL buffer. Output: irradiance. Owns: the range, tile, evaluation and subset buffers, the blur (interleaved).
 * Shaders: shaders/gi/vpl/. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cglm/cglm.h>

#include "gi/gi.h"
#include "gi/interleave.h"
#include "gi/visibility/ism.h"
#include "gl/gl_resources.h"
#include "base/log.h"
#include "gl/shader.h"
#include "base/util.h"

typedef enum VplMethod { VPL_ALL, VPL_CLAMPED, VPL_SLC, VPL_INTERLEAVED, VPL_METALIGHTS } VplMethod;

enum { LIST_BUDGET = 32 * 1024 * 1024 }; /* tile-list entries in all (128 MiB) */

typedef struct VplGi {
    VplMethod method;
    GiParams params;
    ProgramCache *pc;     /* borrowed: owns the programs */
    GLuint params_prog, cull, shade, signature; /* those the method uses */
    GLuint ubo;           /* GpuVplParams */
    GLuint gi_ubo;        /* GpuGiParams (the blur's thresholds) */
    GLuint ranges;        /* vec2 per VPL */
    GLuint tiles;         /* counts[tiles], overflow, lists[tiles × capacity] (VPL_TILE_LIST_BASE) */
    GLuint evals;         /* uint per shading work group, ×2 */
    GLuint subsets;       /* K × L VPL records in subset order (GpuVpl, zero flux
                           * where a subset is short); also the signatures (vec4 per VPL) */
    GiInterleave il;      /* blur (interleaved methods) */
    uint32_t vpl_capacity;
    uint32_t tile_capacity; /* list entries per tile */
    int tiles_x, tiles_y;
    int width, height;
    int groups;           /* shading work groups (groups_x × groups_y) */
    int groups_x, groups_y;
    uint64_t grouping_key;/* what the metalight grouping was computed for */
    int regroups;         /* how many times the grouping was (re)computed */
    uint32_t subset_len;  /* L */
    GpuVplParams gpu;     /* as last uploaded */
    Ism *ism;             /* --gi-visibility: one visibility map per VPL (NULL: off) */
} VplGi;

static bool interleaved(const VplGi *v) { return v->method == VPL_INTERLEAVED || v->method == VPL_METALIGHTS; }
static bool tiled(const VplGi *v) { return v->method == VPL_CLAMPED || v->method == VPL_SLC; }

/* The shading dispatch: 8×8 pixels per work group; interleaved methods
 * cover blocks of 8n × 8m pixels with n·m groups each, one per sub-image
 * (shaders/gi/vpl/shade.comp). */
static void shade_groups(const VplGi *v, int *gx, int *gy)
{
    int n = interleaved(v) ? v->params.interleave.pattern.n : 1;
    int m = interleaved(v) ? v->params.interleave.pattern.m : 1;
    *gx = (v->width + 8 * n - 1) / (8 * n) * n;
    *gy = (v->height + 8 * m - 1) / (8 * m) * m;
}

static unsigned vpl_needs(const GiParams *p)
{
    (void)p;
    return LIGHT_NEEDS_RSM | LIGHT_NEEDS_VPLS;
}

static void vpl_free_sized(VplGi *v)
{
    GLuint b[2] = {v->tiles, v->evals};
    glDeleteBuffers(2, b);
    v->tiles = v->evals = 0;
    if (v->il.blur)
        gi_interleave_destroy(&v->il);
}

static bool vpl_resize(void *state, int w, int h)
{
    VplGi *v = state;
    vpl_free_sized(v);
    v->width = w;
    v->height = h;
    v->tiles_x = (w + VPL_TILE - 1) / VPL_TILE;
    v->tiles_y = (h + VPL_TILE - 1) / VPL_TILE;
    uint32_t ntiles = (uint32_t)(v->tiles_x * v->tiles_y);
    v->tile_capacity = (LIST_BUDGET / ntiles) & ~3u;
    uint32_t all = (v->vpl_capacity + 3u) & ~3u; /* enough for every VPL */
    if (v->tile_capacity > all)
        v->tile_capacity = all;
    shade_groups(v, &v->groups_x, &v->groups_y);
    v->groups = v->groups_x * v->groups_y;
    size_t tile_words = tiled(v) ? VPL_TILE_LIST_BASE(ntiles) + (size_t)ntiles * v->tile_capacity : 1;
    v->tiles = gl_buffer_make(sizeof(uint32_t) * (uint64_t)tile_words, NULL, GL_DYNAMIC_STORAGE_BIT, "vpl.tiles");
    v->evals = gl_buffer_make(sizeof(uint32_t) * 2 * (uint64_t)v->groups, NULL, 0, "vpl.evaluations");
    if (!v->tiles || !v->evals) /* logged */
        return false;
    GpuGiParams g;
    gi_params_to_gpu(&v->params, w, h, &g);
    glNamedBufferSubData(v->gi_ubo, 0, sizeof g, &g);
    if (interleaved(v))
        return gi_interleave_create(&v->il, v->pc, v->params.interleave.pattern.n, v->params.interleave.pattern.m, w,
                                    h, false);
    return true;
}

static void vpl_destroy(void *state)
{
    VplGi *v = state;
    if (!v)
        return;
    vpl_free_sized(v);
    ism_free(v->ism);
    GLuint bufs[4] = {v->ubo, v->gi_ubo, v->ranges, v->subsets};
    glDeleteBuffers(4, bufs);
    free(v);
}

/* The shading programs get the visibility's defines after their own. */
static GLuint cached(VplGi *v, const char *label, const char *comp, const char *defines)
{
    char defs[256];
    snprintf(defs, sizeof defs, "%s%s", defines ? defines : "", strstr(comp, "shade") ? ism_defines(v->ism) : "");
    return program_cache_get(v->pc, &(ShaderProgramDesc){.label = label, .comp = comp, .defines = defs});
}

static void *vpl_create_method(const GiCreateInfo *ci, VplMethod method)
{
    VplGi *v = calloc(1, sizeof *v);
    if (!v) {
        log_error("vpl", "out of memory");
        return NULL;
    }
    v->method = method;
    v->params = *ci->params;
    v->pc = ci->programs;
    v->vpl_capacity = ci->lights->vpls.capacity ? ci->lights->vpls.capacity : 1;
    if (v->params.visibility.on && !(v->ism = ism_new(ISM_FROM_VPLS, ci, "vpl"))) {
        vpl_destroy(v);
        return NULL;
    }
    bool ok = true;
    if (tiled(v)) {
        v->params_prog = method == VPL_SLC
                             ? cached(v, "vpl_params_slc", "gi/vpl/params.comp", "#define MODE_SLC\n")
                             : cached(v, "vpl_params_clamped", "gi/vpl/params.comp", NULL);
        v->cull = cached(v, "vpl_cull", "gi/vpl/cull.comp", NULL);
        v->shade = method == VPL_SLC ? cached(v, "vpl_shade_slc", "gi/vpl/shade.comp", "#define MODE_TILED\n#define SLC\n")
                                     : cached(v, "vpl_shade_clamped", "gi/vpl/shade.comp", "#define MODE_TILED\n");
        ok = v->params_prog && v->cull && v->shade;
    } else if (method == VPL_ALL) {
        ok = (v->shade = cached(v, "vpl_shade_all", "gi/vpl/shade.comp", "#define MODE_ALL\n")) != 0;
    } else {
        char defs[96]; /* the pattern compiled in: constant divisors */
        gi_interleave_defines(defs, sizeof defs, "#define MODE_INTERLEAVED", v->params.interleave.pattern.n,
                              v->params.interleave.pattern.m);
        v->shade = cached(v, "vpl_shade_interleaved", "gi/vpl/shade.comp", defs);
        if (method == VPL_METALIGHTS)
            v->signature = cached(v, "metalight_signature", "gi/vpl/metalight_signature.comp", NULL);
        ok = v->shade && (method != VPL_METALIGHTS || v->signature);
    }
    v->ubo = gi_ubo_make(sizeof(GpuVplParams), "vpl.params");
    v->gi_ubo = gi_ubo_make(sizeof(GpuGiParams), "gi.params");
    v->ranges = gl_buffer_make(sizeof(float) * 2 * (uint64_t)(tiled(v) ? v->vpl_capacity : 1), NULL, 0, "vpl.ranges");
    size_t subset_bytes = interleaved(v) ? sizeof(GpuVpl) * ((size_t)v->vpl_capacity + 256) : 16; /* K ≤ 256 */
    v->subsets = gl_buffer_make(subset_bytes, NULL, GL_DYNAMIC_STORAGE_BIT, "vpl.subsets");
    ok = ok && v->ubo && v->gi_ubo && v->ranges && v->subsets; /* each logs its failure */
    if (!ok || !vpl_resize(v, ci->width, ci->height)) {
        vpl_destroy(v);
        return NULL;
    }
    return v;
}

/* Uploads the parameters: exposure E for SLC, clamped range in metres. */
static void upload_params(VplGi *v, float exposure, float range)
{
    const GiParams *gp = &v->params;
    GpuVplParams u;
    memset(&u, 0, sizeof u);
    u.slc_emax = gp->vpl.slc_emax;
    u.slc_exposure = exposure > 0.f ? exposure : 1.f;
    u.near_clamp = gp->vpl.near_clamp;
    u.range = range;
    u.keep = gp->vpl.keep;
    u.tile_capacity = v->tile_capacity;
    u.subset_count = (uint32_t)(gp->interleave.pattern.n * gp->interleave.pattern.m);
    u.subset_len = v->subset_len;
    u.tiles_x = v->tiles_x;
    u.tiles_y = v->tiles_y;
    u.signature_w = 16;
    u.signature_h = 16;
    u.disk = gp->vpl.disk ? 1 : 0;
    v->gpu = u;
    glNamedBufferSubData(v->ubo, 0, sizeof u, &u);
}

static void bind_all(const VplGi *v, const LightStage *ls)
{
    light_stage_bind_vpls(ls);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_VPL, v->ubo);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_GI, v->gi_ubo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VPL_RANGE, v->ranges);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_TILES, v->tiles);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_EVALS, v->evals);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_SUBSETS, v->subsets);
}

/* Per-VPL ranges and tiled culling (clamped and slc). */
static void cull(VplGi *v, const GiFrame *f)
{
    bind_all(v, f->lights);
    glUseProgram(v->params_prog);
    glDispatchCompute((v->vpl_capacity + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    uint32_t zero = 0;
    uint32_t ntiles = (uint32_t)(v->tiles_x * v->tiles_y);
    glNamedBufferSubData(v->tiles, sizeof(uint32_t) * ntiles, sizeof zero, &zero); /* overflow */
    glBindTextureUnit(TEX_GB_SURFACE, f->gbuffer->surface);
    glUseProgram(v->cull);
    glDispatchCompute((GLuint)v->tiles_x, (GLuint)v->tiles_y, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

/* Interleave-bit Morton code of two 16-bit coordinates. */
static uint32_t morton2(uint32_t x, uint32_t y)
{
    uint32_t r = 0;
    for (int b = 0; b < 16; b++)
        r |= ((x >> b) & 1u) << (2 * b) | ((y >> b) & 1u) << (2 * b + 1);
    return r;
}

typedef struct SortItem {
    uint64_t key;
    uint64_t tie;   /* the VPL's position bits: fixed per texel */
    uint32_t index;
} SortItem;

static int cmp_item(const void *a, const void *b)
{
    const SortItem *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    if (x->tie != y->tie)
        return x->tie < y->tie ? -1 : 1;
    return 0;
}

/* What the metalight grouping depends on: lights, camera, settings, and
 * the VPLs themselves (extracted again when a moved object redrew an RSM). */
static uint64_t grouping_key(const GiFrame *f)
{
    uint64_t h = util_hash_bytes(UTIL_HASH_SEED, f->scene->lights, sizeof(Light) * (size_t)f->scene->light_count);
    h = util_hash_bytes(h, &f->lights->vpl_extractions, sizeof f->lights->vpl_extractions);
    h = util_hash_bytes(h, f->camera, sizeof *f->camera);
    return util_hash_bytes(h, f->params, sizeof *f->params);
}

/* Builds the interleaved subsets: random (interleaved) or from metalights
 * (recomputed only when the grouping key changes; the light stage keeps the
 * VPL buffer's order while the lights and RSM settings stay). Returns false
 * after logging if memory runs out. */
static bool subsets(VplGi *v, const GiFrame *f)
{
    uint64_t key = grouping_key(f);
    if (v->method == VPL_METALIGHTS && v->regroups > 0 && key == v->grouping_key)
        return true; /* nothing changed: keep the grouping */
    const LightStage *ls = f->lights;
    const GiParams *gp = &v->params;
    uint32_t n = light_stage_vpl_count(ls);
    uint32_t K = (uint32_t)(gp->interleave.pattern.n * gp->interleave.pattern.m);
    uint32_t L = (n + K - 1) / K;
    SortItem *items = malloc(sizeof(SortItem) * (n + 1));
    GpuVpl *vpls = malloc(sizeof(GpuVpl) * (n + 1));
    uint32_t *xi_bits = malloc(sizeof(uint32_t) * (n + 1));
    GpuVpl *sub = calloc((size_t)K * L + 1, sizeof(GpuVpl)); /* zero flux: no VPL */
    float(*sig)[4] = v->method == VPL_METALIGHTS ? malloc(sizeof(float) * 4 * (n + 1)) : NULL;
    if (!items || !vpls || !xi_bits || !sub || (v->method == VPL_METALIGHTS && !sig)) {
        log_error("vpl", "out of memory grouping %u VPLs", n);
        free(items), free(vpls), free(xi_bits), free(sub), free(sig);
        return false;
    }
    /* Every VPL's own ξ (fixed by its RSM texel and the seed) orders it, so
     * the subsets do not depend on the order the GPU appended VPLs in. */
    glGetNamedBufferSubData(ls->vpls.vpls, 0, (GLsizeiptr)(sizeof(GpuVpl) * n), vpls);
    for (uint32_t i = 0; i < n; i++) {
        memcpy(&xi_bits[i], &vpls[i].normal_xi[3], sizeof(uint32_t));
        const uint32_t *pb = vpls[i].surface; /* the position's bits */
        items[i].tie = ((uint64_t)pb[0] << 32 | pb[1]) ^ ((uint64_t)pb[2] * 0x9e3779b97f4a7c15ull);
    }
    if (v->method == VPL_METALIGHTS) {
        bind_all(v, ls);
        glBindTextureUnit(TEX_GB_SURFACE, f->gbuffer->surface);
        glUseProgram(v->signature);
        glDispatchCompute((n + 63) / 64, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glGetNamedBufferSubData(v->subsets, 0, (GLsizeiptr)(sizeof(float) * 4 * n), sig);
        for (uint32_t i = 0; i < n; i++) {
            bool none = !(sig[i][2] > 0.f);
            uint32_t cx = (uint32_t)(fminf(fmaxf(sig[i][0], 0.f), 1.f) * 65535.f);
            uint32_t cy = (uint32_t)(fminf(fmaxf(sig[i][1], 0.f), 1.f) * 65535.f);
            /* Metalights group VPLs that light the same part of the view:
             * ordered along a Morton curve of their contribution centroid,
             * with VPLs that light nothing last. */
            items[i].key = none ? UINT64_MAX : ((uint64_t)morton2(cx, cy) << 32 | xi_bits[i]);
            items[i].index = i;
        }
        v->grouping_key = key;
        v->regroups++;
    } else {
        /* Random disjoint subsets: VPLs in the order of their random ξ, dealt round-robin. */
        for (uint32_t i = 0; i < n; i++) {
            items[i].key = xi_bits[i];
            items[i].index = i;
        }
    }
    qsort(items, n, sizeof *items, cmp_item);
    /* Each subset's VPLs are copied in its order, so that the shading loop
     * reads a VPL in two loads with no index in between (on llvmpipe every
     * load in a loop is per lane). */
    for (uint32_t j = 0; j < n; j++) {
        uint32_t group = j / K, member = j % K;
        uint32_t k = v->method == VPL_METALIGHTS ? (member + group) % K : member;
        sub[(size_t)k * L + group] = vpls[items[j].index];
        /* The shading loop reads the VPL's own visibility map by its index
         * in the buffer (ξ, the key above, is not read there). */
        memcpy(&sub[(size_t)k * L + group].normal_xi[3], &items[j].index, sizeof(uint32_t));
    }
    glNamedBufferSubData(v->subsets, 0, (GLsizeiptr)(sizeof(GpuVpl) * (size_t)K * L), sub);
    free(items), free(vpls), free(xi_bits), free(sub), free(sig);
    v->subset_len = L;
    v->gpu.subset_len = L;
    glNamedBufferSubData(v->ubo, 0, sizeof v->gpu, &v->gpu);
    return true;
}

static bool vpl_run(void *state, const GiFrame *f)
{
    VplGi *v = state;
    const GiParams *gp = &v->params;
    GpuTimer *t = f->timer;
    const Scene *s = f->scene;
    float range = gp->vpl.range > 0.f ? gp->vpl.range
                                      : 0.15f * glm_vec3_distance((float *)s->bounds_min, (float *)s->bounds_max);
    upload_params(v, f->exposure, range);
    if (v->ism)
        ism_update(v->ism, f);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_GI, v->gi_ubo);
    if (tiled(v)) {
        gpu_timer_begin(t, v->method == VPL_SLC ? "slc_cull" : "vpl_cull");
        cull(v, f);
        gpu_timer_end(t);
    } else if (interleaved(v)) {
        gpu_timer_begin(t, v->method == VPL_METALIGHTS ? "metalights_group" : "vpl_subsets");
        bool grouped = subsets(v, f); /* logs a failure */
        gpu_timer_end(t);
        if (!grouped)
            return false; /* its subsets would be last frame's, or undefined */
    }
    bool blur = interleaved(v) && gp->interleave.blur;
    GLuint out = blur ? v->il.merged : f->irradiance;
    gpu_timer_begin(t, "vpl_shade");
    bind_all(v, f->lights);
    glBindTextureUnit(TEX_GB_SURFACE, f->gbuffer->surface);
    glBindImageTexture(IMG_OUT, out, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    if (v->ism)
        ism_bind(v->ism, f->lights, v->shade, 0);
    glUseProgram(v->shade);
    /* One dispatch per LOOP_CHUNK entries of the longest list a pixel can
     * have (llvmpipe ends a shader loop after 65535 iterations). */
    uint32_t longest = tiled(v) ? v->tile_capacity : interleaved(v) ? v->subset_len : v->vpl_capacity;
    for (uint32_t chunk = 0; chunk == 0 || chunk < longest; chunk += LOOP_CHUNK) {
        glProgramUniform1ui(v->shade, LOC_CHUNK, chunk);
        glDispatchCompute((GLuint)v->groups_x, (GLuint)v->groups_y, 1);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                        GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    }
    gpu_timer_end(t);
    if (blur) {
        gpu_timer_begin(t, "interleave_blur");
        gi_interleave_blur(&v->il, f->gbuffer, v->il.merged, f->irradiance);
        gpu_timer_end(t);
    }
    return true;
}

static void vpl_stats(void *state, const GiFrame *f, GiStats *st)
{
    VplGi *v = state;
    st->vpl_count = light_stage_vpl_count(f->lights);
    st->gathered_pixels = gi_count_surfaces(f, v->pc, 1);
    uint32_t *e = malloc(sizeof(uint32_t) * 2 * (size_t)v->groups);
    if (e) {
        glGetNamedBufferSubData(v->evals, 0, (GLsizeiptr)(sizeof(uint32_t) * 2 * (size_t)v->groups), e);
        for (int i = 0; i < v->groups; i++) {
            st->vpl_evaluations += e[i];
            st->vpl_candidates += e[v->groups + i];
        }
        free(e);
    }
    if (tiled(v)) {
        uint32_t ntiles = (uint32_t)(v->tiles_x * v->tiles_y);
        glGetNamedBufferSubData(v->tiles, sizeof(uint32_t) * ntiles, sizeof st->tile_overflow, &st->tile_overflow);
    }
    st->metalight_regroups = v->regroups;
    gi_stats_add_gather(st, "vpl_shade", st->vpl_candidates); /* its timer (vpl_run) */
    st->gather_vpl = true;
    const GLuint bufs[6] = {v->ubo, v->gi_ubo, v->ranges, v->tiles, v->evals, v->subsets};
    st->gpu_bytes = gl_buffers_bytes(bufs, 6) + gi_interleave_bytes(&v->il);
    if (v->ism) {
        st->visibility_builds = v->ism->builds;
        st->visibility_bytes = ism_gpu_bytes(v->ism);
        st->gpu_bytes += st->visibility_bytes;
    }
}

static void *vpl_all_create(const GiCreateInfo *ci) { return vpl_create_method(ci, VPL_ALL); }
static void *vpl_clamped_create(const GiCreateInfo *ci) { return vpl_create_method(ci, VPL_CLAMPED); }
static void *vpl_slc_create(const GiCreateInfo *ci) { return vpl_create_method(ci, VPL_SLC); }
static void *vpl_interleaved_create(const GiCreateInfo *ci) { return vpl_create_method(ci, VPL_INTERLEAVED); }
static void *vpl_metalights_create(const GiCreateInfo *ci) { return vpl_create_method(ci, VPL_METALIGHTS); }

/* Every VPL slot the light stage fills at every pixel: tiles visit every
 * VPL in the worst case; vpl-all keeps its fraction. */
static double vpl_cost(const GiCostQuery *q)
{
    return q->pixels * gi_cost_rsm_texels(q, true);
}

static double vpl_all_cost(const GiCostQuery *q) { return vpl_cost(q) * q->params->vpl.keep; }

/* Interleaved: each pixel shades one subset of the VPLs. */
static double vpl_subset_cost(const GiCostQuery *q)
{
    return vpl_cost(q) / ((double)q->params->interleave.pattern.n * q->params->interleave.pattern.m);
}

#define VPL_ROW(id, row_name, row_paper, create_fn, cost_fn, row_flags, text)                           \
    const GiTechnique id = {                                                                           \
        .name = row_name,                                                                              \
        .paper = row_paper,                                                                            \
        .summary = text,                                                                               \
        .flags = (row_flags) | GI_VISIBILITY,                                                          \
        .rsm_from_vpl_count = true,                                                                    \
        .needs = vpl_needs,                                                                            \
        .create = create_fn,                                                                           \
        .resize = vpl_resize,                                                                          \
        .run = vpl_run,                                                                                \
        .stats = vpl_stats,                                                                            \
        .destroy = vpl_destroy,                                                                        \
        .cost = cost_fn,                                                                               \
        .print_stats = gi_print_vpl_stats,                                                             \
    };

VPL_ROW(gi_vpl_all, "vpl-all", "Keller 1997, Instant Radiosity", vpl_all_create, vpl_all_cost, GI_EXHAUSTIVE,
        "every pixel sums every VPL (brute force)")
VPL_ROW(gi_vpl_clamped, "vpl-clamped", "SPEC §4 (clamped-range baseline)", vpl_clamped_create, vpl_cost, 0,
        "each VPL cut at a fixed range (biased baseline), tiled culling")
VPL_ROW(gi_vpl_slc, "vpl-slc", "Tokuyoshi & Harada 2016, Stochastic Light Culling", vpl_slc_create, vpl_cost, 0,
        "stochastic light culling with 16x16 tiled culling")
VPL_ROW(gi_vpl_interleaved, "vpl-interleaved", "Keller & Heidrich 2001; Segovia et al. 2006",
        vpl_interleaved_create, vpl_subset_cost, 0, "interleaved shading with random disjoint VPL subsets")
VPL_ROW(gi_vpl_metalights, "vpl-metalights", "Faure & Chang 2010, Metalights", vpl_metalights_create, vpl_subset_cost, 0,
        "interleaved shading with subsets dealt from metalights")
