#include "passes/pass_composite.h"

#include "gpu_types.h"
#include "shader.h"

bool pass_composite_create(PassComposite *p)
{
    p->program = shader_program_make("composite", "fullscreen.vert", "composite.frag", NULL);
    glCreateVertexArrays(1, &p->vao);
    return p->program != 0;
}

void pass_composite_destroy(PassComposite *p)
{
    glDeleteProgram(p->program);
    glDeleteVertexArrays(1, &p->vao);
    *p = (PassComposite){0};
}

void pass_composite_run(PassComposite *p, const GBuffer *gb, GLuint irradiance, ColorTarget *hdr)
{
    glBindTextureUnit(TEX_GB_ALBEDO, gb->albedo);
    glBindTextureUnit(TEX_GI, irradiance);
    fullscreen_draw(p->program, p->vao, hdr->fbo, hdr->width, hdr->height, true);
}
