/* pass_vbuffer.h — the visibility-buffer G-buffer (`--gbuffer visibility`;
 * Burns & Hunt 2013, "The Visibility Buffer: A Cache-Friendly Approach to
 * Deferred Shading"): a thin raster pass writes depth and, per pixel, the
 * triangle it sees (cluster and triangle in it, frame/vbuffer.frag; alpha-
 * masked materials discard their holes there), then compute passes fetch
 * that triangle's vertices, interpolate its attributes at the pixel centre
 * with perspective-correct barycentrics and analytic uv gradients, read its
 * material and write the same G-buffer texels frame/gbuffer.frag writes
 * (frame/vbuffer.glsl), so every pass that reads the G-buffer works
 * unchanged. Textures in compute without bindless: material
 * classification. The classify pass resolves the pixels of materials
 * without textures itself (their constants come from a table) and counts
 * the others per material; a one-invocation pass turns the counts into
 * list offsets and indirect dispatches; a scatter pass lists each pixel
 * under its material; then one indirect dispatch per textured material,
 * its textures bound, resolves its list (no CPU read-back).
 * Inputs: the scene's buffers, materials and textures, the camera.
 * Output: the renderer's GBuffer (surface, material, depth), as
 * pass_gbuffer_run leaves it up to float rounding and mip selection.
 * Owns: its visibility image and framebuffer (sized with the G-buffer),
 * the cluster and material tables, the bins and the pixel list (its
 * programs are the program cache's). */
#ifndef RTGI_PASS_VBUFFER_H
#define RTGI_PASS_VBUFFER_H

#include <stdbool.h>

#include "core/camera.h"
#include "gl/shader.h"
#include "gpu/gpu_scene.h"
#include "gpu/targets.h"
#include "shared/gpu_types.h"

typedef struct PassVbuffer {
    GLuint raster_opaque, raster_masked; /* frame/vbuffer.frag: ids; masked materials discard holes */
    GLuint classify, scatter, bins_program, resolve; /* frame/vbuffer_*.comp */
    GLuint ids;       /* R32UI at the G-buffer's size: (cluster << VBUFFER_TRIANGLE_BITS | triangle) + 1, 0: none */
    GLuint fbo;       /* ids + the G-buffer's depth */
    GLuint depth;     /* the G-buffer depth texture fbo holds (a new one: remake) */
    int width, height;
    GLuint clusters;  /* SSBO: uint[2] per GpuScene cluster: first triangle, material (bit 31: textured) */
    GLuint materials; /* SSBO: GpuMaterial per scene material (uploaded every run) */
    GLuint bins;      /* SSBO: uint[6] per material (frame/vbuffer.glsl) */
    GLuint pixels;    /* SSBO: a uint per pixel, the binned pixels */
    GpuMaterial *rows;  /* [material_count]: the table as uploaded */
    int material_count;
    int *textured;      /* materials resolved by their own dispatch (textured or alpha-masked) */
    int textured_count;
    int culled; /* clusters outside the view in the last run */
} PassVbuffer;

/* Its programs come from `pc`; its tables from `gs` and `s` (which it
 * must not outlive). false after logging; destroy it then. */
bool pass_vbuffer_create(PassVbuffer *p, ProgramCache *pc, const GpuScene *gs, const Scene *s);
void pass_vbuffer_destroy(PassVbuffer *p);
/* (Re)makes the visibility image, its framebuffer and the pixel list for
 * `gb` where its size or depth texture changed. false after logging. */
bool pass_vbuffer_resize(PassVbuffer *p, const GBuffer *gb);
/* With `cull`, clusters outside the camera's frustum are skipped and the
 * rest drawn nearest first; the image is the same either way. `out` must
 * be the G-buffer of the last pass_vbuffer_resize. */
void pass_vbuffer_run(PassVbuffer *p, const GpuScene *gs, const Scene *s, const Camera *cam, bool cull, GBuffer *out);
/* GPU memory it holds. */
uint64_t pass_vbuffer_bytes(const PassVbuffer *p);

#endif
