/* targets.h — render targets the renderer owns and passes read or write.
 * All are (re)made only when the output size changes. */
#ifndef RTGI_TARGETS_H
#define RTGI_TARGETS_H

#include <epoxy/gl.h>
#include <stdbool.h>

typedef struct GBuffer {
    int width, height;
    GLuint fbo;
    GLuint position; /* RGBA32F: world xyz, w = 1 where geometry */
    GLuint normal;   /* RGBA16F: unit normal facing the camera */
    GLuint albedo;   /* RGBA16F: linear albedo */
    GLuint emission; /* RGBA16F: emitted radiance */
    GLuint depth;    /* DEPTH32F */
} GBuffer;

typedef struct ColorTarget {
    int width, height;
    GLuint fbo;
    GLuint texture;
} ColorTarget;

bool gbuffer_create(GBuffer *g, int width, int height);
void gbuffer_destroy(GBuffer *g);
bool color_target_create(ColorTarget *t, GLenum format, int width, int height, const char *label);
void color_target_destroy(ColorTarget *t);

#endif
