/* pass_tonemap.h — tone mapping: radiance × exposure, clamp, sRGB encode
 * (through an SRGB8_ALPHA8 target).
 * Input: HDR radiance. Output: the LDR target. Owns: its program. */
#ifndef RTGI_PASS_TONEMAP_H
#define RTGI_PASS_TONEMAP_H

#include <stdbool.h>

#include "targets.h"

typedef struct PassTonemap {
    GLuint program;
    GLuint vao;
} PassTonemap;

bool pass_tonemap_create(PassTonemap *p);
void pass_tonemap_destroy(PassTonemap *p);
void pass_tonemap_run(PassTonemap *p, const ColorTarget *hdr, float exposure, ColorTarget *ldr);

#endif
