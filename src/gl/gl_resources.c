#include "gl/gl_resources.h"

#include "base/log.h"

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

int gl_mip_levels(int w, int h, int d)
{
    int m = w > h ? w : h;
    m = m > d ? m : d;
    int levels = 1;
    while (m > 1) {
        m >>= 1;
        levels++;
    }
    return levels;
}

GLuint gl_texture3d_make(GLenum format, int w, int h, int d, int levels, TexFilter filter, const char *label)
{
    if (gl_make_refused("3D texture", label))
        return 0;
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max_size);
    if (w < 1 || h < 1 || d < 1 || w > max_size || h > max_size || d > max_size) {
        log_error("gl", "3D texture %s: size %d, %d, %d outside 1..%d", label, w, h, d, max_size);
        return 0;
    }
    int full = gl_mip_levels(w, h, d);
    if (levels == 0)
        levels = full;
    if (levels < 0 || levels > full) {
        log_error("gl", "3D texture %s: %d mip levels asked, %dx%dx%d has 1..%d", label, levels, w, h, d, full);
        return 0;
    }
    GLuint t;
    glCreateTextures(GL_TEXTURE_3D, 1, &t);
    glTextureStorage3D(t, levels, format, w, h, d);
    /* A failed glTextureStorage3D (unsized or unknown format, out of
     * memory) leaves the texture mutable: check that instead of glGetError,
     * which would also swallow other code's errors. */
    GLint immutable = GL_FALSE;
    glGetTextureParameteriv(t, GL_TEXTURE_IMMUTABLE_FORMAT, &immutable);
    if (!immutable) {
        log_error("gl", "3D texture %s: no storage for format 0x%x at %dx%dx%d, %d levels", label, format, w, h,
                  d, levels);
        glDeleteTextures(1, &t);
        return 0;
    }
    bool linear = filter == TEX_FILTER_LINEAR;
    GLenum min = levels > 1 ? (linear ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST_MIPMAP_NEAREST)
                            : (linear ? GL_LINEAR : GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, (GLint)min);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, linear ? GL_LINEAR : GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    glTextureParameteri(t, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_BORDER);
    const float border[4] = {0.f, 0.f, 0.f, 0.f};
    glTextureParameterfv(t, GL_TEXTURE_BORDER_COLOR, border);
    glObjectLabel(GL_TEXTURE, t, -1, label);
    return t;
}

void gl_texture3d_destroy(GLuint *tex)
{
    if (*tex)
        glDeleteTextures(1, tex);
    *tex = 0;
}

static long g_fail_countdown = -1; /* makes until the armed failure; 0: none armed */
static bool g_fail_fired;

bool gl_make_fail_at(long k)
{
    bool fired = g_fail_fired;
    g_fail_countdown = k > 0 ? k : 0;
    g_fail_fired = false;
    return fired;
}

bool gl_make_refused(const char *what, const char *label)
{
    if (g_fail_countdown < 0) { /* first make: the environment may arm it */
        const char *env = getenv("RTGI_FAIL_GL_MAKE");
        g_fail_countdown = env ? strtol(env, NULL, 10) : 0;
        if (g_fail_countdown < 0)
            g_fail_countdown = 0;
    }
    if (g_fail_countdown == 0 || --g_fail_countdown > 0)
        return false;
    g_fail_fired = true;
    log_error("gl", "%s %s: refused (fault injection)", what, label);
    return true;
}

