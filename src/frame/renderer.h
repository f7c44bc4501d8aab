/* renderer.h — owns the GPU scene, the light stage, the shared targets, the
 * fixed passes and the selected GI technique, and runs one frame top to
 * bottom:
 *   light stage → G-buffer → direct light → GI technique → [temporal
 *   accumulation] → composite → [supersampling resolve] → tone map → [FXAA].
 * With supersampling N the passes up to the composite run at N× the output
 * size and the resolve box-filters their radiance down to the output size.
 * The scene is borrowed and must outlive the renderer. Settings change
 * through renderer_apply, which remakes only what the change touches. */
#ifndef RTGI_RENDERER_H
#define RTGI_RENDERER_H

#include <stdbool.h>
#include <stdint.h>

#include "core/animation.h"
#include "gi/gi.h"
#include "gpu/gpu_scene.h"
#include "gl/gpu_timer.h"
#include "io/image.h"
#include "gpu/light_stage.h"
#include "frame/pass_direct.h"
#include "frame/pass_finish.h"
#include "frame/pass_fxaa.h"
#include "frame/pass_gbuffer.h"
#include "frame/pass_shade.h"
#include "frame/pass_temporal.h"
#include "frame/pass_vbuffer.h"
#include "core/scene.h"
#include "gpu/targets.h"

/* How frames without a GI technique shade (renderer_forward). */
typedef enum ShadingMode { SHADING_AUTO = 0, SHADING_FORWARD = 1, SHADING_DEFERRED = 2 } ShadingMode;

/* How deferred frames fill the G-buffer (renderer_gbuffer_visibility):
 * drawing the scene with its materials (pass_gbuffer) or a visibility
 * buffer resolved in compute (pass_vbuffer); auto: this device class's
 * faster one. */
typedef enum GbufferMode { GBUFFER_AUTO = 0, GBUFFER_RASTER = 1, GBUFFER_VISIBILITY = 2 } GbufferMode;

/* Post-process anti-aliasing of the tone-mapped image. */
typedef enum AaMode { AA_NONE = 0, AA_FXAA = 1 } AaMode;

typedef struct RenderSettings {
    int width, height;
    ShadowMode shadow;
    GiMode gi;
    float exposure;
    Settings set;     /* the settings table's values (core/settings.h) */
    bool timings;     /* per-pass GPU timer queries */
    bool timing_sync; /* also wall time per pass (glFinish around passes) */
    bool cache;       /* keep light products (shadow maps, RSMs) until their light or size changes */
    bool no_cull;     /* draw every cluster in scene order (culling's baseline in tests) */
    ShadingMode shading; /* direct-only frames (no GI technique): forward, deferred, or chosen by the scene */
    GbufferMode gbuffer; /* deferred frames' G-buffer: raster, visibility, or chosen by the device */
    int ssaa;         /* N×N supersampling with a box filter; 0 or 1: off */
    AaMode aa;        /* post-process AA of the tone-mapped image */
    bool display_only; /* only the final image is read: a forward frame that tone-maps as it shades
                          keeps no radiance (renderer_read_hdr then fails; renderer_count_nonfinite
                          still answers) */
} RenderSettings;

typedef GiStats RenderStats;

typedef struct Renderer {
    const Scene *scene;        /* borrowed */
    RenderSettings settings;
    GpuScene gpu_scene;
    GpuTimer timer;
    ProgramCache programs;     /* every program of the passes, stage and technique */
    LightStage lights;
    GBuffer gbuffer;
    ColorTarget hdr;           /* RGBA32F radiance, output size */
    GLuint forward_fbo;        /* the shading target's radiance + the G-buffer's depth (forward shading) */
    GLuint forward_display_fbo; /* hdr + ldr + the G-buffer's depth: forward frames that tone-map as they
                                   shade (renderer_frame); no supersampling only */
    GLuint forward_ldr_fbo;    /* ldr (drawn by location 1) + the G-buffer's depth: the same frames when
                                  display_only */
    bool radiance_kept;        /* whether the last frame wrote hdr */
    ColorTarget hdr_ss;        /* RGBA32F radiance at N× the output size (supersampling only) */
    ColorTarget ldr;           /* SRGB8_ALPHA8, the final image */
    ColorTarget ldr_pre;       /* SRGB8_ALPHA8, tone-mapped before FXAA (FXAA only) */
    GLuint irradiance;         /* RGBA32F indirect irradiance of the technique */
    GLuint specular;           /* RGBA32F indirect specular radiance, techniques with GI_HAS_SPECULAR */
    GLuint brdf_albedo;        /* RG32F: the GGX lobe's directional albedo table (brdf_albedo_table) */
    GLuint frame_ubo;          /* GpuFrame */
    const GiTechnique *gi;     /* the selected row */
    void *gi_state;            /* its state (NULL for "none") */
    bool gi_failed;            /* a frame's technique run failed (logged); see renderer_frames_whole */
    RenderStats stats;         /* filled by renderer_collect_stats */
    GiFrame last_frame;        /* what the technique saw last (for its stats) */
    PassGbuffer pass_gbuffer;
    PassVbuffer pass_vbuffer;  /* made while renderer_gbuffer_visibility (vbuffer_made) */
    bool vbuffer_made;
    bool software;             /* the GL renderer is a software rasterizer (gl_renderer_is_software) */
    PassDirect pass_direct;
    PassShade pass_shade;
    PassFinish pass_finish;
    PassFxaa pass_fxaa;
    PassTemporal pass_temporal; /* --temporal on: accumulates the irradiance over frames */
    int remakes;               /* renderer_apply calls that remade something (technique, light products,
                                  targets, timer); an exposure change remakes nothing */
    bool apply_failed;         /* the last renderer_apply failed part-way: the next makes everything again */
} Renderer;

