/* scene.h — the one scene description that the rasterizer and the path
 * tracer both read: triangles with glTF metallic-roughness materials
 * (constant or texture, with alpha masks), lights in physical units, a pinhole camera,
 * and per-technique parameters that a scene file may set.
 *
 * Units: metres, +y up, radiance in W/(m²·sr). Light "power" quantities:
 *   directional  color = irradiance E (W/m²) on a plane facing the light
 *   spot, point  color = intensity I (W/sr) on the axis / in every direction
 *   quad         color = emitted radiance L (W/(m²·sr)), one-sided along
 *                direction; the rasterizer integrates the polygon exactly
 *                for the diffuse lobe (--area-light exact) or treats it as a
 *                point at its centre with I(θ) = L·A·cosθ (--area-light point).
 * Every light's `size` scales its emitter (quad extents, sphere/disk
 * diameter, sun angular diameter); size 0 makes it a point with the same
 * intensity distribution, on which both renderers must agree exactly. */
#ifndef RTGI_SCENE_H
#define RTGI_SCENE_H

#include <cglm/cglm.h>
#include <stdbool.h>
#include <stdint.h>

typedef enum LightType { LIGHT_DIRECTIONAL = 0, LIGHT_SPOT = 1, LIGHT_POINT = 2, LIGHT_QUAD = 3 } LightType;

typedef struct Light {
    LightType type;
    vec3 position;    /* spot, point, quad: centre (m) */
    vec3 direction;   /* unit; directional/spot: where light travels; quad: emitting normal */
    vec3 color;       /* E, I or L per type, see above */
    float size;       /* spot/point: emitter diameter (m); directional: angular diameter (rad); quad: scale of its extents (1 = as given) */
    float spot_inner; /* spot: half-angle (rad) of full intensity */
    float spot_outer; /* spot: half-angle (rad) beyond which intensity is 0 */
    vec3 quad_u;      /* quad: full edge vectors at size 1; normal = direction */
    vec3 quad_v;
} Light;

typedef struct Camera {
    vec3 position;
    vec3 forward; /* unit */
    vec3 up;      /* unit, orthogonal to forward */
    float fov_y;  /* vertical field of view, radians */
    float znear, zfar;
} Camera;

typedef struct Texture {
    int width, height;
    uint8_t *rgba; /* RGBA8, row 0 = top, owned: sRGB-encoded colour, or data when `linear` */
    bool linear;   /* data (glTF metallicRoughness), not colour: no sRGB decoding */
    char name[256];
} Texture;

/* glTF metallic-roughness material (SPEC §1b; the BRDF is src/brdf.h).
 * Built-in surfaces and OBJ materials have specular 0 and metallic 0: they
 * are Lambertian, f = albedo/π. A scene file's "materials" object sets any
 * of these per material name (docs/guide.md, "Scene files"). */
typedef struct Material {
    char name[64];
    vec3 albedo;        /* base colour factor, linear; multiplies the texture */
    int albedo_tex;     /* base colour texture: index into Scene.textures or -1 */
    float metallic;     /* factor in [0,1]; multiplies the texture's B */
    float roughness;    /* perceptual roughness factor in [0,1] (α = r²); multiplies the texture's G */
    float specular;     /* dielectric reflectance weight: F0 = 0.04·specular (0: Lambertian) */
    int mr_tex;         /* metallicRoughness texture (linear; G roughness, B metallic) or -1 */
    bool alpha_mask;    /* texels with alpha < alpha_cutoff are holes */
    float alpha_cutoff;
    vec3 emission;      /* radiance of an emitter surface (front face only) */
    int light_index;    /* emitter geometry of this light, or -1 */
} Material;

typedef struct Vertex {
    float position[3];
    float normal[3];
    float uv[2];
} Vertex;

/* A run of triangles of one material: indices[first .. first+count). */
typedef struct Submesh {
    uint32_t first_index;
    uint32_t index_count;
    int material;
} Submesh;

/* Technique parameters a scene file may set and the CLI overrides; their
 * keys, options, ranges and defaults are rows of the settings table
 * (settings.c). */
typedef struct ShadowParams {
    int map_size;          /* 2D shadow map / cube face resolution */
    float bias_const;      /* world-space constant bias (m) */
    float bias_slope;      /* slope-scaled bias, in shadow-map texels × tanθ */
    float normal_offset;   /* receiver offset along the normal, in texels */
    int pcf_samples;       /* Poisson disk samples (≤ 64) */
    float pcf_radius;      /* PCF filter radius in texels */
    int blocker_samples;   /* PCSS blocker-search samples (≤ 64) */
    float pcss_max_radius; /* PCSS search/filter radius cap in texels */
    int filter_bias;       /* PCF/PCSS depth test: 0 receiver plane (Poisson disk), 1 legacy (slope bias × filter radius, spiral) */
    int pcf_filter;        /* ShadowPcfFilter: Poisson disk, or a grid of hardware-compare bilinear taps */
    int area_light;        /* AreaLightMode: quad lights' exact polygon irradiance, or a point at the centre */
} ShadowParams;

