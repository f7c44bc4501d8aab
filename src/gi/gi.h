/* gi.h — the global-illumination technique table. One row per `--gi`
 * value; a technique is its row, its C file under src/gi/, its shaders under
 * shaders/gi/, its settings rows (settings.c) and its tests.
 *
 * Contract: each frame, after the light stage and the G-buffer, `run`
 * writes the indirect diffuse irradiance E (W/m², RGBA32F, full output
 * resolution) into `GiFrame.irradiance`; the composite adds ρ/π · E ·
 * indirect_scale. A technique with a specular image (`GI_HAS_SPECULAR`)
 * writes outgoing indirect radiance into `GiFrame.specular`, which the
 * composite adds as it is. A technique declares which light products it
 * needs (`needs`), and the light stage makes exactly those.
 *
 * Lifetime: `create` when the technique is selected (and on a settings
 * change it depends on), `resize` when the output size changes, `destroy`
 * when another is selected. `stats` reads counters back from the GPU and is
 * only called when statistics are asked for. */
#ifndef RTGI_GI_H
#define RTGI_GI_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "gpu/gpu_scene.h"
#include "gl/gpu_timer.h"
#include "gpu/light_stage.h"
#include "core/scene.h"
#include "gl/shader.h"
#include "shared/gpu_types.h"
#include "gpu/targets.h"

/* A pass that evaluates samples or VPLs per pixel, named as its GPU timer:
 * `--timings` prints each one's evaluations/s and its fraction of the
 * probe's bound (issue 11). */
#define GI_GATHER_PASSES 2
typedef struct GiGatherPass {
    const char *name;     /* its timer's name (a literal) */
    uint64_t evaluations; /* its sample (or VPL) evaluations in one frame */
} GiGatherPass;

/* Counters of a frame's GI work (read back on request). */
typedef struct GiStats {
    uint32_t vpl_count;       /* VPLs in the buffer (VPL techniques, exhaustive gathers) */
    uint32_t lowres_gathers;  /* rsm-interp: low-resolution gathers */
    uint32_t full_gathers;    /* rsm-interp: pixels that needed a full gather */
    uint32_t gathered_pixels; /* pixels that ran a gather */
    uint64_t vpl_evaluations; /* VPL–pixel evaluations in the shading pass */
    uint64_t vpl_candidates;  /* VPL–pixel pairs visited (tile-list entries for tiled modes) */
    uint32_t tile_overflow;   /* tile-list entries dropped (should be 0) */
    int metalight_regroups;   /* times the metalight grouping was computed */
    int rsm_importance_builds; /* times an RSM's flux pyramid and sample list were built (importance weighting) */
    int volume_builds;        /* lpv: times the volumes were injected and propagated; vct: times radiance was
                                 injected and filtered (both kept while the light products and grids stand) */
    uint64_t gather_evaluations; /* sample (or VPL) evaluations of the gather passes, the sum of: */
    GiGatherPass gather_passes[GI_GATHER_PASSES]; /* (gi_stats_add_gather) */
    int gather_pass_count;
    bool gather_cube;         /* they read cube maps (the probe's matching bound) */
    int gather_map_size;      /* side of the maps they read (the probe's maps for --probe run); 0: none */
    bool gather_vpl;          /* they loop over VPLs in a storage buffer */
    float gather_from_list;   /* fraction of their samples read from a storage-buffer list */
    uint64_t gpu_bytes;       /* GPU memory the technique holds (its own textures and buffers) */
    int visibility_builds;    /* --gi-visibility: times the visibility maps were built */
    uint64_t visibility_bytes; /* --gi-visibility: GPU memory of the visibility maps (in gpu_bytes too) */
    int voxelizations;        /* vct: times the scene was voxelized */
    int region_voxelizations; /* vct: of them, a moved object's region alone */
    uint64_t region_voxels;   /* vct: voxels of the last such region */
    double voxelize_ms;       /* vct: wall time of the last voxelization (glFinish on both sides) */
} GiStats;

/* What a technique is given at creation. */
typedef struct GiCreateInfo {
    const Scene *scene;      /* borrowed, outlives the technique */
    const GiParams *params;  /* the settings it was created with (copied by the technique if kept) */
    const LightStage *lights;/* already configured with the technique's needs (sizes its buffers) */
    ProgramCache *programs;  /* where its programs come from (the cache owns them) */
    int width, height;       /* output size */
    uint64_t geometry_version; /* GpuScene.version of the geometry `scene` holds now */
    bool software;           /* the GL renderer is a software rasterizer (Renderer.software): a device class */
} GiCreateInfo;

/* What a technique reads and writes each frame. */
typedef struct GiFrame {
    const Scene *scene;
    const GpuScene *gpu_scene; /* the scene's meshes (techniques that draw them: vct voxelization) */
    const Camera *camera;
    const GiParams *params;
    float exposure;           /* the frame's exposure (SLC's error bound is relative to it) */
    const GBuffer *gbuffer;
    const LightStage *lights; /* the products declared in `needs` */
    GpuTimer *timer;
    GLuint irradiance;        /* out: RGBA32F E, full resolution */
    GLuint specular;          /* out: RGBA32F radiance, when GI_HAS_SPECULAR */
    GLuint brdf_albedo;       /* RG32F: the GGX lobe's directional albedo (brdf.h; TEX_BRDF_ALBEDO) */
} GiFrame;

