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
    UBO_GI = 2,        /* GpuGiParams */
    SSBO_PATTERN = 0,  /* RSM sample pattern: vec4 per sample */
    SSBO_VPL = 1,      /* GpuVpl[] */
    SSBO_COUNTERS = 2, /* uint counters: [0] VPLs, [1] full-gather pixels, [2..] list */
    TEX_RSM_POSITION = 8,
    TEX_RSM_NORMAL = 9,
    TEX_RSM_FLUX = 10,
    TEX_GI = 11,       /* indirect irradiance */
    TEX_LOWRES = 12,   /* low-resolution indirect irradiance */
    IMG_OUT = 0,       /* image unit written by GI compute passes */
    UBO_VPL = 3,       /* GpuVplParams */
    SSBO_VPL_RANGE = 3,/* vec2 per VPL: α, culling range */
    SSBO_TILES = 4,    /* per-tile VPL counts and lists */
    SSBO_EVALS = 5,    /* VPL–pixel evaluations per work group */
    SSBO_SUBSETS = 6,  /* interleaved VPL subsets; metalight signatures */
    VPL_TILE = 16,     /* culling tile size in pixels */
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

/* Parameters of the RSM-based GI passes (std140). */
typedef struct GpuGiParams {
    float rsm[4];        /* x: r_max (map widths), y: samples N, z: weighting (0 paper ξ1², 1 unbiased), w: RSM resolution */
    float rsm2[4];       /* x: texels in the sampling disk K, y: cube (1/0), z: VPL count, w: indirect scale */
    float interp[4];     /* x: factor f, y: normal cos threshold, z: distance threshold (× view distance) */
    float interleave[4]; /* x: n, y: m, z: sub-image width, w: sub-image height */
    float camera[4];     /* xyz: camera position */
    int size[4];         /* x, y: full resolution; z, w: low resolution */
} GpuGiParams;
static_assert(sizeof(GpuGiParams) == 6 * 16, "GpuGiParams must match types.glsl (std140)");

/* One virtual point light (std430). */
typedef struct GpuVpl {
    float position_xi[4]; /* xyz: position; w: its fixed random ξ in (0,1] */
    float normal[4];      /* xyz: unit normal (lit side) */
    float flux[4];        /* rgb: reflected flux Φ (W) */
} GpuVpl;
static_assert(sizeof(GpuVpl) == 48, "GpuVpl must match types.glsl (std430)");

/* Parameters of the many-VPL passes (std140). */
typedef struct GpuVplParams {
    float slc[4];   /* x: e_max, y: exposure E, z: near clamp d² (0 = off), w: clamped range R */
    float misc[4];  /* x: keep fraction q, y: tile list capacity, z: K = n·m, w: subset length L */
    int tiles[4];   /* x, y: tile counts; z, w: interleave n, m */
    int samples[4]; /* x, y: metalight signature grid */
} GpuVplParams;
static_assert(sizeof(GpuVplParams) == 4 * 16, "GpuVplParams must match types.glsl (std140)");

#endif
