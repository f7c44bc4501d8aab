#include "frame/pass_fxaa.h"

#include "shared/gpu_types.h"

bool pass_fxaa_create(PassFxaa *p, ProgramCache *pc)
{
    p->program = program_cache_get(pc, &(ShaderProgramDesc){.label = "fxaa", .comp = "frame/fxaa.comp"});
    if (!p->program)
        return false;
    glCreateSamplers(1, &p->sampler);
    glSamplerParameteri(p->sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(p->sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(p->sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(p->sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glObjectLabel(GL_SAMPLER, p->sampler, -1, "fxaa.linear");
    return true;
}

void pass_fxaa_destroy(PassFxaa *p)
{
    glDeleteSamplers(1, &p->sampler);
    *p = (PassFxaa){0};
}

void pass_fxaa_run(PassFxaa *p, const ColorTarget *in, ColorTarget *out)
{
    glBindTextureUnit(TEX_LDR, in->texture);
    glBindSampler(TEX_LDR, p->sampler);
    glBindImageTexture(IMG_LDR, out->storage, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glUseProgram(p->program);
    fullscreen_dispatch(out->width, out->height);
    glUseProgram(0);
    glBindSampler(TEX_LDR, 0);
}
