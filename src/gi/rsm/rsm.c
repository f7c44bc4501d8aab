/* rsm.c — one-bounce gathering from reflective shadow maps (Dachsbacher &
 * Stamminger 2005), SPEC §3, and its two accelerations; three rows of the
 * technique table:
 *   rsm              N samples per pixel on the paper's polar pattern
 *                    (--rsm-exhaustive: every VPL of the light stage)
 *   rsm-interp       gather at 1/f resolution, interpolate where 3–4 of the
 *                    4 surrounding low-res samples agree in normal and
 *                    position, full gather for the listed rest (the paper's
 *                    screen-space interpolation)
 *   rsm-interleaved  n×m de-interleaved sub-images with disjoint sample
 *                    subsets, reassembled, then a geometry-aware blur
 * With --gi-visibility on, every sample's contribution is multiplied by its
 * visibility of the pixel, from imperfect shadow maps (gi/visibility/ism.h:
 * one per block of RSM texels; exhaustive: one per VPL).
 * Inputs: G-buffer, the light stage's RSMs (and VPLs when exhaustive).
 * Output: irradiance. Owns: its programs, the sample pattern, the low-res
 * image and pixel list (interp), the interleaving helper (interleaved);
 * its programs come from the renderer's cache.
 * Shaders: shaders/gi/rsm/ (gather.comp, sampling.glsl, interp.comp). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gi/gi.h"
#include "gi/interleave.h"
#include "gi/visibility/ism.h"
#include "gl/gl_resources.h"
#include "base/log.h"
#include "gl/shader.h"

/* The interp pixel list: count, indirect dispatch arguments (x, y, z),
 * then the entries (gi/rsm/interp.comp). */
#define PIXEL_LIST_HEADER 4

typedef enum RsmVariant { RSM_FULL, RSM_INTERP, RSM_INTERLEAVED } RsmVariant;
typedef enum GatherLayout { GATHER_FULL, GATHER_LOWRES, GATHER_LIST, GATHER_INTERLEAVED, GATHER_LAYOUTS } GatherLayout;

typedef struct RsmGi {
    RsmVariant variant;
    GiParams params;
    ProgramCache *pc;                 /* borrowed: owns the programs */
    int width, height;
    GLuint gather[GATHER_LAYOUTS][2]; /* [layout][cube], those the variant uses */
    GLuint interp;                    /* interp.comp */
    GLuint ubo;                       /* GpuGiParams */
    GLuint lowres;                    /* interp: RGBA32F low-res irradiance */
    GLuint list;                      /* interp: SSBO {count, pixels[]} */
    GiInterleave il;                  /* interleaved */
    GpuGiParams gpu;                  /* as uploaded for the current size (low-res size, ...) */
    /* Importance weighting, per light: */
    int lights;
    GLuint importance_blocks[2];      /* importance.comp's programs: levels 1-2 from the RSM [cube], */
    GLuint importance_reduce;         /* the levels above, */
    GLuint importance_sample[2];      /* the sample list [cube] */
    GLuint *pyramid;                  /* R32F 2D array: flux luminance sums, level L >= 1 of a power-of-two
                                         pyramid at mip L - 1 (level 0 is the RSM itself, gi/rsm/importance.comp) */
    int *pyramid_levels;              /* levels, counting level 0 */
    GLuint *samples;                  /* SSBO: GpuVpl[list_size], flux Φ/p */
    uint64_t *built_from;             /* RsmMap.version each pyramid and list were built from (0: none) */
    int importance_builds;            /* how many times one was built */
    Ism *ism;                         /* --gi-visibility: the visibility maps (NULL: off) */
} RsmGi;

static unsigned rsm_needs(const GiParams *p)
{
    return LIGHT_NEEDS_RSM | (p->rsm.exhaustive ? LIGHT_NEEDS_VPLS : 0u);
}

