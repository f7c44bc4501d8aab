#include "frame/pass_temporal.h"

#include <string.h>

#include "core/camera.h"
#include "gi/gi.h"
#include "gl/gl_resources.h"
#include "base/log.h"
#include "shared/gpu_types.h"

void pass_temporal_create(PassTemporal *p, ProgramCache *pc)
{
    memset(p, 0, sizeof *p);
    p->programs = pc;
}

static void free_images(PassTemporal *p)
{
    GLuint t[3] = {p->history[0], p->history[1], p->prev_surface};
    glDeleteTextures(3, t);
    p->history[0] = p->history[1] = p->prev_surface = 0;
    p->width = p->height = 0;
    p->have_history = false;
}

void pass_temporal_destroy(PassTemporal *p)
{
    free_images(p);
    memset(p, 0, sizeof *p);
}

void pass_temporal_reset(PassTemporal *p) { p->have_history = false; }

/* Its images at w×h; false after logging (none left then). */
static bool make_images(PassTemporal *p, int w, int h)
{
    free_images(p);
    p->history[0] = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, w, h, "temporal.history0");
    p->history[1] = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, w, h, "temporal.history1");
    p->prev_surface = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32UI, w, h, "temporal.prev_surface");
    if (!p->history[0] || !p->history[1] || !p->prev_surface) { /* logged */
        free_images(p);
        return false;
    }
    p->width = w;
    p->height = h;
    return true;
}

GLuint pass_temporal_run(PassTemporal *p, const GBuffer *gb, GLuint irradiance, const Camera *cam, bool clamp)
{
    if (!p->program)
        p->program = program_cache_get(p->programs, &(ShaderProgramDesc){.label = "temporal_accumulate",
                                                                           .comp = "temporal/accumulate.comp"});
    if (!p->program) /* logged by the cache */
        return 0;
    if ((p->width != gb->width || p->height != gb->height) && !make_images(p, gb->width, gb->height))
        return 0;
    int next = 1 - p->current;
    mat4 vp;
    camera_view_proj(cam, (float)gb->width / (float)gb->height, vp);
    glProgramUniformMatrix4fv(p->program, LOC_TEMPORAL_PREV_VIEW_PROJ, 1, GL_FALSE, (const float *)p->prev_view_proj);
    glProgramUniform4f(p->program, LOC_TEMPORAL_PARAMS, TEMPORAL_ALPHA, p->have_history ? 1.f : 0.f,
                       TEMPORAL_PLANE_TOLERANCE, clamp ? TEMPORAL_CLAMP_GAMMA : 0.f);
    glUseProgram(p->program);
    glBindTextureUnit(TEX_GB_SURFACE, gb->surface);
    glBindTextureUnit(TEX_GI, irradiance);
    glBindTextureUnit(TEX_TEMPORAL_HISTORY, p->history[p->current]);
    glBindTextureUnit(TEX_TEMPORAL_SURFACE, p->prev_surface);
    glBindImageTexture(IMG_OUT, p->history[next], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    gi_dispatch_pixels(gb->width, gb->height);
    /* This frame's surface and camera are the next one's history. */
    glCopyImageSubData(gb->surface, GL_TEXTURE_2D, 0, 0, 0, 0, p->prev_surface, GL_TEXTURE_2D, 0, 0, 0, 0,
                       gb->width, gb->height, 1);
    glm_mat4_copy(vp, p->prev_view_proj);
    p->current = next;
    p->have_history = true;
    return p->history[next];
}

uint64_t pass_temporal_bytes(const PassTemporal *p)
{
    const GLuint t[3] = {p->history[0], p->history[1], p->prev_surface};
    return gl_textures_bytes(t, 3);
}
