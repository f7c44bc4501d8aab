#include "frame/pass_shade.h"

#include <stdio.h>

#include "shared/gpu_types.h"

#define GLOSSY_DEFINE "#define GLOSSY\n"

bool pass_shade_create(PassShade *p, ProgramCache *pc)
{
    p->pc = pc;
    p->program = program_cache_get(pc, &(ShaderProgramDesc){.label = "shade", .comp = "frame/shade.comp"});
    p->program_glossy = program_cache_get(
        pc, &(ShaderProgramDesc){.label = "shade", .comp = "frame/shade.comp", .defines = GLOSSY_DEFINE});
    return p->program && p->program_glossy;
}

void pass_shade_destroy(PassShade *p) { *p = (PassShade){0}; }

/* The program for light `l` (NULL: none): the variant of its type and the
 * shadow filter, built on first use; one that does not build falls back to
 * the general program (logged once by the cache). */
static GLuint shade_program(PassShade *p, const PassDirect *d, const Scene *s, const Light *l)
{
    bool glossy = scene_has_glossy(s);
    GLuint general = glossy ? p->program_glossy : p->program;
    if (!l || d->general)
        return general;
    char defines[320];
    pass_direct_variant_defines(d, s, l, glossy ? GLOSSY_DEFINE : "", defines, sizeof defines);
    GLuint prog = program_cache_get(
        p->pc, &(ShaderProgramDesc){.label = "shade", .comp = "frame/shade.comp", .defines = defines});
    return prog ? prog : general;
}

void pass_shade_run(PassShade *p, const PassDirect *d, const LightStage *ls, const GBuffer *gb, const ShadeGi *gi,
                    ColorTarget *hdr, ColorTarget *ldr)
{
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_SHADOW, d->shadow_ubo);
    glBindTextureUnit(TEX_GB_SURFACE, gb->surface);
    glBindTextureUnit(TEX_GB_MATERIAL, gb->material);
    bool composite = gi && gi->irradiance;
    if (composite) {
        glBindTextureUnit(TEX_BRDF_ALBEDO, gi->brdf_albedo);
        glBindTextureUnit(TEX_GI, gi->irradiance);
        glBindTextureUnit(TEX_SPECULAR, gi->specular ? gi->specular : gi->irradiance);
    }
    glBindImageTexture(IMG_HDR, hdr->texture, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    if (ldr)
        glBindImageTexture(IMG_LDR, ldr->storage, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    /* No light: slot 0 of the light array is all zero, and the one
     * dispatch adds emission (and GI) alone. */
    int n = ls->light_count > 0 ? ls->light_count : 1;
    for (int i = 0; i < n; i++) {
        const Light *l = ls->light_count > 0 ? &ls->scene->lights[i] : NULL;
        GLuint prog = shade_program(p, d, ls->scene, l);
        bool last = i == n - 1;
        int steps = (i > 0 ? SHADE_ACCUMULATE : SHADE_EMISSION) | (l ? SHADE_LIGHT : 0) |
                    (last && composite ? SHADE_COMPOSITE : 0) | (last && ldr ? SHADE_TONEMAP : 0);
        glProgramUniform1i(prog, LOC_SHADE_STEPS, steps);
        glProgramUniform1i(prog, LOC_DIRECT_AREA_LIGHT, d->area_light);
        glProgramUniform1i(prog, LOC_COMPOSITE_SPECULAR, composite && gi->specular ? 1 : 0);
        light_stage_bind_shadow(ls, i);
        glUseProgram(prog);
        fullscreen_dispatch(hdr->width, hdr->height);
    }
    glUseProgram(0);
}
