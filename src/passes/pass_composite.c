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
    glBindFramebuffer(GL_FRAMEBUFFER, hdr->fbo);
    glViewport(0, 0, hdr->width, hdr->height);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glUseProgram(p->program);
    glBindVertexArray(p->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}
