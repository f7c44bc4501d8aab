/* light_stage.h — everything the frame derives from its lights, made once
 * per frame in one place:
 *   - each light's frame (shadow projection) into one GPU light array (a
 *     uniform buffer of GpuLight, one aligned slot per light and product),
 *   - shadow maps (Williams 1978; bias/PCF/PCSS are applied where the map is
 *     read, shaders/common/shadow.glsl) when shadows are on,
 *   - reflective shadow maps (Dachsbacher & Stamminger 2005) when the GI
 *     technique declares LIGHT_NEEDS_RSM,
 *   - the VPL buffer (every lit RSM texel a VPL, SPEC §3–4) when it declares
 *     LIGHT_NEEDS_VPLS; re-extracted only when a light or an RSM setting
 *     changes, so its order is stable for techniques that index it.
 * With `cache` set, a shadow map or RSM is redrawn only when its light,
 * its size or the scene's geometry (GpuScene.version: an object moved)
 * changed since it was last drawn; light_stage_invalidate forces a redraw.
 * Maps are 2D for directional/spot lights and cubes for point/quad lights.
 * Inputs: the scene (borrowed), its GpuScene. Owns: every map, the light
 * array, the VPL buffer. Shaders: shaders/light/. */
#ifndef RTGI_LIGHT_STAGE_H
#define RTGI_LIGHT_STAGE_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>

#include "gpu/gpu_scene.h"
#include "gl/gpu_timer.h"
#include "core/scene.h"
#include "gl/shader.h"
#include "gpu/shadow_frame.h"

typedef enum LightNeeds {
    LIGHT_NEEDS_SHADOW_MAPS = 1u << 0, /* direct light with shadows */
    LIGHT_NEEDS_RSM = 1u << 1,         /* reflective shadow maps */
    LIGHT_NEEDS_VPLS = 1u << 2,        /* VPL buffer (implies RSM) */
} LightNeeds;

typedef struct ShadowMap {
    int size;          /* texels per side (per cube face) */
    bool cube;
    GLuint texture;    /* DEPTH32F 2D or cube: distance to the light / far */
    GLuint fbo;
    ShadowFrame frame; /* projection of the last frame */
    uint64_t key;      /* what it was last drawn for (0: never) */
    uint64_t version;  /* which draw it holds (as RsmMap.version) */
} ShadowMap;

typedef struct RsmMap {
    int size;          /* texels per side (per face) */
    bool cube;
    GLuint texel;      /* RGBA32UI: position, normal of the lit side and flux, packed
                          (shaders/common/rsm_texel.glsl); 0 where no surface */
    GLuint depth;      /* DEPTH32F */
    GLuint fbo;
    ShadowFrame frame; /* projection of the last frame */
    uint64_t key;      /* what it was last drawn for (0: never) */
    uint64_t version;  /* which draw it holds (unique in the process; 0: none): what is derived
                          from it is current while this is unchanged */
} RsmMap;

typedef struct VplBuffer {
    GLuint vpls;       /* GpuVpl[capacity] */
    GLuint counters;   /* uint[1]: VPL count */
    uint32_t capacity;
} VplBuffer;

/* What the stage must make; fixed until light_stage_configure. */
typedef struct LightStageDesc {
    unsigned needs;       /* LightNeeds */
    int shadow_map_size;  /* per side */
    int rsm_size;         /* per side, when vpl_count is 0 */
    int vpl_count;        /* > 0: RSM size per light from this VPL budget */
    unsigned vpl_seed;    /* seed of the VPLs' fixed random ξ */
    bool cache;           /* redraw maps only when their light or size changed */
    bool no_cull;         /* draw every cluster into every face (culling's baseline in tests) */
} LightStageDesc;

typedef struct LightStage {
    const Scene *scene;   /* borrowed */
    LightStageDesc desc;
    int light_count;
    GLuint light_array;   /* UBO: GpuLight per light and product, `slot_stride` apart */
    int slot_stride;      /* bytes between slots (UBO offset alignment) */
    ShadowMap *shadow;    /* [light_count] when LIGHT_NEEDS_SHADOW_MAPS */
    RsmMap *rsm;          /* [light_count] when LIGHT_NEEDS_RSM */
    VplBuffer vpls;       /* when LIGHT_NEEDS_VPLS */
    uint64_t vpl_key;     /* what the VPLs were extracted from (0: none yet) */
    int vpl_extractions;  /* how many times VPLs were extracted */
    int map_draws;        /* shadow maps and RSMs drawn, in all */
    int faces_drawn;      /* map faces the scene was drawn into, in all */
    int clusters_culled;  /* clusters those faces skipped (outside their frustum), in all */
    GLuint shadow_programs[2][2]; /* [directional][alpha-masked], from the program cache */
    GLuint shadow_program;        /* nonzero when all four built */
    GLuint rsm_program;              /* from the program cache */
    GLuint vpl_program[2];           /* [cube]: VPL extraction, per kind of map (light_stage_rsm_kind) */
    GLuint rsm_program_opaque;       /* rsm_program for opaque materials: early depth */
    GLuint rsm_program_untextured;   /* the same for opaque materials without textures */
    GLuint dummy_2d, dummy_cube; /* bound in place of the map type a light does not use */
    GLuint shadow_compare;       /* depth-compare sampler for TEX_SHADOW_COMPARE_2D/CUBE */
    bool kind_warned;            /* a light's map kind changed under its products (light_stage_run) */
    bool made;                   /* the products of `desc` exist (false after a make failed: remade next time) */
} LightStage;

