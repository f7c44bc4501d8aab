#include "passes/pass_composite.h"

#include "shader.h"
#include "shared/gpu_types.h"

bool pass_composite_create(PassComposite *p, ProgramCache *pc, GLuint vao)
{
    p->program = program_cache_get(pc, &(ShaderProgramDesc){.label = "composite", .vert = "frame/fullscreen.vert", .frag = "frame/composite.frag"});
    p->vao = vao;
    return p->program != 0;
}

void pass_composite_destroy(PassComposite *p)
{
    *p = (PassComposite){0};
}

void pass_composite_run(PassComposite *p, const GBuffer *gb, GLuint irradiance, GLuint specular, ColorTarget *hdr)
{
    glBindTextureUnit(TEX_GB_ALBEDO, gb->albedo);
    glBindTextureUnit(TEX_GI, irradiance);
    glBindTextureUnit(TEX_SPECULAR, specular ? specular : irradiance);
    glProgramUniform1i(p->program, LOC_COMPOSITE_SPECULAR, specular ? 1 : 0);
    fullscreen_draw(p->program, p->vao, hdr->fbo, hdr->width, hdr->height, true);
}