/* PCF's taps (ShadowParams.pcf_filter; SHADOW_FILTER_* in shared/gpu_types.h). */
typedef enum ShadowPcfFilter { SHADOW_PCF_FILTER_DISK = 0, SHADOW_PCF_FILTER_GRID = 1 } ShadowPcfFilter;

/* Visibility of the bounce (SPEC §9): how RSM and VPL gathers test it. */
typedef enum GiVisibilityMethod { GI_VISIBILITY_ISM = 0 } GiVisibilityMethod;
/* Imperfect shadow maps' texels per side (GiParams.ism_size: an index). */
typedef enum IsmSize { ISM_SIZE_16 = 0, ISM_SIZE_32 = 1, ISM_SIZE_64 = 2 } IsmSize;

typedef enum VctCones { VCT_CONES_6 = 0, VCT_CONES_9 = 1, VCT_CONES_16 = 2 } VctCones;
/* How vct voxelizes: triangles projected and rasterized, or in compute. */
typedef enum VctVoxelize { VCT_VOXELIZE_RASTER = 0, VCT_VOXELIZE_COMPUTE = 1 } VctVoxelize;
/* How the rasterizer lights with quad lights (values AREA_LIGHT_* in
 * shared/gpu_types.h). */
typedef enum AreaLightMode { AREA_LIGHT_MODE_EXACT = 0, AREA_LIGHT_MODE_POINT = 1 } AreaLightMode;

typedef enum LpvInject { LPV_INJECT_COMPUTE = 0, LPV_INJECT_POINTS = 1 } LpvInject;
/* How a propagation step moves light (shaders/gi/lpv/propagate.comp):
 * along the directions it travels in, or through the paper's 5 faces per
 * neighbour, re-emitted towards the faces' normals. */
typedef enum LpvPropagation { LPV_PROPAGATION_DIRECTIONAL = 0, LPV_PROPAGATION_FACES = 1 } LpvPropagation;

typedef enum RsmWeighting { RSM_WEIGHT_PAPER = 0, RSM_WEIGHT_UNBIASED = 1, RSM_WEIGHT_IMPORTANCE = 2 } RsmWeighting;

