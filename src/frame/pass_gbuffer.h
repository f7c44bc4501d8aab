/* pass_gbuffer.h — G-buffer pass (deferred shading, Saito & Takahashi 1990).
 * A depth pre-pass first (no shading: alpha-masked materials only discard
 * their holes), then the G-buffer with the depth test at LEQUAL and depth
 * writes off, so each pixel is shaded once, by the surface it shows: on
 * llvmpipe the overdraw of Sponza's G-buffer (two trilinear texture fetches
 * and the packing per fragment) cost more than drawing the geometry twice
 * (1280×720: 208 -> 173 ms, min of 3 alternated; the Cornell box: the same
 * within noise; images identical).
 * Inputs: the scene's meshes and materials, the camera.
 * Output: the renderer's GBuffer (surface, material, depth).
 * Owns: nothing (its programs are the program cache's). */
#ifndef RTGI_PASS_GBUFFER_H
#define RTGI_PASS_GBUFFER_H

#include <stdbool.h>

#include "gpu/gpu_scene.h"
#include "gl/shader.h"
#include "gpu/targets.h"

typedef struct PassGbuffer {
    GLuint program;        /* every material (alpha-masked ones discard holes) */
    GLuint program_opaque; /* opaque materials only: early depth */
    GLuint program_untextured; /* opaque materials without textures: no texture code */
    GLuint depth_opaque;   /* pre-pass: opaque materials, no fragment work */
    GLuint depth_masked;   /* pre-pass: alpha-masked materials, discard only */
    int culled; /* clusters outside the view in the last run (of pass_vbuffer's, copied by
                   renderer_frame, where it filled the G-buffer) */
} PassGbuffer;

/* Its program comes from `pc`. */
bool pass_gbuffer_create(PassGbuffer *p, ProgramCache *pc);
void pass_gbuffer_destroy(PassGbuffer *p);
/* With `cull`, clusters outside the camera's frustum are skipped and the
 * rest drawn nearest first; the image is the same either way. */
void pass_gbuffer_run(PassGbuffer *p, const GpuScene *gs, const Scene *s, const Camera *cam, bool cull, GBuffer *out);
/* The depth pre-pass alone (forward shading's, pass_direct_forward): the
 * G-buffer's depth as pass_gbuffer_run leaves it; its colour targets are
 * left as they were (stale: nothing reads them in a forward frame). */
void pass_gbuffer_depth_run(PassGbuffer *p, const GpuScene *gs, const Scene *s, const Camera *cam, bool cull,
                            GBuffer *out);

#endif
