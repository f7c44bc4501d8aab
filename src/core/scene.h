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

#include "core/settings.h"

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

/* glTF metallic-roughness material (SPEC §1b; the BRDF is src/core/brdf.h).
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

/* Time (animation.h): what the scene holds of a scene file's "objects" and
 * "animation"; animation.c reads and applies them, scene_free frees them. */
typedef enum AnimTarget { ANIM_TARGET_LIGHT, ANIM_TARGET_CAMERA, ANIM_TARGET_OBJECT } AnimTarget;

typedef enum AnimChannel {
    ANIM_POSITION,  /* light or camera position (m) */
    ANIM_DIRECTION, /* light direction (normalised after interpolation) */
    ANIM_POWER,     /* light intensity / irradiance / radiance */
    ANIM_TARGET,    /* camera target (m): the camera looks at it */
    ANIM_FOV,       /* camera fov_y_deg (scalar) */
    ANIM_TRANSLATE, /* object translation (m) */
    ANIM_ROTATE,    /* object rotation (degrees about x, y, z) */
} AnimChannel;

typedef enum AnimInterp { ANIM_LINEAR = 0, ANIM_CATMULL_ROM = 1 } AnimInterp;

typedef struct AnimTrack {
    AnimTarget target;
    int index;          /* light or object index (camera: 0) */
    AnimChannel channel;
    AnimInterp interp;
    int dims;           /* 3, or 1 for fov */
    int key_count;      /* ≥ 1 */
    float *times;       /* [key_count], strictly increasing (owned) */
    float (*values)[3]; /* [key_count] (owned; scalars in [0]) */
} AnimTrack;

typedef struct SceneObject {
    char name[64];
    uint32_t *vertices;   /* [vertex_count] scene vertex indices it moves (owned, sorted) */
    uint32_t vertex_count;
    float (*rest)[6];     /* [vertex_count] position and normal as built (owned) */
    vec3 pivot;           /* centre of its rest bounds: rotations turn about it */
    vec3 translate;       /* the file's transform (tracks override it per channel) */
    vec3 rotate_deg;
    vec3 placed_translate;/* the transform its vertices hold now */
    vec3 placed_rotate_deg;
    bool placed;          /* false: its vertices are at rest (as built) */
} SceneObject;

typedef struct Animation {
    float duration;       /* seconds, > 0 */
    AnimTrack *tracks;    /* [track_count] (owned) */
    int track_count;
    vec3 camera_up;       /* the file's camera "up" (unit; the camera's up is made orthogonal to it) */
    double time;          /* of the state the scene holds now */
    bool camera_degenerate; /* the last apply found the camera's target at its position (kept the old view) */
} Animation;

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
    Settings settings;     /* the scene's default technique settings */
    vec3 bounds_min, bounds_max; /* of all geometry but light emitters */
    /* Time (animation.h): named rigid objects and keyframe tracks of a
     * scene file's "objects" and "animation"; NULL/0 when it has none. */
    SceneObject *objects;  /* owned, [object_count] */
    int object_count;
    Animation *animation;  /* owned, or NULL */
} Scene;


/* Every exposure, the scene file's and every --exposure: positive (0
 * would make every image black, and SSIM and FLIP of any two images
 * perfect). */
#define SCENE_EXPOSURE_MIN 1e-9
#define SCENE_EXPOSURE_MAX 1e9

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
/* The radiance of quad light l's emitter (its material's emission): the
 * same power at any size, L / size². */
void scene_emitter_radiance(const Light *l, vec3 out);

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
