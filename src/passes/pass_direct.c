#include "passes/pass_direct.h"

#include <math.h>
#include <string.h>

#include <cglm/cglm.h>

#include "gpu_types.h"
#include "shader.h"

bool pass_direct_create(PassDirect *p)
{
    p->program = shader_program_make("direct", "fullscreen.vert", "direct.frag", NULL);
    if (!p->program)
        return false;
    glCreateBuffers(1, &p->shadow_ubo);
    glNamedBufferStorage(p->shadow_ubo, sizeof(GpuShadowParams), NULL, GL_DYNAMIC_STORAGE_BIT);
    glCreateBuffers(1, &p->light_ubo);
    glNamedBufferStorage(p->light_ubo, sizeof(GpuLight), NULL, GL_DYNAMIC_STORAGE_BIT);
    glCreateVertexArrays(1, &p->vao);
    return true;
}

void pass_direct_destroy(PassDirect *p)
{
    glDeleteProgram(p->program);
    GLuint b[2] = {p->shadow_ubo, p->light_ubo};
    glDeleteBuffers(2, b);
    glDeleteVertexArrays(1, &p->vao);
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

void pass_direct_set_shadow(PassDirect *p, ShadowMode mode, const ShadowParams *sp)
{
    GpuShadowParams g;
    memset(&g, 0, sizeof g);
    g.bias[0] = sp->bias_const;
    g.bias[1] = sp->bias_slope;
    g.bias[2] = sp->normal_offset;
    g.bias[3] = (float)mode;
    g.filter[0] = sp->pcf_radius;
    g.filter[1] = (float)sp->pcf_samples;
    g.filter[2] = (float)sp->blocker_samples;
    g.filter[3] = sp->pcss_max_radius;
    int n = sp->pcf_samples > sp->blocker_samples ? sp->pcf_samples : sp->blocker_samples;
    poisson_disk_spiral(n, 10, g.poisson);
    glNamedBufferSubData(p->shadow_ubo, 0, sizeof g, &g);
}

void pass_direct_run(PassDirect *p, const PassShadow *ps, const ShadowMap *sm, const GBuffer *gb,
                     bool add_emission, ColorTarget *hdr)
{
    glNamedBufferSubData(p->light_ubo, 0, sizeof(GpuLight), &sm->gpu);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_LIGHT, p->light_ubo);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_SHADOW, p->shadow_ubo);
    pass_shadow_bind(ps, sm);
    glBindTextureUnit(TEX_GB_POSITION, gb->position);
    glBindTextureUnit(TEX_GB_NORMAL, gb->normal);
    glBindTextureUnit(TEX_GB_ALBEDO, gb->albedo);
    glBindTextureUnit(TEX_GB_EMISSION, gb->emission);
    glProgramUniform1i(p->program, 10, add_emission ? 1 : 0);
    fullscreen_draw(p->program, p->vao, hdr->fbo, hdr->width, hdr->height, true);
}
