#include "passes/pass_composite.h"

#include "shader.h"
#include "shared/gpu_types.h"

bool pass_composite_create(PassComposite *p, ProgramCache *pc, GLuint vao)
{
    p->program = program_cache_get(pc, &(ShaderProgramDesc){.label = "composite", .vert = "frame/fullscreen.vert", .frag = "frame/composite.frag"});
    p->program_glossy = program_cache_get(pc, &(ShaderProgramDesc){.label = "composite_glossy", .vert = "frame/fullscreen.vert",
                                                                   .frag = "frame/composite.frag", .defines = "#define GLOSSY\n"});
    p->vao = vao;
    return p->program != 0 && p->program_glossy != 0;
}

void pass_composite_destroy(PassComposite *p)
{
    *p = (PassComposite){0};
}

void pass_composite_run(PassComposite *p, const GBuffer *gb, GLuint irradiance, GLuint specular, GLuint brdf_albedo,
                        bool glossy, ColorTarget *hdr)
{
    GLuint prog = glossy ? p->program_glossy : p->program;
    glBindTextureUnit(TEX_GB_SURFACE, gb->surface);
    glBindTextureUnit(TEX_GB_MATERIAL, gb->material);
    glBindTextureUnit(TEX_BRDF_ALBEDO, brdf_albedo);
    glBindTextureUnit(TEX_GI, irradiance);
    glBindTextureUnit(TEX_SPECULAR, specular ? specular : irradiance);
    glProgramUniform1i(prog, LOC_COMPOSITE_SPECULAR, specular ? 1 : 0);
    fullscreen_draw(prog, p->vao, hdr->fbo, hdr->width, hdr->height, true);
}
