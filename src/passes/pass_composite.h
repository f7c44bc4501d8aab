/* pass_composite.h — adds the GI technique's result to the HDR target:
 * ρ/π · E · w · indirect_scale from its irradiance image, plus its specular
 * radiance image (× indirect_scale) when it has one. w is the diffuse
 * lobe's Fresnel transmission for irradiance (brdf_diffuse_irradiance_weight),
 * 1 on Lambertian surfaces: scenes without glossy materials use a program
 * without it.
 * Inputs: GBuffer (material; glossy: also surface), the irradiance (and
 * specular) image, UBO_FRAME.
 * Output: HDR target (additive). Owns: nothing (its program is the program
 * cache's, its empty VAO the renderer's). */
#ifndef RTGI_PASS_COMPOSITE_H
#define RTGI_PASS_COMPOSITE_H

#include <stdbool.h>

#include "shader.h"
#include "targets.h"

typedef struct PassComposite {
    GLuint program;        /* Lambertian surfaces */
    GLuint program_glossy; /* with the diffuse lobe's Fresnel weight */
    GLuint vao; /* borrowed empty vertex array */
} PassComposite;

/* Its program comes from `pc`; `vao` is an empty vertex array (borrowed). */
bool pass_composite_create(PassComposite *p, ProgramCache *pc, GLuint vao);
void pass_composite_destroy(PassComposite *p);
/* `specular` may be 0 (the technique has none); `glossy`: the scene has a
 * material with F0 > 0 (scene_has_glossy). */
void pass_composite_run(PassComposite *p, const GBuffer *gb, GLuint irradiance, GLuint specular, bool glossy,
                        ColorTarget *hdr);

#endif
