#include "passes/pass_rsm_gather.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <cglm/cglm.h>

#include "gpu_types.h"
#include "shader.h"

static float radical_inverse2(uint32_t i)
{
    i = (i << 16u) | (i >> 16u);
    i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
    i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
    i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
    i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
    return (float)i * 2.3283064365386963e-10f;
}

void rsm_pattern(int n, float (*out)[4])
{
    for (int i = 0; i < n; i++) {
        float xi1 = ((float)i + 0.5f) / (float)n, xi2 = radical_inverse2((uint32_t)i);
        out[i][0] = xi1 * sinf(2.f * GLM_PIf * xi2);
        out[i][1] = xi1 * cosf(2.f * GLM_PIf * xi2);
        out[i][2] = xi1;
        out[i][3] = xi2;
    }
}

float rsm_disk_texels(const GiParams *gp)
{
    float r = gp->r_max * (float)gp->rsm_size;
    return GLM_PIf * r * r;
}

bool pass_rsm_gather_create(PassRsmGather *p, const GiParams *gp, int w, int h)
{
    static const char *layout_def[GATHER_LAYOUTS] = {"#define MODE_FULL\n", "#define MODE_LOWRES\n",
                                                     "#define MODE_LIST\n", "#define MODE_INTERLEAVED\n"};
    char defs[128];
    for (int l = 0; l < GATHER_LAYOUTS; l++)
        for (int c = 0; c < 2; c++) {
            snprintf(defs, sizeof defs, "%s%s", layout_def[l], c ? "#define RSM_CUBE\n" : "");
            p->gather[l][c] = shader_compute_make("rsm_gather", "rsm_gather.comp", defs);
            if (!p->gather[l][c])
                return false;
        }
    p->interp = shader_compute_make("rsm_interp", "rsm_interp.comp", NULL);
    p->split = shader_compute_make("interleave_split", "gi_interleave.comp", "#define MODE_SPLIT\n");
    p->merge = shader_compute_make("interleave_merge", "gi_interleave.comp", "#define MODE_MERGE\n");
    p->blur = shader_compute_make("interleave_blur", "gi_interleave.comp", "#define MODE_BLUR\n");
    if (!p->interp || !p->split || !p->merge || !p->blur)
        return false;

    int n = gp->samples;
    float(*pat)[4] = malloc(sizeof(float) * 4 * (size_t)n);
    rsm_pattern(n, pat);
    glCreateBuffers(1, &p->pattern);
    glNamedBufferStorage(p->pattern, (GLsizeiptr)(sizeof(float) * 4 * (size_t)n), pat, 0);
    glObjectLabel(GL_BUFFER, p->pattern, -1, "rsm.pattern");
    free(pat);
    glCreateBuffers(1, &p->light_ubo);
    glNamedBufferStorage(p->light_ubo, sizeof(GpuLight), NULL, GL_DYNAMIC_STORAGE_BIT);

    p->width = w;
    p->height = h;
    p->low_w = (w + gp->interp_factor - 1) / gp->interp_factor;
    p->low_h = (h + gp->interp_factor - 1) / gp->interp_factor;
    p->sub_w = (w + gp->interleave_n - 1) / gp->interleave_n;
    p->sub_h = (h + gp->interleave_m - 1) / gp->interleave_m;
    p->lowres = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, p->low_w, p->low_h, "gi.lowres");
    p->di_w = p->sub_w * gp->interleave_n;
    p->di_h = p->sub_h * gp->interleave_m;
    p->di_position = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, p->di_w, p->di_h, "gi.di_position");
    p->di_normal = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, p->di_w, p->di_h, "gi.di_normal");
    p->di_irradiance = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, p->di_w, p->di_h, "gi.di_irradiance");
    p->merged = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, w, h, "gi.merged");
    return true;
}

