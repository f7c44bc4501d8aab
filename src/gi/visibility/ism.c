/* ism.c — imperfect shadow maps for the visibility of the bounce (see
 * ism.h). Shaders: shaders/gi/visibility/ (ism.glsl: the lookup;
 * reps.comp, splat.comp, pull_push.comp: the passes). */
#include "gi/visibility/ism.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gl/gl_resources.h"
#include "gl/gpu_budget.h"
#include "base/log.h"
#include "shared/hash.h" /* hash_u32 */
#include "gl/shader.h"
#include "base/util.h"

/* Visible while distance <= stored · (1 + ISM_BIAS_REL) + ISM_BIAS_ABS·scale
 * (scale: the scene's diagonal): the nearest point in a texel's cone lies
 * up to its angular width (about 4/size radians) times the tangent of the
 * incidence nearer than the shaded point on the point's own surface, and
 * pull-push averages depths into the holes (ism.glsl's ism_visibility adds
 * the slope term). Measured in docs/techniques.md, "Visibility of the bounce". */
#define ISM_BIAS_REL 0.05f
#define ISM_BIAS_ABS 0.002f

/* Scene points the maps draw from: a few tens of maps' worth. */
#define ISM_POINT_SETS 128
/* Cells per side of the grid the points are sorted by: a map's near points
 * come from the 3×3×3 cells around its source. */
#define ISM_GRID 32

static int size_texels(int ism_size) { return 16 << (ism_size < 0 ? 0 : ism_size > 2 ? 2 : ism_size); }

/* ---- Points --------------------------------------------------------------- */

static float rnd(uint32_t *state)
{
    *state = hash_u32(*state + 0x9e3779b9u);
    return (float)(*state >> 8) / 16777216.f;
}

/* Alpha of the material's texture at uv (nearest texel, wrapping; row 0 is
 * v = 0), as the path tracer's alpha test reads it. */
static bool opaque_at(const Scene *s, const Material *mat, const float uv[2])
{
    if (!mat->alpha_mask || mat->albedo_tex < 0)
        return true;
    const Texture *t = &s->textures[mat->albedo_tex];
    int x = (int)floorf(uv[0] * (float)t->width) % t->width, y = (int)floorf(uv[1] * (float)t->height) % t->height;
    x += x < 0 ? t->width : 0;
    y += y < 0 ? t->height : 0;
    return t->rgba[4 * ((size_t)y * t->width + x) + 3] / 255.f >= mat->alpha_cutoff;
}

/* common/packing.glsl's pack_oct16 of unit n. */
static uint32_t oct16(const float n[3])
{
    float l1 = fabsf(n[0]) + fabsf(n[1]) + fabsf(n[2]);
    float p[2] = {n[0] / l1, n[1] / l1};
    if (n[2] < 0.f) {
        float x = p[0], y = p[1];
        p[0] = (1.f - fabsf(y)) * (x >= 0.f ? 1.f : -1.f);
        p[1] = (1.f - fabsf(x)) * (y >= 0.f ? 1.f : -1.f);
    }
    uint32_t o[2];
    for (int k = 0; k < 2; k++)
        o[k] = (uint32_t)lrintf(fminf(fmaxf(p[k] * 0.5f + 0.5f, 0.f), 1.f) * 65535.f);
    return o[0] | o[1] << 16;
}

/* `count` points uniform over the scene's triangles by area, the holes of
 * alpha-masked materials left out, into out[4·i] (xyz, and the bits of the
 * triangle's normal, pack_oct16, in w); the area they cover
 * into *area. false after logging if memory runs out. */
