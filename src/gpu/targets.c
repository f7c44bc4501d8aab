#include "gpu/targets.h"

#include <stdio.h>

#include "gl/gl_resources.h"
#include "base/log.h"
#include "shared/gpu_types.h"

GLuint gl_texture_make(GLenum target, GLenum fmt, int w, int h, const char *label)
{
    return gl_texture_make_levels(target, fmt, w, h, 1, 1, label);
}

GLuint gl_texture_make_levels(GLenum target, GLenum fmt, int w, int h, int layers, int levels, const char *label)
{
    if (gl_make_refused("texture", label))
        return 0;
    GLint max_size = 0;
    glGetIntegerv(target == GL_TEXTURE_CUBE_MAP ? GL_MAX_CUBE_MAP_TEXTURE_SIZE : GL_MAX_TEXTURE_SIZE, &max_size);
    if (w < 1 || h < 1 || w > max_size || h > max_size) {
        log_error("gl", "texture %s: %dx%d is outside this driver's 1..%d", label, w, h, max_size);
        return 0;
    }
    if (levels == 0)
        levels = gl_mip_levels(w, h, 1);
    GLuint t;
    glCreateTextures(target, 1, &t);
    if (target == GL_TEXTURE_2D_ARRAY)
        glTextureStorage3D(t, levels, fmt, w, h, layers);
    else
        glTextureStorage2D(t, levels, fmt, w, h);
    GLint ok = GL_FALSE; /* storage that could not be made leaves the texture mutable */
    glGetTextureParameteriv(t, GL_TEXTURE_IMMUTABLE_FORMAT, &ok);
    if (!ok) {
        log_error("gl", "cannot allocate texture %s (%dx%d%s, %d levels, format 0x%x)", label, w, h,
                  target == GL_TEXTURE_CUBE_MAP ? " x 6 faces" : "", levels, fmt);
        glDeleteTextures(1, &t);
        return 0;
    }
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    glObjectLabel(GL_TEXTURE, t, -1, label);
    return t;
}

void fullscreen_dispatch(int width, int height)
{
    glDispatchCompute((GLuint)(width + SHADE_GROUP - 1) / SHADE_GROUP, (GLuint)(height + SHADE_GROUP - 1) / SHADE_GROUP,
                      1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT);
}

void fbo_attach(GLuint fbo, GLenum attachment, GLuint tex, bool cube, int face)
{
    if (cube)
        glNamedFramebufferTextureLayer(fbo, attachment, tex, 0, face);
    else
        glNamedFramebufferTexture(fbo, attachment, tex, 0);
}

bool fbo_check(GLuint fbo, const char *label)
{
    GLenum st = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    if (st != GL_FRAMEBUFFER_COMPLETE) {
        log_error("gl", "framebuffer %s incomplete (0x%x)", label, st);
        return false;
    }
    glObjectLabel(GL_FRAMEBUFFER, fbo, -1, label);
    return true;
}

bool fbo_make(GLuint *fbo, const GLuint *colors, int n, GLuint depth, bool cube, const char *label)
{
    if (gl_make_refused("framebuffer", label)) {
        *fbo = 0;
        return false;
    }
    GLenum bufs[8];
    glCreateFramebuffers(1, fbo);
    for (int i = 0; i < n && i < 8; i++) {
        bufs[i] = GL_COLOR_ATTACHMENT0 + (GLenum)i;
        fbo_attach(*fbo, bufs[i], colors[i], cube, 0);
    }
    if (n > 0) {
        glNamedFramebufferDrawBuffers(*fbo, n, bufs);
    } else {
        glNamedFramebufferDrawBuffer(*fbo, GL_NONE);
        glNamedFramebufferReadBuffer(*fbo, GL_NONE);
    }
    if (depth)
        fbo_attach(*fbo, GL_DEPTH_ATTACHMENT, depth, cube, 0);
    return fbo_check(*fbo, label);
}

void scene_raster_begin(GLuint fbo, int width, int height, GLenum depth_func)
{
    const float one = 1.f;
    glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &one);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(depth_func);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
}

bool gbuffer_create(GBuffer *g, int w, int h)
{
    g->width = w;
    g->height = h;
    g->surface = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32UI, w, h, "gbuffer.surface");
    g->material = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32UI, w, h, "gbuffer.material");
    g->depth = gl_texture_make(GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, w, h, "gbuffer.depth");
    const GLuint colors[2] = {g->surface, g->material};
    /* A texture that failed logged its line: no second about the framebuffer. */
    return g->surface && g->material && g->depth && fbo_make(&g->fbo, colors, 2, g->depth, false, "gbuffer");
}

void gbuffer_destroy(GBuffer *g)
{
    GLuint tex[3] = {g->surface, g->material, g->depth};
    glDeleteTextures(3, tex);
    glDeleteFramebuffers(1, &g->fbo);
    *g = (GBuffer){0};
}

bool color_target_create(ColorTarget *t, GLenum fmt, int w, int h, const char *label)
{
    t->width = w;
    t->height = h;
    t->texture = gl_texture_make(GL_TEXTURE_2D, fmt, w, h, label); /* logs a failure */
    return t->texture && fbo_make(&t->fbo, &t->texture, 1, 0, false, label);
}

bool display_target_create(ColorTarget *t, int w, int h, const char *label)
{
    t->width = w;
    t->height = h;
    t->storage = gl_texture_make(GL_TEXTURE_2D, GL_RGBA8, w, h, label); /* logs a failure */
    if (!t->storage)
        return false;
    glGenTextures(1, &t->texture); /* a view's name must not be bound before glTextureView */
    glTextureView(t->texture, GL_TEXTURE_2D, t->storage, GL_SRGB8_ALPHA8, 0, 1, 0, 1);
    char view[96];
    snprintf(view, sizeof view, "%s.srgb", label);
    glObjectLabel(GL_TEXTURE, t->texture, -1, view);
    glTextureParameteri(t->texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST); /* a view has its own sampling state */
    glTextureParameteri(t->texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(t->texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t->texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return fbo_make(&t->fbo, &t->texture, 1, 0, false, label);
}

void color_target_destroy(ColorTarget *t)
{
    glDeleteTextures(1, &t->storage);
    glDeleteTextures(1, &t->texture);
    glDeleteFramebuffers(1, &t->fbo);
    *t = (ColorTarget){0};
}
