/* pass_tonemap.h — tone mapping: radiance × exposure, clamp, sRGB encode
 * (through an SRGB8_ALPHA8 target).
 * Input: HDR radiance. Output: the LDR target. Owns: nothing (its program is the program
 * cache's, its empty VAO the renderer's). */
#ifndef RTGI_PASS_TONEMAP_H
#define RTGI_PASS_TONEMAP_H

#include <stdbool.h>

#include "shader.h"
#include "targets.h"

typedef struct PassTonemap {
    GLuint program;
    GLuint vao; /* borrowed empty vertex array */
} PassTonemap;

/* Its program comes from `pc`; `vao` is an empty vertex array (borrowed). */
bool pass_tonemap_create(PassTonemap *p, ProgramCache *pc, GLuint vao);
void pass_tonemap_destroy(PassTonemap *p);
void pass_tonemap_run(PassTonemap *p, const ColorTarget *hdr, float exposure, ColorTarget *ldr);

#endif