static bool sample_points(const Scene *s, uint32_t count, float *out, double *area)
{
    uint32_t tris = s->index_count / 3;
    double *cdf = malloc(sizeof(double) * (tris + 1));
    int *mat_of = malloc(sizeof(int) * (tris + 1));
    if (!cdf || !mat_of) {
        free(cdf);
        free(mat_of);
        log_error("ism", "out of memory for the point sampling of %u triangles", tris);
        return false;
    }
    for (int k = 0; k < s->submesh_count; k++)
        for (uint32_t t = s->submeshes[k].first_index / 3; t < (s->submeshes[k].first_index + s->submeshes[k].index_count) / 3 && t < tris; t++)
            mat_of[t] = s->submeshes[k].material;
    double total = 0;
    for (uint32_t t = 0; t < tris; t++) {
        const float *a = s->vertices[s->indices[3 * t]].position, *b = s->vertices[s->indices[3 * t + 1]].position,
                    *c = s->vertices[s->indices[3 * t + 2]].position;
        vec3 e1 = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2 = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, n;
        glm_vec3_cross(e1, e2, n);
        total += 0.5 * glm_vec3_norm(n);
        cdf[t] = total;
    }
    uint32_t state = 0x2545f491u, tries = 0, got = 0;
    while (got < count && tris > 0 && total > 0 && tries < 16u * count) {
        tries++;
        double u = rnd(&state) * total;
        uint32_t lo = 0, hi = tris - 1;
        while (lo < hi) { /* the first triangle whose cdf exceeds u */
            uint32_t mid = (lo + hi) / 2;
            if (cdf[mid] > u)
                hi = mid;
            else
                lo = mid + 1;
        }
        float r1 = sqrtf(rnd(&state)), r2 = rnd(&state), w[3] = {1.f - r1, r1 * (1.f - r2), r1 * r2};
        float p[3] = {0, 0, 0}, uv[2] = {0, 0};
        for (int k = 0; k < 3; k++) {
            const Vertex *v = &s->vertices[s->indices[3 * lo + (uint32_t)k]];
            for (int c = 0; c < 3; c++)
                p[c] += w[k] * v->position[c];
            uv[0] += w[k] * v->uv[0];
            uv[1] += w[k] * v->uv[1];
        }
        if (!opaque_at(s, &s->materials[mat_of[lo]], uv))
            continue;
        const float *a = s->vertices[s->indices[3 * lo]].position, *b = s->vertices[s->indices[3 * lo + 1]].position,
                    *c = s->vertices[s->indices[3 * lo + 2]].position;
        vec3 e1 = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2 = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, n;
        glm_vec3_cross(e1, e2, n);
        glm_vec3_normalize(n);
        memcpy(out + 4 * got, p, sizeof p);
        uint32_t code = oct16(n);
        memcpy(out + 4 * got + 3, &code, sizeof code);
        got++;
    }
    for (uint32_t i = got; i < count; i++) { /* a scene with nothing to sample: points nowhere, far away */
        memcpy(out + 4 * i, (float[3]){1e30f, 1e30f, 1e30f}, 3 * sizeof(float));
        memset(out + 4 * i + 3, 0, sizeof(float));
    }
    *area = tries ? total * (double)got / (double)tries : 0.0;
    free(cdf);
    free(mat_of);
    return true;
}

/* Sorts the points by the cell of the grid (origin, cell size, n per side)
 * that holds them (a counting sort; x fastest) and writes where each
 * cell's points start into start[n³ + 1]. false after logging if memory
 * runs out. */
