/* lpv.c — light propagation volumes (Kaplanyan & Dachsbacher 2010), SPEC
 * §5; one row of the technique table, `--gi lpv`. Per frame and cascade:
 *   lpv_inject     every VPL (every lit RSM texel, from the light stage's
 *                  VPL buffer) moved half a cell along its normal adds
 *                  Φ/π · SH(max(0, n·ω)) to its cell in three RGBA32F 3D
 *                  textures (R, G, B; 2-band SH each), in the layers of its
 *                  light group (--lpv-groups 2: surfaces facing +x/+y/+z
 *                  and those facing away apart; see lpv_in_group), so the
 *                  grid holds the RSM's flux: by compute with integer
 *                  atomics in fixed point into a buffer and a resolve pass
 *                  (default; 2–3× faster on llvmpipe), or (--lpv-inject
 *                  points) as a point drawn into the textures' layers with
 *                  additive blending
 *   lpv_geometry   every RSM texel and (--lpv-gbuffer-occlusion, default
 *                  on) G-buffer pixel as a surfel into the geometry volume,
 *                  offset by half a cell (normal tensor; see
 *                  shaders/gi/lpv/geometry.vert)
 *   lpv_propagate  `iterations` gathering steps from the 6 neighbours per
 *                  light group, attenuated by the geometry volume (each
 *                  face's factor computed once per build into an image),
 *                  ping-pong, summed into the accumulated volume: light
 *                  keeps its direction (--lpv-propagation directional,
 *                  default) or goes through the paper's 5 faces per
 *                  neighbour (faces); see shaders/gi/lpv/propagate.comp
 *   lpv_lookup     trilinear, half a cell along the normal, cosine lobe →
 *                  irradiance E into GiFrame.irradiance
 * Grids: one of N³ cells fitted to the scene bounds (a cell of margin on
 * each side), or K nested grids centred on the camera, the coarsest just
 * holding the scene bounds around the camera and each finer one half the
 * last, their origins snapped to whole cells (the image does not swim as
 * the camera moves). A finer grid propagates only the VPLs inside it, so every
 * coarser cascade k ≥ 1 propagates two volume sets: every VPL inside it,
 * and only those outside cascade k−1. A point inside cascade k takes the
 * light of cascade k's VPLs from cascade k and that of the rest from the
 * coarser "outer" sets; across the outer tenth of a cascade the lookup
 * fades to the next coarser one.
 * Inputs: light stage (RSMs, VPL buffer), G-buffer, camera. Output:
 * irradiance. Owns: its 3D textures (per cascade and set: injected,
 * accumulated, the light groups stacked in z; per cascade: geometry;
 * shared: the ping-pong pair), their layered framebuffers, a UBO, an
 * indirect draw buffer, the fixed-point buffers of compute injection, the
 * face factors; programs come from the renderer's cache.
 * Shaders: shaders/gi/lpv/. */
#include "gi/lpv/lpv.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cglm/cglm.h>

#include "gi/gi.h"
#include "gl/gl_resources.h"
#include "gl/gpu_budget.h"
#include "base/log.h"
#include "gl/shader.h"
#include "base/util.h"

/* Volume sets of a cascade: every VPL inside it, and (k ≥ 1) only those
 * outside the next finer cascade. */
enum { SET_ALL, SET_OUTER, SETS };

typedef struct LpvCascade {
    GLuint inject[SETS][3];  /* RGBA32F N × N × groups·N: SH of the injected intensity, per channel, the groups
                                stacked in z */
    GLuint sum[SETS][3];     /* the same layout: accumulated */
    GLuint gv[2];            /* RGBA32F (N+1)³: normal tensor (xx yy zz, xy xz yz) */
    GLuint fbo_inject[SETS]; /* layered: inject[set][0..2] */
    GLuint fbo_gv;           /* layered: gv[0..1] */
} LpvCascade;

typedef struct LpvGi {
    GiParams params;
    ProgramCache *pc;       /* borrowed: owns the programs */
    int n;                  /* cells per side */
    int groups;             /* light groups propagated apart (--lpv-groups; see lpv_group in sh.glsl) */
    int cascades;
    int iterations;
    vec3 bmin, bmax;        /* scene bounds */
    LpvCascade c[LPV_MAX_CASCADES];
    GLuint pp[2];           /* ping-pong propagation volumes (3N × N × N: R, G, B side by side), shared by the cascades */
    GLuint inject, geom_rsm[2], geom_gbuf, propagate, lookup; /* programs (geom_rsm: [cube], light_stage_rsm_kind) */
    GLuint inject_fixed, inject_resolve; /* programs of --lpv-inject compute */
    GLuint geom_fixed_rsm[2], geom_fixed_gbuf, geom_resolve; /* geom_fixed_rsm: [cube] */
    GLuint fixed;           /* --lpv-inject compute: int[12·N³] fixed-point SH sums */
    GLuint gv_fixed;        /* --lpv-inject compute: int[6·(N+1)³] fixed-point tensor sums */
    GLuint faces;           /* --lpv-occlusion on: RGBA32F 8N × N × N, the propagation's face factors (propagate.comp) */
    GLuint propagate_faces; /* program filling `faces` from a cascade's geometry volume */
    float scene_power;      /* bound on the light the RSMs can reflect (W), for the fixed-point scale */
    float test_power;       /* the same for lpv_set_vpls' VPLs */
    GLuint ubo;             /* GpuLpvParams */
    GLuint indirect;        /* DrawArraysIndirectCommand of the injection */
    GLuint vao;             /* empty */
    GLuint test_vpls;       /* lpv_set_vpls' buffer, or 0 */
    int test_count;
    GpuLpvParams gpu;       /* as last uploaded */
    uint64_t built_for;     /* the light products and grids the volumes hold (0: none) */
    int builds;             /* times the volumes were injected and propagated */
    int last_step;          /* pp[last_step]: the last step of the last volume propagated (lpv_read_volume) */
    uint32_t vpls_injected; /* last build (stats) */
    int width, height;
} LpvGi;

