/* pass_gbuffer.h — G-buffer pass (deferred shading, Saito & Takahashi 1990).
 * Inputs: the scene's meshes and materials, the camera.
 * Output: the renderer's GBuffer (position, normal, albedo, emission, depth).
 * Owns: nothing (its program is the program cache's). */
#ifndef RTGI_PASS_GBUFFER_H
#define RTGI_PASS_GBUFFER_H

#include <stdbool.h>

#include "gpu_scene.h"
#include "shader.h"
#include "targets.h"

typedef struct PassGbuffer {
    GLuint program;
} PassGbuffer;

/* Its program comes from `pc`. */
bool pass_gbuffer_create(PassGbuffer *p, ProgramCache *pc);
void pass_gbuffer_destroy(PassGbuffer *p);
void pass_gbuffer_run(PassGbuffer *p, const GpuScene *gs, const Scene *s, const Camera *cam, GBuffer *out);

#endif