static bool make_gather(RsmGi *g, GatherLayout layout)
{
    static const char *const layout_def[GATHER_LAYOUTS] = {"#define MODE_FULL\n", "#define MODE_LOWRES\n",
                                                           "#define MODE_LIST\n", "#define MODE_INTERLEAVED\n"};
    char defs[256];
    for (int c = 0; c < 2; c++) {
        /* The weighting, the exhaustive sum and the visibility are compiled in (gather.comp). */
        snprintf(defs, sizeof defs, "%s%s#define WEIGHTING %d\n%s%s%s", layout_def[layout], light_stage_rsm_kind(c),
                 (int)g->params.rsm.weighting, g->params.rsm.exhaustive ? "#define EXHAUSTIVE\n" : "",
                 g->params.rsm.reads_only ? "#define READS_ONLY\n" : "", ism_defines(g->ism));
        g->gather[layout][c] = program_cache_get(g->pc, &(ShaderProgramDesc){.label = "rsm_gather", .comp = "gi/rsm/gather.comp", .defines = defs});
        if (!g->gather[layout][c])
            return false;
    }
    return true;
}

static void rsm_free_sized(RsmGi *g)
{
    glDeleteTextures(1, &g->lowres);
    glDeleteBuffers(1, &g->list);
    g->lowres = g->list = 0;
    if (g->il.blur)
        gi_interleave_destroy(&g->il);
}

static bool rsm_resize(void *state, int w, int h)
{
    RsmGi *g = state;
    rsm_free_sized(g);
    g->width = w;
    g->height = h;
    gi_params_to_gpu(&g->params, w, h, &g->gpu);
    glNamedBufferSubData(g->ubo, 0, sizeof g->gpu, &g->gpu);
    if (g->variant == RSM_INTERP) {
        g->lowres = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, g->gpu.low_width, g->gpu.low_height, "gi.lowres");
        g->list = gl_buffer_make(sizeof(uint32_t) * (PIXEL_LIST_HEADER + (uint64_t)w * h), NULL,
                                 GL_DYNAMIC_STORAGE_BIT, "gi.pixel_list");
        return g->lowres && g->list; /* each logs its failure */
    } else if (g->variant == RSM_INTERLEAVED) {
        return gi_interleave_create(&g->il, g->pc, g->params.interleave.pattern.n, g->params.interleave.pattern.m, w,
                                    h, true);
    }
    return true;
}

static bool importance_on(const RsmGi *g)
{
    return g->params.rsm.weighting == RSM_WEIGHT_IMPORTANCE && !g->params.rsm.exhaustive;
}

static void importance_destroy(RsmGi *g)
{
    if (g->pyramid)
        glDeleteTextures(g->lights, g->pyramid);
    if (g->samples)
        glDeleteBuffers(g->lights, g->samples);
    free(g->pyramid);
    free(g->samples);
    free(g->pyramid_levels);
    free(g->built_from);
    g->pyramid = g->samples = NULL;
    g->pyramid_levels = NULL;
    g->built_from = NULL;
}

static GLuint importance_program(RsmGi *g, const char *mode, const char *kind)
{
    char defs[64];
    snprintf(defs, sizeof defs, "%s%s", mode, kind);
    return program_cache_get(g->pc, &(ShaderProgramDesc){.label = "rsm_importance", .comp = "gi/rsm/importance.comp", .defines = defs});
}

