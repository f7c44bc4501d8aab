/* targets.h — render targets the renderer owns and passes read or write.
 * All are (re)made only when the output size changes. */
#ifndef RTGI_TARGETS_H
#define RTGI_TARGETS_H

#include <epoxy/gl.h>
#include <stdbool.h>

typedef struct GBuffer {
    int width, height;
    GLuint fbo;
    GLuint surface;  /* RGBA32UI: world position, camera-facing normal, valid bit (shaders/common/gbuffer.glsl) */
    GLuint material; /* RGBA32UI: base colour, roughness, emission, metallic, specular weight (same file) */
    GLuint depth;    /* DEPTH32F */
} GBuffer;

typedef struct ColorTarget {
    int width, height;
    GLuint fbo;
    GLuint texture; /* what passes sample and the framebuffer holds (a display target's sRGB view) */
    GLuint storage; /* a display target's RGBA8 storage, which compute passes write; else 0 */
} ColorTarget;

/* An immutable texture (2D or cube) with nearest filtering and clamped
 * edges, labelled for debuggers. Caller deletes it. 0 after logging if the
 * size is over the driver's largest or the device could not allocate it. */
GLuint gl_texture_make(GLenum target, GLenum format, int width, int height, const char *label);
/* The same with `levels` mip levels (0: the full chain) and, for
 * GL_TEXTURE_2D_ARRAY, `layers` layers (else 1). */
GLuint gl_texture_make_levels(GLenum target, GLenum format, int width, int height, int layers, int levels,
                              const char *label);

/* Attaches `tex` to `fbo`: the whole 2D texture, or face `face` of a cube. */
void fbo_attach(GLuint fbo, GLenum attachment, GLuint tex, bool cube, int face);
/* Makes `*fbo` with `n` colour attachments (draw buffers 0..n-1; none: no
 * draw or read buffer) and an optional depth attachment (0: none), face 0
 * of cube textures; labelled and checked like fbo_check. */
bool fbo_make(GLuint *fbo, const GLuint *colors, int n, GLuint depth, bool cube, const char *label);
/* true if `fbo` is complete; else logs one line naming it and returns false. */
bool fbo_check(GLuint fbo, const char *label);

/* Runs the current compute program over a width × height image in
 * SHADE_GROUP² work groups (shared/gpu_types.h: shade, finish, fxaa) and
 * puts the barrier that makes its image stores visible to the next pass,
 * sampled, drawn or blitted. */
void fullscreen_dispatch(int width, int height);

/* The state of a pass that draws the scene into `fbo` (width × height):
 * its depth cleared to 1, bound, the viewport set, the depth test with
 * `depth_func`, no face culling, no blending (the G-buffer's passes). */
void scene_raster_begin(GLuint fbo, int width, int height, GLenum depth_func);

bool gbuffer_create(GBuffer *g, int width, int height);
void gbuffer_destroy(GBuffer *g);
bool color_target_create(ColorTarget *t, GLenum format, int width, int height, const char *label);
/* A display target: RGBA8 storage that compute passes write sRGB-encoded
 * bytes into (image stores take no sRGB format), and an SRGB8_ALPHA8 view
 * of it, the texture that passes sample (decoded to linear) and that the
 * framebuffer holds. */
bool display_target_create(ColorTarget *t, int width, int height, const char *label);
void color_target_destroy(ColorTarget *t);

#endif
