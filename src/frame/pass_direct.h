/* pass_direct.h — direct lighting: the light model and its program
 * variants, and forward shading while drawing the scene
 * (common/direct_light.glsl): the BRDF of brdf.h (Lambert + GGX), quad
 * lights as exact polygons (--area-light), physical light model
 * (common/lights.glsl), shadow visibility (hard, PCF, PCSS;
 * common/shadow.glsl). The first light of a frame also adds emitted
 * radiance. Deferred frames shade in pass_shade (compute), with the same
 * variants and shadow parameters.
 * Inputs: the scene and the pre-pass depth (forward), the light stage
 * (light block and shadow map of each light), shadow parameters.
 * Output: HDR radiance target (RGBA32F): the first light written, the
 * others blended additively.
 * Owns: the shadow-parameter uniform buffer (its programs are the program
 * cache's). */
#ifndef RTGI_PASS_DIRECT_H
#define RTGI_PASS_DIRECT_H

#include <stdbool.h>

#include "core/camera.h"
#include "gpu/gpu_scene.h"
#include "gpu/light_stage.h"
#include "core/scene.h"
#include "gl/shader.h"
#include "gpu/targets.h"

/* How PCF and PCSS bias their depth tests (ShadowParams.filter_bias; the
 * values are SHADOW_BIAS_* in shared/gpu_types.h). */
typedef enum ShadowFilterBias { SHADOW_BIAS_RECEIVER_PLANE = 0, SHADOW_BIAS_LEGACY = 1 } ShadowFilterBias;

typedef enum ShadowMode { SHADOW_MODE_NONE = 0, SHADOW_MODE_HARD = 1, SHADOW_MODE_PCF = 2, SHADOW_MODE_PCSS = 3 } ShadowMode;

typedef struct PassDirect {
    GLuint forward[2]; /* forward shading, any light and mode: textured (opaque and masked), untextured draws */
    ProgramCache *pc;  /* borrowed: builds the per-light-type, per-mode variants */
    GLuint shadow_ubo; /* GpuShadowParams */
    int area_light; /* AreaLightMode of quad lights */
    ShadowMode mode;  /* the shadow mode and */
    int filter_bias;  /* ShadowFilterBias the variants are built for */
    int pcf_filter;   /* ShadowPcfFilter the variants are built for */
    float pcf_radius; /* the grid's radius (its taps are fixed per variant) */
    bool general;     /* shade every light with the general programs (tests compare the variants with them) */
} PassDirect;

/* Its programs come from `pc`. */
bool pass_direct_create(PassDirect *p, ProgramCache *pc);
void pass_direct_destroy(PassDirect *p);
/* Uploads the shadow parameters (call when they change). */
void pass_direct_set_shadow(PassDirect *p, ShadowMode mode, const ShadowParams *sp);
/* The defines that specialise a program to light `l`'s type and the shadow
 * mode and filter, then `extra`, into `out` (`extra` alone for no light or
 * with `general`): with both fixed at compile time the compiler drops the
 * other types' and filters' code, which llvmpipe would otherwise pay for
 * although no pixel takes it (pcf_sun.json 800x600 with PCF, one thread:
 * 160-210 -> 35-63 ms, the image bit for bit the same, see test_direct). A
 * scene without glossy materials drops the GGX code too. */
void pass_direct_variant_defines(const PassDirect *p, const Scene *s, const Light *l, const char *extra, char *out,
                                 size_t size);
/* Forward: the same radiance, shaded while drawing the scene (seen from
 * `cam`, clusters outside its frustum skipped with `cull`) into `fbo`
 * (width × height): its colour the radiance target, cleared here, its depth
 * what pass_gbuffer_depth_run left, tested at GL_EQUAL so each pixel is
 * shaded once per light by the surface it shows. One draw of the scene per
 * light, the first one's with the emission, the others blended. With
 * `display` (at most one light), `fbo`'s second colour attachment is the
 * final sRGB image, which the draw also writes tone-mapped (× the frame's
 * exposure, clamped, sRGB-encoded: common/tonemap.glsl), so no tone-mapping pass
 * follows, with alpha 0 where the radiance is NaN or infinite (1
 * elsewhere); an `fbo` whose first draw buffer is GL_NONE keeps no radiance
 * (display-only frames). */
void pass_direct_forward(PassDirect *p, const LightStage *ls, const GpuScene *gs, const Camera *cam, bool cull,
                         GLuint fbo, bool display, int width, int height);

/* The Poisson disk of the notes: `n` (≤ SHADOW_MAX_SAMPLES) samples on a
 * spiral of `rings` turns (radius grows as ((i+1)/n)^0.75), in the unit disk. */
void poisson_disk_spiral(int n, int rings, float out[][4]);
/* A Poisson disk of `n` samples in the unit disk by Mitchell's best
 * candidate (deterministic; every prefix is well spread). */
void poisson_disk_best_candidate(int n, float out[][4]);

#endif
