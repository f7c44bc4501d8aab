/* renderer.h — owns the GPU scene, the shared targets and every pass, and
 * runs one frame top to bottom:
 *   shadow(light) → G-buffer → direct(light, shadow) → [GI] → tone map.
 * The scene is borrowed and must outlive the renderer. */
#ifndef RTGI_RENDERER_H
#define RTGI_RENDERER_H

#include <stdbool.h>
#include <stdint.h>

#include "gpu_scene.h"
#include "gpu_timer.h"
#include "image.h"
#include "passes/pass_direct.h"
#include "passes/pass_gbuffer.h"
#include "passes/pass_shadow.h"
#include "passes/pass_tonemap.h"
#include "scene.h"
#include "targets.h"

typedef enum GiMode { GI_NONE = 0 } GiMode;

typedef struct RenderSettings {
    int width, height;
    ShadowMode shadow;
    GiMode gi;
    float exposure;
    ShadowParams shadow_params;
    bool timings;     /* per-pass GPU timer queries */
    bool timing_sync; /* also wall time per pass (glFinish around passes) */
} RenderSettings;

typedef struct Renderer {
    const Scene *scene;        /* borrowed */
    RenderSettings settings;
    GpuScene gpu_scene;
    GpuTimer timer;
    GBuffer gbuffer;
    ColorTarget hdr;           /* RGBA32F radiance */
    ColorTarget ldr;           /* SRGB8_ALPHA8 */
    ShadowMap *shadow_maps;    /* one per light */
    PassShadow pass_shadow;
    PassGbuffer pass_gbuffer;
    PassDirect pass_direct;
    PassTonemap pass_tonemap;
} Renderer;

/* Needs a current GL 4.5 context. false after logging. */
bool renderer_create(Renderer *r, const Scene *s, const RenderSettings *rs);
void renderer_destroy(Renderer *r);
/* Renders one frame from `cam`. */
void renderer_frame(Renderer *r, const Camera *cam);
/* Reads back radiance (row 0 = top). */
bool renderer_read_hdr(Renderer *r, ImageF *out);
/* Reads back the tone-mapped image as 8-bit RGB, row 0 = top. Caller frees. */
uint8_t *renderer_read_ldr(Renderer *r);

#endif
