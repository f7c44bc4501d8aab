/* light_stage.c — light frames, the GPU light array, shadow maps, RSMs and
 * the VPL buffer (see light_stage.h). */
#include "gpu/light_stage.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gl/gl_resources.h"
#include "gl/gpu_budget.h"
#include "base/log.h"
#include "gl/shader.h"
#include "shared/gpu_types.h"
#include "gpu/targets.h"
#include "base/util.h"

enum { SLOT_SHADOW = 0, SLOT_RSM = 1, SLOTS_PER_LIGHT = 2 };

/* Map draws in this process: each draw's ShadowMap/RsmMap.version, unique
 * even across light stages, so what a technique derived from an earlier map
 * never passes for current. */
static uint64_t s_map_draws;

static bool light_is_cube(const Scene *s, const Light *l)
{
    return shadow_frame_is_cube(l, s->bounds_min, s->bounds_max);
}

float light_stage_lit_layers(const Scene *s, const Light *l)
{
    /* Texels that can hold a lit surface: a 2D map, half a cube for a
     * one-sided quad (one face and four half faces), a whole cube. */
    return l->type == LIGHT_QUAD ? 3.f : light_is_cube(s, l) ? 6.f : 1.f;
}

int light_stage_rsm_size_for_vpls(const Scene *s, const Light *l, int vpls)
{
    int size = (int)lrintf(sqrtf((float)vpls / light_stage_lit_layers(s, l)));
    return size < 4 ? 4 : size;
}

/* Texels per side of the block one VPL stands for (vpl_extract.comp). */
#define VPL_MAX_SUPERSAMPLE 4
static int vpl_block(const LightStageDesc *d)
{
    int k = d->vpl_count > 0 ? d->vpl_supersample : 1;
    return k < 1 ? 1 : k > VPL_MAX_SUPERSAMPLE ? VPL_MAX_SUPERSAMPLE : k;
}

static int rsm_size_for(const LightStageDesc *d, const Scene *s, const Light *l)
{
    return d->vpl_count > 0 ? light_stage_rsm_size_for_vpls(s, l, d->vpl_count) * vpl_block(d) : d->rsm_size;
}

/* ---- Products ------------------------------------------------------------ */

static bool shadow_map_create(ShadowMap *m, bool cube, int size)
{
    m->size = size;
    m->cube = cube;
    m->texture = gl_texture_make(cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, size, size,
                                 cube ? "shadow.cube" : "shadow.2d");
    return m->texture && fbo_make(&m->fbo, NULL, 0, m->texture, cube, "shadow map"); /* a texture logs its failure */
}

static void shadow_map_destroy(ShadowMap *m)
{
    glDeleteTextures(1, &m->texture);
    glDeleteFramebuffers(1, &m->fbo);
    *m = (ShadowMap){0};
}

static bool rsm_map_create(RsmMap *m, bool cube, int size)
{
    GLenum target = cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D;
    m->size = size;
    m->cube = cube;
    m->texel = gl_texture_make(target, GL_RGBA32UI, size, size, "rsm.texel");
    m->depth = gl_texture_make(target, GL_DEPTH_COMPONENT32F, size, size, "rsm.depth");
    return m->texel && m->depth && fbo_make(&m->fbo, &m->texel, 1, m->depth, cube, "rsm"); /* as above */
}

static void rsm_map_destroy(RsmMap *m)
{
    GLuint t[2] = {m->texel, m->depth};
    glDeleteTextures(2, t);
    glDeleteFramebuffers(1, &m->fbo);
    *m = (RsmMap){0};
}

/* false after logging (gl_buffer_make logs). */
static bool vpl_buffer_create(VplBuffer *b, uint32_t capacity)
{
    b->capacity = capacity;
    b->vpls = gl_buffer_make(sizeof(GpuVpl) * (uint64_t)(capacity ? capacity : 1), NULL, 0, "vpls");
    b->counters = gl_buffer_make(2 * sizeof(uint32_t), NULL, GL_DYNAMIC_STORAGE_BIT, "vpl.counters"); /* count, seed */
    return b->vpls && b->counters;
}

static void vpl_buffer_destroy(VplBuffer *b)
{
    glDeleteBuffers(1, &b->vpls);
    glDeleteBuffers(1, &b->counters);
    *b = (VplBuffer){0};
}

/* ---- Lifetime ------------------------------------------------------------ */