static unsigned lpv_needs(const GiParams *p)
{
    (void)p;
    return LIGHT_NEEDS_RSM | LIGHT_NEEDS_VPLS;
}

/* n × n × depth, trilinear. */
static GLuint volume(GLenum fmt, int n, int depth, const char *label)
{
    return gl_texture3d_make(fmt, n, n, depth, 1, TEX_FILTER_LINEAR, label);
}

static GLuint layered_fbo(const GLuint *tex, int count, const char *label)
{
    GLuint fbo;
    GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glCreateFramebuffers(1, &fbo);
    for (int i = 0; i < count; i++)
        glNamedFramebufferTexture(fbo, bufs[i], tex[i], 0); /* a 3D texture attaches layered */
    glNamedFramebufferDrawBuffers(fbo, count, bufs);
    glObjectLabel(GL_FRAMEBUFFER, fbo, -1, label);
    if (!fbo_check(fbo, label)) {
        glDeleteFramebuffers(1, &fbo);
        return 0;
    }
    return fbo;
}

static void lpv_destroy(void *state)
{
    LpvGi *l = state;
    if (!l)
        return;
    for (int k = 0; k < LPV_MAX_CASCADES; k++) {
        LpvCascade *c = &l->c[k];
        for (int set = 0; set < SETS; set++) {
            for (int i = 0; i < 3; i++) {
                gl_texture3d_destroy(&c->inject[set][i]);
                gl_texture3d_destroy(&c->sum[set][i]);
            }
            gl_fbo_destroy(&c->fbo_inject[set]);
        }
        gl_texture3d_destroy(&c->gv[0]);
        gl_texture3d_destroy(&c->gv[1]);
        gl_fbo_destroy(&c->fbo_gv);
    }
    gl_texture3d_destroy(&l->pp[0]);
    gl_texture3d_destroy(&l->pp[1]);
    GLuint b[5] = {l->ubo, l->indirect, l->test_vpls, l->fixed, l->gv_fixed};
    glDeleteBuffers(5, b);
    gl_texture3d_destroy(&l->faces);
    glDeleteVertexArrays(1, &l->vao);
    free(l);
}

static bool lpv_resize(void *state, int w, int h)
{
    LpvGi *l = state;
    l->width = w;
    l->height = h;
    return true;
}

static bool directional(const LpvGi *l) { return l->params.lpv.propagation == LPV_PROPAGATION_DIRECTIONAL; }

/* Texels per cell of the propagation's face factors (propagate.comp):
 * directional 6 factors in 2, faces 30 in 8. */
static int face_texels(const GiParams *p) { return p->lpv.propagation == LPV_PROPAGATION_DIRECTIONAL ? 2 : 8; }

static GLuint program(LpvGi *l, const char *label, const char *vert, const char *geom, const char *frag,
                      const char *comp, const char *defines)
{
    return program_cache_get(l->pc, &(ShaderProgramDesc){
                                        .label = label, .vert = vert, .geom = geom, .frag = frag, .comp = comp,
                                        .defines = defines});
}

/* The bytes lpv_create asks for: per cascade the injected and summed SH
 * volumes (three RGBA32F N³ per set; finer cascades keep two sets) and the
 * geometry volume's two (N+1)³; the propagation's two 3N·N·N ping-pong
 * volumes; with occlusion the 8N·N·N face factors; with compute injection
 * the fixed-point sums (12 words per cell, 6 per geometry corner). */
static uint64_t lpv_bytes(const GiParams *p)
{
    uint64_t n = (uint64_t)p->lpv.size, n3 = n * n * n, g3 = (n + 1) * (n + 1) * (n + 1), texel = 16;
    uint64_t sets = 1 + 2 * (uint64_t)(p->lpv.cascades - 1);
    uint64_t bytes = sets * 2 * 3 * n3 * (uint64_t)p->lpv.groups * texel + (uint64_t)p->lpv.cascades * 2 * g3 * texel +
                     2 * 3 * n3 * texel;
    if (p->lpv.occlusion)
        bytes += (uint64_t)face_texels(p) * n3 * texel;
    if (p->lpv.inject == LPV_INJECT_COMPUTE)
        bytes += 4 * (12 * n3 + 6 * g3);
    return bytes;
}

