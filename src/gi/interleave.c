/* interleave.c — de-interleaving, reassembly and the geometry-aware blur. */
#include "gi/interleave.h"

#include <stdio.h>
#include <string.h>

#include "gi/gi.h"
#include "gl/gl_resources.h"
#include "gl/shader.h"
#include "shared/gpu_types.h"

void gi_interleave_defines(char *out, size_t size, const char *mode, int n, int m)
{
    snprintf(out, size, "%s\n#define INTERLEAVE_N %d\n#define INTERLEAVE_M %d\n", mode, n, m);
}

bool gi_interleave_create(GiInterleave *g, ProgramCache *pc, int n, int m, int w, int h, bool deinterleave)
{
    memset(g, 0, sizeof *g);
    g->n = n;
    g->m = m;
    g->width = w;
    g->height = h;
    g->sub_w = (w + n - 1) / n;
    g->sub_h = (h + m - 1) / m;
    g->di_w = g->sub_w * n;
    g->di_h = g->sub_h * m;
    /* The pattern is compiled in (gi/interleave.comp): constant divisors
     * and a blur window of a constant size. */
    char defs[4][128];
    static const char *const mode[4] = {"#define MODE_BLUR", "#define MODE_SPLIT", "#define MODE_MERGE",
                                        "#define MODE_BLUR\n#define DEINTERLEAVED_INPUT"};
    for (int k = 0; k < 4; k++)
        gi_interleave_defines(defs[k], sizeof defs[k], mode[k], n, m);
    g->blur = program_cache_get(pc, &(ShaderProgramDesc){.label = "interleave_blur", .comp = "gi/interleave.comp", .defines = defs[0]});
    if (!g->blur)
        return false;
    if (!deinterleave) /* shaded in place, then blurred from a copy */
        return (g->merged = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, w, h, "gi.merged")) != 0;
    g->split = program_cache_get(pc, &(ShaderProgramDesc){.label = "interleave_split", .comp = "gi/interleave.comp", .defines = defs[1]});
    g->merge = program_cache_get(pc, &(ShaderProgramDesc){.label = "interleave_merge", .comp = "gi/interleave.comp", .defines = defs[2]});
    g->merge_blur = program_cache_get(pc, &(ShaderProgramDesc){.label = "interleave_merge_blur", .comp = "gi/interleave.comp", .defines = defs[3]});
    g->di_surface = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32UI, g->di_w, g->di_h, "gi.di_surface");
    g->di_irradiance = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, g->di_w, g->di_h, "gi.di_irradiance");
    return g->split && g->merge && g->merge_blur && g->di_surface && g->di_irradiance; /* each logs its failure */
}

void gi_interleave_destroy(GiInterleave *g)
{
    GLuint t[3] = {g->di_surface, g->di_irradiance, g->merged};
    glDeleteTextures(3, t);
    memset(g, 0, sizeof *g);
}

uint64_t gi_interleave_bytes(const GiInterleave *g)
{
    const GLuint t[3] = {g->di_surface, g->di_irradiance, g->merged};
    return gl_textures_bytes(t, 3);
}

void gi_interleave_split(GiInterleave *g, const GBuffer *gb)
{
    glBindTextureUnit(TEX_GB_SURFACE, gb->surface);
    const GLuint zero[4] = {0, 0, 0, 0}; /* padding texels: no surface */
    glClearTexImage(g->di_surface, 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, zero);
    glBindImageTexture(IMG_OUT, g->di_surface, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
    glUseProgram(g->split);
    gi_dispatch_pixels(g->width, g->height);
}

void gi_interleave_merge(GiInterleave *g, const GBuffer *gb, bool blur, GLuint out)
{
    /* With the blur, one pass: it reads each neighbour's sub-image texel
     * (gi/interleave.comp, DEINTERLEAVED_INPUT). */
    if (blur)
        glBindTextureUnit(TEX_GB_SURFACE, gb->surface);
    glBindTextureUnit(TEX_INPUT, g->di_irradiance);
    glBindImageTexture(IMG_OUT, out, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glUseProgram(blur ? g->merge_blur : g->merge);
    gi_dispatch_pixels(g->width, g->height);
}

void gi_interleave_blur(GiInterleave *g, const GBuffer *gb, GLuint in, GLuint out)
{
    glBindTextureUnit(TEX_GB_SURFACE, gb->surface);
    glBindTextureUnit(TEX_INPUT, in);
    glBindImageTexture(IMG_OUT, out, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glUseProgram(g->blur);
    gi_dispatch_pixels(g->width, g->height);
}
