/* gpu_types.h — blocks shared between C and GLSL, defined once here and in
 * shaders/common/types.glsl, with their std140 sizes checked. A change here
 * is a change there. */
#ifndef RTGI_GPU_TYPES_H
#define RTGI_GPU_TYPES_H

#include <assert.h>

/* Fixed binding points of uniform blocks and textures. */
enum {
    UBO_LIGHT = 0,     /* GpuLight of the light being shaded */
    UBO_SHADOW = 1,    /* GpuShadowParams */
    TEX_ALBEDO = 0,    /* material texture while drawing the scene */
    TEX_SHADOW_2D = 1, /* shadow map of a directional/spot light */
    TEX_SHADOW_CUBE = 2,
    TEX_GB_POSITION = 3,
    TEX_GB_NORMAL = 4,
    TEX_GB_ALBEDO = 5,
    TEX_GB_EMISSION = 6,
    TEX_HDR = 7,
};

/* Uniform locations used by every program that draws the scene's meshes. */
enum {
    LOC_MATERIAL_ALBEDO = 0,   /* vec3 */
    LOC_MATERIAL_HAS_TEX = 1,  /* int */
    LOC_MATERIAL_CUTOFF = 2,   /* float; < 0: no alpha mask */
    LOC_MATERIAL_EMISSION = 3, /* vec3 */
    LOC_VIEW_PROJ = 4,         /* mat4 */
    LOC_EYE = 5,               /* vec3: camera or light position (for facing) */
};

/* One light as the shaders see it (std140). */
typedef struct GpuLight {
    float position_type[4];  /* xyz: position; w: LightType */
    float direction_width[4];/* xyz: unit direction; w: PCSS width (m), or tan of the sun's angular diameter */
    float color[4];          /* rgb: E (directional), I (spot, point), L·A (quad) */
    float spot[4];           /* x: cos outer, y: cos inner */
    float shadow_view_proj[16]; /* directional/spot: world → shadow clip space */
    float shadow_origin[4];  /* directional: point on the ortho near plane; others: light position */
    float shadow_info[4];    /* x: far (stored depth × far = metres), y: texel size k (world texel = k·d, ortho: k),
                                z: map resolution, w: 1 for a cube map */
} GpuLight;
static_assert(sizeof(GpuLight) == 10 * 16, "GpuLight must match types.glsl (std140)");

/* Shadow filtering parameters (std140). */
typedef struct GpuShadowParams {
    float bias[4];       /* x: constant (m), y: slope (texels·tanθ), z: normal offset (texels), w: mode */
    float filter[4];     /* x: PCF radius (texels), y: PCF samples, z: blocker samples, w: PCSS max radius */
    float poisson[64][4];/* xy: Poisson disk in the unit disk */
} GpuShadowParams;
static_assert(sizeof(GpuShadowParams) == 66 * 16, "GpuShadowParams must match types.glsl (std140)");

#endif
