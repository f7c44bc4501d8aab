#include "frame/pass_finish.h"

#include "shared/gpu_types.h"

bool pass_finish_create(PassFinish *p, ProgramCache *pc)
{
    p->program = program_cache_get(pc, &(ShaderProgramDesc){.label = "finish", .comp = "frame/finish.comp"});
    return p->program != 0;
}

void pass_finish_destroy(PassFinish *p) { *p = (PassFinish){0}; }

void pass_finish_run(PassFinish *p, const ColorTarget *in, int factor, ColorTarget *hdr, ColorTarget *ldr)
{
    glProgramUniform1i(p->program, LOC_FINISH_FACTOR, factor);
    glProgramUniform1i(p->program, LOC_FINISH_RADIANCE, factor > 1 ? 1 : 0);
    glBindTextureUnit(TEX_HDR, in->texture);
    glBindImageTexture(IMG_HDR, hdr->texture, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(IMG_LDR, ldr->storage, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glUseProgram(p->program);
    fullscreen_dispatch(ldr->width, ldr->height);
    glUseProgram(0);
}
