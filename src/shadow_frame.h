/* shadow_frame.h — a light's shadow projection, the notes' CalcLightMVP:
 * model = T·R·S (the scene is in world space, so identity), view = inverse
 * of the light's frame (look-at), projection orthographic (directional,
 * fitted to the scene's bounding sphere) or perspective (spot: the cone;
 * point and quad: six 90° cube faces). Pure CPU maths, no GL. */
#ifndef RTGI_SHADOW_FRAME_H
#define RTGI_SHADOW_FRAME_H

#include <cglm/cglm.h>
#include <stdbool.h>

#include "shared/gpu_types.h"
#include "scene.h"

typedef struct ShadowFrame {
    int face_count;      /* 1 (2D map) or 6 (cube map) */
    mat4 view[6];        /* world → light view */
    mat4 proj[6];        /* light view → clip */
    mat4 view_proj[6];
    vec3 origin;         /* directional: centre of the ortho near plane; others: light position */
    float far;           /* stored depth × far = metres */
    float texel_k;       /* world size of a texel: k·d (perspective, cube) or k (ortho) */
    bool cube, ortho;
} ShadowFrame;

/* The frame of light l's map at `resolution` texels per side. Directional
 * maps fit the scene's bounding sphere with a 1% margin, and at least
 * `margin_texels` texels (shadow maps: 2, see light_stage.c shadow_face). */
void shadow_frame_compute(const Light *l, const vec3 bounds_min, const vec3 bounds_max, int resolution,
                          int margin_texels, ShadowFrame *out);
/* Maps a world point through face 0 to shadow-map coordinates (u, v in
 * [0,1], depth = stored distance / far). */
void shadow_frame_project(const ShadowFrame *f, const Light *l, const vec3 world, vec3 out_uvd);
/* Fills the light block the shaders read. */
void shadow_frame_to_gpu(const Light *l, const ShadowFrame *f, int resolution, GpuLight *out);

#endif