/* Every program the settings call for; false after one failed (it logged). */
static bool lpv_programs(LpvGi *l)
{
    l->inject = program(l, "lpv_inject", "gi/lpv/inject.vert", "gi/lpv/layer.geom", "gi/lpv/accumulate.frag", NULL,
                        NULL);
    for (int cube = 0; cube < 2; cube++)
        l->geom_rsm[cube] = program(l, "lpv_geometry", "gi/lpv/geometry.vert", "gi/lpv/layer.geom",
                                    "gi/lpv/accumulate.frag", NULL, light_stage_rsm_kind(cube));
    l->geom_gbuf = program(l, "lpv_geometry_gbuffer", "gi/lpv/geometry.vert", "gi/lpv/layer.geom",
                           "gi/lpv/accumulate.frag", NULL, "#define GBUFFER\n");
    /* Occlusion is compiled in: the faces' factors are then read from
     * `faces`, else they are constants (llvmpipe runs a branch's both arms). */
    const char *mode = directional(l) ? "#define DIRECTIONAL\n" : "";
    char defs[192];
    snprintf(defs, sizeof defs, "%s%s", mode, l->params.lpv.occlusion ? "#define OCCLUSION\n" : "");
    l->propagate = program(l, "lpv_propagate", NULL, NULL, NULL, "gi/lpv/propagate.comp", defs);
    snprintf(defs, sizeof defs, "%s#define OCCLUSION\n#define MODE_FACES\n", mode);
    if (l->params.lpv.occlusion &&
        !(l->propagate_faces = program(l, "lpv_propagate_faces", NULL, NULL, NULL, "gi/lpv/propagate.comp", defs)))
        return false;
    /* The cascade count is compiled in: with it known, every cascade's
     * fetches name their samplers (gi/lpv/lookup.comp). */
    char cascades_def[192];
    snprintf(cascades_def, sizeof cascades_def, "%s#define LPV_CASCADES %d\n#define LPV_GROUPS %d\n", mode, l->cascades,
             l->groups);
    l->lookup = program(l, "lpv_lookup", NULL, NULL, NULL, "gi/lpv/lookup.comp", cascades_def);
    if (!l->inject || !l->geom_rsm[0] || !l->geom_rsm[1] || !l->geom_gbuf || !l->propagate || !l->lookup)
        return false;
    if (l->params.lpv.inject != LPV_INJECT_COMPUTE)
        return true;
    l->inject_fixed = program(l, "lpv_inject_fixed", NULL, NULL, NULL, "gi/lpv/inject_fixed.comp", NULL);
    l->inject_resolve = program(l, "lpv_inject_resolve", NULL, NULL, NULL, "gi/lpv/inject_resolve.comp", NULL);
    for (int cube = 0; cube < 2; cube++)
        l->geom_fixed_rsm[cube] = program(l, "lpv_geometry_fixed", NULL, NULL, NULL, "gi/lpv/geometry_fixed.comp",
                                          light_stage_rsm_kind(cube));
    l->geom_fixed_gbuf = program(l, "lpv_geometry_fixed_gbuffer", NULL, NULL, NULL, "gi/lpv/geometry_fixed.comp",
                                 "#define GBUFFER\n");
    l->geom_resolve = program(l, "lpv_geometry_resolve", NULL, NULL, NULL, "gi/lpv/geometry_resolve.comp", NULL);
    return l->inject_fixed && l->inject_resolve && l->geom_fixed_rsm[0] && l->geom_fixed_rsm[1] &&
           l->geom_fixed_gbuf && l->geom_resolve;
}

/* Every volume and buffer lpv_bytes counts, the parameter block and the
 * indirect command; false after one failed (it logged). */