static bool sort_points(float *pts, uint32_t count, const float origin[3], float cell, int n, uint32_t *start)
{
    uint32_t cells = (uint32_t)(n * n * n), *of = malloc(sizeof(uint32_t) * (count + 1));
    float *sorted = malloc(sizeof(float) * 4 * (count + 1));
    if (!of || !sorted) {
        free(of);
        free(sorted);
        log_error("ism", "out of memory sorting %u points", count);
        return false;
    }
    memset(start, 0, sizeof(uint32_t) * (cells + 1));
    for (uint32_t i = 0; i < count; i++) {
        int c[3];
        for (int k = 0; k < 3; k++) {
            float f = (pts[4 * i + k] - origin[k]) / cell;
            c[k] = f < 0.f || !(f == f) ? 0 : f >= (float)n ? n - 1 : (int)f;
        }
        of[i] = (uint32_t)((c[2] * n + c[1]) * n + c[0]);
        start[of[i] + 1]++;
    }
    for (uint32_t c = 0; c < cells; c++)
        start[c + 1] += start[c];
    uint32_t *fill = malloc(sizeof(uint32_t) * cells);
    if (!fill) {
        free(of);
        free(sorted);
        log_error("ism", "out of memory sorting %u points", count);
        return false;
    }
    memcpy(fill, start, sizeof(uint32_t) * cells);
    for (uint32_t i = 0; i < count; i++)
        memcpy(sorted + 4 * fill[of[i]]++, pts + 4 * i, 4 * sizeof(float));
    memcpy(pts, sorted, sizeof(float) * 4 * count);
    free(fill);
    free(of);
    free(sorted);
    return true;
}

#define ISM_CELLS (ISM_GRID * ISM_GRID * ISM_GRID)

/* Draws the scene's points (sample_points) as its vertices stand now,
 * sorts them by the cells of a grid over its bounds, uploads both and sets
 * the parameters that follow from them and the bounds (point_area,
 * far_area, grid, bias_abs). false after logging. */
static bool make_points(Ism *m)
{
    const Scene *s = m->scene;
    vec3 ext;
    glm_vec3_sub((float *)s->bounds_max, (float *)s->bounds_min, ext);
    float cell = fmaxf(fmaxf(ext[0], ext[1]), fmaxf(ext[2], 1e-6f)) / (float)ISM_GRID * 1.001f;
    float *pts = malloc(sizeof(float) * 4 * m->point_count);
    uint32_t *start = malloc(sizeof(uint32_t) * (ISM_CELLS + 1));
    double area = 0;
    if (!pts || !start)
        log_error("ism", "out of memory for %u points", m->point_count);
    bool ok = pts && start && sample_points(s, m->point_count, pts, &area) &&
              sort_points(pts, m->point_count, s->bounds_min, cell, ISM_GRID, start);
    if (ok) {
        glNamedBufferSubData(m->point_buffer, 0, sizeof(float) * 4 * (GLsizeiptr)m->point_count, pts);
        glNamedBufferSubData(m->cells, 0, sizeof(uint32_t) * (ISM_CELLS + 1), start);
        GpuIsmParams *g = &m->gpu;
        uint32_t far_points = (uint32_t)(m->points - m->points / 2);
        g->point_area = (float)(area / m->point_count);
        g->far_area = (float)(area / far_points);
        glm_vec3_copy((float *)s->bounds_min, g->grid);
        g->grid[3] = cell;
        g->bias_abs = ISM_BIAS_ABS * glm_vec3_norm(ext);
    }
    free(pts);
    free(start);
    return ok;
}

/* ---- Lifetime ------------------------------------------------------------- */

static GLuint program(Ism *m, const char *label, const char *comp, const char *defines)
{
    return program_cache_get(m->pc, &(ShaderProgramDesc){.label = label, .comp = comp, .defines = defines});
}

void ism_destroy(Ism *m)
{
    GLuint bufs[4] = {m->point_buffer, m->reps, m->ubo, m->cells};
    glDeleteBuffers(4, bufs);
    glDeleteTextures(1, &m->atlas);
    free(m->blocks);
    free(m->block_texels);
    memset(m, 0, sizeof *m);
}

