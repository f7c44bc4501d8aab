#include "passes/pass_tonemap.h"

#include "shared/gpu_types.h"
#include "shader.h"

bool pass_tonemap_create(PassTonemap *p, ProgramCache *pc, GLuint vao)
{
    p->program = program_cache_get(pc, &(ShaderProgramDesc){.label = "tonemap", .vert = "frame/fullscreen.vert", .frag = "frame/tonemap.frag"});
    p->vao = vao;
    return p->program != 0;
}

void pass_tonemap_destroy(PassTonemap *p)
{
    *p = (PassTonemap){0};
}

void pass_tonemap_run(PassTonemap *p, const ColorTarget *hdr, float exposure, ColorTarget *ldr)
{
    glProgramUniform1f(p->program, LOC_TONEMAP_EXPOSURE, exposure);
    glBindTextureUnit(TEX_HDR, hdr->texture);
    /* The shader encodes (common/tonemap.glsl): GL_FRAMEBUFFER_SRGB stays off. */
    fullscreen_draw(p->program, p->vao, ldr->fbo, ldr->width, ldr->height, false);
}