/* RSM layers (2D maps or cube faces) whose texels can hold a lit surface
 * for light `l` of scene `s`: 1 for a 2D map (a fitted point light's too,
 * shadow_frame_point_fitted), 3 for a one-sided quad's half cube, 6 for a
 * point light's cube. At most layers × size² VPLs come from its RSM. */
float light_stage_lit_layers(const Scene *s, const Light *l);
/* RSM texels per side that give about `vpls` VPLs for light `l`. */
int light_stage_rsm_size_for_vpls(const Scene *s, const Light *l, int vpls);

/* Programs come from `pc` (owned by the caller, outlives the stage). */
bool light_stage_create(LightStage *ls, const Scene *s, const LightStageDesc *desc, ProgramCache *pc);
void light_stage_destroy(LightStage *ls);
/* GPU memory of the light products (shadow maps, RSMs, VPLs) and the light
 * array (gl_texture_bytes, gl_buffer_bytes). */
uint64_t light_stage_gpu_bytes(const LightStage *ls);
/* Remakes what differs between the current and the new description. */
bool light_stage_configure(LightStage *ls, const LightStageDesc *desc);

/* Computes every light's frames into the light array and builds the
 * products of the description (timer scopes "shadow", "rsm", "vpl_generate").
 * A light's map kind (cube or 2D, shadow_frame_is_cube) is fixed when its
 * products are made, and the GI techniques size their own buffers from it:
 * a point light moved across shadow_frame_point_fitted's bound needs a new
 * renderer (renderer_create); renderer_scene_changed makes one light's
 * products again when an animation moves it across (a caller that moves
 * lights otherwise gets one error line here, not a silent wrong image). */
void light_stage_run(LightStage *ls, const GpuScene *gs, GpuTimer *t);

/* Whether a light has crossed the bound between a cube map and a fitted
 * 2D map (moved) since its products were made: they must be made again
 * (renderer_scene_changed does). */
bool light_stage_kind_changed(const LightStage *ls);

/* Forgets what the maps were drawn for: the next run redraws them all. */
void light_stage_invalidate(LightStage *ls);

/* Binds light i's shadow-lookup block to UBO_LIGHT and its shadow map (or a
 * dummy) to TEX_SHADOW_2D/CUBE, and through the depth-compare sampler to
 * TEX_SHADOW_COMPARE_2D/CUBE. */
void light_stage_bind_shadow(const LightStage *ls, int i);
/* What the light products hold now, as one key (never 0): the lights and
 * which draw each shadow map and RSM holds. A technique that derives
 * volumes from them (LPV injection, VCT radiance) rebuilds them when this
 * changes and keeps them while it does not. */
uint64_t light_stage_products_key(const LightStage *ls);
/* Binds light i's RSM block to UBO_LIGHT and the RSM (2D or cube) to
 * TEX_RSM. */
void light_stage_bind_rsm(const LightStage *ls, int i);
/* How light g's RSM texels are packed (shaders/common/rsm_texel.glsl),
 * given g's other fields (shadow_frame_to_gpu): positions in the scene's
 * bounds (padded by 1e-4 of their extent) at 2^21 − 1 steps per axis, flux
 * in units of 1/16384 of the most a texel can receive, M = max(color)·a
 * (I ≤ color for every light type; a = texel_k², the texel's area or solid
 * angle on the projection plane): RGB9E5 keeps its 9 bits from 2^-15 to
 * 65408 units, i.e. from 1.9e-9·M to 4·M (albedo up to 4). */
void light_stage_rsm_texel_frame(const vec3 bounds_min, const vec3 bounds_max, GpuLight *g);
/* Binds light i's RSM block to UBO_LIGHT and the RSM as a read-only image
 * at IMG_RSM (layered: a cube's six faces), for passes that walk its texels
 * (shaders/common/rsm_layers.glsl); their programs are built per kind of
 * map with light_stage_rsm_kind. */
void light_stage_bind_rsm_layers(const LightStage *ls, int i);
/* The define that builds a program reading RSMs of one kind: RSM_CUBE
 * (point and quad lights) or RSM_2D (spot and directional). */
const char *light_stage_rsm_kind(bool cube);
/* Binds the VPL buffer to SSBO_VPL and SSBO_COUNTERS. */
void light_stage_bind_vpls(const LightStage *ls);
/* The VPL count of the last extraction (waits for the GPU). */
uint32_t light_stage_vpl_count(const LightStage *ls);

#endif