static void free_products(LightStage *ls)
{
    if (ls->shadow)
        for (int i = 0; i < ls->light_count; i++)
            shadow_map_destroy(&ls->shadow[i]);
    if (ls->rsm)
        for (int i = 0; i < ls->light_count; i++)
            rsm_map_destroy(&ls->rsm[i]);
    free(ls->shadow);
    free(ls->rsm);
    ls->shadow = NULL;
    ls->rsm = NULL;
    vpl_buffer_destroy(&ls->vpls); /* what a failed create made too */
    ls->vpl_key = 0;
}

/* GPU bytes of the products of `d` (shadow maps: depth; RSMs: the packed
 * texel, depth and a technique's importance pyramid; the VPLs). */
static bool products_fit(const LightStage *ls, const LightStageDesc *d)
{
    uint64_t shadow = 0, rsm = 0;
    for (int i = 0; i < ls->light_count; i++) {
        const Light *l = &ls->scene->lights[i];
        uint64_t faces = light_is_cube(ls->scene, l) ? 6 : 1, rs = (uint64_t)rsm_size_for(d, ls->scene, l);
        if (d->needs & LIGHT_NEEDS_SHADOW_MAPS)
            shadow += faces * (uint64_t)d->shadow_map_size * (uint64_t)d->shadow_map_size * 4;
        if (d->needs & (LIGHT_NEEDS_RSM | LIGHT_NEEDS_VPLS))
            rsm += faces * rs * rs * (16 + 4 + 6 + ((d->needs & LIGHT_NEEDS_VPLS) ? 48 : 0));
    }
    char what[128];
    snprintf(what, sizeof what, "shadow.map_size %d (%d light%s)", d->shadow_map_size, ls->light_count,
             ls->light_count == 1 ? "" : "s");
    if (!gpu_budget_check(shadow, what))
        return false;
    if (d->vpl_count > 0)
        snprintf(what, sizeof what, "vpl.count %d (the RSMs and VPLs of %d light%s)", d->vpl_count, ls->light_count,
                 ls->light_count == 1 ? "" : "s");
    else
        snprintf(what, sizeof what, "rsm.size %d (%d light%s)", d->rsm_size, ls->light_count,
                 ls->light_count == 1 ? "" : "s");
    return gpu_budget_check(shadow + rsm, what);
}

static bool make_products(LightStage *ls)
{
    const LightStageDesc *d = &ls->desc;
    const Scene *s = ls->scene;
    bool ok = products_fit(ls, d);
    if (!ok)
        return false;
    if (d->needs & LIGHT_NEEDS_SHADOW_MAPS) {
        ls->shadow = calloc((size_t)ls->light_count + 1, sizeof(ShadowMap));
        if (!ls->shadow) {
            log_error("lights", "out of memory for %d shadow maps", ls->light_count);
            return false;
        }
        for (int i = 0; i < ls->light_count && ok; i++)
            ok = shadow_map_create(&ls->shadow[i], light_is_cube(s, &s->lights[i]), d->shadow_map_size);
    }
    if (ok && (d->needs & (LIGHT_NEEDS_RSM | LIGHT_NEEDS_VPLS))) {
        ls->rsm = calloc((size_t)ls->light_count + 1, sizeof(RsmMap));
        if (!ls->rsm) {
            log_error("lights", "out of memory for %d RSMs", ls->light_count);
            return false;
        }
        uint32_t total = 0;
        for (int i = 0; i < ls->light_count && ok; i++) {
            bool cube = light_is_cube(s, &s->lights[i]);
            int size = rsm_size_for(d, s, &s->lights[i]);
            ok = rsm_map_create(&ls->rsm[i], cube, size);
            uint32_t blocks = (uint32_t)((size + vpl_block(d) - 1) / vpl_block(d));
            total += blocks * blocks * (cube ? 6u : 1u);
        }
        if (ok && (d->needs & LIGHT_NEEDS_VPLS))
            ok = vpl_buffer_create(&ls->vpls, total);
    }
    return ok;
}

