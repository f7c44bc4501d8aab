#include "frame/pass_direct.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <string.h>

#include <cglm/cglm.h>

#include "core/camera.h"
#include "base/log.h"
#include "shared/gpu_types.h"
#include "gl/shader.h"

/* In every forward program: the light block and the draw's other
 * constants as flat inputs (common/lights.glsl). */
#define FLAT_UNIFORMS_DEFINE "#define FLAT_UNIFORMS\n"

/* The forward program for kind k of material draw with `defines` before:
 * 0 textured (opaque and alpha-masked materials alike, see
 * forward_programs), 1 untextured (gpu_scene.h DrawPrograms). */
static GLuint forward_program(ProgramCache *pc, int k, const char *defines)
{
    static const char *const kinds[2] = {FLAT_UNIFORMS_DEFINE "#define OPAQUE_DRAW\n",
                                         FLAT_UNIFORMS_DEFINE "#define OPAQUE_DRAW\n#define UNTEXTURED\n"};
    char all[400];
    snprintf(all, sizeof all, "%s%s", defines, kinds[k]);
    return program_cache_get(pc, &(ShaderProgramDesc){.label = "forward", .vert = "frame/scene.vert",
                                                      .frag = "frame/forward.frag", .defines = all});
}

bool pass_direct_create(PassDirect *p, ProgramCache *pc)
{
    for (int k = 0; k < 2; k++)
        p->forward[k] = forward_program(pc, k, "");
    if (!p->forward[0] || !p->forward[1])
        return false;
    p->pc = pc;
    glCreateBuffers(1, &p->shadow_ubo);
    glNamedBufferStorage(p->shadow_ubo, sizeof(GpuShadowParams), NULL, GL_DYNAMIC_STORAGE_BIT);
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
    g.pcf_filter = sp->pcf_filter;
    p->pcf_filter = sp->pcf_filter;
    p->pcf_radius = sp->pcf_radius;
    p->area_light = sp->area_light;
    if (sp->filter_bias == SHADOW_BIAS_LEGACY)
        poisson_disk_spiral(n, 10, g.poisson);
    else
        poisson_disk_best_candidate(n, g.poisson);
    glNamedBufferSubData(p->shadow_ubo, 0, sizeof g, &g);
}

/* The grid PCF's taps per side for a radius (common/shadow.glsl's
 * shadow_grid_taps). */
static int shadow_grid_taps(float radius)
{
    int k = 2 * (int)ceilf(fmaxf(radius, 0.5f));
    return k < 8 ? k : 8;
}

void pass_direct_variant_defines(const PassDirect *p, const Scene *s, const Light *l, const char *extra, char *out,
                                 size_t size)
{
    if (!l || p->general) {
        snprintf(out, size, "%s", extra);
        return;
    }
    char grid[96] = "";
    if (p->mode == SHADOW_MODE_PCF && p->pcf_filter == SHADOW_PCF_FILTER_GRID) {
        /* Taps exactly one texel apart (an integer radius up to 4):
         * SHADOW_GRID_UNIT_STEP, see shadow_pcf_grid. */
        int k = shadow_grid_taps(p->pcf_radius);
        bool unit = 2.f * fmaxf(p->pcf_radius, 0.5f) == (float)k;
        snprintf(grid, sizeof grid, "#define SHADOW_GRID_TAPS %d\n%s", k, unit ? "#define SHADOW_GRID_UNIT_STEP\n" : "");
    }
    snprintf(out, size,
             "#define LIGHT_FIXED_TYPE %d\n#define SHADOW_FIXED_CUBE %d\n#define SHADOW_FIXED_MODE %d\n"
             "#define SHADOW_FIXED_BIAS %d\n#define SHADOW_FIXED_FILTER %d\n%s%s%s",
             (int)l->type, shadow_frame_is_cube(l, s->bounds_min, s->bounds_max) ? 1 : 0, (int)p->mode,
             p->filter_bias, p->pcf_filter, grid,
             scene_has_glossy(s) ? "" : "#define DIRECT_DIFFUSE_ONLY\n", extra);
}

/* Light `l`'s forward programs (pass_direct_variant_defines; NULL: no light), each
 * falling back to the general one (logged once by the cache). Alpha-masked
 * materials draw with the textured opaque program: the depth pre-pass
 * discarded their holes, and at GL_EQUAL a hole's fragment (nearer than
 * what the pre-pass left there) fails the test. So no fragment of the
 * shading pass discards, and every one tests its depth before shading: a
 * masked fragment behind another costs no shading. */
static void forward_programs(PassDirect *p, const Scene *s, const Light *l, GLuint progs[2])
{
    progs[0] = p->forward[0];
    progs[1] = p->forward[1];
    if (!l || p->general)
        return;
    char defines[320];
    pass_direct_variant_defines(p, s, l, "", defines, sizeof defines);
    for (int k = 0; k < 2; k++) {
        GLuint prog = forward_program(p->pc, k, defines);
        progs[k] = prog ? prog : progs[k];
    }
}

void pass_direct_forward(PassDirect *p, const LightStage *ls, const GpuScene *gs, const Camera *cam, bool cull,
                         GLuint fbo, bool display, int width, int height)
{
    const Scene *s = ls->scene;
    mat4 vp;
    camera_view_proj(cam, (float)width / (float)height, vp);
    const float zero[4] = {0.f, 0.f, 0.f, 0.f};
    const float black[4] = {0.f, 0.f, 0.f, 1.f};
    /* (Clearing a draw buffer that is GL_NONE, display-only frames', does nothing.) */
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, zero); /* the background */
    if (display)
        glClearNamedFramebufferfv(fbo, GL_COLOR, 1, black); /* tone-mapped (and encoded): opaque */
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_SHADOW, p->shadow_ubo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_EQUAL);
    glDepthMask(GL_FALSE);
    glDisable(GL_CULL_FACE);
    glBlendFunc(GL_ONE, GL_ONE);
    DrawView view = {.view_proj = (const float *)vp, .eye = cam->position, .culled = NULL};
    int n = ls->light_count > 0 ? ls->light_count : 1; /* no light: slot 0 is a zero light, emission only */
    for (int i = 0; i < n; i++) {
        GLuint progs[2];
        forward_programs(p, s, ls->light_count > 0 ? &s->lights[i] : NULL, progs);
        for (int k = 0; k < 2; k++) {
            glProgramUniformMatrix4fv(progs[k], LOC_VIEW_PROJ, 1, GL_FALSE, (const float *)vp);
            glProgramUniform3fv(progs[k], LOC_EYE, 1, cam->position);
            glProgramUniform1i(progs[k], LOC_DIRECT_AREA_LIGHT, p->area_light);
            glProgramUniform1i(progs[k], LOC_DIRECT_EMISSION, i == 0 ? 1 : 0);
        }
        light_stage_bind_shadow(ls, i);
        if (i == 1)
            glEnable(GL_BLEND);
        gpu_scene_draw_view(gs, s, &(DrawPrograms){progs[0], progs[0], progs[1]}, DRAW_ALL, cull ? &view : NULL);
    }
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}
