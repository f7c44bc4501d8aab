/* pass_composite.h — adds indirect radiance ρ/π · E · scale to the HDR
 * target. Inputs: GBuffer albedo, an irradiance texture, UBO_GI (scale).
 * Output: HDR target (additive). Owns: its program. */
#ifndef RTGI_PASS_COMPOSITE_H
#define RTGI_PASS_COMPOSITE_H

#include <stdbool.h>

#include "targets.h"

typedef struct PassComposite {
    GLuint program;
    GLuint vao;
} PassComposite;

bool pass_composite_create(PassComposite *p);
void pass_composite_destroy(PassComposite *p);
void pass_composite_run(PassComposite *p, const GBuffer *gb, GLuint irradiance, ColorTarget *hdr);

#endif