bool light_stage_create(LightStage *ls, const Scene *s, const LightStageDesc *desc, ProgramCache *pc)
{
    memset(ls, 0, sizeof *ls);
    ls->scene = s;
    ls->desc = *desc;
    ls->light_count = s->light_count;
    static const char *const shadow_defs[2][2] = {
        {"", "#define ALPHA_MASK\n"},
        {"#define DEPTH_FROM_RASTER\n", "#define DEPTH_FROM_RASTER\n#define ALPHA_MASK\n"}};
    for (int ortho = 0; ortho < 2; ortho++)
        for (int masked = 0; masked < 2; masked++)
            ls->shadow_programs[ortho][masked] = program_cache_get(
                pc, &(ShaderProgramDesc){.label = "shadow", .vert = "frame/scene.vert",
                                         .frag = "light/shadow_depth.frag", .defines = shadow_defs[ortho][masked]});
    ls->shadow_program = ls->shadow_programs[0][0] && ls->shadow_programs[0][1] && ls->shadow_programs[1][0] &&
                         ls->shadow_programs[1][1];
    ls->rsm_program = program_cache_get(pc, &(ShaderProgramDesc){.label = "rsm", .vert = "frame/scene.vert", .frag = "light/rsm.frag", .defines = "#define FLAT_UNIFORMS\n"});
    ls->rsm_program_opaque = program_cache_get(pc, &(ShaderProgramDesc){.label = "rsm_opaque", .vert = "frame/scene.vert",
                                                                        .frag = "light/rsm.frag", .defines = "#define FLAT_UNIFORMS\n#define OPAQUE_DRAW\n"});
    for (int cube = 0; cube < 2; cube++)
        ls->vpl_program[cube] = program_cache_get(pc, &(ShaderProgramDesc){.label = "vpl_extract", .comp = "light/vpl_extract.comp",
                                                                            .defines = light_stage_rsm_kind(cube)});
    ls->rsm_program_untextured = program_cache_get(
        pc, &(ShaderProgramDesc){.label = "rsm_untextured", .vert = "frame/scene.vert", .frag = "light/rsm.frag",
                                 .defines = "#define FLAT_UNIFORMS\n#define OPAQUE_DRAW\n#define UNTEXTURED\n"});
    if (!ls->shadow_program || !ls->rsm_program || !ls->rsm_program_opaque || !ls->rsm_program_untextured ||
        !ls->vpl_program[0] || !ls->vpl_program[1])
        return false;
    GLint align = 256;
    glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &align);
    ls->slot_stride = (int)((sizeof(GpuLight) + (size_t)align - 1) / (size_t)align * (size_t)align);
    int slots = SLOTS_PER_LIGHT * (ls->light_count > 0 ? ls->light_count : 1);
    ls->light_array = gl_buffer_make((uint64_t)ls->slot_stride * (uint64_t)slots, NULL, GL_DYNAMIC_STORAGE_BIT, "lights");
    ls->dummy_2d = gl_texture_make(GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, 1, 1, "shadow.dummy2d");
    ls->dummy_cube = gl_texture_make(GL_TEXTURE_CUBE_MAP, GL_DEPTH_COMPONENT32F, 1, 1, "shadow.dummycube");
    if (!ls->light_array || !ls->dummy_2d || !ls->dummy_cube) /* each logs its failure */
        return false;
    const uint32_t zero = 0; /* a scene without lights reads slot 0 as a zero light */
    glClearNamedBufferData(ls->light_array, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    /* The grid PCF's taps (common/shadow.glsl): a bilinear blend of four
     * depth tests, lit where reference <= stored. Off the map, lit: a 2D
     * map's outermost texels are never drawn (shadow_face), so they hold
     * the clear depth 1, which the edge clamp reads for whatever lies
     * beyond (on llvmpipe 4% fewer instructions per frame than a border
     * colour, whose texels it selects lane by lane). */
    glCreateSamplers(1, &ls->shadow_compare);
    glSamplerParameteri(ls->shadow_compare, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glSamplerParameteri(ls->shadow_compare, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glSamplerParameteri(ls->shadow_compare, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(ls->shadow_compare, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    const GLenum wraps[3] = {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R};
    for (int k = 0; k < 3; k++)
        glSamplerParameteri(ls->shadow_compare, wraps[k], GL_CLAMP_TO_EDGE);
    glObjectLabel(GL_SAMPLER, ls->shadow_compare, -1, "shadow.compare");
    ls->made = make_products(ls);
    return ls->made;
}

void light_stage_destroy(LightStage *ls)
{
    free_products(ls);
    glDeleteBuffers(1, &ls->light_array);
    GLuint t[2] = {ls->dummy_2d, ls->dummy_cube};
    glDeleteTextures(2, t);
    glDeleteSamplers(1, &ls->shadow_compare);
    memset(ls, 0, sizeof *ls);
}

uint64_t light_stage_gpu_bytes(const LightStage *ls)
{
    const GLuint bufs[3] = {ls->light_array, ls->vpls.vpls, ls->vpls.counters}, dummies[2] = {ls->dummy_2d, ls->dummy_cube};
    uint64_t bytes = gl_buffers_bytes(bufs, 3) + gl_textures_bytes(dummies, 2);
    for (int i = 0; i < ls->light_count; i++) {
        if (ls->shadow)
            bytes += gl_texture_bytes(ls->shadow[i].texture);
        if (ls->rsm)
            bytes += gl_texture_bytes(ls->rsm[i].texel) + gl_texture_bytes(ls->rsm[i].depth);
    }
    return bytes;
}

bool light_stage_configure(LightStage *ls, const LightStageDesc *desc)
{
    if (ls->made && !memcmp(desc, &ls->desc, sizeof *desc))
        return true;
    free_products(ls);
    ls->desc = *desc;
    ls->made = make_products(ls);
    return ls->made;
}

/* ---- The frame ----------------------------------------------------------- */

static void upload_slot(LightStage *ls, int light, int slot, const GpuLight *g)
{
    GLintptr at = (GLintptr)ls->slot_stride * (SLOTS_PER_LIGHT * light + slot);
    glNamedBufferSubData(ls->light_array, at, sizeof *g, g);
}

static void bind_slot(const LightStage *ls, int light, int slot)
{
    GLintptr at = (GLintptr)ls->slot_stride * (SLOTS_PER_LIGHT * light + slot);
    glBindBufferRange(GL_UNIFORM_BUFFER, UBO_LIGHT, ls->light_array, at, sizeof(GpuLight));
}

/* Draws the scene (emitters skipped) into each face of a map with
 * `programs` (gpu_scene.h: opaque, alpha-masked and untextured materials). */
/* A one-sided quad light lights nothing through a cube face whose every
 * direction lies behind its emitting plane: the emitter normal's dot with
 * the face's directions, linear over the face plane, is at most 0 at all
 * four corners (axis ± right ± up of the 90° face). Such a face stays
 * cleared: empty in the RSM (no VPL), no blocker in the shadow map, whose
 * lookups ignore what lies behind a quad light's plane anyway. */
static bool face_behind_quad(const Light *l, const ShadowFrame *f, int face)
{
    if (l->type != LIGHT_QUAD || !f->cube)
        return false;
    const float *v = (const float *)f->view[face];
    const vec3 right = {v[0], v[4], v[8]}, up = {v[1], v[5], v[9]}, axis = {-v[2], -v[6], -v[10]};
    for (int k = 0; k < 4; k++) {
        vec3 c;
        for (int i = 0; i < 3; i++)
            c[i] = axis[i] + ((k & 1) ? right[i] : -right[i]) + ((k & 2) ? up[i] : -up[i]);
        if (glm_vec3_dot(c, (float *)l->direction) > 0.f)
            return false;
    }
    return true;
}

static void draw_faces(LightStage *ls, const Light *l, const DrawPrograms *programs, const ShadowFrame *f, int size,
                       GLuint fbo, const GpuScene *gs, void (*per_face)(const LightStage *, int face, void *),
                       void *user)
{
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glViewport(0, 0, size, size);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    for (int face = 0; face < f->face_count; face++) {
        per_face(ls, face, user); /* attaches and clears the face */
        if (face_behind_quad(l, f, face))
            continue;
        ls->faces_drawn++;
        const GLuint progs[3] = {programs->opaque, programs->masked, programs->untextured};
        for (int k = 0; k < 3; k++)
            if (progs[k])
                glProgramUniformMatrix4fv(progs[k], LOC_VIEW_PROJ, 1, GL_FALSE, (const float *)f->view_proj[face]);
        /* Clusters outside the face's frustum are skipped; the rest are
         * drawn nearest to the light first (directional: scene order). */
        int culled = 0;
        DrawView view = {.view_proj = (const float *)f->view_proj[face],
                         .eye = l->type == LIGHT_DIRECTIONAL ? NULL : l->position, .culled = &culled};
        gpu_scene_draw_view(gs, ls->scene, programs, DRAW_SKIP_EMITTERS, ls->desc.no_cull ? NULL : &view);
        ls->clusters_culled += culled;
    }
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

/* Clears the face to depth 1. A 2D map is then drawn inside its outermost
 * ring of texels only (draw_faces turns the scissor off after): the ring
 * keeps depth 1, what the depth-compare sampler's edge clamp reads off the
 * map, where nothing is recorded. A directional map's ring holds nothing
 * anyway (the scene's bounding sphere lies a hundredth of its radius, and at
 * least two texels, inside the map: shadow_frame_compute's margin); a spot
 * map's lies outside its cone (5% wider than the cone angle), unless the
 * 170° cap on its field of view cuts it. RSMs keep every texel. */
static void shadow_face(const LightStage *ls, int face, void *user)
{
    (void)ls;
    ShadowMap *m = user;
    if (m->cube)
        fbo_attach(m->fbo, GL_DEPTH_ATTACHMENT, m->texture, true, face);
    const float one = 1.f;
    glClearNamedFramebufferfv(m->fbo, GL_DEPTH, 0, &one);
    if (!m->cube) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(1, 1, m->size - 2, m->size - 2);
    }
}

static void rsm_face(const LightStage *ls, int face, void *user)
{
    RsmMap *m = user;
    if (m->cube) {
        fbo_attach(m->fbo, GL_COLOR_ATTACHMENT0, m->texel, true, face);
        fbo_attach(m->fbo, GL_DEPTH_ATTACHMENT, m->depth, true, face);
    }
    const GLuint zero[4] = {0, 0, 0, 0};
    const float one = 1.f;
    glClearNamedFramebufferuiv(m->fbo, GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(m->fbo, GL_DEPTH, 0, &one);
    vec3 axis; /* the face's (or spot's, or fitted map's) */
    shadow_frame_axis(&m->frame, face, axis);
    const GLuint programs[3] = {ls->rsm_program, ls->rsm_program_opaque, ls->rsm_program_untextured};
    for (int i = 0; i < 3; i++)
        glProgramUniform3fv(programs[i], LOC_RSM_FACE_AXIS, 1, axis);
}

void light_stage_rsm_texel_frame(const vec3 bounds_min, const vec3 bounds_max, GpuLight *g)
{
    for (int k = 0; k < 3; k++) {
        float ext = bounds_max[k] - bounds_min[k];
        float pad = 1e-4f * (ext > 0.f ? ext : 0.f) + 1e-6f;
        g->rsm_box_min[k] = bounds_min[k] - pad;
        g->rsm_box_step[k] = (ext + 2.f * pad) / 2097151.f;
    }
    float most = glm_vec3_max(g->color) * g->shadow_info[1] * g->shadow_info[1];
    g->rsm_box_min[3] = most > 0.f && isfinite(most) ? most / 16384.f : 1.f;
}

/* What the VPLs depend on: the lights, the RSM sizes and the seed, and
 * the geometry (gs->version: a moved object changes what the RSMs hold). */
static uint64_t vpl_key(const LightStage *ls, const GpuScene *gs)
{
    uint64_t h = util_hash_bytes(UTIL_HASH_SEED, ls->scene->lights, sizeof(Light) * (size_t)ls->light_count);
    h = util_hash_bytes(h, &ls->desc, sizeof ls->desc);
    h = util_hash_bytes(h, &gs->version, sizeof gs->version);
    return h ? h : 1;
}

/* What a map of light i at `size` depends on (never 0): the light, the
 * size and the geometry (gs->version: objects move, animation.h). */
static uint64_t map_key(const Light *l, int size, uint64_t kind, const GpuScene *gs)
{
    uint64_t h = util_hash_bytes(UTIL_HASH_SEED ^ kind, l, sizeof *l);
    h = util_hash_bytes(h, &size, sizeof size);
    h = util_hash_bytes(h, &gs->version, sizeof gs->version);
    return h ? h : 1;
}

void light_stage_invalidate(LightStage *ls)
{
    for (int i = 0; i < ls->light_count; i++) {
        if (ls->shadow)
            ls->shadow[i].key = 0;
        if (ls->rsm)
            ls->rsm[i].key = 0;
    }
    ls->vpl_key = 0;
}

bool light_stage_kind_changed(const LightStage *ls)
{
    const Scene *s = ls->scene;
    for (int i = 0; i < ls->light_count && (ls->shadow || ls->rsm); i++) {
        bool cube = light_is_cube(s, &s->lights[i]);
        if ((ls->shadow && ls->shadow[i].cube != cube) || (ls->rsm && ls->rsm[i].cube != cube))
            return true;
    }
    return false;
}

/* One line, once, when a light has crossed the bound between a cube map
 * and a fitted 2D map: its maps were made for the other kind. */
static void warn_kind_changes(LightStage *ls)
{
    const Scene *s = ls->scene;
    for (int i = 0; i < ls->light_count && (ls->shadow || ls->rsm) && !ls->kind_warned; i++) {
        bool cube = light_is_cube(s, &s->lights[i]);
        if ((ls->shadow && ls->shadow[i].cube != cube) || (ls->rsm && ls->rsm[i].cube != cube)) {
            ls->kind_warned = true;
            log_error("lights", "light %d moved across the bound between a cube map and a fitted 2D map "
                      "(shadow_frame_point_fitted): its maps keep their kind until the renderer is made again", i);
        }
    }
}

/* Every light's shadow-lookup block, whether or not maps are drawn; a map
 * is drawn unless caching finds it current. */
static void draw_shadow_maps(LightStage *ls, const GpuScene *gs, GpuTimer *t)
{
    const Scene *s = ls->scene;
    const LightStageDesc *d = &ls->desc;
    bool maps = (d->needs & LIGHT_NEEDS_SHADOW_MAPS) != 0, timing = false;
    for (int i = 0; i < ls->light_count; i++) {
        ShadowMap none = {0}, *m = maps ? &ls->shadow[i] : &none;
        GpuLight g;
        shadow_frame_compute(&s->lights[i], s->bounds_min, s->bounds_max, d->shadow_map_size, 2, &m->frame);
        shadow_frame_to_gpu(&s->lights[i], &m->frame, d->shadow_map_size, &g);
        upload_slot(ls, i, SLOT_SHADOW, &g);
        uint64_t key = map_key(&s->lights[i], d->shadow_map_size, 1, gs);
        if (!maps || (d->cache && m->key == key))
            continue;
        if (!timing)
            gpu_timer_begin(t, "shadow");
        timing = true;
        m->key = key;
        m->version = ++s_map_draws;
        ls->map_draws++;
        bind_slot(ls, i, SLOT_SHADOW);
        int ortho = s->lights[i].type == LIGHT_DIRECTIONAL;
        DrawPrograms programs = {ls->shadow_programs[ortho][0], ls->shadow_programs[ortho][1], 0};
        draw_faces(ls, &s->lights[i], &programs, &m->frame, m->size, m->fbo, gs, shadow_face, m);
    }
    if (timing)
        gpu_timer_end(t);
}

/* Every light's RSM block, and its map unless caching finds it current. */
static void draw_rsms(LightStage *ls, const GpuScene *gs, GpuTimer *t)
{
    const Scene *s = ls->scene;
    bool timing = false;
    for (int i = 0; i < ls->light_count; i++) {
        RsmMap *m = &ls->rsm[i];
        GpuLight g;
        shadow_frame_compute(&s->lights[i], s->bounds_min, s->bounds_max, m->size, 0, &m->frame);
        shadow_frame_to_gpu(&s->lights[i], &m->frame, m->size, &g);
        light_stage_rsm_texel_frame(s->bounds_min, s->bounds_max, &g);
        upload_slot(ls, i, SLOT_RSM, &g);
        uint64_t key = map_key(&s->lights[i], m->size, 2, gs);
        if (ls->desc.cache && m->key == key)
            continue;
        if (!timing)
            gpu_timer_begin(t, "rsm");
        timing = true;
        m->key = key;
        m->version = ++s_map_draws;
        ls->map_draws++;
        bind_slot(ls, i, SLOT_RSM);
        /* Texel area on the projection plane: ortho (2r/res)², perspective at
         * distance 1: k² with k = 2·tan(fov/2)/res. */
        const GLuint area_programs[3] = {ls->rsm_program, ls->rsm_program_opaque, ls->rsm_program_untextured};
        for (int k = 0; k < 3; k++)
            glProgramUniform1f(area_programs[k], LOC_RSM_TEXEL_AREA, m->frame.texel_k * m->frame.texel_k);
        DrawPrograms programs = {ls->rsm_program_opaque, ls->rsm_program, ls->rsm_program_untextured};
        draw_faces(ls, &s->lights[i], &programs, &m->frame, m->size, m->fbo, gs, rsm_face, m);
    }
    if (timing)
        gpu_timer_end(t);
}

/* The VPL buffer from every RSM, when the techniques need VPLs and what
 * they depend on changed. */
static void extract_vpls(LightStage *ls, const GpuScene *gs, GpuTimer *t)
{
    uint64_t key = vpl_key(ls, gs);
    if (!(ls->desc.needs & LIGHT_NEEDS_VPLS) || key == ls->vpl_key)
        return;
    gpu_timer_begin(t, "vpl_generate");
    const uint32_t count_seed[2] = {0u, ls->desc.vpl_seed}; /* the seed of their ξ: vpl_extract.comp and shade.comp's SLC loop */
    glNamedBufferSubData(ls->vpls.counters, 0, sizeof count_seed, count_seed);
    light_stage_bind_vpls(ls);
    for (int i = 0; i < ls->light_count; i++) {
        const RsmMap *m = &ls->rsm[i];
        GLuint prog = ls->vpl_program[m->cube];
        int k = vpl_block(&ls->desc);
        glProgramUniform1i(prog, LOC_VPL_STRIDE, k);
        glUseProgram(prog);
        light_stage_bind_rsm_layers(ls, i);
        GLuint n = (GLuint)((m->size + k - 1) / k);
        glDispatchCompute((n + 7) / 8, (n + 7) / 8, m->cube ? 6 : 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    gpu_timer_end(t);
    ls->vpl_key = key;
    ls->vpl_extractions++;
}

void light_stage_run(LightStage *ls, const GpuScene *gs, GpuTimer *t)
{
    warn_kind_changes(ls);
    draw_shadow_maps(ls, gs, t);
    if (!ls->rsm)
        return;
    draw_rsms(ls, gs, t);
    extract_vpls(ls, gs, t);
}

uint64_t light_stage_products_key(const LightStage *ls)
{
    uint64_t h = util_hash_bytes(UTIL_HASH_SEED, ls->scene->lights, sizeof(Light) * (size_t)ls->light_count);
    for (int i = 0; i < ls->light_count; i++) {
        if (ls->shadow)
            h = util_hash_bytes(h, &ls->shadow[i].version, sizeof(uint64_t));
        if (ls->rsm)
            h = util_hash_bytes(h, &ls->rsm[i].version, sizeof(uint64_t));
    }
    return h ? h : 1;
}

void light_stage_bind_shadow(const LightStage *ls, int i)
{
    bind_slot(ls, i, SLOT_SHADOW);
    const ShadowMap *m = ls->shadow && i < ls->light_count ? &ls->shadow[i] : NULL;
    GLuint map_2d = m && !m->cube ? m->texture : ls->dummy_2d, cube = m && m->cube ? m->texture : ls->dummy_cube;
    glBindTextureUnit(TEX_SHADOW_2D, map_2d);
    glBindTextureUnit(TEX_SHADOW_CUBE, cube);
    glBindTextureUnit(TEX_SHADOW_COMPARE_2D, map_2d);
    glBindTextureUnit(TEX_SHADOW_COMPARE_CUBE, cube);
    glBindSampler(TEX_SHADOW_COMPARE_2D, ls->shadow_compare);
    glBindSampler(TEX_SHADOW_COMPARE_CUBE, ls->shadow_compare);
}

void light_stage_bind_rsm(const LightStage *ls, int i)
{
    bind_slot(ls, i, SLOT_RSM);
    glBindTextureUnit(TEX_RSM, ls->rsm[i].texel);
}

void light_stage_bind_rsm_layers(const LightStage *ls, int i)
{
    bind_slot(ls, i, SLOT_RSM);
    glBindImageTexture(IMG_RSM, ls->rsm[i].texel, 0, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA32UI);
}

const char *light_stage_rsm_kind(bool cube) { return cube ? "#define RSM_CUBE\n" : "#define RSM_2D\n"; }

void light_stage_bind_vpls(const LightStage *ls)
{
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VPL, ls->vpls.vpls);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_COUNTERS, ls->vpls.counters);
}

uint32_t light_stage_vpl_count(const LightStage *ls)
{
    if (!ls->vpls.counters)
        return 0;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    uint32_t v = 0;
    glGetNamedBufferSubData(ls->vpls.counters, 0, sizeof v, &v);
    return v;
}
