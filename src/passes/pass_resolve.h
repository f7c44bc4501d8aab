/* pass_resolve.h — the supersampling resolve: each output pixel is the mean
 * of its N×N block of the supersampled radiance (a box filter over the
 * pixel, the path tracer's pixel filter: it jitters uniformly within the
 * pixel; here the N² samples sit on a stratified grid at the sub-pixel
 * centres).
 * Input: the N× HDR radiance target. Output: the HDR radiance target.
 * Owns: nothing (its program is the program cache's, its empty VAO the
 * renderer's). */
#ifndef RTGI_PASS_RESOLVE_H
#define RTGI_PASS_RESOLVE_H

#include <stdbool.h>

#include "shader.h"
#include "targets.h"

typedef struct PassResolve {
    GLuint program;
    GLuint vao; /* borrowed empty vertex array */
} PassResolve;

/* Its program comes from `pc`; `vao` is an empty vertex array (borrowed). */
bool pass_resolve_create(PassResolve *p, ProgramCache *pc, GLuint vao);
void pass_resolve_destroy(PassResolve *p);
/* out(x, y) = mean of in over [N·x, N·x + N) × [N·y, N·y + N); `in` must be
 * N times `out`'s size. */
void pass_resolve_run(PassResolve *p, const ColorTarget *in, int n, ColorTarget *out);

#endif
