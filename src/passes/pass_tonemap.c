#include "passes/pass_tonemap.h"

#include "gpu_types.h"
#include "shader.h"

bool pass_tonemap_create(PassTonemap *p)
{
    p->program = shader_program_make("tonemap", "fullscreen.vert", "tonemap.frag", NULL);
    glCreateVertexArrays(1, &p->vao);
    return p->program != 0;
}

void pass_tonemap_destroy(PassTonemap *p)
{
    glDeleteProgram(p->program);
    glDeleteVertexArrays(1, &p->vao);
    *p = (PassTonemap){0};
}

void pass_tonemap_run(PassTonemap *p, const ColorTarget *hdr, float exposure, ColorTarget *ldr)
{
    glProgramUniform1f(p->program, 0, exposure);
    glBindTextureUnit(TEX_HDR, hdr->texture);
    glBindFramebuffer(GL_FRAMEBUFFER, ldr->fbo);
    glEnable(GL_FRAMEBUFFER_SRGB);
    glViewport(0, 0, ldr->width, ldr->height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glUseProgram(p->program);
    glBindVertexArray(p->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDisable(GL_FRAMEBUFFER_SRGB);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}
