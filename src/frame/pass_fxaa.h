/* pass_fxaa.h — FXAA-class post-process anti-aliasing of the tone-mapped
 * image (Lottes 2009; shaders/frame/fxaa.comp describes the steps), as
 * compute: for the window, where supersampling costs too much. It works on
 * display colours, so measurements on radiance do not see it.
 * Input: the tone-mapped image (a display target, read through its sRGB
 * view). Output: the final display target.
 * Owns: a sampler with bilinear filtering (its program is the program
 * cache's). */
#ifndef RTGI_PASS_FXAA_H
#define RTGI_PASS_FXAA_H

#include <stdbool.h>

#include "gl/shader.h"
#include "gpu/targets.h"

typedef struct PassFxaa {
    GLuint program;
    GLuint sampler; /* linear, clamp to edge */
} PassFxaa;

bool pass_fxaa_create(PassFxaa *p, ProgramCache *pc);
void pass_fxaa_destroy(PassFxaa *p);
/* Anti-aliases `in` into `out` (same size, both display targets). */
void pass_fxaa_run(PassFxaa *p, const ColorTarget *in, ColorTarget *out);

#endif
