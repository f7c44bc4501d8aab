/* pass_fxaa.h — FXAA-class post-process anti-aliasing of the tone-mapped
 * image (Lottes 2009; shaders/frame/fxaa.frag describes the steps): for the
 * window, where supersampling costs too much. It works on display colours,
 * so measurements on radiance do not see it.
 * Input: the tone-mapped image (sRGB texture). Output: the final LDR target.
 * Owns: a sampler with bilinear filtering (its program is the program
 * cache's, its empty VAO the renderer's). */
#ifndef RTGI_PASS_FXAA_H
#define RTGI_PASS_FXAA_H

#include <stdbool.h>

#include "shader.h"
#include "targets.h"

typedef struct PassFxaa {
    GLuint program;
    GLuint sampler; /* linear, clamp to edge */
    GLuint vao;     /* borrowed empty vertex array */
} PassFxaa;

/* Its program comes from `pc`; `vao` is an empty vertex array (borrowed). */
bool pass_fxaa_create(PassFxaa *p, ProgramCache *pc, GLuint vao);
void pass_fxaa_destroy(PassFxaa *p);
/* Anti-aliases `in` into `out` (same size, both SRGB8_ALPHA8). */
void pass_fxaa_run(PassFxaa *p, const ColorTarget *in, ColorTarget *out);

#endif
