/* pass_rsm.h — reflective shadow map pass (Dachsbacher & Stamminger 2005).
 * Inputs: the scene's meshes (emitters skipped), one light.
 * Output: an RsmMap — world position, normal (lit side) and reflected flux
 * per texel, plus depth; 2D for directional/spot lights, a cube for point
 * and quad lights — with 2D-array views of it for compute passes.
 * Owns: its program. The RsmMap owns its textures. */
#ifndef RTGI_PASS_RSM_H
#define RTGI_PASS_RSM_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "gpu_scene.h"
#include "gpu_types.h"
#include "shadow_frame.h"

typedef struct RsmMap {
    int size;              /* texels per side (per face) */
    bool cube;
    GLuint position;       /* RGBA32F: xyz, w = 1 where a surface */
    GLuint normal;         /* RGBA16F */
    GLuint flux;           /* RGBA32F: Φ in W */
    GLuint depth;          /* DEPTH32F */
    GLuint view[3];        /* 2D-array views of position, normal, flux */
    GLuint fbo;
    ShadowFrame frame;     /* projection of the last run */
    GpuLight gpu;          /* light block for the gather shaders */
} RsmMap;

typedef struct PassRsm {
    GLuint program;
    GLuint light_ubo;
} PassRsm;

bool pass_rsm_create(PassRsm *p);
void pass_rsm_destroy(PassRsm *p);
bool rsm_map_create(RsmMap *m, bool cube, int size);
void rsm_map_destroy(RsmMap *m);
void pass_rsm_run(PassRsm *p, RsmMap *m, const GpuScene *gs, const Scene *s, const Light *l);
/* Binds the map for sampling (TEX_RSM_*) and its light block (UBO_LIGHT). */
void rsm_map_bind(const RsmMap *m, GLuint light_ubo);
/* Binds the 2D-array views to TEX_RSM_* (for VPL extraction). */
void rsm_map_bind_views(const RsmMap *m);

#endif
