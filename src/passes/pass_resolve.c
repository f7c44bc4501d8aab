#include "passes/pass_resolve.h"

#include <assert.h>

#include "shared/gpu_types.h"

bool pass_resolve_create(PassResolve *p, ProgramCache *pc, GLuint vao)
{
    p->program = program_cache_get(pc, &(ShaderProgramDesc){.label = "resolve", .vert = "frame/fullscreen.vert", .frag = "frame/resolve.frag"});
    p->vao = vao;
    return p->program != 0;
}

void pass_resolve_destroy(PassResolve *p)
{
    *p = (PassResolve){0};
}

void pass_resolve_run(PassResolve *p, const ColorTarget *in, int n, ColorTarget *out)
{
    assert(in->width == n * out->width && in->height == n * out->height);
    glProgramUniform1i(p->program, LOC_RESOLVE_FACTOR, n);
    glBindTextureUnit(TEX_HDR, in->texture);
    fullscreen_draw(p->program, p->vao, out->fbo, out->width, out->height, false);
}