enum {
    GI_HAS_SPECULAR = 1u << 0,
    GI_EXHAUSTIVE = 1u << 1, /* brute force, the check of the others: not in bench's default list */
    GI_VISIBILITY = 1u << 2, /* tests the bounce's visibility with --gi-visibility on */
    GI_READS_TWIN = 1u << 3, /* its gathers have a reads-only twin (GiParams.rsm.reads_only; --probe) */
    GI_AO = 1u << 4,         /* writes ambient visibility for --out-ao (GiParams.vct.ao) */
};

/* What a cost model is asked (gi_cost_evaluations). */
typedef struct GiCostQuery {
    const struct GiTechnique *row;
    const GiParams *params;
    const Scene *scene;
    double pixels; /* shading pixels */
} GiCostQuery;

typedef struct GiTechnique {
    const char *name;        /* the --gi value */
    const char *paper;       /* what it implements */
    const char *summary;     /* one line for --help and the UI */
    unsigned flags;          /* GI_HAS_SPECULAR, GI_EXHAUSTIVE, GI_VISIBILITY */
    bool rsm_from_vpl_count; /* its RSM size comes from --vpls */
    /* Light products (LightNeeds) for these settings. */
    unsigned (*needs)(const GiParams *p);
    void *(*create)(const GiCreateInfo *ci); /* NULL after logging */
    bool (*resize)(void *state, int width, int height);
    /* One frame's GI into f->irradiance (and f->specular). false after
     * logging where it could not be made as asked (the frame is then not
     * whole: renderer_frames_whole). */
    bool (*run)(void *state, const GiFrame *f);
    void (*stats)(void *state, const GiFrame *f, GiStats *out);
    void (*destroy)(void *state);
    /* Work of one frame in gather evaluations: an upper bound for estimates
     * before it runs (gi_cost_evaluations; NULL: none). */
    double (*cost)(const GiCostQuery *q);
    /* Its own lines of the --timings report from `st` (NULL: none);
     * `pixels` are the frame's shading pixels. */
    void (*print_stats)(const GiStats *st, double pixels, FILE *out);
} GiTechnique;

/* The technique table, in --gi order: one line per technique, whose row
 * (GiTechnique `row`) lives in the technique's own file. The GiMode enum,
 * the table and the rows' declarations are made from this list; nothing
 * else outside the technique's folder names it (docs/developing.md). */
#define GI_TECHNIQUE_LIST(X)                                                                                     \
    X(GI_NONE, gi_none)                       /* direct light only */                                            \
    X(GI_RSM, gi_rsm)                         /* full-resolution RSM gather */                                   \
    X(GI_RSM_INTERP, gi_rsm_interp)           /* low-res gather + screen-space interpolation */                  \
    X(GI_RSM_INTERLEAVED, gi_rsm_interleaved) /* interleaved sampling + geometry-aware blur */                   \
    X(GI_VPL_ALL, gi_vpl_all)                 /* brute force over every VPL */                                   \
    X(GI_VPL_CLAMPED, gi_vpl_clamped)         /* VPLs cut at a fixed range (biased baseline) */                  \
    X(GI_VPL_SLC, gi_vpl_slc)                 /* stochastic light culling, tiled */                              \
    X(GI_VPL_INTERLEAVED, gi_vpl_interleaved) /* interleaved shading, random VPL subsets */                      \
    X(GI_VPL_METALIGHTS, gi_vpl_metalights)   /* interleaved shading, subsets dealt from metalights */           \
    X(GI_LPV, gi_lpv)                         /* light propagation volumes */                                    \
    X(GI_VCT, gi_vct)                         /* voxel cone tracing */

/* Rows of the technique table, by index. */
typedef enum GiMode {
#define GI_MODE_ENUM(mode, row) mode,
    GI_TECHNIQUE_LIST(GI_MODE_ENUM)
#undef GI_MODE_ENUM
    GI_MODE_COUNT
} GiMode;

#define GI_ROW_EXTERN(mode, row) extern const GiTechnique row;
GI_TECHNIQUE_LIST(GI_ROW_EXTERN)
#undef GI_ROW_EXTERN

/* The table, in --gi order; NULL-terminated. Row 0 is "none". */
extern const GiTechnique *const gi_techniques[];
/* The names, NULL-terminated, in table order (for option parsing). */
const char *const *gi_technique_names(void);
int gi_technique_count(void);
/* Index of `name`, or -1. */
int gi_technique_find(const char *name);

/* Importance-sampled RSM gathers: a pixel spends half its N samples on the
 * paper's disk around its own projection (a Hammersley set of N/2 points
 * after the N of the paper's pattern) and the rest on one of RSM_LIST_SETS
 * (shared/gpu_types.h) independently shifted sets of flux-importance samples. */