static bool lpv_volumes(LpvGi *l)
{
    int n = l->n;
    bool ok = true;
    if (l->params.lpv.occlusion)
        ok = (l->faces = gl_texture3d_make(GL_RGBA32F, face_texels(&l->params) * n, n, n, 1, TEX_FILTER_NEAREST,
                                           "lpv.faces")) != 0;
    if (ok && l->params.lpv.inject == LPV_INJECT_COMPUTE) {
        size_t n3 = (size_t)n * n * n, g3 = (size_t)(n + 1) * (n + 1) * (n + 1);
        ok = (l->fixed = gl_buffer_make(sizeof(int32_t) * 12 * n3, NULL, GL_DYNAMIC_STORAGE_BIT, "lpv.fixed")) &&
             (l->gv_fixed = gl_buffer_make(sizeof(int32_t) * 6 * g3, NULL, GL_DYNAMIC_STORAGE_BIT, "lpv.geometry_fixed"));
    }
    for (int k = 0; ok && k < l->cascades; k++) {
        LpvCascade *c = &l->c[k];
        for (int set = 0; ok && set < (k > 0 ? SETS : 1); set++) {
            for (int i = 0; ok && i < 3; i++)
                ok = (c->inject[set][i] = volume(GL_RGBA32F, n, l->groups * n, "lpv.inject")) &&
                     (c->sum[set][i] = volume(GL_RGBA32F, n, l->groups * n, "lpv.sum"));
            ok = ok && (c->fbo_inject[set] = layered_fbo(c->inject[set], 3, "lpv.inject"));
        }
        for (int i = 0; ok && i < 2; i++)
            ok = (c->gv[i] = volume(GL_RGBA32F, n + 1, n + 1, "lpv.geometry")) != 0;
        ok = ok && (c->fbo_gv = layered_fbo(c->gv, 2, "lpv.geometry"));
    }
    for (int i = 0; ok && i < 2; i++)
        ok = (l->pp[i] = gl_texture3d_make(GL_RGBA32F, 3 * n, n, n, 1, TEX_FILTER_NEAREST, "lpv.propagate")) != 0;
    const GLuint cmd[4] = {0, 1, 0, 0};
    return ok && (l->ubo = gi_ubo_make(sizeof(GpuLpvParams), "lpv.params")) &&
           (l->indirect = gl_buffer_make(sizeof cmd, cmd, GL_DYNAMIC_STORAGE_BIT, "lpv.indirect"));
}

/* What the RSMs can reflect at most: every light's power into the scene
 * (directional: E over the bounds' diagonal squared; others: the on-axis
 * intensity, their largest, over the whole sphere). */
static float scene_power(const Scene *s)
{
    vec3 ext;
    glm_vec3_sub((float *)s->bounds_max, (float *)s->bounds_min, ext);
    float power = 0.f;
    for (int i = 0; i < s->light_count; i++) {
        const Light *li = &s->lights[i];
        vec3 on_axis;
        light_intensity(li, (float *)li->direction, on_axis);
        power += li->type == LIGHT_DIRECTIONAL ? glm_vec3_max((float *)li->color) * glm_vec3_norm2(ext)
                                               : glm_vec3_max(on_axis) * 4.f * GLM_PIf;
    }
    return power;
}

static void *lpv_create(const GiCreateInfo *ci)
{
    char what[64];
    snprintf(what, sizeof what, "--lpv-size %d with --lpv-cascades %d", ci->params->lpv.size, ci->params->lpv.cascades);
    if (!gpu_budget_check(lpv_bytes(ci->params), what))
        return NULL;
    LpvGi *l = calloc(1, sizeof *l);
    if (!l) {
        log_error("lpv", "out of memory");
        return NULL;
    }
    l->params = *ci->params;
    l->pc = ci->programs;
    l->n = ci->params->lpv.size;
    l->cascades = ci->params->lpv.cascades;
    l->groups = ci->params->lpv.groups;
    /* 0: enough steps to cross the grid's diagonal, √3·N cells (directional:
     * LPV_SPEED = 1/√3 cells a step; faces: a cell a step along an axis). */
    l->iterations = ci->params->lpv.iterations > 0 ? ci->params->lpv.iterations : directional(l) ? 3 * l->n : l->n;
    glm_vec3_copy((float *)ci->scene->bounds_min, l->bmin);
    glm_vec3_copy((float *)ci->scene->bounds_max, l->bmax);
    l->width = ci->width;
    l->height = ci->height;
    l->scene_power = scene_power(ci->scene);
    glCreateVertexArrays(1, &l->vao);
    if (!lpv_programs(l) || !lpv_volumes(l)) { /* what failed logged its line */
        lpv_destroy(l);
        return NULL;
    }
    return l;
}

/* Places the cascades for this camera and uploads the block. */
static void place_grids(LpvGi *l, const Camera *cam)
{
    GpuLpvParams *u = &l->gpu;
    memset(u, 0, sizeof *u);
    u->size = l->n;
    u->offset = l->params.lpv.offset;
    u->blend = 0.1f;
    if (l->cascades == 1) {
        /* The bounds plus one cell of margin on each side. */
        u->cascade[0][3] = gi_grid_around(l->bmin, l->bmax, l->n, u->cascade[0]);
    } else {
        /* The coarsest holds the whole scene around the camera. */
        float coarsest = gi_clipmap_extent(l->bmin, l->bmax, cam->position, l->n);
        for (int k = 0; k < l->cascades; k++)
            gi_clipmap_level(coarsest, l->n, l->cascades, k, cam->position, u->cascade[k]);
    }
    glNamedBufferSubData(l->ubo, 0, sizeof *u, u);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_LPV, l->ubo);
}

static void clear_volume(GLuint tex)
{
    glClearTexImage(tex, 0, GL_RGBA, GL_FLOAT, NULL);
}

/* --lpv-inject compute: fixed-point atomics per VPL, then a resolve into
 * the injected volumes, per cascade and set. */
