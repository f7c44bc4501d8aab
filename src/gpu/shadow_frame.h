/* shadow_frame.h — a light's shadow projection, the notes' CalcLightMVP:
 * model = T·R·S (the scene is in world space, so identity), view = inverse
 * of the light's frame (look-at), projection orthographic (directional,
 * fitted to the scene's bounding sphere) or perspective (spot: the cone;
 * point and quad: six 90° cube faces; a point light far outside the scene:
 * one map fitted to the scene's bounding sphere). Pure CPU maths, no GL. */
#ifndef RTGI_SHADOW_FRAME_H
#define RTGI_SHADOW_FRAME_H

#include <cglm/cglm.h>
#include <stdbool.h>

#include "shared/gpu_types.h"
#include "core/scene.h"

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

/* Whether point light l lies so far outside the scene's bounding sphere
 * (radius r at distance d ≥ 2r: it subtends at most 30°) that one
 * perspective map fitted to the sphere sees all of the scene, with finer
 * texels there than a cube face's (2·tan(≤ 31.5°) = 1.23 against 2 per
 * texel at distance 1); a cube map's 90° faces would spread the scene over a
 * few texels once the light is far away (a light 170 m from the Cornell box:
 * 0.33 m per texel of a 1024² face, light through every wall). */
bool shadow_frame_point_fitted(const Light *l, const vec3 bounds_min, const vec3 bounds_max);
/* Whether light l's maps are cube maps: point lights (unless fitted) and
 * quad lights. */
bool shadow_frame_is_cube(const Light *l, const vec3 bounds_min, const vec3 bounds_max);

/* The frame of light l's map at `resolution` texels per side. Directional
 * and fitted point maps fit the scene's bounding sphere with a margin (1% of
 * the radius, 5% of the angle), and at least `margin_texels` texels (shadow
 * maps: 2, see light_stage.c shadow_face). */
void shadow_frame_compute(const Light *l, const vec3 bounds_min, const vec3 bounds_max, int resolution,
                          int margin_texels, ShadowFrame *out);
/* The unit direction face `face` looks along (the spot's or fitted map's
 * axis, a cube face's): its view matrix's −z row. */
void shadow_frame_axis(const ShadowFrame *f, int face, vec3 axis);
/* Maps a world point through face 0 to shadow-map coordinates (u, v in
 * [0,1], depth = stored distance / far). */
void shadow_frame_project(const ShadowFrame *f, const Light *l, const vec3 world, vec3 out_uvd);
/* Fills the light block the shaders read; a fitted point light's direction
 * there is its map's axis (its light is the same in every direction). */
void shadow_frame_to_gpu(const Light *l, const ShadowFrame *f, int resolution, GpuLight *out);

#endif