static inline int rsm_local_samples(int n) { return n / 2 > 0 ? n / 2 : 1; }
static inline int rsm_far_samples(int n) { return n - rsm_local_samples(n) > 0 ? n - rsm_local_samples(n) : 1; }

/* The GpuGiParams block (RSM gathers, interpolation, interleaving) for
 * these settings at an output of width × height. */
void gi_params_to_gpu(const GiParams *p, int width, int height, GpuGiParams *out);
/* A uniform buffer of `size` bytes updatable with glNamedBufferSubData. */
GLuint gi_ubo_make(GLsizeiptr size, const char *label);

/* Dispatches a compute pass over w×h pixels in 8×8 groups and makes its
 * image and storage writes visible to what follows. */
void gi_dispatch_pixels(int w, int h);
/* How many of the pixels a per-pixel pass visits hold a surface: those at
 * min(g·step + step/2, size − 1) on the lattice of `step` (1: every pixel;
 * rsm-interp's low-res gather and vct's traced lattice: their factor) of
 * f's G-buffer (gi/count_surfaces.comp). Background pixels gather nothing,
 * so GiStats counts only these. Reads the count back (stats time, not a
 * frame's pass); 0 if its program could not be built. */
uint32_t gi_count_surfaces(const GiFrame *f, ProgramCache *pc, int step);

/* Records gather pass `name` (its timer's, a literal) with its evaluations
 * in st->gather_passes and adds them to st->gather_evaluations. */
void gi_stats_add_gather(GiStats *st, const char *name, uint64_t evaluations);
/* Gather evaluations/s (one RSM sample or one VPL at one pixel) assumed
 * for estimates before a device has been measured; the window then uses
 * the rate it measures. llvmpipe on this project's shared 2-core machine,
 * quiet: gather_evals_per_s of rsm 9.1e7, vpl-all 7.4e7 to 9.1e7 (64² to
 * 128²), vpl-slc 7.7e7, vpl-clamped 6.9e7; `rtgi probe`: ssbo_vpl 8.8e7,
 * 2d_fetch2 6.6e7, cube_fetch2 4.0e7. Taken at about half the gathers'
 * rate (the machine is shared; an estimate errs towards slow). It was
 * 1.5e7, from an earlier, busier probe (1.1e7 to 1.8e7): VPL techniques
 * were then estimated 10 to 50 times their wall time. */
#define GI_COST_DEFAULT_EVALS_PER_S 4e7
/* Work of one frame of technique `gi` (a row index of gi_techniques) with
 * `p` on scene `s` at `px` shading pixels, in gather evaluations: an upper
 * bound for estimates before it runs (the row's `cost`; src/gi/cost.c says
 * how the models were fitted). */
double gi_cost_evaluations(int gi, const GiParams *p, const Scene *s, double px);
/* For the rows' cost models: every RSM texel of every light (each face of
 * a cube), or with `lit_only` only the texels that can hold a lit surface
 * (about --vpls per light for the VPL rows). */
double gi_cost_rsm_texels(const GiCostQuery *q, bool lit_only);
/* The LPV and VCT models count cell updates and voxel fetches, fitted to
 * wall time at 1.5e7 of them per second: each costs this many gather
 * evaluations at GI_COST_DEFAULT_EVALS_PER_S. */
#define GI_COST_VOLUME_EVAL (GI_COST_DEFAULT_EVALS_PER_S / 1.5e7)
/* The VPL rows' --timings lines (vpl_count, vpl_evaluations, ...); LPV's too. */
void gi_print_vpl_stats(const GiStats *st, double pixels, FILE *out);
/* Seconds of that work at `evals_per_s` (a measured rate, or
 * GI_COST_DEFAULT_EVALS_PER_S): the gather's share of a frame. */
double gi_cost_seconds(int gi, const GiParams *p, const Scene *s, double px, double evals_per_s);
/* A cubic grid of n cells per side around the box [bmin, bmax], centred on
 * it with a cell of margin on each side of its largest extent: writes the
 * grid's low corner and returns the cell size (LPV's single cascade, VCT's
 * single volume). */
float gi_grid_around(const float bmin[3], const float bmax[3], int n, float corner[3]);
/* Nested grids around the camera (LPV's cascades, VCT's clipmap), n cells
 * per side. The side the coarsest needs to hold the box [bmin, bmax] from
 * `cam`: twice the box's farthest extent from cam along an axis, plus two
 * cells each side for the snapping (n > 4; else no margin). */
float gi_clipmap_extent(const float bmin[3], const float bmax[3], const float cam[3], int n);
/* Level k of `levels` such grids, the coarsest (k = levels − 1) `coarsest`
 * wide and each finer one half the cell of the next: its low corner snapped
 * to whole cells with cam in its middle cell, and its cell size in [3]. */
void gi_clipmap_level(float coarsest, int n, int levels, int k, const float cam[3], float corner_cell[4]);

#endif
