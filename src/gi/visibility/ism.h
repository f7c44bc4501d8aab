/* ism.h — visibility of the bounce from imperfect shadow maps (Ritschel,
 * Grosch, Kim, Seidel, Dachsbacher & Kautz 2008), SPEC §9: the scene as a
 * few thousand point samples per map, splatted into small paraboloid depth
 * maps (one per VPL, or per block of an RSM's texels) in one atlas, holes
 * filled by pull-push; a gather multiplies each VPL's (or RSM sample's)
 * contribution by the map's depth test (shaders/gi/visibility/ism.glsl).
 * The stochastic light culling paper (Tokuyoshi & Harada 2016) shaded its
 * VPLs with visibility this way.
 *
 * Two kinds of source:
 *   ISM_FROM_VPLS  map i is made from VPL i of the light stage's buffer
 *                  (the VPL techniques, rsm --rsm-exhaustive): exact sources
 *   ISM_FROM_RSM   the RSM of each light cut into B×B blocks per layer
 *                  (B² ≈ ism_maps / layers); a block's map is made from
 *                  its brightest texel (centre-weighted, reps.comp), and
 *                  every sample of the block reads it (the RSM gathers,
 *                  whose samples are any of the map's texels)
 * Passes (GPU timer scopes): ism_reps (ISM_FROM_RSM: the blocks'
 * representatives), ism_splat (clear, points into the maps), ism_pull_push
 * (holes). The points are drawn once, on the CPU, when the maps are made
 * (uniform over the scene's area, alpha-masked holes excluded, sorted by
 * the cells of a 32³ grid); a map splats half its points from the whole
 * scene and half from the 3×3×3 cells around its source. The maps
 * are rebuilt only when the light products change
 * (light_stage_products_key, and the VPL extraction); the points are drawn
 * again when an object moves (GpuScene.version).
 * Inputs: the scene (borrowed), the light stage. Owns: the atlas, the
 * points, the representatives, its parameter block. */
#ifndef RTGI_ISM_H
#define RTGI_ISM_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>

#include "gi/gi.h"

typedef enum IsmSource { ISM_FROM_VPLS, ISM_FROM_RSM } IsmSource;

typedef struct Ism {
    IsmSource source;
    ProgramCache *pc;      /* borrowed: owns the programs */
    int size;              /* texels per side of one map */
    int points;            /* points splatted into each map: half the scene's, half near its source */
    int per_row;           /* maps per atlas row (a power of two) */
    uint32_t maps;         /* maps in the atlas */
    uint32_t maps_per_light; /* ISM_FROM_RSM: maps of each light's blocks */
    int lights;
    int *blocks;           /* ISM_FROM_RSM: blocks per side of each light's layers */
    int *block_texels;     /* ISM_FROM_RSM: texels per side of a block */
    GLuint atlas;          /* R32UI, per_row·size × rows·size: distances' bits; mips: pull-push's levels */
    int levels;            /* the atlas's mips: one texel per map at the last */
    GLuint point_buffer;   /* vec4[point_count], sorted by grid cell */
    uint32_t point_count;  /* a power of two */
    GLuint cells;          /* uint[grid³ + 1]: where each cell's points start */
    const Scene *scene;    /* borrowed: the points are drawn from it */
    uint64_t points_version; /* GpuScene.version the points were drawn at */
    GLuint reps;           /* ISM_FROM_RSM: uvec4 per map */
    GLuint ubo;            /* GpuIsmParams, per light (ISM_FROM_RSM: its block layout) */
    GpuIsmParams gpu;      /* as last uploaded */
    GLuint splat[2][2];    /* [from rsm][cube] (from VPLs: [0][0]) */
    GLuint reps_prog[2];   /* [cube] */
    GLuint pull_push;
    uint64_t built_key;    /* what the maps were built from (0: nothing) */
    int builds;            /* times they were built */
} Ism;

/* Makes the maps for technique parameters p (ism_size, ism_points,
 * ism_maps) over the light stage's products: ISM_FROM_VPLS sizes the
 * atlas from the VPL buffer's capacity. false after logging. */
bool ism_create(Ism *m, IsmSource source, const GiCreateInfo *ci);
void ism_destroy(Ism *m);
/* ism_create into a new allocation: NULL after logging (`tag`: the
 * technique's log tag, for running out of memory). */
Ism *ism_new(IsmSource source, const GiCreateInfo *ci, const char *tag);
/* ism_destroy and free; NULL does nothing. */
void ism_free(Ism *m);
/* Builds the maps if the light products changed since the last build
 * (timer scopes ism_reps, ism_splat, ism_pull_push). */
void ism_update(Ism *m, const GiFrame *f);
/* Binds the atlas (TEX_ISM), the parameter block (UBO_ISM) and, from an
 * RSM, the representatives (SSBO_ISM_REPS), light i's block layout and
 * its first map (LOC_ISM_MAP_BASE of `program`) for a gather of light i. */
void ism_bind(Ism *m, const LightStage *ls, GLuint program, int light);
/* GPU memory the maps hold. */
uint64_t ism_gpu_bytes(const Ism *m);
/* The defines that build a gather with visibility from these maps:
 * "#define GI_VISIBILITY\n" and the source's (ISM_FROM_RSM); "" for NULL. */
const char *ism_defines(const Ism *m);

#endif