/* Needs a current GL 4.5 context. false after logging (destroy it then). */
bool renderer_create(Renderer *r, const Scene *s, const RenderSettings *rs);
void renderer_destroy(Renderer *r);
/* Switches to new settings, remaking only what they touch: nothing for the
 * exposure, the targets and the technique's sized images for the size, the
 * light products for shadow/RSM settings, the technique for its own, the
 * targets and the technique's sized images for supersampling, the final
 * targets for the post-process AA. false
 * after logging: the renderer is then unusable until an apply succeeds,
 * and the next apply makes again what the failed one left unmade, even
 * with the same settings. */
bool renderer_apply(Renderer *r, const RenderSettings *rs);
/* After the scene under the renderer changed (animation_apply at a new
 * time, or a light edited by hand; animation.h): uploads moved vertices
 * (the light products and voxels drawn from the old ones are then redrawn:
 * they key on the geometry's version), remakes a light's products whose
 * map kind changed, and remakes the technique where the scene's bounds
 * moved (its grids are fitted to them). Lights and the camera need no call:
 * every frame reads them. false after logging (as renderer_apply). */
bool renderer_scene_changed(Renderer *r, const SceneChange *c);
/* Makes the next frame a cold one: every cached light product is redrawn. */
void renderer_invalidate(Renderer *r);
/* Renders one frame from `cam`. */
void renderer_frame(Renderer *r, const Camera *cam);
/* Untimed frames before a measurement: `frames` of them and, on a GPU
 * (exact timer queries), as many more as fill RENDERER_WARMUP_S of wall
 * time after them, so that clocks lowered while the CPU worked (compiling,
 * or bench's metrics of the previous technique) are up again when the
 * timed frames start: an idle H200 drops from 1980 to 345 MHz within 1.5 s,
 * and bench's passes had measured up to 3.4 times their time at full clock. */
#define RENDERER_WARMUP_S 0.5
void renderer_warm_up(Renderer *r, const Camera *cam, int frames);
/* Reads the last frame's GI counters back into r->stats (waits for the GPU). */
const RenderStats *renderer_collect_stats(Renderer *r);
/* The time of st's gather passes (pass < 0: all of them summed; else that
 * one) in r's timer: each pass's fastest frame (`fastest`) or its mean, wall
 * time where the timer syncs; 0 where none ran. */
double renderer_gather_ms(const Renderer *r, const RenderStats *st, int pass, bool fastest);

/* GPU memory by owner, from GL's sizes of each object (gl_texture_bytes,
 * gl_buffer_bytes): the technique's own (its stats' gpu_bytes: call
 * renderer_collect_stats first), the light products', the frame's targets
 * and images, and the scene's meshes and textures. */
typedef struct RenderMemory {
    uint64_t gi, lights, frame, scene;
} RenderMemory;
RenderMemory renderer_gpu_memory(const Renderer *r);
uint64_t render_memory_total(const RenderMemory *m);
/* Bytes in MiB, as every memory line prints them. */
static inline double render_mib(uint64_t bytes) { return (double)bytes / (1024.0 * 1024.0); }
/* Supersampling factor (≥ 1) and the size the shading passes run at. */
int renderer_ssaa(const RenderSettings *rs);
/* Whether r's frames shade forward: a depth pre-pass and one draw of the
 * scene per light, no G-buffer. Only without a GI technique (they read the
 * G-buffer); SHADING_AUTO picks forward where the scene has fewer
 * triangles than shading pixels / 64 (see renderer.c). */
bool renderer_forward(const Renderer *r);
/* Whether r's deferred frames fill the G-buffer through the visibility
 * buffer (pass_vbuffer) rather than by drawing the materials
 * (pass_gbuffer): GBUFFER_AUTO picks by device class (see renderer.c). */
bool renderer_gbuffer_visibility(const Renderer *r);
/* Whether the frames so far were drawn as asked: every program they asked
 * for was built and every technique run succeeded. Where a program was not
 * (a shader under --shader-dir that does not compile, say), the frame drew
 * on without it, or with the general program where a specialised one
 * failed, which gives the same image more slowly: the window goes on like
 * that, a command that writes images must not. Where false, each failure
 * was logged as it happened (one line each; a program's names its file,
 * line and program); nothing more is. */
bool renderer_frames_whole(const Renderer *r);
/* Reads back radiance at the output size (row 0 = top). false after
 * logging where the last frame kept none (display_only). */
bool renderer_read_hdr(Renderer *r, ImageF *out);
/* Reads back the GI irradiance image's alpha (--gi vct: ambient visibility)
 * at the shading size, grey in all three channels (row 0 = top). false
 * after logging. */
bool renderer_read_gi_alpha(Renderer *r, ImageF *out);
/* The last frame's pixels of NaN or infinite radiance (*x, *y: the first,
 * row 0 = top), from its radiance or, where it kept none, from the forward
 * draw's count. false after logging if it cannot be read back. */
bool renderer_count_nonfinite(Renderer *r, size_t *count, int *x, int *y);
/* Reads back the tone-mapped image as 8-bit RGB, row 0 = top. Caller frees;
 * NULL after logging if memory runs out. */
uint8_t *renderer_read_ldr(Renderer *r);

#endif