/* Parameters of the RSM family of GI techniques (SPEC §3). */
typedef struct GiParams {
    int rsm_size;          /* RSM texels per side (per cube face for point/quad lights) */
    int samples;           /* N samples per gather (paper: ~400) */
    float r_max;           /* sampling radius, in RSM widths (cube: face widths) */
    RsmWeighting weighting;/* paper's ξ1² normalised, unbiased for the polar pdf, or importance
                              sampling of the whole map by flux */
    bool exhaustive;       /* sum over every RSM texel instead of sampling */
    int interp_factor;     /* screen-space interpolation: low-res = full / factor */
    float interp_normal;   /* min cosine between normals for a usable low-res sample */
    float interp_dist;     /* max world distance, as a fraction of the view distance */
    int interleave_n, interleave_m; /* interleaved sampling pattern n×m */
    bool interleave_blur;  /* geometry-aware blur after reassembly */
    float scale;           /* indirect intensity scale (1 = physical) */
    /* Many-VPL techniques (SPEC §4). */
    int vpl_count;         /* VPLs per light wanted (sets the RSM size); 0: the RSM size decides */
    float slc_emax;        /* stochastic light culling error bound e_max (0.0005) */
    float vpl_near_clamp;  /* falloff 1/max(d², c) with c in m²; 0 = off (the notes use 0.1) */
    bool vpl_disk;         /* VPLs fall off as disks of their texel's area: 1/(d² + A/π) */
    float vpl_range;       /* clamped-range baseline, metres; 0 = 0.15 × scene diagonal */
    float vpl_keep;        /* vpl-all: fraction q of VPLs kept (uniform subsampling, weight 1/q) */
    unsigned vpl_seed;     /* seed of the VPLs' fixed random ξ */
    /* Visibility of the bounce (SPEC §9, src/gi/visibility/): */
    bool gi_visibility;    /* RSM and VPL gathers test whether each VPL (sample) sees the shaded point */
    int gi_visibility_method; /* GiVisibilityMethod */
    int ism_size;          /* IsmSize: texels per side of each imperfect shadow map */
    int ism_points;        /* scene points splatted into each map */
    int ism_maps;          /* RSM gathers: maps per light, one per block of RSM texels */
    /* Light propagation volumes (SPEC §5). */
    int lpv_size;          /* cells per side of each grid */
    int lpv_cascades;      /* 1: one grid fitted to the scene; 2–3: nested grids centred on the camera */
    int lpv_iterations;    /* propagation steps; 0: the grid size (enough to cross it) */
    bool lpv_occlusion;    /* attenuate propagation by the geometry volume */
    float lpv_offset;      /* VPLs move this many cells along their normal before injection (0.5) */
    bool lpv_gbuffer_occlusion; /* also inject the camera's G-buffer into the geometry volume */
    int lpv_inject;        /* LpvInject: compute with fixed-point atomics, or points into 3D-texture layers with blending */
    int lpv_propagation;   /* LpvPropagation: directional (light keeps its direction) or the paper's faces */
    int lpv_groups;        /* 1, or 2: the light of surfaces facing +x/+y/+z and of those facing away propagated apart */
    /* Voxel cone tracing (SPEC §6). */
    int vct_size;          /* voxels per side of the volume over the scene bounds (of each clipmap level) */
    int vct_levels;        /* 1: one volume over the bounds; 2–4: a clipmap centred on the camera */
    bool vct_aniso;        /* six directional mip volumes (Crassin's anisotropic voxels) */
    int vct_cones;         /* VctCones: the diffuse cone set (6, 9 or 16 cones) */
    int vct_bounces;       /* 1: direct light in the voxels; 2: plus one cone-traced bounce */
    float vct_step;        /* cone sampling step, in units of the cone's current diameter */
    int vct_trace_scale;   /* cones traced at every Nth pixel per axis, upsampled by depth and normal */
    bool vct_ao;           /* ambient occlusion from the diffuse cones (irradiance alpha, --out-ao) */
    bool vct_conservative; /* conservative voxelization (off: one voxel per fragment centre; tests) */
    int vct_voxelize;      /* VctVoxelize: rasterized (geometry shader, fragments) or compute (a thread per triangle) */
    float vct_roughness;   /* with vct_f0 > 0: GGX perceptual roughness of every surface's specular cone */
    float vct_f0;          /* > 0: F0 of every surface's specular cone instead of the material's (tests); 0: the material's */
    /* Time (SPEC §10). */
    bool temporal;         /* temporal accumulation of the indirect light (passes/pass_temporal.h) */
    bool temporal_clamp;   /* its neighbourhood clamp (off: the history lags a moving light; for measuring) */
    /* Diagnostic, no scene key: the RSM gathers' twin for `render --timings
     * --probe run`, which reads every sample and evaluates none (the image
     * is meaningless); its rate is the limit of the gather's own reads. */
    bool gather_reads_only;
} GiParams;


typedef struct Scene {
    char source[512];      /* what it was loaded from, for messages */
    Vertex *vertices;      /* owned */
    uint32_t vertex_count;
    uint32_t *indices;     /* owned, triangles */
    uint32_t index_count;
    Submesh *submeshes;    /* owned */
    int submesh_count;
    Material *materials;   /* owned */
    int material_count;
    Texture *textures;     /* owned, with their pixels */
    int texture_count;
    Light *lights;         /* owned */
    int light_count;
    Camera camera;
    float exposure;        /* scene's default exposure */
    ShadowParams shadow;   /* scene's default shadow parameters */
    GiParams gi;           /* scene's default GI parameters */
    vec3 bounds_min, bounds_max; /* of all geometry but light emitters */
    /* Time (animation.h): named rigid objects and keyframe tracks of a
     * scene file's "objects" and "animation"; NULL/0 when it has none. */
    struct SceneObject *objects; /* owned, [object_count] */
    int object_count;
    struct Animation *animation; /* owned, or NULL */
} Scene;


/* Every exposure, the scene file's and every --exposure: positive (0
 * would make every image black, and SSIM and FLIP of any two images
 * perfect). */
#define SCENE_EXPOSURE_MIN 1e-9f
#define SCENE_EXPOSURE_MAX 1e9f

/* Empty scene with default camera/exposure/parameters. */
void scene_init(Scene *s);
void scene_free(Scene *s);

/* Appends a material, returns its index (-1 after logging if out of memory). */
int scene_add_material(Scene *s, const char *name, const vec3 albedo);
/* Appends a planar quad (two triangles) p0,p1,p2,p3 in order, normal from
 * (p1-p0)×(p3-p0). false after logging if out of memory. */
