/* gpu_scene.h — the scene's meshes and textures on the GPU.
 * Owns one vertex buffer, one index buffer, a VAO and a texture per scene
 * texture; the Scene keeps the CPU copies (the path tracer reads them). */
#ifndef RTGI_GPU_SCENE_H
#define RTGI_GPU_SCENE_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/scene.h"

/* A run of at most GPU_CLUSTER_TRIANGLES triangles of one submesh, close
 * together in space (sorted along a Morton curve of their centroids), with
 * its bounds: the unit of culling and of front-to-back order. */
#define GPU_CLUSTER_TRIANGLES 2048
typedef struct GpuCluster {
    uint32_t first_index; /* into the GPU index buffer */
    uint32_t index_count;
    int submesh;
    float bounds_min[3], bounds_max[3];
} GpuCluster;

/* One upload of moved vertices: the geometry went from version `from` to
 * `to`, and every triangle whose position changed lies, before and after,
 * within [min, max] (world space). */
typedef struct GpuSceneMove {
    uint64_t from, to;
    float min[3], max[3];
} GpuSceneMove;
#define GPU_SCENE_MOVES 8 /* the last moves kept (gpu_scene_moved_since) */

typedef struct GpuScene {
    GLuint vao;
    GLuint vbo;       /* Vertex[] */
    GLuint ibo;       /* uint32 indices, each submesh's triangles in cluster order */
    GLuint *textures; /* one per Scene.textures: RGBA16F, linear (colour decoded), with mipmaps */
    int texture_count;
    GpuCluster *clusters; /* submesh by submesh, in scene order */
    int cluster_count;
    uint32_t *cluster_indices; /* the index buffer's order on the CPU (cluster bounds after a move) */
    uint64_t version; /* which geometry the buffers hold: unique in the process, new after every move
                         (light products and voxels drawn from it keep it in their keys) */
    struct GpuDrawItem *draw_items; /* [cluster_count]: a draw's visible clusters (scratch, gpu_scene.c) */
    GpuSceneMove moves[GPU_SCENE_MOVES]; /* the last moves, a ring: moves[(move_count - 1) % N] the newest */
    uint32_t move_count;
} GpuScene;

bool gpu_scene_create(GpuScene *g, const Scene *s);
void gpu_scene_destroy(GpuScene *g);
/* After the scene's vertices [first, first + count) moved (animation_apply):
 * uploads them, recomputes the bounds of every cluster and takes a new
 * version. */
void gpu_scene_update_vertices(GpuScene *g, const Scene *s, uint32_t first, uint32_t count);
/* Whether the geometry of `version` differs from today's only within a box
 * (true: [min, max] holds every moved triangle before and after each move
 * since; empty, min > max, when nothing moved); false when `version` is
 * not one of the last GPU_SCENE_MOVES moves' (then anything may differ). */
bool gpu_scene_moved_since(const GpuScene *g, uint64_t version, float min[3], float max[3]);
/* GPU memory of its vertices, indices and textures. */
uint64_t gpu_scene_bytes(const GpuScene *g);

typedef enum DrawFlags {
    DRAW_ALL = 0,
    DRAW_SKIP_EMITTERS = 1, /* light emitter geometry (shadow maps, RSM) */
} DrawFlags;

/* What a draw sees: clusters wholly outside the frustum of `view_proj` are
 * skipped, and with `eye` the rest are drawn nearest first (so early depth
 * rejects what they hide). NULL fields: every cluster, in scene order.
 * `culled`, when set, receives the number of clusters skipped. */
typedef struct DrawView {
    const float *view_proj; /* column-major 4×4 (cglm mat4) */
    const float *eye;       /* vec3 */
    int *culled;
    bool draw_ids; /* set LOC_VBUFFER_DRAW (uint) to each draw's cluster index (GpuScene.clusters)
                      before it: the visibility buffer's ids (frame/vbuffer.frag) */
} DrawView;

/* Draws every submesh with `program`, setting the material uniforms
 * (LOC_MATERIAL_*) and binding its albedo texture to TEX_ALBEDO and its
 * metallicRoughness texture to TEX_MATERIAL_MR. */
void gpu_scene_draw(const GpuScene *g, const Scene *s, GLuint program, DrawFlags flags);
/* The same with opaque materials drawn by `opaque` (which may skip the
 * material altogether) and alpha-masked ones by `masked`. */
void gpu_scene_draw_split(const GpuScene *g, const Scene *s, GLuint opaque, GLuint masked, DrawFlags flags);
/* The programs a draw uses per kind of material. */
typedef struct DrawPrograms {
    GLuint opaque;     /* opaque materials (may skip the material altogether) */
    GLuint masked;     /* alpha-masked ones (may equal opaque: one pass) */
    GLuint untextured; /* opaque ones with neither an albedo nor a metallicRoughness texture, built
                          with UNTEXTURED (common/material.glsl); 0: opaque draws them */
} DrawPrograms;

/* gpu_scene_draw_split seen from `view` (NULL: the whole scene in order),
 * with an optional program for untextured opaque materials: llvmpipe pays
 * for the texture code behind a branch that no fragment takes (Cornell
 * G-buffer 800×600: 10.9 -> 9.0 ms). */
void gpu_scene_draw_view(const GpuScene *g, const Scene *s, const DrawPrograms *programs, DrawFlags flags,
                         const DrawView *view);
/* Sets material `m`'s uniforms (LOC_MATERIAL_*) in `program` and binds
 * its textures, as gpu_scene_draw does per submesh (compute passes over
 * the scene's triangles: vct's voxelize.comp). */
void gpu_scene_bind_material(const GpuScene *g, const Material *m, GLuint program);

#endif