GLuint gl_buffer_make(uint64_t bytes, const void *data, GLbitfield flags, const char *label)
{
    if (gl_make_refused("buffer", label))
        return 0;
    if (bytes < 1 || bytes > (uint64_t)PTRDIFF_MAX) {
        log_error("gl", "buffer %s: size %llu bytes outside 1..%lld", label, (unsigned long long)bytes,
                  (long long)PTRDIFF_MAX);
        return 0;
    }
    GLuint b;
    glCreateBuffers(1, &b);
    glNamedBufferStorage(b, (GLsizeiptr)bytes, data, flags);
    /* As for textures, the object is asked rather than glGetError, which
     * would also swallow other code's errors: a failed store leaves it
     * mutable or of size 0 (Mesa marks it immutable first). */
    GLint immutable = GL_FALSE;
    GLint64 size = 0;
    glGetNamedBufferParameteriv(b, GL_BUFFER_IMMUTABLE_STORAGE, &immutable);
    glGetNamedBufferParameteri64v(b, GL_BUFFER_SIZE, &size);
    if (!immutable || size != (GLint64)bytes) {
        log_error("gl", "buffer %s: no store of %llu MiB (out of GPU memory?)", label,
                  (unsigned long long)((bytes + (1u << 20) - 1) >> 20));
        glDeleteBuffers(1, &b);
        return 0;
    }
    glObjectLabel(GL_BUFFER, b, -1, label);
    return b;
}

void gl_texture_level_size(GLuint tex, int level, int size[3])
{
    glGetTextureLevelParameteriv(tex, level, GL_TEXTURE_WIDTH, &size[0]);
    glGetTextureLevelParameteriv(tex, level, GL_TEXTURE_HEIGHT, &size[1]);
    glGetTextureLevelParameteriv(tex, level, GL_TEXTURE_DEPTH, &size[2]);
}

void gl_texture3d_bind_image(GLuint unit, GLuint tex, int level, GLenum access, GLenum format)
{
    glBindImageTexture(unit, tex, level, GL_TRUE, 0, access, format);
}

void gl_texture_generate_mips(GLuint tex)
{
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glGenerateTextureMipmap(tex);
}

