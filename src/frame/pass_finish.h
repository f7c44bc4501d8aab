/* pass_finish.h — the frame's last steps on radiance, as compute
 * (shaders/frame/finish.comp): the supersampling resolve (box filter over
 * each pixel's N×N block, the reference's pixel filter) and the display
 * transform (radiance × exposure, clamp, sRGB encode). For the frames whose
 * shading could not tone-map as it shaded: forward frames of several
 * lights or with FXAA, and supersampled frames.
 * Input: radiance (the supersampled image, or the output-size one).
 * Outputs: the resolved radiance (supersampling) and the display target.
 * Owns: nothing (its program is the program cache's). */
#ifndef RTGI_PASS_FINISH_H
#define RTGI_PASS_FINISH_H

#include <stdbool.h>

#include "gl/shader.h"
#include "gpu/targets.h"

typedef struct PassFinish {
    GLuint program;
} PassFinish;

bool pass_finish_create(PassFinish *p, ProgramCache *pc);
void pass_finish_destroy(PassFinish *p);
/* Resolves `in` (factor × the output size) into `hdr` when factor > 1, and
 * tone-maps it into `ldr` (the output size). */
void pass_finish_run(PassFinish *p, const ColorTarget *in, int factor, ColorTarget *hdr, ColorTarget *ldr);

#endif
