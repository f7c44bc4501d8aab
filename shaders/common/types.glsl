// types.glsl — blocks shared with C (src/gpu_types.h). Keep in sync.
#define LIGHT_DIRECTIONAL 0
#define LIGHT_SPOT 1
#define LIGHT_POINT 2
#define LIGHT_QUAD 3

#define UBO_LIGHT 0
#define UBO_SHADOW 1
#define TEX_ALBEDO 0
#define TEX_SHADOW_2D 1
#define TEX_SHADOW_CUBE 2
#define TEX_GB_POSITION 3
#define TEX_GB_NORMAL 4
#define TEX_GB_ALBEDO 5
#define TEX_GB_EMISSION 6
#define TEX_HDR 7

#define LOC_MATERIAL_ALBEDO 0
#define LOC_MATERIAL_HAS_TEX 1
#define LOC_MATERIAL_CUTOFF 2
#define LOC_MATERIAL_EMISSION 3
#define LOC_VIEW_PROJ 4
#define LOC_EYE 5

struct GpuLight {
    vec4 position_type;   // xyz position, w type
    vec4 direction_width; // xyz direction, w PCSS width
    vec4 color;           // E / I / L·A
    vec4 spot;            // x cos outer, y cos inner
    mat4 shadow_view_proj;
    vec4 shadow_origin;
    vec4 shadow_info;     // x far, y texel factor k, z resolution, w cube
};

layout(std140, binding = UBO_LIGHT) uniform LightBlock { GpuLight u_light; };

#define SHADOW_NONE 0
#define SHADOW_HARD 1
#define SHADOW_PCF 2
#define SHADOW_PCSS 3

layout(std140, binding = UBO_SHADOW) uniform ShadowBlock {
    vec4 bias;    // x const (m), y slope (texels·tanθ), z normal offset (texels), w mode
    vec4 filt;    // x PCF radius, y PCF samples, z blocker samples, w PCSS max radius
    vec4 poisson[64];
} u_shadow;

#define UBO_GI 2
#define SSBO_PATTERN 0
#define SSBO_VPL 1
#define SSBO_COUNTERS 2
#define TEX_RSM_POSITION 8
#define TEX_RSM_NORMAL 9
#define TEX_RSM_FLUX 10
#define TEX_GI 11
#define TEX_LOWRES 12
#define IMG_OUT 0

layout(std140, binding = UBO_GI) uniform GiBlock {
    vec4 rsm;        // x r_max, y N, z weighting (0 paper, 1 unbiased), w RSM resolution
    vec4 rsm2;       // x texels in disk K, y cube, z VPL count, w indirect scale
    vec4 interp;     // x factor, y normal cos threshold, z distance threshold (× view distance)
    vec4 interleave; // x n, y m, z sub-image width, w sub-image height
    vec4 camera;     // xyz camera position
    ivec4 size;      // xy full resolution, zw low resolution
} u_gi;

struct Vpl {
    vec4 position_xi; // xyz position, w fixed random ξ
    vec4 normal;
    vec4 flux;        // rgb Φ
};

#define UBO_VPL 3
#define SSBO_VPL_RANGE 3
#define SSBO_TILES 4
#define SSBO_EVALS 5
#define SSBO_SUBSETS 6
#define VPL_TILE 16

layout(std140, binding = UBO_VPL) uniform VplParamBlock {
    vec4 slc;        // x e_max, y exposure E, z near clamp d² (0 = off), w clamped range R
    vec4 misc;       // x keep fraction q (vpl-all subsampling), y tile list capacity, z K = n·m, w subset length L
    ivec4 tiles;     // x, y tile counts; z, w interleave n, m
    ivec4 samples;   // x, y metalight signature grid
} u_vpl;