void gl_texture3d_build_mips(GLuint tex, GLuint program, GLenum format, int local_size)
{
    GLint levels = 1;
    glGetTextureParameteriv(tex, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
    glUseProgram(program);
    for (int l = 1; l < levels; l++) {
        int s[3];
        gl_texture_level_size(tex, l, s);
        gl_texture3d_bind_image(0, tex, l - 1, GL_READ_ONLY, format);
        gl_texture3d_bind_image(1, tex, l, GL_WRITE_ONLY, format);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        glDispatchCompute((GLuint)((s[0] + local_size - 1) / local_size),
                          (GLuint)((s[1] + local_size - 1) / local_size),
                          (GLuint)((s[2] + local_size - 1) / local_size));
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

GLuint gl_fbo_empty_make(int w, int h, int layers, int samples, const char *label)
{
    if (gl_make_refused("framebuffer", label))
        return 0;
    GLint max_w = 0, max_h = 0, max_layers = 0, max_samples = 0;
    glGetIntegerv(GL_MAX_FRAMEBUFFER_WIDTH, &max_w);
    glGetIntegerv(GL_MAX_FRAMEBUFFER_HEIGHT, &max_h);
    glGetIntegerv(GL_MAX_FRAMEBUFFER_LAYERS, &max_layers);
    glGetIntegerv(GL_MAX_FRAMEBUFFER_SAMPLES, &max_samples);
    if (w < 1 || h < 1 || w > max_w || h > max_h || layers < 0 || layers > max_layers || samples < 0 ||
        samples > max_samples) {
        log_error("gl",
                  "empty framebuffer %s: width %d, height %d, %d layers, %d samples outside the limits "
                  "(1..%d, 1..%d, 0..%d, 0..%d)",
                  label, w, h, layers, samples, max_w, max_h, max_layers, max_samples);
        return 0;
    }
    GLuint fbo;
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferParameteri(fbo, GL_FRAMEBUFFER_DEFAULT_WIDTH, w);
    glNamedFramebufferParameteri(fbo, GL_FRAMEBUFFER_DEFAULT_HEIGHT, h);
    glNamedFramebufferParameteri(fbo, GL_FRAMEBUFFER_DEFAULT_LAYERS, layers);
    glNamedFramebufferParameteri(fbo, GL_FRAMEBUFFER_DEFAULT_SAMPLES, samples);
    GLenum st = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    if (st != GL_FRAMEBUFFER_COMPLETE) {
        log_error("gl", "empty framebuffer %s incomplete (0x%x)", label, st);
        glDeleteFramebuffers(1, &fbo);
        return 0;
    }
    glObjectLabel(GL_FRAMEBUFFER, fbo, -1, label);
    return fbo;
}

void gl_fbo_destroy(GLuint *fbo)
{
    if (*fbo)
        glDeleteFramebuffers(1, fbo);
    *fbo = 0;
}

uint64_t gl_texture_bytes(GLuint tex)
{
    if (!tex)
        return 0;
    GLint target = 0, levels = 0;
    glGetTextureParameteriv(tex, GL_TEXTURE_TARGET, &target);
    glGetTextureParameteriv(tex, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
    if (levels <= 0)
        levels = 1; /* mutable: what level 0 holds (rtgi makes none) */
    static const GLenum bits[] = {GL_TEXTURE_RED_SIZE,   GL_TEXTURE_GREEN_SIZE, GL_TEXTURE_BLUE_SIZE,
                                  GL_TEXTURE_ALPHA_SIZE, GL_TEXTURE_DEPTH_SIZE, GL_TEXTURE_STENCIL_SIZE,
                                  GL_TEXTURE_SHARED_SIZE};
    uint64_t total = 0;
    for (GLint l = 0; l < levels; l++) {
        GLint w = 0, h = 0, d = 0, b = 0;
        glGetTextureLevelParameteriv(tex, l, GL_TEXTURE_WIDTH, &w);
        glGetTextureLevelParameteriv(tex, l, GL_TEXTURE_HEIGHT, &h);
        glGetTextureLevelParameteriv(tex, l, GL_TEXTURE_DEPTH, &d);
        for (size_t k = 0; k < sizeof bits / sizeof bits[0]; k++) {
            GLint n = 0;
            glGetTextureLevelParameteriv(tex, l, bits[k], &n);
            b += n;
        }
        uint64_t texels = (uint64_t)(w > 0 ? w : 0) * (uint64_t)(h > 0 ? h : 1) * (uint64_t)(d > 0 ? d : 1);
        total += texels * (uint64_t)b / 8u * (target == GL_TEXTURE_CUBE_MAP ? 6u : 1u);
    }
    return total;
}

uint64_t gl_buffer_bytes(GLuint buf)
{
    GLint64 size = 0;
    if (buf)
        glGetNamedBufferParameteri64v(buf, GL_BUFFER_SIZE, &size);
    return size > 0 ? (uint64_t)size : 0;
}

uint64_t gl_textures_bytes(const GLuint *tex, int n)
{
    uint64_t total = 0;
    for (int i = 0; i < n; i++)
        total += gl_texture_bytes(tex[i]);
    return total;
}

uint64_t gl_buffers_bytes(const GLuint *buf, int n)
{
    uint64_t total = 0;
    for (int i = 0; i < n; i++)
        total += gl_buffer_bytes(buf[i]);
    return total;
}

GlObjectCounts gl_count_live_objects(GLuint max_name)
{
    GlObjectCounts c = {0};
    for (GLuint n = 1; n <= max_name; n++) {
        c.textures += glIsTexture(n) == GL_TRUE;
        c.buffers += glIsBuffer(n) == GL_TRUE;
        c.framebuffers += glIsFramebuffer(n) == GL_TRUE;
        c.renderbuffers += glIsRenderbuffer(n) == GL_TRUE;
        c.programs += glIsProgram(n) == GL_TRUE;
        c.shaders += glIsShader(n) == GL_TRUE;
        c.vertex_arrays += glIsVertexArray(n) == GL_TRUE;
        c.queries += glIsQuery(n) == GL_TRUE;
        c.samplers += glIsSampler(n) == GL_TRUE;
    }
    return c;
}

int gl_object_counts_total(const GlObjectCounts *c)
{
    return c->textures + c->buffers + c->framebuffers + c->renderbuffers + c->programs + c->shaders +
           c->vertex_arrays + c->queries + c->samplers;
}
