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
#include "passes/pass_composite.h"
#include "passes/pass_direct.h"
#include "passes/pass_gbuffer.h"
#include "passes/pass_rsm.h"
#include "passes/pass_rsm_gather.h"
#include "passes/pass_vpl.h"
#include "passes/pass_vpl_shade.h"
#include "passes/pass_shadow.h"
#include "passes/pass_tonemap.h"
#include "scene.h"
#include "targets.h"

typedef enum GiMode {
    GI_NONE = 0,
    GI_RSM,             /* full-resolution RSM gather */
    GI_RSM_INTERP,      /* low-res gather + screen-space interpolation */
    GI_RSM_INTERLEAVED, /* interleaved sampling + geometry-aware blur */
    GI_VPL_ALL,         /* brute force over every VPL */
    GI_VPL_CLAMPED,     /* VPLs cut at a fixed range (biased baseline) */
    GI_VPL_SLC,         /* stochastic light culling, tiled */
    GI_VPL_INTERLEAVED, /* interleaved shading, random VPL subsets */
    GI_VPL_METALIGHTS,  /* interleaved shading, subsets dealt from metalights */
    GI_MODE_COUNT
} GiMode;

extern const char *const gi_mode_names[]; /* NULL-terminated, in GiMode order */

typedef struct RenderSettings {
    int width, height;
    ShadowMode shadow;
    GiMode gi;
    float exposure;
    ShadowParams shadow_params;
    GiParams gi_params;
    bool timings;     /* per-pass GPU timer queries */
    bool timing_sync; /* also wall time per pass (glFinish around passes) */
} RenderSettings;

/* Counts from the last frame (read back from the GPU). */
typedef struct RenderStats {
    uint32_t vpl_count;          /* VPLs extracted (exhaustive gathers), last light */
    uint32_t lowres_gathers;     /* GI_RSM_INTERP: low-resolution gathers */
    uint32_t full_gathers;       /* GI_RSM_INTERP: pixels that needed a full gather */
    uint32_t gathered_pixels;    /* pixels that ran a gather (any GI mode) */
    uint64_t vpl_evaluations;    /* VPL–pixel evaluations in the shading pass (VPL modes) */
    uint64_t vpl_candidates;     /* VPL–pixel pairs visited (tile-list entries for tiled modes) */
    uint32_t tile_overflow;      /* tile-list entries dropped (should be 0) */
    int metalight_regroups;      /* times the metalight grouping was computed */
} RenderStats;

typedef struct Renderer {
    const Scene *scene;        /* borrowed */
    RenderSettings settings;
    GpuScene gpu_scene;
    GpuTimer timer;
    GBuffer gbuffer;
    ColorTarget hdr;           /* RGBA32F radiance */
    ColorTarget ldr;           /* SRGB8_ALPHA8 */
    ShadowMap *shadow_maps;    /* one per light */
    RsmMap *rsm_maps;          /* one per light, when GI is on */
    VplBuffer vpls;            /* VPLs and GI counters, when GI is on */
    GLuint gi_ubo;             /* GpuGiParams */
    GLuint irradiance;         /* RGBA32F indirect irradiance, full resolution */
    RenderStats stats;
    PassShadow pass_shadow;
    PassGbuffer pass_gbuffer;
    PassDirect pass_direct;
    PassTonemap pass_tonemap;
    PassRsm pass_rsm;
    PassVpl pass_vpl;
    PassRsmGather pass_gather;
    PassComposite pass_composite;
    PassVplShade pass_vpl_shade;
} Renderer;

/* RSM texels per side that give about `vpls` VPLs for light `l`. */
int renderer_rsm_size_for_vpls(const Light *l, int vpls);

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