bool ism_create(Ism *m, IsmSource source, const GiCreateInfo *ci)
{
    memset(m, 0, sizeof *m);
    const GiParams *p = ci->params;
    const LightStage *ls = ci->lights;
    const Scene *s = ci->scene;
    m->source = source;
    m->pc = ci->programs;
    m->size = size_texels(p->visibility.ism_size);
    m->points = p->visibility.ism_points;
    m->lights = ls->light_count;
    m->blocks = calloc((size_t)m->lights + 1, sizeof(int));
    m->block_texels = calloc((size_t)m->lights + 1, sizeof(int));
    if (!m->blocks || !m->block_texels) {
        log_error("ism", "out of memory");
        ism_destroy(m);
        return false;
    }
    if (source == ISM_FROM_VPLS) {
        m->maps = ls->vpls.capacity ? ls->vpls.capacity : 1;
    } else {
        for (int i = 0; i < m->lights; i++) {
            const RsmMap *r = &ls->rsm[i];
            int layers = r->cube ? 6 : 1;
            int b = (int)floor(sqrt((double)p->visibility.ism_maps / layers));
            b = b < 1 ? 1 : b > r->size ? r->size : b;
            m->block_texels[i] = (r->size + b - 1) / b;
            m->blocks[i] = (r->size + m->block_texels[i] - 1) / m->block_texels[i];
            uint32_t n = (uint32_t)(layers * m->blocks[i] * m->blocks[i]);
            if (n > m->maps_per_light)
                m->maps_per_light = n;
        }
        m->maps = m->maps_per_light * (uint32_t)(m->lights > 0 ? m->lights : 1);
    }
    /* The atlas about square, a power-of-two number of maps per row. */
    m->per_row = 1;
    while ((uint64_t)m->per_row * m->per_row < m->maps)
        m->per_row *= 2;
    int rows = (int)((m->maps + (uint32_t)m->per_row - 1) / (uint32_t)m->per_row);
    m->point_count = 1;
    while (m->point_count < (uint32_t)m->points * ISM_POINT_SETS)
        m->point_count *= 2;
    uint64_t bytes = (uint64_t)m->per_row * m->size * (uint64_t)rows * m->size * 4 * 4 / 3 + (uint64_t)m->point_count * 16 +
                     (source == ISM_FROM_RSM ? (uint64_t)m->maps * 16 : 0);
    char what[160];
    snprintf(what, sizeof what, "visibility.on's %u imperfect shadow maps of %d² (visibility.ism_size, %s)", m->maps,
             m->size, source == ISM_FROM_VPLS ? "one per VPL: vpl.count" : "visibility.ism_maps");
    if (!gpu_budget_check(bytes, what)) {
        ism_destroy(m);
        return false;
    }
    const char *const kind[2] = {"#define RSM_2D\n", "#define RSM_CUBE\n"};
    char defs[96];
    if (source == ISM_FROM_VPLS) {
        m->splat[0][0] = program(m, "ism_splat", "gi/visibility/splat.comp", "#define ISM_FROM_VPLS\n");
    } else {
        for (int cube = 0; cube < 2; cube++) {
            snprintf(defs, sizeof defs, "#define ISM_FROM_RSM\n%s", kind[cube]);
            m->splat[1][cube] = program(m, "ism_splat", "gi/visibility/splat.comp", defs);
            m->reps_prog[cube] = program(m, "ism_reps", "gi/visibility/reps.comp", kind[cube]);
        }
    }
    m->pull_push = program(m, "ism_pull_push", "gi/visibility/pull_push.comp", NULL);
    bool progs = m->pull_push && (source == ISM_FROM_VPLS ? m->splat[0][0] != 0
                                                         : m->splat[1][0] && m->splat[1][1] && m->reps_prog[0] &&
                                                               m->reps_prog[1]);
    int levels = 1;
    while ((1 << (levels - 1)) < m->size)
        levels++;
    m->levels = levels; /* down to one texel per map: pull-push's pyramid */
    m->atlas = gl_texture_make_levels(GL_TEXTURE_2D, GL_R32UI, m->per_row * m->size, rows * m->size, 1, levels,
                                      "ism.atlas");
    m->ubo = gi_ubo_make(sizeof(GpuIsmParams), "ism.params");
    if (source == ISM_FROM_RSM)
        m->reps = gl_buffer_make((uint64_t)m->maps * 16, NULL, 0, "ism.representatives");
    bool ok = progs && m->atlas && m->ubo && (source == ISM_FROM_VPLS || m->reps) &&
              (m->point_buffer = gl_buffer_make(sizeof(float) * 4 * (uint64_t)m->point_count, NULL,
                                                GL_DYNAMIC_STORAGE_BIT, "ism.points")) &&
              (m->cells = gl_buffer_make(sizeof(uint32_t) * (uint64_t)(ISM_CELLS + 1), NULL, GL_DYNAMIC_STORAGE_BIT,
                                         "ism.cells"));
    m->scene = s;
    m->points_version = ci->geometry_version; /* the geometry make_points draws from */
    if (!ok || !make_points(m)) {
        ism_destroy(m);
        return false;
    }
    GpuIsmParams *g = &m->gpu;
    g->size = m->size;
    g->per_row = m->per_row;
    g->far_points = (uint32_t)(m->points - m->points / 2);
    g->near_points = (uint32_t)(m->points / 2);
    g->point_count = m->point_count;
    g->far_stride = (uint32_t)(0.6180339887 * m->point_count) | 1u; /* odd: a permutation of the buffer */
    g->grid_n = ISM_GRID;
    g->bias_rel = ISM_BIAS_REL;

    g->maps = m->maps;
    g->maps_per_light = m->maps_per_light;
    glNamedBufferSubData(m->ubo, 0, sizeof *g, g);
    log_debug("ism", "%u maps of %d² (%s), %u points (%.3g m² each), %d points per map", m->maps, m->size,
              source == ISM_FROM_VPLS ? "one per VPL" : "one per block of RSM texels", m->point_count, g->point_area,
              m->points);
    return true;
}

