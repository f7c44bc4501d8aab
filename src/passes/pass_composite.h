/* pass_composite.h — adds the GI technique's result to the HDR target:
 * what each surface returns of the irradiance E in its image (ρ_d/π · E on
 * Lambertian surfaces; on glossy ones, for light arriving evenly, the
 * diffuse lobe's share and, where the technique has no specular image,
 * the GGX lobe's directional albedo × E/π: frame/composite.frag), plus its
 * specular radiance image when it has one; all × indirect_scale. Scenes
 * without glossy materials use a program without the glossy terms.
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
void pass_composite_run(PassComposite *p, const GBuffer *gb, GLuint irradiance, GLuint specular, GLuint brdf_albedo,
                        bool glossy, ColorTarget *hdr);

#endif
