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
    GLuint program;        /* every material (alpha-masked ones discard holes) */
    GLuint program_opaque; /* opaque materials only: early depth */
    int culled; /* clusters outside the view in the last run */
} PassGbuffer;

/* Its program comes from `pc`. */
bool pass_gbuffer_create(PassGbuffer *p, ProgramCache *pc);
void pass_gbuffer_destroy(PassGbuffer *p);
/* With `cull`, clusters outside the camera's frustum are skipped and the
 * rest drawn nearest first; the image is the same either way. */
void pass_gbuffer_run(PassGbuffer *p, const GpuScene *gs, const Scene *s, const Camera *cam, bool cull, GBuffer *out);

#endif