Ism *ism_new(IsmSource source, const GiCreateInfo *ci, const char *tag)
{
    Ism *m = malloc(sizeof *m);
    if (!m)
        log_error(tag, "out of memory for the visibility maps");
    else if (!ism_create(m, source, ci)) {
        free(m);
        m = NULL;
    }
    return m;
}

void ism_free(Ism *m)
{
    if (!m)
        return;
    ism_destroy(m);
    free(m);
}

uint64_t ism_gpu_bytes(const Ism *m)
{
    const GLuint bufs[4] = {m->point_buffer, m->reps, m->ubo, m->cells};
    return gl_texture_bytes(m->atlas) + gl_buffers_bytes(bufs, 4);
}

const char *ism_defines(const Ism *m)
{
    if (!m)
        return "";
    return m->source == ISM_FROM_RSM ? "#define GI_VISIBILITY\n#define ISM_FROM_RSM\n" : "#define GI_VISIBILITY\n";
}

/* Light i's block layout into the parameter block (ISM_FROM_RSM). */
static void upload_light(Ism *m, const LightStage *ls, int i)
{
    if (m->source != ISM_FROM_RSM)
        return;
    m->gpu.blocks = m->blocks[i];
    m->gpu.block_texels = m->block_texels[i];
    m->gpu.rsm_size = ls->rsm[i].size;
    glNamedBufferSubData(m->ubo, 0, sizeof m->gpu, &m->gpu);
}

void ism_bind(Ism *m, const LightStage *ls, GLuint prog, int light)
{
    upload_light(m, ls, light);
    glBindTextureUnit(TEX_ISM, m->atlas);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_ISM, m->ubo);
    if (m->source == ISM_FROM_RSM) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_ISM_REPS, m->reps);
        glProgramUniform1ui(prog, LOC_ISM_MAP_BASE, (GLuint)light * m->maps_per_light);
    }
}

/* ---- Building ------------------------------------------------------------- */

/* groups_x work groups along x for each of `maps` maps, the maps spread
 * over y and z (each at most 65535): the shaders' ism_dispatch_map. */