static void inject_light_fixed(LpvGi *l, const GiFrame *f)
{
    float power = l->test_vpls ? l->test_power : l->scene_power;
    /* Every coefficient of a cell is at most 1.0233·P/π: 2^30 units for that. */
    float scale = power > 0.f ? 1073741824.f / (1.0233f * power / GLM_PIf) : 1.f;
    uint32_t capacity = l->test_vpls ? (uint32_t)l->test_count : f->lights->vpls.capacity;
    if (l->test_vpls)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_COUNTERS, l->indirect); /* [0] = count */
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_LPV_FIXED, l->fixed);
    glProgramUniform1f(l->inject_fixed, LOC_LPV_FIXED_SCALE, scale);
    glProgramUniform1f(l->inject_resolve, LOC_LPV_FIXED_SCALE, scale);
    GLuint wg = (GLuint)(l->n + 7) / 8;
    for (int k = 0; k < l->cascades; k++) {
        LpvCascade *c = &l->c[k];
        for (int set = 0; set < (k > 0 ? SETS : 1); set++)
            for (int g = 0; g < l->groups; g++) {
                glClearNamedBufferData(l->fixed, GL_R32I, GL_RED_INTEGER, GL_INT, NULL);
                glProgramUniform1i(l->inject_fixed, LOC_LPV_CASCADE, k);
                glProgramUniform1i(l->inject_fixed, LOC_LPV_EXCLUDE, set == SET_OUTER ? k - 1 : -1);
                glProgramUniform1i(l->inject_fixed, LOC_LPV_GROUP, l->groups > 1 ? g : -1);
                glUseProgram(l->inject_fixed);
                glDispatchCompute((capacity + 64 * LPV_INJECT_RUN - 1) / (64 * LPV_INJECT_RUN), 1, 1);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
                for (int i = 0; i < 3; i++)
                    glBindImageTexture(IMG_LPV_DST + i, c->inject[set][i], 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
                glProgramUniform1i(l->inject_resolve, LOC_LPV_GROUP, g);
                glUseProgram(l->inject_resolve);
                glDispatchCompute(wg, wg, (GLuint)l->n);
                glMemoryBarrier(GL_ALL_BARRIER_BITS);
            }
    }
}

static void inject_light(LpvGi *l, const GiFrame *f)
{
    if (l->test_vpls) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VPL, l->test_vpls);
        GLuint count = (GLuint)l->test_count;
        glNamedBufferSubData(l->indirect, 0, sizeof count, &count);
    } else {
        light_stage_bind_vpls(f->lights);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
        glCopyNamedBufferSubData(f->lights->vpls.counters, l->indirect, 0, 0, sizeof(GLuint));
    }
    glMemoryBarrier(GL_COMMAND_BARRIER_BIT);
    if (l->params.lpv.inject == LPV_INJECT_COMPUTE) {
        inject_light_fixed(l, f);
        return;
    }
    glUseProgram(l->inject);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, l->indirect);
    glViewport(0, 0, l->n, l->n);
    for (int k = 0; k < l->cascades; k++) {
        LpvCascade *c = &l->c[k];
        for (int set = 0; set < (k > 0 ? SETS : 1); set++) {
            for (int i = 0; i < 3; i++)
                clear_volume(c->inject[set][i]);
            glBindFramebuffer(GL_FRAMEBUFFER, c->fbo_inject[set]);
            glProgramUniform1i(l->inject, LOC_LPV_CASCADE, k);
            glProgramUniform1i(l->inject, LOC_LPV_EXCLUDE, set == SET_OUTER ? k - 1 : -1);
            for (int g = 0; g < l->groups; g++) { /* each group into its layers */
                glProgramUniform1i(l->inject, LOC_LPV_GROUP, l->groups > 1 ? g : -1);
                glDrawArraysIndirect(GL_POINTS, NULL);
            }
        }
    }
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
}

/* geometry_fixed.comp's work groups across a row of `width` texels: 8
 * invocations of LPV_GEOMETRY_RUN texels each. */
static GLuint run_groups(int width)
{
    return (GLuint)((width + LPV_GEOMETRY_RUN - 1) / LPV_GEOMETRY_RUN + 7) / 8;
}

/* --lpv-inject compute: the surfels' tensors in fixed point (2^20 units
 * per 1: a cell's entries stay far below 2^11, where blocking long
 * saturated at 1), then a resolve into the two textures. */
