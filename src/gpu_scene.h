/* gpu_scene.h — the scene's meshes and textures on the GPU.
 * Owns one vertex buffer, one index buffer, a VAO and a texture per scene
 * texture; the Scene keeps the CPU copies (the path tracer reads them). */
#ifndef RTGI_GPU_SCENE_H
#define RTGI_GPU_SCENE_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "scene.h"

typedef struct GpuScene {
    GLuint vao;
    GLuint vbo;       /* Vertex[] */
    GLuint ibo;       /* uint32 indices */
    GLuint *textures; /* one per Scene.textures, sRGB (colour) or RGBA8 (linear data) with mipmaps */
    int texture_count;
} GpuScene;

bool gpu_scene_create(GpuScene *g, const Scene *s);
void gpu_scene_destroy(GpuScene *g);

typedef enum DrawFlags {
    DRAW_ALL = 0,
    DRAW_SKIP_EMITTERS = 1, /* light emitter geometry (shadow maps, RSM) */
} DrawFlags;

/* Draws every submesh with `program`, setting the material uniforms
 * (LOC_MATERIAL_*) and binding its albedo texture to TEX_ALBEDO and its
 * metallicRoughness texture to TEX_MATERIAL_MR. */
void gpu_scene_draw(const GpuScene *g, const Scene *s, GLuint program, DrawFlags flags);
/* The same with opaque materials drawn by `opaque` (which may skip the
 * material altogether) and alpha-masked ones by `masked`. */
void gpu_scene_draw_split(const GpuScene *g, const Scene *s, GLuint opaque, GLuint masked, DrawFlags flags);

#endif