static void dispatch_maps(uint32_t groups_x, uint32_t maps)
{
    uint32_t z = (maps + 65534u) / 65535u, y = (maps + z - 1) / z;
    glDispatchCompute(groups_x, y > 0 ? y : 1, z > 0 ? z : 1);
}

static uint64_t build_key(const LightStage *ls)
{
    uint64_t h = light_stage_products_key(ls);
    h = util_hash_bytes(h, &ls->vpl_extractions, sizeof ls->vpl_extractions);
    return h ? h : 1;
}

void ism_update(Ism *m, const GiFrame *f)
{
    const LightStage *ls = f->lights;
    uint64_t version = f->gpu_scene ? f->gpu_scene->version : 0;
    if (version != m->points_version) { /* an object moved (animation.h): draw the points again */
        if (!make_points(m))
            return; /* logged; the maps stay as they were */
        glNamedBufferSubData(m->ubo, 0, sizeof m->gpu, &m->gpu);
        m->points_version = version;
        m->built_key = 0;
    }
    uint64_t key = build_key(ls);
    if (key == m->built_key)
        return;
    GpuTimer *t = f->timer;
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_ISM, m->ubo);
    if (m->source == ISM_FROM_RSM) {
        gpu_timer_begin(t, "ism_reps");
        const GLuint none = 0xffffffffu; /* maps past a light's blocks: no source */
        glClearNamedBufferData(m->reps, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_ISM_REPS, m->reps);
        for (int i = 0; i < ls->light_count; i++) {
            const RsmMap *r = &ls->rsm[i];
            GLuint prog = m->reps_prog[r->cube];
            upload_light(m, ls, i);
            light_stage_bind_rsm_layers(ls, i);
            glProgramUniform1ui(prog, LOC_ISM_MAP_BASE, (GLuint)i * m->maps_per_light);
            glUseProgram(prog);
            GLuint b = (GLuint)m->blocks[i];
            glDispatchCompute((b + 7) / 8, (b + 7) / 8, r->cube ? 6 : 1);
        }
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        gpu_timer_end(t);
    }
    gpu_timer_begin(t, "ism_splat");
    const GLuint empty = ISM_EMPTY;
    glClearTexImage(m->atlas, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &empty);
    glBindImageTexture(IMG_OUT, m->atlas, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_ISM_POINTS, m->point_buffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_ISM_CELLS, m->cells);
    uint32_t point_groups = ((uint32_t)m->points + 255u) / 256u; /* 64 invocations of 4 points: far, then near */
    if (m->source == ISM_FROM_VPLS) {
        light_stage_bind_vpls(ls);
        glUseProgram(m->splat[0][0]);
        glProgramUniform1ui(m->splat[0][0], LOC_ISM_MAP_BASE, 0);
        dispatch_maps(point_groups, m->maps);
    } else {
        for (int i = 0; i < ls->light_count; i++) {
            GLuint prog = m->splat[1][ls->rsm[i].cube];
            upload_light(m, ls, i);
            glProgramUniform1ui(prog, LOC_ISM_MAP_BASE, (GLuint)i * m->maps_per_light);
            glUseProgram(prog);
            dispatch_maps(point_groups, m->maps_per_light);
        }
    }
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    gpu_timer_end(t);
    gpu_timer_begin(t, "ism_pull_push");
    glUseProgram(m->pull_push);
    for (int push = 0; push < 2; push++)
        for (int k = 1; k < m->levels; k++) {
            int l = push ? m->levels - 1 - k : k; /* pull 1 .. top; push top−1 .. 0 */
            int other = push ? l + 1 : l - 1, size[3];
            glProgramUniform1i(m->pull_push, LOC_ISM_PUSH, push);
            glBindImageTexture(IMG_OUT, m->atlas, l, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
            glBindImageTexture(IMG_OUT2, m->atlas, other, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
            gl_texture_level_size(m->atlas, l, size);
            gi_dispatch_pixels(size[0], size[1]);
        }
    gpu_timer_end(t);
    m->built_key = key;
    m->builds++;
}
