/* pass_shadow.h — shadow-map pass (Williams 1978; bias, PCF and PCSS are
 * applied where the map is read, in shaders/common/shadow.glsl).
 * Inputs: the scene's meshes (emitters skipped), one light.
 * Output: a ShadowMap — 2D depth for directional/spot lights, a depth cube
 * map for point and quad lights — holding distance to the light / far.
 * Owns: its program and a 1-texel dummy of each kind, bound in place of the
 * map type a light does not use. */
#ifndef RTGI_PASS_SHADOW_H
#define RTGI_PASS_SHADOW_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "gpu_scene.h"
#include "gpu_types.h"
#include "shadow_frame.h"

typedef struct ShadowMap {
    int size;        /* texels per side (per cube face) */
    bool cube;
    GLuint texture;  /* DEPTH32F 2D or cube */
    GLuint fbo;
    ShadowFrame frame; /* projection of the last run */
    GpuLight gpu;      /* light block for the shaders, with the frame filled in */
} ShadowMap;

typedef struct PassShadow {
    GLuint program;
    GLuint light_ubo;  /* GpuLight of the light being rendered */
    GLuint dummy_2d, dummy_cube;
} PassShadow;

bool pass_shadow_create(PassShadow *p);
void pass_shadow_destroy(PassShadow *p);

bool shadow_map_create(ShadowMap *m, bool cube, int size);
void shadow_map_destroy(ShadowMap *m);

/* Computes light `l`'s projection for a `size`² map over scene `s`, fills
 * the shaders' light block from it, uploads that to `ubo` and binds it to
 * UBO_LIGHT. Shared by the shadow and RSM passes. */
void light_frame_bind(const Light *l, const Scene *s, int size, GLuint ubo, ShadowFrame *frame, GpuLight *gpu);

/* Renders light `l` of scene `s` into `m`. */
void pass_shadow_run(PassShadow *p, ShadowMap *m, const GpuScene *gs, const Scene *s, const Light *l);
/* Binds `m` (and a dummy for the other map type) to TEX_SHADOW_2D/CUBE. */
void pass_shadow_bind(const PassShadow *p, const ShadowMap *m);

#endif