bool scene_add_quad(Scene *s, int material, const vec3 p0, const vec3 p1, const vec3 p2, const vec3 p3);
/* Appends a light (its direction is normalised); returns its index (-1
 * after logging if out of memory). */
int scene_add_light(Scene *s, const Light *l);

/* Call after geometry and lights are final: merges submeshes by material,
 * adds emitter geometry for quad lights of size > 0, computes bounds.
 * false after logging (out of memory). */
bool scene_finalize(Scene *s);
/* Whether any material has a specular lobe (F0 > 0: metallic or a
 * dielectric specular weight, see brdf_surface); without one every surface
 * is exactly Lambertian and shaders may drop the GGX code. */
bool scene_has_glossy(const Scene *s);

/* The built-in Cornell box from ../shared/assets/cornell (metres). false
 * after logging (out of memory; free the scene then). */
bool scene_build_cornell(Scene *s);

/* Recomputes the scene's bounds from its geometry (emitters left out), as
 * scene_finalize does: after vertices moved (animation_apply). */
void scene_compute_bounds(Scene *s);
/* The four corners of quad light l's emitter at its size, wound so that
 * (p1 − p0) × (p3 − p0) points along its direction. */
void scene_emitter_corners(const Light *l, vec3 p[4]);

/* Scales every light's emitter size (see header comment) and rebuilds the
 * emitter geometry of a finalized scene. false after logging. */
bool scene_rescale_lights(Scene *s, float scale);

/* Loads a scene: "cornell", a .json scene file, or a mesh file (.gltf,
 * .glb, .obj, ...) that gets a default sun and camera. false after logging
 * one line naming the file and the problem (scene_check_view included;
 * scene_check_lights is the caller's, once the light sizes are final:
 * scene_load_scaled). */
bool scene_load(Scene *s, const char *what);
/* The scene a command renders: scene_load, every light's emitter size
 * scaled by `light_scale` where it is >= 0 (--light-scale; < 0: as the
 * file gives them), then scene_check_lights. false after logging; the
 * scene is freed then. */
bool scene_load_scaled(Scene *s, const char *what, float light_scale);
/* The built-in scene's name that `what` is a likely typo of ("cornel":
 * "cornell"), when `what` is a bare name (no '/' or '.') and no file; else
 * NULL. scene_load refuses such names; the CLI checks them first, as a
 * usage error. */
const char *scene_builtin_near(const char *what);
/* Loads a mesh file through assimp, appending to `s`. */
bool scene_load_mesh(Scene *s, const char *path, const mat4 transform);
/* The same with every node's meshes kept apart (not joined by material)
 * and, per node name, the submeshes under it into *nodes (animation.h;
 * the caller frees it with scene_node_map_free). */
struct SceneNodeMap;
bool scene_load_mesh_nodes(Scene *s, const char *path, const mat4 transform, struct SceneNodeMap *nodes);

/* Checks of a finalized scene that parsing cannot make, false after logging
 * one line naming the file and the problem:
 *  - every point light's sphere lies outside every surface (inside it the
 *    renderers cannot agree), and every quad light of nonzero size has
 *    sides of at least 1e-5 of the scene's size (smaller ones are points
 *    to every pixel and collapse in float); `after` names what set the
 *    sizes ("" or ", after --light-scale");
 *  - the camera sees some of the scene's bounds: camera.far reaches them,
 *    camera.near starts before their far side, and they are not all behind
 *    it. */
bool scene_check_lights(const Scene *s, const char *after);
/* Squared distance from p to the box [lo, hi] (0 inside): a scene's or a
 * draw cluster's bounds. */
float scene_box_dist2(const vec3 p, const vec3 lo, const vec3 hi);
bool scene_check_view(const Scene *s);

/* Default sun and camera for a scene without them, from its bounds (the
 * sun: false after logging). */
bool scene_add_default_sun(Scene *s);
void scene_default_camera(Scene *s);

/* ---- Light model shared by the rasterizer's shaders and the path tracer ---- */

/* Quad area A at the light's current size. */
float light_quad_area(const Light *l);
/* Spot cone falloff: smoothstep(cos outer, cos inner, cosθ), as in GLSL. */
float light_spot_falloff(const Light *l, float cos_theta);
/* Radiant intensity (W/sr, RGB) of a spot/point/quad light toward unit
 * direction `dir` (from the light outward). */
void light_intensity(const Light *l, const vec3 dir, vec3 out);
/* Width used by PCSS: spot/point diameter, quad mean edge length (m). */
float light_width(const Light *l);

#endif