void pass_rsm_gather_destroy(PassRsmGather *p)
{
    for (int l = 0; l < GATHER_LAYOUTS; l++)
        for (int c = 0; c < 2; c++)
            glDeleteProgram(p->gather[l][c]);
    glDeleteProgram(p->interp);
    glDeleteProgram(p->split);
    glDeleteProgram(p->merge);
    glDeleteProgram(p->blur);
    GLuint b[2] = {p->pattern, p->light_ubo};
    glDeleteBuffers(2, b);
    GLuint t[5] = {p->lowres, p->di_position, p->di_normal, p->di_irradiance, p->merged};
    glDeleteTextures(5, t);
    *p = (PassRsmGather){0};
}

static void dispatch(int w, int h)
{
    glDispatchCompute((GLuint)(w + 7) / 8, (GLuint)(h + 7) / 8, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT);
}

void pass_rsm_gather_run(PassRsmGather *p, GatherLayout layout, const RsmMap *m, bool exhaustive, bool accumulate,
                         const GBuffer *gb, const VplBuffer *vb, GLuint out)
{
    GLuint prog = p->gather[layout][m->cube ? 1 : 0];
    rsm_map_bind(m, p->light_ubo);
    vpl_buffer_bind(vb);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_PATTERN, p->pattern);
    bool di = layout == GATHER_INTERLEAVED;
    glBindTextureUnit(TEX_GB_POSITION, di ? p->di_position : gb->position);
    glBindTextureUnit(TEX_GB_NORMAL, di ? p->di_normal : gb->normal);
    GLuint target = layout == GATHER_LOWRES ? p->lowres : di ? p->di_irradiance : out;
    glBindImageTexture(IMG_OUT, target, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glProgramUniform1i(prog, 0, exhaustive ? 1 : 0);
    glProgramUniform1i(prog, 1, accumulate ? 1 : 0);
    glUseProgram(prog);
    switch (layout) {
    case GATHER_FULL:
        dispatch(p->width, p->height);
        break;
    case GATHER_LOWRES:
        dispatch(p->low_w, p->low_h);
        break;
    case GATHER_LIST: /* one thread per possible entry; those past the count return at once */
        dispatch(p->width, p->height);
        break;
    case GATHER_INTERLEAVED:
        dispatch(p->di_w, p->di_h);
        break;
    default:
        break;
    }
}

void pass_rsm_interp_run(PassRsmGather *p, const GBuffer *gb, const VplBuffer *vb, GLuint out)
{
    vpl_buffer_bind(vb);
    glBindTextureUnit(TEX_GB_POSITION, gb->position);
    glBindTextureUnit(TEX_GB_NORMAL, gb->normal);
    glBindTextureUnit(TEX_LOWRES, p->lowres);
    glBindImageTexture(IMG_OUT, out, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glUseProgram(p->interp);
    dispatch(p->width, p->height);
}

void pass_interleave_split(PassRsmGather *p, const GBuffer *gb)
{
    glBindTextureUnit(TEX_GB_POSITION, gb->position);
    glBindTextureUnit(TEX_GB_NORMAL, gb->normal);
    const float zero[4] = {0, 0, 0, 0};
    glClearTexImage(p->di_position, 0, GL_RGBA, GL_FLOAT, zero);
    glBindImageTexture(0, p->di_position, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(1, p->di_normal, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glUseProgram(p->split);
    dispatch(p->width, p->height);
}

void pass_interleave_merge(PassRsmGather *p, const GBuffer *gb, bool blur, GLuint out)
{
    glBindTextureUnit(TEX_LOWRES, p->di_irradiance);
    glBindImageTexture(IMG_OUT, blur ? p->merged : out, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glUseProgram(p->merge);
    dispatch(p->width, p->height);
    if (blur)
        pass_interleave_blur(p, gb, p->merged, out);
}

void pass_interleave_blur(PassRsmGather *p, const GBuffer *gb, GLuint in, GLuint out)
{
    glBindTextureUnit(TEX_GB_POSITION, gb->position);
    glBindTextureUnit(TEX_GB_NORMAL, gb->normal);
    glBindTextureUnit(TEX_LOWRES, in);
    glBindImageTexture(IMG_OUT, out, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glUseProgram(p->blur);
    dispatch(p->width, p->height);
}
