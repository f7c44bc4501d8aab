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
    /* The target encodes sRGB: here llvmpipe's conversion is cheaper than
     * the shader's (common/tonemap.glsl's srgb_encode, which the forward
     * draw uses): 2.9 against 3.5 ms, pcf_sun.json 800x600 deferred, one
     * thread, medians of 7 alternated runs. */
    glEnable(GL_FRAMEBUFFER_SRGB);
    fullscreen_draw(p->program, p->vao, ldr->fbo, ldr->width, ldr->height, false);
    glDisable(GL_FRAMEBUFFER_SRGB);
}