static void inject_geometry_fixed(LpvGi *l, const GiFrame *f)
{
    const LightStage *ls = f->lights;
    const float scale = 1048576.f;
    GLuint g = (GLuint)(l->n + 1 + 7) / 8;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_LPV_FIXED, l->gv_fixed);
    for (int k = 0; k < l->cascades; k++) {
        LpvCascade *c = &l->c[k];
        float cell = l->gpu.cascade[k][3];
        glClearNamedBufferData(l->gv_fixed, GL_R32I, GL_RED_INTEGER, GL_INT, NULL);
        GLuint progs[3] = {l->geom_fixed_rsm[0], l->geom_fixed_rsm[1],
                           l->params.lpv.gbuffer_occlusion ? l->geom_fixed_gbuf : 0};
        for (int pi = 0; pi < 3 && progs[pi]; pi++) {
            glProgramUniform1i(progs[pi], LOC_LPV_CASCADE, k);
            glProgramUniform1f(progs[pi], LOC_LPV_SURFEL_AREA, 4.f * cell * cell);
            glProgramUniform1f(progs[pi], LOC_LPV_FIXED_SCALE, scale);
        }
        for (int i = 0; i < ls->light_count; i++) { /* the RSMs, each with its kind's program */
            const RsmMap *m = &ls->rsm[i];
            glUseProgram(progs[m->cube]);
            light_stage_bind_rsm_layers(ls, i);
            glDispatchCompute(run_groups(m->size), (GLuint)(m->size + 7) / 8, m->cube ? 6 : 1);
        }
        if (progs[2]) { /* and the G-buffer */
            glUseProgram(progs[2]);
            glBindTextureUnit(TEX_GB_SURFACE, f->gbuffer->surface);
            glDispatchCompute(run_groups(f->gbuffer->width), (GLuint)(f->gbuffer->height + 7) / 8, 1);
        }
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glProgramUniform1f(l->geom_resolve, LOC_LPV_FIXED_SCALE, scale);
        glUseProgram(l->geom_resolve);
        glBindImageTexture(IMG_LPV_DST + 0, c->gv[0], 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glBindImageTexture(IMG_LPV_DST + 1, c->gv[1], 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glDispatchCompute(g, g, (GLuint)(l->n + 1));
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
    }
}

static void inject_geometry(LpvGi *l, const GiFrame *f)
{
    if (l->params.lpv.inject == LPV_INJECT_COMPUTE && l->params.lpv.occlusion) {
        inject_geometry_fixed(l, f);
        return;
    }
    const LightStage *ls = f->lights;
    glViewport(0, 0, l->n + 1, l->n + 1);
    for (int k = 0; k < l->cascades; k++) {
        LpvCascade *c = &l->c[k];
        float cell = l->gpu.cascade[k][3];
        clear_volume(c->gv[0]);
        clear_volume(c->gv[1]);
        if (!l->params.lpv.occlusion)
            continue;
        glBindFramebuffer(GL_FRAMEBUFFER, c->fbo_gv);
        /* A surfel larger than 4 cell faces is a depth discontinuity. */
        for (int cube = 0; cube < 2; cube++) {
            glProgramUniform1i(l->geom_rsm[cube], LOC_LPV_CASCADE, k);
            glProgramUniform1f(l->geom_rsm[cube], LOC_LPV_SURFEL_AREA, 4.f * cell * cell);
        }
        for (int i = 0; i < ls->light_count; i++) {
            const RsmMap *m = &ls->rsm[i];
            glUseProgram(l->geom_rsm[m->cube]);
            light_stage_bind_rsm_layers(ls, i);
            glDrawArrays(GL_POINTS, 0, m->size * m->size * (m->cube ? 6 : 1));
        }
        if (l->params.lpv.gbuffer_occlusion) {
            glProgramUniform1i(l->geom_gbuf, LOC_LPV_CASCADE, k);
            glProgramUniform1f(l->geom_gbuf, LOC_LPV_SURFEL_AREA, 4.f * cell * cell);
            glUseProgram(l->geom_gbuf);
            glBindTextureUnit(TEX_GB_SURFACE, f->gbuffer->surface);
            glDrawArrays(GL_POINTS, 0, f->gbuffer->width * f->gbuffer->height);
        }
    }
}

/* Propagates light group g of volume set `set` of cascade c: its injected
 * light → ping-pong[0] and the sum, then `iterations` steps, each adding
 * to the sum. */
static void propagate_set(LpvGi *l, const LpvCascade *c, int set, int g)
{
    int n = l->n;
    GLuint wg = (GLuint)(n + 7) / 8; /* propagate.comp: 8×8×1 per work group */
    for (int i = 0; i < 3; i++) {
        glCopyImageSubData(c->inject[set][i], GL_TEXTURE_3D, 0, 0, 0, g * n, l->pp[0], GL_TEXTURE_3D, 0, i * n, 0, 0, n,
                           n, n);
        glCopyImageSubData(c->inject[set][i], GL_TEXTURE_3D, 0, 0, 0, g * n, c->sum[set][i], GL_TEXTURE_3D, 0, 0, 0,
                           g * n, n, n, n);
        glBindImageTexture(IMG_LPV_SUM + i, c->sum[set][i], 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA32F);
    }
    glProgramUniform1i(l->propagate, LOC_LPV_GROUP, g);
    int cur = 0;
    for (int it = 0; it < l->iterations; it++) {
        glBindImageTexture(IMG_LPV_STEP_SRC, l->pp[cur], 0, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(IMG_LPV_STEP_DST, l->pp[1 - cur], 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glDispatchCompute(wg, wg, (GLuint)n);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
        cur = 1 - cur;
    }
    l->last_step = cur;
}

/* Each cascade: with occlusion, its faces' factors from its geometry
 * volume (once: every step and set reads them), then its sets. */
static void propagate(LpvGi *l)
{
    GLuint groups = (GLuint)(l->n + 7) / 8;
    if (l->faces)
        glBindImageTexture(IMG_LPV_FACES, l->faces, 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA32F);
    for (int k = 0; k < l->cascades; k++) {
        if (l->params.lpv.occlusion) {
            glBindTextureUnit(TEX_LPV_GV0, l->c[k].gv[0]);
            glBindTextureUnit(TEX_LPV_GV1, l->c[k].gv[1]);
            glUseProgram(l->propagate_faces);
            glDispatchCompute(groups, groups, (GLuint)l->n);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
        glUseProgram(l->propagate);
        for (int set = 0; set < (k > 0 ? SETS : 1); set++)
            for (int g = 0; g < l->groups; g++)
                propagate_set(l, &l->c[k], set, g);
    }
}

static void lookup(LpvGi *l, const GiFrame *f)
{
    /* Unused slots get cascade 0's volumes (never read). */
    for (int k = 0; k < LPV_MAX_CASCADES; k++)
        for (int i = 0; i < 3; i++) {
            glBindTextureUnit((GLuint)(TEX_LPV_SUM + 3 * k + i), l->c[k < l->cascades ? k : 0].sum[SET_ALL][i]);
            if (k > 0)
                glBindTextureUnit((GLuint)(TEX_LPV_OUTER + 3 * (k - 1) + i),
                                  k < l->cascades ? l->c[k].sum[SET_OUTER][i] : l->c[0].sum[SET_ALL][i]);
        }
    glBindTextureUnit(TEX_GB_SURFACE, f->gbuffer->surface);
    glBindImageTexture(IMG_OUT, f->irradiance, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glUseProgram(l->lookup);
    gi_dispatch_pixels(l->width, l->height);
}

static bool lpv_run(void *state, const GiFrame *f)
{
    LpvGi *l = state;
    GpuTimer *t = f->timer;
    place_grids(l, f->camera);
    /* Injection and propagation depend on the light products and where the
     * grids stand (the cascades follow the camera), and, with G-buffer
     * occlusion, on the camera's view (the G-buffer's objects move only
     * with the light products): kept while those stand still. */
    uint64_t key = util_hash_bytes(light_stage_products_key(f->lights), &l->gpu, sizeof l->gpu);
    key = util_hash_bytes(key, &l->test_vpls, sizeof l->test_vpls);
    key = util_hash_bytes(key, &l->test_count, sizeof l->test_count);
    key = util_hash_bytes(key, &l->iterations, sizeof l->iterations);
    if (l->params.lpv.gbuffer_occlusion) {
        key = util_hash_bytes(key, f->camera, sizeof *f->camera);
        key = util_hash_bytes(key, &l->width, sizeof l->width);
        key = util_hash_bytes(key, &l->height, sizeof l->height);
    }
    if (key != 0 && key == l->built_for) {
        gpu_timer_begin(t, "lpv_lookup");
        lookup(l, f);
        gpu_timer_end(t);
        return true;
    }
    l->built_for = key;
    l->builds++;
    GLint viewport[4];
    glGetIntegerv(GL_VIEWPORT, viewport);
    glBindVertexArray(l->vao);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE);

    gpu_timer_begin(t, "lpv_inject");
    inject_light(l, f);
    gpu_timer_end(t);
    gpu_timer_begin(t, "lpv_geometry");
    inject_geometry(l, f);
    gpu_timer_end(t);

    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    glBindVertexArray(0);

    gpu_timer_begin(t, "lpv_propagate");
    propagate(l);
    gpu_timer_end(t);
    gpu_timer_begin(t, "lpv_lookup");
    lookup(l, f);
    gpu_timer_end(t);
    return true;
}

static void lpv_stats(void *state, const GiFrame *f, GiStats *st)
{
    LpvGi *l = state;
    st->vpl_count = l->test_vpls ? (uint32_t)l->test_count : light_stage_vpl_count(f->lights);
    st->gathered_pixels = gi_count_surfaces(f, l->pc, 1);
    st->volume_builds = l->builds;
    for (int k = 0; k < l->cascades; k++)
        st->gpu_bytes += gl_textures_bytes(&l->c[k].inject[0][0], SETS * 3) +
                         gl_textures_bytes(&l->c[k].sum[0][0], SETS * 3) + gl_textures_bytes(l->c[k].gv, 2);
    const GLuint bufs[5] = {l->fixed, l->gv_fixed, l->ubo, l->indirect, l->test_vpls};
    st->gpu_bytes += gl_textures_bytes(l->pp, 2) + gl_texture_bytes(l->faces) + gl_buffers_bytes(bufs, 5);
}

void lpv_set_vpls(void *state, const GpuVpl *vpls, int count)
{
    LpvGi *l = state;
    glDeleteBuffers(1, &l->test_vpls);
    l->test_vpls = 0;
    l->test_count = 0;
    l->built_for = 0; /* a new buffer may reuse the old name */
    if (count <= 0)
        return;
    glCreateBuffers(1, &l->test_vpls);
    glNamedBufferStorage(l->test_vpls, (GLsizeiptr)(sizeof(GpuVpl) * (size_t)count), vpls, 0);
    glObjectLabel(GL_BUFFER, l->test_vpls, -1, "lpv.test_vpls");
    l->test_count = count;
    l->test_power = 0.f;
    for (int i = 0; i < count; i++)
        l->test_power += glm_vec3_max((float *)vpls[i].flux);
}

int lpv_grid_size(const void *state) { return ((const LpvGi *)state)->n; }

int lpv_groups(const void *state) { return ((const LpvGi *)state)->groups; }

void lpv_grid(const void *state, int cascade, float origin[3], float *cell)
{
    const LpvGi *l = state;
    for (int a = 0; a < 3; a++)
        origin[a] = l->gpu.cascade[cascade][a];
    *cell = l->gpu.cascade[cascade][3];
}

bool lpv_read_volume(void *state, int cascade, LpvVolume which, float *out)
{
    LpvGi *l = state;
    if (cascade < 0 || cascade >= l->cascades || (which == LPV_VOLUME_INJECTED_OUTER && cascade == 0))
        return false;
    size_t n = (size_t)l->n, n3 = n * n * n, gn3 = n3 * (size_t)l->groups;
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    if (which == LPV_VOLUME_STEP) { /* R, G, B side by side in x: one row at a time */
        float *row = malloc(sizeof(float) * 4 * 3 * n3);
        if (!row)
            return false;
        glGetTextureImage(l->pp[l->last_step], 0, GL_RGBA, GL_FLOAT, (GLsizei)(sizeof(float) * 4 * 3 * n3), row);
        memset(out, 0, sizeof(float) * 4 * 3 * gn3);
        for (size_t zy = 0; zy < n * n; zy++)
            for (size_t c = 0; c < 3; c++)
                memcpy(out + (c * gn3 + zy * n) * 4, row + (zy * 3 * n + c * n) * 4, sizeof(float) * 4 * n);
        free(row);
        return true;
    }
    for (int i = 0; i < 3; i++) {
        const LpvCascade *c = &l->c[cascade];
        GLuint tex = which == LPV_VOLUME_INJECTED         ? c->inject[SET_ALL][i]
                     : which == LPV_VOLUME_INJECTED_OUTER ? c->inject[SET_OUTER][i]
                                                          : c->sum[SET_ALL][i];
        glGetTextureImage(tex, 0, GL_RGBA, GL_FLOAT, (GLsizei)(gn3 * 4 * sizeof(float)), out + (size_t)i * gn3 * 4);
    }
    return true;
}

void lpv_set_iterations(void *state, int iterations)
{
    LpvGi *l = state;
    l->iterations = iterations;
    l->built_for = 0;
}

bool lpv_read_geometry(void *state, int cascade, float *out)
{
    LpvGi *l = state;
    if (cascade < 0 || cascade >= l->cascades)
        return false;
    size_t g3 = (size_t)(l->n + 1) * (size_t)(l->n + 1) * (size_t)(l->n + 1);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    for (int t = 0; t < 2; t++)
        glGetTextureImage(l->c[cascade].gv[t], 0, GL_RGBA, GL_FLOAT, (GLsizei)(g3 * 4 * sizeof(float)),
                          out + (size_t)t * g3 * 4);
    return true;
}

/* Cell updates of the propagation (six neighbours a step), the injection
 * of every RSM texel per cascade, and the lookup per pixel. */
static double lpv_cost(const GiCostQuery *q)
{
    const GiParams *p = q->params;
    double cells = pow(p->lpv.size, 3) * p->lpv.cascades * p->lpv.groups;
    int steps = p->lpv.iterations > 0                                  ? p->lpv.iterations
                : p->lpv.propagation == LPV_PROPAGATION_DIRECTIONAL ? 3 * p->lpv.size
                                                                     : p->lpv.size;
    return (cells * steps * 6 + gi_cost_rsm_texels(q, false) * p->lpv.cascades + q->pixels) * GI_COST_VOLUME_EVAL;
}

const GiTechnique gi_lpv = {
    .name = "lpv",
    .paper = "Kaplanyan & Dachsbacher 2010, Cascaded Light Propagation Volumes",
    .summary = "light propagation volumes: VPLs injected into SH grids, propagated cell to cell, looked up per pixel",
    .needs = lpv_needs,
    .create = lpv_create,
    .resize = lpv_resize,
    .run = lpv_run,
    .stats = lpv_stats,
    .destroy = lpv_destroy,
    .cost = lpv_cost,
    .print_stats = gi_print_vpl_stats,
};
