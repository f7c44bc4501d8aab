#include "passes/pass_direct.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <string.h>

#include <cglm/cglm.h>

#include "log.h"
#include "shared/gpu_types.h"
#include "shader.h"

bool pass_direct_create(PassDirect *p, ProgramCache *pc, GLuint vao)
{
    p->program = program_cache_get(pc, &(ShaderProgramDesc){.label = "direct", .vert = "frame/fullscreen.vert", .frag = "frame/direct.frag"});
    if (!p->program)
        return false;
    p->pc = pc;
    glCreateBuffers(1, &p->shadow_ubo);
    glNamedBufferStorage(p->shadow_ubo, sizeof(GpuShadowParams), NULL, GL_DYNAMIC_STORAGE_BIT);
    p->vao = vao;
    return true;
}

void pass_direct_destroy(PassDirect *p)
{
    glDeleteBuffers(1, &p->shadow_ubo);
    *p = (PassDirect){0};
}

void poisson_disk_spiral(int n, int rings, float out[][4])
{
    float angle_step = 2.f * GLM_PIf * (float)rings / (float)n;
    float angle = 0.f;
    for (int i = 0; i < n; i++) {
        float r = powf((float)(i + 1) / (float)n, 0.75f);
        out[i][0] = r * cosf(angle);
        out[i][1] = r * sinf(angle);
        out[i][2] = out[i][3] = 0.f;
        angle += angle_step;
    }
}

void poisson_disk_best_candidate(int n, float out[][4])
{
    /* Mitchell's best candidate: point i is the one of 16·i + 1 uniform
     * candidates in the disk farthest from points 0..i-1, so every prefix is
     * well spread. A fixed LCG makes the disk the same on every run. */
    uint32_t state = 0x9e3779b9u;
    for (int i = 0; i < n; i++) {
        float best[2] = {0, 0}, best_d = -1.f;
        for (int c = 0; c < 16 * i + 1; c++) {
            float u[2];
            for (int k = 0; k < 2; k++) {
                state = state * 1664525u + 1013904223u;
                u[k] = (float)(state >> 8) / 16777216.f;
            }
            float r = sqrtf(u[0]), a = 2.f * GLM_PIf * u[1];
            float p[2] = {r * cosf(a), r * sinf(a)};
            float d = 1e9f;
            for (int j = 0; j < i; j++) {
                float dx = p[0] - out[j][0], dy = p[1] - out[j][1];
                d = fminf(d, dx * dx + dy * dy);
            }
            if (d > best_d) {
                best_d = d;
                best[0] = p[0];
                best[1] = p[1];
            }
        }
        out[i][0] = best[0];
        out[i][1] = best[1];
        out[i][2] = out[i][3] = 0.f;
    }
}

void pass_direct_set_shadow(PassDirect *p, ShadowMode mode, const ShadowParams *sp)
{
    GpuShadowParams g;
    memset(&g, 0, sizeof g);
    g.bias_const = sp->bias_const;
    g.bias_slope = sp->bias_slope;
    g.normal_offset = sp->normal_offset;
    g.mode = (int)mode;
    p->mode = mode;
    p->filter_bias = sp->filter_bias;
    g.pcf_radius = sp->pcf_radius;
    g.pcf_samples = sp->pcf_samples;
    g.blocker_samples = sp->blocker_samples;
    g.pcss_max_radius = sp->pcss_max_radius;
    /* The settings table bounds both counts by SHADOW_MAX_SAMPLES. */
    int n = sp->pcf_samples > sp->blocker_samples ? sp->pcf_samples : sp->blocker_samples;
    assert(n >= 1 && n <= SHADOW_MAX_SAMPLES);
    g.filter_bias = sp->filter_bias;
    p->area_light = sp->area_light;
    if (sp->filter_bias == SHADOW_BIAS_LEGACY)
        poisson_disk_spiral(n, 10, g.poisson);
    else
        poisson_disk_best_candidate(n, g.poisson);
    glNamedBufferSubData(p->shadow_ubo, 0, sizeof g, &g);
}

/* The direct program specialised to light `l`'s type and the shadow mode:
 * with both fixed at compile time the compiler drops the other types' and
 * filters' code, which llvmpipe would otherwise pay for although no pixel
 * takes it (pcf_sun.json 800x600 with PCF, one thread: 160-210 -> 35-63 ms,
 * the image bit for bit the same, see test_direct). A scene without glossy
 * materials drops the GGX code too (10-12 ms of the unshadowed pass's ~35 in
 * one measurement, within the noise in another). Variants are built on
 * first use; one that does not build falls back to the general program
 * (logged once by the cache). */
static GLuint direct_program(PassDirect *p, const Scene *s, const Light *l)
{
    if (p->general)
        return p->program;
    bool diffuse_only = !scene_has_glossy(s);
    char defines[128];
    snprintf(defines, sizeof defines, "#define LIGHT_FIXED_TYPE %d\n#define SHADOW_FIXED_MODE %d\n#define SHADOW_FIXED_BIAS %d\n%s",
             (int)l->type, (int)p->mode, p->filter_bias, diffuse_only ? "#define DIRECT_DIFFUSE_ONLY\n" : "");
    GLuint prog = program_cache_get(
        p->pc, &(ShaderProgramDesc){.label = "direct", .vert = "frame/fullscreen.vert", .frag = "frame/direct.frag",
                                    .defines = defines});
    return prog ? prog : p->program;
}

/* One light's draw with `prog`. The first draw of a frame writes
 * without blending, so the target needs no clear and no read-back of what it
 * held; background pixels write zero there and are discarded after. */
static void direct_draw(PassDirect *p, GLuint prog, bool first, ColorTarget *hdr)
{
    glProgramUniform1i(prog, LOC_DIRECT_AREA_LIGHT, p->area_light);
    glProgramUniform1i(prog, LOC_DIRECT_EMISSION, first ? 1 : 0);
    fullscreen_draw(prog, p->vao, hdr->fbo, hdr->width, hdr->height, !first);
}

void pass_direct_run(PassDirect *p, const LightStage *ls, const GBuffer *gb, ColorTarget *hdr)
{
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_SHADOW, p->shadow_ubo);
    glBindTextureUnit(TEX_GB_SURFACE, gb->surface);
    glBindTextureUnit(TEX_GB_MATERIAL, gb->material);
    if (ls->light_count == 0) {
        /* No light: slot 0 of the light array is all zero (zero light
         * colour), so the draw adds emission only. */
        light_stage_bind_shadow(ls, 0);
        direct_draw(p, p->program, true, hdr);
        return;
    }
    for (int i = 0; i < ls->light_count; i++) {
        light_stage_bind_shadow(ls, i);
        direct_draw(p, direct_program(p, ls->scene, &ls->scene->lights[i]), i == 0, hdr);
    }
}
