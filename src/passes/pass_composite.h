/* pass_composite.h — adds the GI technique's result to the HDR target:
 * ρ/π · E · indirect_scale from its irradiance image, plus its specular
 * radiance image (× indirect_scale) when it has one.
 * Inputs: GBuffer albedo, the irradiance (and specular) image, UBO_FRAME.
 * Output: HDR target (additive). Owns: nothing (its program is the program
 * cache's, its empty VAO the renderer's). */
#ifndef RTGI_PASS_COMPOSITE_H
#define RTGI_PASS_COMPOSITE_H

#include <stdbool.h>

#include "shader.h"
#include "targets.h"

typedef struct PassComposite {
    GLuint program;
    GLuint vao; /* borrowed empty vertex array */
} PassComposite;

/* Its program comes from `pc`; `vao` is an empty vertex array (borrowed). */
bool pass_composite_create(PassComposite *p, ProgramCache *pc, GLuint vao);
void pass_composite_destroy(PassComposite *p);
/* `specular` may be 0 (the technique has none). */
void pass_composite_run(PassComposite *p, const GBuffer *gb, GLuint irradiance, GLuint specular, ColorTarget *hdr);

#endif