/* A flux pyramid and a sample list for each light's RSM. */
static bool importance_create(RsmGi *g, const LightStage *ls)
{
    g->importance_reduce = importance_program(g, "#define MODE_REDUCE\n", "");
    for (int cube = 0; cube < 2; cube++) {
        g->importance_blocks[cube] = importance_program(g, "#define MODE_BLOCKS\n", light_stage_rsm_kind(cube));
        g->importance_sample[cube] = importance_program(g, "#define MODE_SAMPLE\n", light_stage_rsm_kind(cube));
    }
    if (!g->importance_reduce || !g->importance_blocks[0] || !g->importance_blocks[1] || !g->importance_sample[0] ||
        !g->importance_sample[1])
        return false;
    g->lights = ls->light_count;
    g->pyramid = calloc((size_t)g->lights + 1, sizeof(GLuint));
    g->samples = calloc((size_t)g->lights + 1, sizeof(GLuint));
    g->pyramid_levels = calloc((size_t)g->lights + 1, sizeof(int));
    g->built_from = calloc((size_t)g->lights + 1, sizeof(uint64_t));
    if (!g->pyramid || !g->samples || !g->pyramid_levels || !g->built_from) {
        log_error("rsm", "out of memory for %d importance pyramids", g->lights);
        return false;
    }
    size_t list = (size_t)rsm_far_samples(g->params.rsm.samples) * RSM_LIST_SETS;
    for (int i = 0; i < g->lights; i++) {
        const RsmMap *m = &ls->rsm[i];
        int p = 4, levels = 3; /* the blocks pass writes levels 1 and 2 (RSM sizes are at least 4) */
        while (p < m->size) {
            p *= 2;
            levels++;
        }
        g->pyramid_levels[i] = levels;
        g->pyramid[i] = gl_texture_make_levels(GL_TEXTURE_2D_ARRAY, GL_R32F, p / 2, p / 2, m->cube ? 6 : 1, levels - 1,
                                               "rsm.importance_pyramid");
        g->samples[i] = gl_buffer_make(sizeof(GpuVpl) * (uint64_t)list, NULL, 0, "rsm.importance_samples");
        if (!g->pyramid[i] || !g->samples[i]) /* each logs its failure */
            return false;
        glTextureParameteri(g->pyramid[i], GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    }
    return true;
}

/* Builds light i's pyramid from its RSM and draws its sample list. */
static void importance_run(RsmGi *g, const LightStage *ls, int i)
{
    const RsmMap *m = &ls->rsm[i];
    int layers = m->cube ? 6 : 1, top = g->pyramid_levels[i] - 1;
    int p = 1 << top;
    light_stage_bind_rsm_layers(ls, i);
    /* Levels 1 and 2 (mips 0 and 1) straight from the RSM, then the rest. */
    glBindImageTexture(IMG_OUT, g->pyramid[i], 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindImageTexture(IMG_OUT2, g->pyramid[i], 1, GL_TRUE, 0, GL_WRITE_ONLY, GL_R32F);
    glUseProgram(g->importance_blocks[m->cube]);
    glDispatchCompute((GLuint)(p / 4 + 7) / 8, (GLuint)(p / 4 + 7) / 8, (GLuint)layers);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glBindTextureUnit(TEX_INPUT, g->pyramid[i]);
    glUseProgram(g->importance_reduce);
    for (int l = 3; l <= top; l++) {
        int s = p >> l;
        glBindImageTexture(IMG_OUT, g->pyramid[i], l - 1, GL_TRUE, 0, GL_WRITE_ONLY, GL_R32F);
        glProgramUniform1i(g->importance_reduce, LOC_IMPORTANCE_LEVEL, l);
        glDispatchCompute((GLuint)(s + 7) / 8, (GLuint)(s + 7) / 8, (GLuint)layers);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_SAMPLES, g->samples[i]);
    glProgramUniform1i(g->importance_sample[m->cube], LOC_IMPORTANCE_LEVEL, top);
    glUseProgram(g->importance_sample[m->cube]);
    GLuint n = (GLuint)(rsm_far_samples(g->params.rsm.samples) * RSM_LIST_SETS);
    glDispatchCompute((n + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

static void rsm_destroy(void *state)
{
    RsmGi *g = state;
    if (!g)
        return;
    ism_free(g->ism);
    importance_destroy(g);
    rsm_free_sized(g);
    glDeleteBuffers(1, &g->ubo);
    free(g);
}

static void *rsm_create_variant(const GiCreateInfo *ci, RsmVariant variant)
{
    RsmGi *g = calloc(1, sizeof *g);
    if (!g) {
        log_error("rsm", "out of memory");
        return NULL;
    }
    g->variant = variant;
    g->params = *ci->params;
    g->pc = ci->programs;
    if (g->params.visibility.on &&
        !(g->ism = ism_new(g->params.rsm.exhaustive ? ISM_FROM_VPLS : ISM_FROM_RSM, ci, "rsm"))) {
        rsm_destroy(g);
        return NULL;
    }
    bool ok;
    switch (variant) {
    case RSM_FULL:
        ok = make_gather(g, GATHER_FULL);
        break;
    case RSM_INTERP:
        ok = make_gather(g, GATHER_LOWRES) && make_gather(g, GATHER_LIST) &&
             (g->interp = program_cache_get(g->pc, &(ShaderProgramDesc){.label = "rsm_interp", .comp = "gi/rsm/interp.comp", .defines = NULL})) != 0;
        break;
    default:
        ok = make_gather(g, GATHER_INTERLEAVED);
        break;
    }
    ok = ok && (g->ubo = gi_ubo_make(sizeof(GpuGiParams), "gi.params")) != 0;
    if (ok && importance_on(g))
        ok = importance_create(g, ci->lights);
    if (!ok || !rsm_resize(g, ci->width, ci->height)) {
        rsm_destroy(g);
        return NULL;
    }
    return g;
}

static void *rsm_create(const GiCreateInfo *ci) { return rsm_create_variant(ci, RSM_FULL); }
static void *rsm_interp_create(const GiCreateInfo *ci) { return rsm_create_variant(ci, RSM_INTERP); }
static void *rsm_interleaved_create(const GiCreateInfo *ci) { return rsm_create_variant(ci, RSM_INTERLEAVED); }

/* Gathers every light into `out` (the first light writes, the rest add). An
 * exhaustive gather sums the whole VPL buffer, every light's, at once. */
static void gather_lights(RsmGi *g, const GiFrame *f, GatherLayout layout, GLuint out)
{
    const LightStage *ls = f->lights;
    bool exh = g->params.rsm.exhaustive;
    if (exh)
        light_stage_bind_vpls(ls);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_PIXEL_LIST, g->list);
    bool di = layout == GATHER_INTERLEAVED;
    glBindTextureUnit(TEX_GB_SURFACE, di ? g->il.di_surface : f->gbuffer->surface);
    GLuint target = layout == GATHER_LOWRES ? g->lowres : di ? g->il.di_irradiance : out;
    glBindImageTexture(IMG_OUT, target, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    int lights = exh && ls->light_count > 0 ? 1 : ls->light_count;
    for (int i = 0; i < lights; i++) {
        GLuint prog = g->gather[layout][ls->rsm[i].cube ? 1 : 0];
        light_stage_bind_rsm(ls, i);
        if (importance_on(g))
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_SAMPLES, g->samples[i]);
        if (g->ism)
            ism_bind(g->ism, ls, prog, i);
        glUseProgram(prog);
        /* Exhaustive: one dispatch per LOOP_CHUNK VPLs (llvmpipe ends a
         * shader loop after 65535 iterations), the later ones adding. */
        uint32_t vpls = exh ? ls->vpls.capacity : 1;
        for (uint32_t chunk = 0; chunk < vpls; chunk += LOOP_CHUNK) {
            glProgramUniform1i(prog, LOC_GATHER_ACCUMULATE, i > 0 || chunk > 0 ? 1 : 0);
            glProgramUniform1ui(prog, LOC_CHUNK, chunk);
            switch (layout) {
            case GATHER_LOWRES:
                gi_dispatch_pixels(g->gpu.low_width, g->gpu.low_height);
                break;
            case GATHER_INTERLEAVED:
                gi_dispatch_pixels(g->il.di_w, g->il.di_h);
                break;
            case GATHER_LIST: /* 64 entries per group, as many as interp.comp counted */
                glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, g->list);
                glDispatchComputeIndirect(sizeof(uint32_t));
                glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
                glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                                GL_SHADER_STORAGE_BARRIER_BIT);
                break;
            default:
                gi_dispatch_pixels(g->width, g->height);
                break;
            }
        }
    }
}

static bool rsm_run(void *state, const GiFrame *f)
{
    RsmGi *g = state;
    GpuTimer *t = f->timer;
    if (g->ism)
        ism_update(g->ism, f);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_GI, g->ubo);
    /* The pyramid and the sample list derive from the RSM alone: rebuilt
     * when the light stage redrew it (a light or the scene moved, caching
     * off), kept while it keeps it. */
    bool timing = false;
    for (int i = 0; importance_on(g) && i < f->lights->light_count; i++) {
        if (g->built_from[i] == f->lights->rsm[i].version)
            continue;
        if (!timing)
            gpu_timer_begin(t, "rsm_importance");
        timing = true;
        importance_run(g, f->lights, i);
        g->built_from[i] = f->lights->rsm[i].version;
        g->importance_builds++;
    }
    if (timing)
        gpu_timer_end(t);
    switch (g->variant) {
    case RSM_FULL:
        gpu_timer_begin(t, "rsm_gather");
        gather_lights(g, f, GATHER_FULL, f->irradiance);
        gpu_timer_end(t);
        break;
    case RSM_INTERP: {
        gpu_timer_begin(t, "rsm_gather_lowres");
        gather_lights(g, f, GATHER_LOWRES, f->irradiance);
        gpu_timer_end(t);
        gpu_timer_begin(t, "rsm_interp");
        /* Count 0; the full gathers' indirect dispatch: 0 × 1 × 1 groups. */
        const uint32_t header[PIXEL_LIST_HEADER] = {0, 0, 1, 1};
        glNamedBufferSubData(g->list, 0, sizeof header, header);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_PIXEL_LIST, g->list);
        glBindTextureUnit(TEX_GB_SURFACE, f->gbuffer->surface);
        glBindTextureUnit(TEX_INPUT, g->lowres);
        glBindImageTexture(IMG_OUT, f->irradiance, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glUseProgram(g->interp);
        gi_dispatch_pixels(g->width, g->height);
        glMemoryBarrier(GL_COMMAND_BARRIER_BIT); /* the list's dispatch arguments */
        gpu_timer_end(t);
        gpu_timer_begin(t, "rsm_gather_full");
        gather_lights(g, f, GATHER_LIST, f->irradiance);
        gpu_timer_end(t);
        break;
    }
    case RSM_INTERLEAVED:
        gpu_timer_begin(t, "interleave_split");
        gi_interleave_split(&g->il, f->gbuffer);
        gpu_timer_end(t);
        gpu_timer_begin(t, "rsm_gather_interleaved");
        gather_lights(g, f, GATHER_INTERLEAVED, f->irradiance);
        gpu_timer_end(t);
        gpu_timer_begin(t, "interleave_merge_blur");
        gi_interleave_merge(&g->il, f->gbuffer, g->params.interleave.blur, f->irradiance);
        gpu_timer_end(t);
        break;
    }
    return true;
}

static void rsm_stats(void *state, const GiFrame *f, GiStats *st)
{
    RsmGi *g = state;
    st->vpl_count = g->params.rsm.exhaustive ? light_stage_vpl_count(f->lights) : 0;
    if (g->variant == RSM_INTERP) {
        st->lowres_gathers = gi_count_surfaces(f, g->pc, g->params.rsm.interp_factor);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glGetNamedBufferSubData(g->list, 0, sizeof st->full_gathers, &st->full_gathers);
        st->gathered_pixels = st->lowres_gathers + st->full_gathers;
    } else {
        st->gathered_pixels = gi_count_surfaces(f, g->pc, 1); /* interleaved: each pixel once, padding none */
    }
    uint64_t per_pixel = g->params.rsm.exhaustive ? st->vpl_count : (uint64_t)g->params.rsm.samples;
    if (g->variant == RSM_INTERLEAVED && !g->params.rsm.exhaustive)
        per_pixel =
            (uint64_t)(g->params.rsm.samples / (g->params.interleave.pattern.n * g->params.interleave.pattern.m));
    per_pixel = per_pixel ? per_pixel : 1;
    switch (g->variant) { /* each gather pass, named as its timer (rsm_run) */
    case RSM_FULL:
        gi_stats_add_gather(st, "rsm_gather", st->gathered_pixels * per_pixel);
        break;
    case RSM_INTERP:
        gi_stats_add_gather(st, "rsm_gather_lowres", st->lowres_gathers * per_pixel);
        gi_stats_add_gather(st, "rsm_gather_full", st->full_gathers * per_pixel);
        break;
    case RSM_INTERLEAVED:
        gi_stats_add_gather(st, "rsm_gather_interleaved", st->gathered_pixels * per_pixel);
        break;
    }
    st->gather_cube = f->lights->light_count > 0 && f->lights->rsm[0].cube;
    st->gather_map_size = f->lights->light_count > 0 ? f->lights->rsm[0].size : 0;
    st->rsm_importance_builds = g->importance_builds;
    st->gather_vpl = g->params.rsm.exhaustive;
    st->gather_from_list = importance_on(g) ? 0.5f : 0.f;
    const GLuint bufs[2] = {g->ubo, g->list};
    st->gpu_bytes = gl_texture_bytes(g->lowres) + gl_buffers_bytes(bufs, 2) + gi_interleave_bytes(&g->il);
    if (g->pyramid && g->samples)
        st->gpu_bytes += gl_textures_bytes(g->pyramid, g->lights) + gl_buffers_bytes(g->samples, g->lights);
    if (g->ism) {
        st->gpu_bytes += ism_gpu_bytes(g->ism);
        st->visibility_builds = g->ism->builds;
        st->visibility_bytes = ism_gpu_bytes(g->ism);
    }
}

/* Per pixel its samples (interleaving splits the pattern, not the count). */
static double rsm_cost(const GiCostQuery *q)
{
    const GiParams *p = q->params;
    return q->pixels * (p->rsm.exhaustive ? gi_cost_rsm_texels(q, false) : p->rsm.samples);
}

/* Low-res gathers plus a tenth of the pixels in full (Cornell: 5%). */
static double rsm_interp_cost(const GiCostQuery *q)
{
    double f = q->params->rsm.interp_factor;
    return rsm_cost(q) * (1.0 / (f * f) + 0.1);
}

static void rsm_interp_print_stats(const GiStats *st, double pixels, FILE *out)
{
    fprintf(out, "rsm_full_gather_fraction: %.4f\n", (double)st->full_gathers / pixels);
}

#define RSM_PAPER "Dachsbacher & Stamminger 2005, Reflective Shadow Maps"
#define RSM_ROW(id, variant_name, row_paper, create_fn, cost_fn, print_fn, text)                       \
    const GiTechnique id = {                                                                           \
        .name = variant_name,                                                                          \
        .paper = row_paper,                                                                            \
        .summary = text,                                                                               \
        .flags = GI_VISIBILITY | GI_READS_TWIN,                                                        \
        .needs = rsm_needs,                                                                            \
        .create = create_fn,                                                                           \
        .resize = rsm_resize,                                                                          \
        .run = rsm_run,                                                                                \
        .stats = rsm_stats,                                                                            \
        .destroy = rsm_destroy,                                                                        \
        .cost = cost_fn,                                                                               \
        .print_stats = print_fn,                                                                       \
    };

RSM_ROW(gi_rsm, "rsm", RSM_PAPER, rsm_create, rsm_cost, NULL, "RSM gather, N samples per pixel on the paper's polar pattern")
RSM_ROW(gi_rsm_interp, "rsm-interp", RSM_PAPER, rsm_interp_create, rsm_interp_cost, rsm_interp_print_stats,
        "RSM gather at 1/f resolution + the paper's screen-space interpolation")
RSM_ROW(gi_rsm_interleaved, "rsm-interleaved", RSM_PAPER "; Keller & Heidrich 2001, Interleaved Sampling",
        rsm_interleaved_create, rsm_cost, NULL,
        "RSM gather with interleaved sampling and a geometry-aware blur")
