/* gi.c — the technique table, and "none". */
#include "gi/gi.h"

#include <assert.h>
#include <cglm/vec3.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "gl/gl_resources.h"

const GiTechnique *const gi_techniques[] = {
#define GI_ROW_ADDRESS(mode, row) &row,
    GI_TECHNIQUE_LIST(GI_ROW_ADDRESS)
#undef GI_ROW_ADDRESS
    NULL,
};

const char *const *gi_technique_names(void)
{
    static const char *names[64];
    if (!names[0])
        for (int i = 0; gi_techniques[i] && i < 63; i++)
            names[i] = gi_techniques[i]->name;
    return names;
}

int gi_technique_count(void)
{
    int n = 0;
    while (gi_techniques[n])
        n++;
    return n;
}

int gi_technique_find(const char *name)
{
    for (int i = 0; gi_techniques[i]; i++)
        if (!strcmp(gi_techniques[i]->name, name))
            return i;
    return -1;
}

void gi_dispatch_pixels(int w, int h)
{
    glDispatchCompute((GLuint)(w + 7) / 8, (GLuint)(h + 7) / 8, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT);
}

float gi_grid_around(const float bmin[3], const float bmax[3], int n, float corner[3])
{
    vec3 ext, mid;
    glm_vec3_sub((float *)bmax, (float *)bmin, ext);
    glm_vec3_add((float *)bmax, (float *)bmin, mid);
    glm_vec3_scale(mid, 0.5f, mid);
    float largest = fmaxf(ext[0], fmaxf(ext[1], ext[2]));
    if (largest <= 0.f)
        largest = 1.f;
    float cell = largest / (float)(n > 2 ? n - 2 : n);
    for (int a = 0; a < 3; a++)
        corner[a] = mid[a] - 0.5f * cell * (float)n;
    return cell;
}

float gi_clipmap_extent(const float bmin[3], const float bmax[3], const float cam[3], int n)
{
    float half = 0.f;
    for (int a = 0; a < 3; a++)
        half = fmaxf(half, fmaxf(fabsf(bmin[a] - cam[a]), fabsf(bmax[a] - cam[a])));
    return 2.f * half * (float)n / (float)(n > 4 ? n - 4 : n);
}

void gi_clipmap_level(float coarsest, int n, int levels, int k, const float cam[3], float corner_cell[4])
{
    float cell = coarsest / (float)n / (float)(1 << (levels - 1 - k));
    for (int a = 0; a < 3; a++)
        corner_cell[a] = (floorf(cam[a] / cell) - (float)(n / 2)) * cell;
    corner_cell[3] = cell;
}

void gi_params_to_gpu(const GiParams *p, int w, int h, GpuGiParams *u)
{
    memset(u, 0, sizeof *u);
    float r = p->rsm.r_max * (float)p->rsm.size;
    u->rsm_r_max = p->rsm.r_max;
    u->rsm_samples = p->rsm.samples;
    u->rsm_size = p->rsm.size;
    u->disk_texels = 3.14159265358979f * r * r;
    u->rsm_interp_factor = p->rsm.interp_factor;
    u->rsm_interp_normal = p->rsm.interp_normal;
    u->rsm_interp_dist = p->rsm.interp_dist;
    u->low_width = (w + p->rsm.interp_factor - 1) / p->rsm.interp_factor;
    u->low_height = (h + p->rsm.interp_factor - 1) / p->rsm.interp_factor;
    u->interleave_pattern_n = p->interleave.pattern.n;
    u->interleave_pattern_m = p->interleave.pattern.m;
    u->sub_width = (w + p->interleave.pattern.n - 1) / p->interleave.pattern.n;
    u->sub_height = (h + p->interleave.pattern.m - 1) / p->interleave.pattern.m;
    u->list_set = rsm_far_samples(p->rsm.samples);
    u->list_size = u->list_set * RSM_LIST_SETS;
    u->disk_r2_per_area = p->vpl.disk ? 1.f / 3.14159265358979f : 0.f;
}

GLuint gi_ubo_make(GLsizeiptr size, const char *label)
{
    return gl_buffer_make((uint64_t)size, NULL, GL_DYNAMIC_STORAGE_BIT, label);
}

/* ---- none: direct light only --------------------------------------------- */

static unsigned none_needs(const GiParams *p)
{
    (void)p;
    return 0;
}

const GiTechnique gi_none = {
    .name = "none",
    .paper = "-",
    .summary = "direct light only",
    .needs = none_needs,
};

void gi_print_vpl_stats(const GiStats *st, double pixels, FILE *out)
{
    fprintf(out, "vpl_count: %u\n", st->vpl_count);
    fprintf(out, "vpl_evaluations: %llu\n", (unsigned long long)st->vpl_evaluations);
    fprintf(out, "vpl_evaluations_per_pixel: %.1f\n", (double)st->vpl_evaluations / pixels);
    fprintf(out, "vpl_candidates: %llu\n", (unsigned long long)st->vpl_candidates);
    if (st->tile_overflow)
        fprintf(out, "vpl_tile_overflow: %u\n", st->tile_overflow);
}

void gi_stats_add_gather(GiStats *st, const char *name, uint64_t evaluations)
{
    assert(st->gather_pass_count < GI_GATHER_PASSES);
    if (st->gather_pass_count >= GI_GATHER_PASSES)
        return;
    st->gather_passes[st->gather_pass_count++] = (GiGatherPass){name, evaluations};
    st->gather_evaluations += evaluations;
}

uint32_t gi_count_surfaces(const GiFrame *f, ProgramCache *pc, int step)
{
    GLuint prog = program_cache_get(pc, &(ShaderProgramDesc){.label = "count_surfaces", .comp = "gi/count_surfaces.comp"});
    if (!prog || !f->gbuffer || step < 1)
        return 0;
    uint32_t count = 0;
    GLuint buf;
    glCreateBuffers(1, &buf);
    glNamedBufferStorage(buf, sizeof count, &count, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_STATS, buf);
    glBindTextureUnit(TEX_GB_SURFACE, f->gbuffer->surface);
    glProgramUniform1i(prog, LOC_COUNT_STEP, step);
    glUseProgram(prog);
    int lw = (f->gbuffer->width + step - 1) / step, lh = (f->gbuffer->height + step - 1) / step;
    glDispatchCompute((GLuint)(lw + 63) / 64, (GLuint)(lh + 7) / 8, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buf, 0, sizeof count, &count);
    glDeleteBuffers(1, &buf);
    return count;
}
