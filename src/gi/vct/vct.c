/* vct.c — voxel cone tracing (Crassin, Neyret, Sainz, Green, Eisemann
 * 2011, "Interactive Indirect Illumination Using Voxel Cone Tracing"),
 * SPEC §6; one row of the technique table, `--gi vct`. Passes:
 *   vct_voxelize  once, and again when the scene's geometry moves (an
 *                 animated object: GpuScene.version; with the compute
 *                 voxelization only the voxels within a voxel of where
 *                 the moved triangles were and are, from the clusters that
 *                 reach them, else the whole volume; no voxel of where an
 *                 object was stays): each
 *                 triangle's voxel columns along its dominant axis, its
 *                 pixel squares conservatively and each voxel by an exact
 *                 triangle–box test (shaders/gi/vct/voxelize.*), found by
 *                 compute (--vct-voxelize compute, voxelize.comp: a thread
 *                 per triangle, large ones in tiles of columns) or by
 *                 rasterizing into an N×N attachment-less framebuffer
 *                 (raster: voxelize.geom/.frag); albedo, normal and a count
 *                 summed in fixed point with atomics (a voxel's first
 *                 sample lists it as opaque), then resolved over the
 *                 opaque list into the albedo/opacity and normal volumes
 *   vct_inject    per light: each opaque voxel's outgoing diffuse radiance
 *                 ρ/π · E · V, V from the light's shadow map
 *   vct_mips      without --vct-aniso the isotropic mip chain (box filter
 *                 of premultiplied radiance and opacity, mip.comp), with
 *                 it the six directional volumes from level 0 by
 *                 front-to-back compositing (one texture per axis holding
 *                 both signs: GpuVctParams)
 *   vct_bounce    (--vct-bounces 2) every voxel gathers with the diffuse
 *                 cones and adds ρ/π · E; its mips are rebuilt
 *   vct_trace     per pixel (with --vct-trace-scale s > 1: per s×s block,
 *                 at its centre pixel): the diffuse cone set → irradiance E
 *                 (alpha: ambient visibility with --vct-ao), one specular
 *                 cone along the reflection → the specular image
 *   vct_upsample  (s > 1) every pixel: the mean of the traced pixels on its
 *                 surface around it, or its own cones where there are none
 * Volume: N³ voxels over a cube around the scene bounds (one voxel of
 * margin each side), or with --vct-levels L > 1 a clipmap of L levels of
 * N³ voxels centred on the camera, each twice the last, the coarsest
 * holding the scene; the levels are stacked along z in one texture per
 * volume (power-of-two N keeps every mip's levels apart) and revoxelized
 * when the camera moves a level by a voxel.
 * Inputs: the scene's meshes, the light stage's shadow maps, the G-buffer.
 * Outputs: irradiance (alpha: ambient visibility), specular radiance.
 * Owns: its volumes, the voxelization's sums and work buffer, framebuffer,
 * UBO, low-resolution images (programs come from the cache). */
#include "gi/vct/vct.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cglm/cglm.h>

#include "gi/gi.h"
#include "gl/gl_resources.h"
#include "gl/gpu_budget.h"
#include "base/log.h"
#include "gl/shader.h"
#include "gpu/targets.h"
#include "base/util.h"

enum { ANISO_AXES = 3 }; /* directional volumes: one texture per axis, both signs */

/* The compute voxelization's program per kind of material: llvmpipe runs
 * the texture code behind a uniform branch, fetches included. */
typedef enum VoxelizeKind {
    VOXELIZE_OPAQUE,     /* textured, no alpha mask (OPAQUE_DRAW: no level-0 alpha read) */
    VOXELIZE_UNTEXTURED, /* neither texture nor mask (UNTEXTURED) */
    VOXELIZE_MASKED,     /* alpha-masked */
    VOXELIZE_KINDS
} VoxelizeKind;

typedef struct VctGi {
    GiParams params;
    ProgramCache *pc;        /* borrowed: owns the programs */
    int n;                   /* voxels per side of a level */
    int clip;                /* clipmap levels L (1: one volume over the bounds) */
    int levels;              /* mips of the radiance volumes */
    vec3 bmin, bmax;         /* scene bounds */
    float coarsest;          /* clipmap: side of the coarsest level (m); 0 before the first frame */
    GLuint albedo, normal;   /* RGBA16F N×N×N·L, one level */
    GLuint radiance[2];      /* RGBA16F N×N×N·L with mips: direct; direct + bounce (--vct-bounces 2) */
    GLuint aniso[ANISO_AXES];/* RGBA16F N/2 × N/2 × 2·S·L with mips (--vct-aniso; GpuVctParams) */
    GLuint fbo;              /* attachment-less N×N, for the raster voxelization */
    GLuint sums;             /* SSBO: uint[8] per voxel, the voxelization's fixed-point sums; all 0 between voxelizations */
    GLuint work;             /* SSBO (--vct-voxelize compute): per level and submesh a header, then the large triangles */
    uint32_t work_headers;   /* headers in `work`: levels × submeshes */
    GLuint opaque;           /* SSBO: the opaque voxels (gi/vct/voxelize.glsl appends them), a 4-word header (the count) first */
    uint32_t opaque_capacity;/* entries: N³·L / VCT_OPAQUE_SHARE */
    GLuint args;             /* the indirect dispatches over the list or every voxel (gi/vct/args.comp) */
    GLuint ubo;              /* GpuVctParams */
    GLuint voxelize_tris[3], voxelize_tiles[3]; /* voxelize.comp (--vct-voxelize compute) per VoxelizeKind */
    GLuint voxelize, resolve, resolve_list, inject, mip, aniso_prog, aniso_first, bounce, trace, upsample; /* programs */
    GLuint bounce_list;      /* bounce.comp over the opaque-voxel list (OPAQUE_LIST) */
    GLuint list[3];          /* list.comp after a region (compute): every voxel, LIST_FILTER, LIST_REGION */
    GLuint opaque_prev;      /* SSBO (compute): the opaque list before a region's revoxelization (swapped with opaque) */
    GLuint args_prog;        /* args.comp */
    GLuint probe;            /* probe.comp (vct_probe, tests), built on first use */
    int scale;               /* --vct-trace-scale */
    GLuint low_irradiance, low_specular; /* RGBA32F ⌈w/scale⌉ × ⌈h/scale⌉ (scale > 1) */
    GpuVctParams gpu;        /* as uploaded */
    bool voxelized;          /* the volumes hold the scene */
    uint64_t voxels_version; /* the geometry they hold (GpuScene.version): a moved object revoxelizes */
    int voxelizations;
    int region_voxelizations;/* of them, of a moved object's region alone (voxelize with a region) */
    uint64_t region_voxels;  /* voxels of the last region, every level */
    uint64_t built_for;      /* the light products and voxels the radiance volumes hold (0: none) */
    int builds;              /* times radiance was injected and filtered */
    double voxelize_ms;      /* wall time of the last voxelization timed (vct_voxelize_wall_ms) */
    uint64_t bytes;          /* GPU memory held by the volumes */
    int width, height;
} VctGi;

static unsigned vct_needs(const GiParams *p)
{
    (void)p;
    return LIGHT_NEEDS_SHADOW_MAPS;
}

/* ---- Diffuse cone sets ---------------------------------------------------- */

/* Directions: the zenith and rings at polar angles (degrees), each ring's
 * cones spread evenly in azimuth (rings offset by half a step). Each cone's
 * weight is ∫cosθ dω over its Voronoi cell of the hemisphere (numerically;
 * they sum to π), and its half-angle α gives its cone the cell's solid
 * angle, 2π(1 − cos α) = Ω. The rings sit at 50–60° rather than nearer the
 * horizon: a cone whose footprint reaches below the surface's plane sees
 * the surface's own voxels (measured on the Cornell box, 64³: ring 45°,
 * 52°, 60° → relMSE 0.0173, 0.0177, 0.0189 against one-bounce). */
int vct_cone_set(int set, float dirs[][4], float *tan_half)
{
    static const struct { int count; float theta; } rings[3][3] = {
        {{5, 50.f}},                 /* 6 = 1 + 5 */
        {{8, 50.f}},                 /* 9 = 1 + 8 */
        {{5, 30.f}, {10, 60.f}},     /* 16 = 1 + 5 + 10 */
    };
    int k = 0;
    dirs[k][0] = 0.f, dirs[k][1] = 0.f, dirs[k][2] = 1.f;
    k++;
    for (int r = 0; r < 3 && rings[set][r].count; r++) {
        float th = glm_rad(rings[set][r].theta);
        for (int i = 0; i < rings[set][r].count; i++) {
            float ph = 2.f * GLM_PIf * ((float)i + 0.5f * (float)r) / (float)rings[set][r].count;
            dirs[k][0] = sinf(th) * cosf(ph);
            dirs[k][1] = sinf(th) * sinf(ph);
            dirs[k][2] = cosf(th);
            k++;
        }
    }
    /* NP a multiple of 40, so that the grid has every set's symmetry (5 and
     * 8 cones a ring, 10 offset by half a step): with NP = 512 the 16-cone
     * set's five 30° cones, equal by symmetry, got weights 1% apart
     * (tests/test_vct.c, cone_weights_integrate_the_cosine_lobe). */
    double w[VCT_MAX_CONES] = {0}, omega[VCT_MAX_CONES] = {0};
    enum { NT = 512, NP = 640 };
    for (int i = 0; i < NT; i++) {
        double th = (i + 0.5) * (GLM_PI / 2) / NT, dth = (GLM_PI / 2) / NT;
        for (int j = 0; j < NP; j++) {
            double ph = (j + 0.5) * 2 * GLM_PI / NP, dph = 2 * GLM_PI / NP;
            double d[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
            int best = 0;
            double bd = -2;
            for (int c = 0; c < k; c++) {
                double dd = d[0] * dirs[c][0] + d[1] * dirs[c][1] + d[2] * dirs[c][2];
                if (dd > bd)
                    bd = dd, best = c;
            }
            double dw = sin(th) * dth * dph;
            omega[best] += dw;
            w[best] += cos(th) * dw;
        }
    }
    for (int c = 0; c < k; c++) {
        dirs[c][3] = (float)w[c];
        double cos_a = 1 - omega[c] / (2 * GLM_PI);
        tan_half[c] = (float)(sqrt(fmax(1 - cos_a * cos_a, 0)) / fmax(cos_a, 1e-6));
    }
    return k;
}

/* ---- Lifetime ---------------------------------------------------------------- */

static void vct_destroy(void *state)
{
    VctGi *v = state;
    if (!v)
        return;
    gl_texture3d_destroy(&v->albedo);
    gl_texture3d_destroy(&v->normal);
    for (int i = 0; i < 2; i++)
        gl_texture3d_destroy(&v->radiance[i]);
    for (int i = 0; i < ANISO_AXES; i++)
        gl_texture3d_destroy(&v->aniso[i]);
    gl_fbo_destroy(&v->fbo);
    glDeleteBuffers(1, &v->sums);
    glDeleteBuffers(1, &v->work);
    glDeleteBuffers(1, &v->opaque);
    glDeleteBuffers(1, &v->opaque_prev);
    glDeleteBuffers(1, &v->args);
    glDeleteBuffers(1, &v->ubo);
    glDeleteTextures(1, &v->low_irradiance);
    glDeleteTextures(1, &v->low_specular);
    free(v);
}

/* The low-resolution images the cones are traced into (scale > 1). */
static bool make_low_images(VctGi *v)
{
    glDeleteTextures(1, &v->low_irradiance);
    glDeleteTextures(1, &v->low_specular);
    v->low_irradiance = v->low_specular = 0;
    if (v->scale == 1)
        return true;
    int lw = (v->width + v->scale - 1) / v->scale, lh = (v->height + v->scale - 1) / v->scale;
    v->low_irradiance = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, lw, lh, "vct.low_irradiance");
    v->low_specular = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, lw, lh, "vct.low_specular");
    return v->low_irradiance && v->low_specular; /* gl_texture_make logs a failure */
}

static bool vct_resize(void *state, int w, int h)
{
    VctGi *v = state;
    v->width = w;
    v->height = h;
    return make_low_images(v);
}

/* Every VCT program has the clipmap's level count compiled in
 * (VCT_CLIP_LEVELS, gi/vct/volume.glsl): with one level the cone steps'
 * level lookups fold away, and the steps below mip 1 are a loop of their
 * own (gi/vct/cone.glsl). */
static GLuint program(VctGi *v, const char *label, const char *vert, const char *geom, const char *frag,
                      const char *comp, const char *defines)
{
    char all[256];
    snprintf(all, sizeof all, "#define VCT_CLIP_LEVELS %d\n%s", v->clip, defines ? defines : "");
    return program_cache_get(v->pc, &(ShaderProgramDesc){.label = label, .vert = vert, .geom = geom, .frag = frag,
                                                          .comp = comp, .defines = all});
}

/* The directional volumes' side: N/2, at least 1. */
static int aniso_side(int n)
{
    return n / 2 > 0 ? n / 2 : 1;
}

/* The depth S of a directional slab (GpuVctParams.aniso_slab): N/2
 * rounded up to a multiple of 2^(levels − 2), so that each of the
 * directional chain's levels − 1 mips halves it exactly and the slabs stay
 * apart (S = N/2 when N is a power of two). */
static int aniso_slab(int n, int levels)
{
    int half = aniso_side(n), m = levels > 2 ? 1 << (levels - 2) : 1;
    return (half + m - 1) / m * m;
}

/* Bytes of an RGBA16F box w × h × d with `levels` mips. */
static uint64_t box_bytes(int w, int h, int d, int levels)
{
    uint64_t b = 0;
    for (int l = 0; l < levels; l++) {
        uint64_t x = (uint64_t)(w >> l > 0 ? w >> l : 1), y = (uint64_t)(h >> l > 0 ? h >> l : 1);
        b += x * y * (uint64_t)(d >> l > 0 ? d >> l : 1) * 8u;
    }
    return b;
}

/* Mip levels of the isotropic radiance volumes: with the directional
 * volumes the cones read its level 0 alone (cone.glsl's vct_sample: the
 * directional chain starts from it), so it has no chain of its own. */
static int radiance_levels(const GiParams *p, int levels)
{
    return p->vct.aniso && p->vct.size >= 2 ? 1 : levels;
}

/* Entries of the opaque-voxel list: N³·L / VCT_OPAQUE_SHARE. */
static uint32_t opaque_capacity(int n, int clip)
{
    return (uint32_t)((uint64_t)clip * n * n * n / VCT_OPAQUE_SHARE);
}

/* Words of the compute voxelization's work buffer on `s`: a header of 4
 * per level and submesh, a slot per level and triangle; 0 for raster. */
static uint64_t work_words(const GiParams *p, const Scene *s)
{
    if (p->vct.voxelize != VCT_VOXELIZE_COMPUTE)
        return 0;
    return (uint64_t)p->vct.levels * (4u * (uint64_t)s->submesh_count + s->index_count / 3);
}

/* GPU memory the settings' volumes, opaque list and voxelization buffers
 * hold on `s` (vct_stats' figure). */
static uint64_t vct_bytes(const GiParams *p, const Scene *s)
{
    int n = p->vct.size, clip = p->vct.levels;
    int levels = gl_mip_levels(n, n, n);
    int half = aniso_side(n), slab = aniso_slab(n, levels);
    uint64_t bytes = (uint64_t)clip * (2 * box_bytes(n, n, n, 1) + (uint64_t)(p->vct.bounces > 1 ? 2 : 1) *
                                                                       box_bytes(n, n, n, radiance_levels(p, levels))) +
                     (p->vct.aniso ? ANISO_AXES * box_bytes(half, half, 2 * slab * clip, levels - 1) : 0);
    uint64_t sums = 32u * (uint64_t)clip * n * n * n;
    uint64_t lists = p->vct.voxelize == VCT_VOXELIZE_COMPUTE ? 2 : 1; /* and the list before a region */
    return bytes + lists * 4u * (4u + (uint64_t)opaque_capacity(n, clip)) + sums + 4u * work_words(p, s);
}

/* Every program the settings call for; false after the first that failed
 * (it logged its one line; as lpv_programs). */
static bool vct_programs(VctGi *v, bool software)
{
    const GiParams *p = &v->params;
    /* The cone tracers read the directional volumes only when compiled
     * with VCT_ANISO (gi/vct/cone.glsl): llvmpipe runs both sides of a
     * branch on a uniform, fetches included. */
    const char *cones = p->vct.aniso && v->n >= 2 ? "#define VCT_ANISO\n" : NULL;
    char list_defs[64];
    snprintf(list_defs, sizeof list_defs, "%s#define OPAQUE_LIST\n", cones ? cones : "");
    bool ok = true;
    if (p->vct.voxelize == VCT_VOXELIZE_COMPUTE) {
        static const char *const kinds[VOXELIZE_KINDS] = {"#define OPAQUE_DRAW\n", "#define UNTEXTURED\n", ""};
        /* Larger triangles walk their own columns on a software rasterizer
         * (voxelize.comp, SMALL_COLUMNS) */
        const char *small = software ? "#define SMALL_COLUMNS 1024\n" : "";
        for (int u = 0; ok && u < VOXELIZE_KINDS; u++) {
            char tris[96], tiles[96];
            snprintf(tris, sizeof tris, "%s%s", small, kinds[u]);
            snprintf(tiles, sizeof tiles, "#define VOXELIZE_TILES\n%s%s", small, kinds[u]);
            ok = (v->voxelize_tris[u] = program(v, "vct_voxelize_tris", NULL, NULL, NULL, "gi/vct/voxelize.comp", tris)) &&
                 (v->voxelize_tiles[u] = program(v, "vct_voxelize_tiles", NULL, NULL, NULL, "gi/vct/voxelize.comp", tiles));
        }
    } else {
        ok = (v->voxelize = program(v, "vct_voxelize", "frame/scene.vert", "gi/vct/voxelize.geom",
                                    "gi/vct/voxelize.frag", NULL, NULL));
    }
    ok = ok && (v->resolve = program(v, "vct_resolve", NULL, NULL, NULL, "gi/vct/resolve.comp", NULL)) &&
              (v->resolve_list =
                   program(v, "vct_resolve_list", NULL, NULL, NULL, "gi/vct/resolve.comp", "#define OPAQUE_LIST\n")) &&
              (p->vct.voxelize != VCT_VOXELIZE_COMPUTE ||
               ((v->list[0] = program(v, "vct_list", NULL, NULL, NULL, "gi/vct/list.comp", NULL)) &&
                (v->list[1] = program(v, "vct_list_filter", NULL, NULL, NULL, "gi/vct/list.comp",
                                      "#define LIST_FILTER\n")) &&
                (v->list[2] = program(v, "vct_list_region", NULL, NULL, NULL, "gi/vct/list.comp",
                                      "#define LIST_REGION\n")))) &&
              (v->args_prog = program(v, "vct_args", NULL, NULL, NULL, "gi/vct/args.comp", NULL)) &&
              (v->inject = program(v, "vct_inject", NULL, NULL, NULL, "gi/vct/inject.comp", NULL)) &&
              (v->mip = program(v, "vct_mip", NULL, NULL, NULL, "gi/vct/mip.comp", NULL)) &&
              (v->aniso_prog = program(v, "vct_aniso", NULL, NULL, NULL, "gi/vct/aniso.comp", NULL)) &&
              (v->aniso_first =
                   program(v, "vct_aniso_first", NULL, NULL, NULL, "gi/vct/aniso.comp", "#define MODE_FIRST\n")) &&
              (v->bounce = program(v, "vct_bounce", NULL, NULL, NULL, "gi/vct/bounce.comp", cones)) &&
              (v->trace = program(v, "vct_trace", NULL, NULL, NULL, "gi/vct/trace.comp", cones)) &&
              (v->upsample = program(v, "vct_upsample", NULL, NULL, NULL, "gi/vct/upsample.comp", NULL));
    /* Not needed for a frame: without it vct_run bounces over every voxel
     * (the window goes on so; render and bench fail, as for any program
     * that did not build). */
    if (ok && p->vct.bounces > 1)
        v->bounce_list = program(v, "vct_bounce_list", NULL, NULL, NULL, "gi/vct/bounce.comp", list_defs);
    return ok;
}

/* Every volume vct_bytes counts, the voxelization's sums (cleared: the
 * resolve clears them after each voxelization), work buffer and
 * framebuffer, the low-resolution images, the opaque list and the
 * parameter block; false after one failed (it logged). */
static bool vct_volumes(VctGi *v, const Scene *s)
{
    const GiParams *p = &v->params;
    int n = v->n, clip = v->clip, levels = v->levels;
    int half = aniso_side(n), slab = aniso_slab(n, levels);
    int d = n * clip; /* the levels stacked along z */
    bool ok = (v->albedo = gl_texture3d_make(GL_RGBA16F, n, n, d, 1, TEX_FILTER_NEAREST, "vct.albedo")) &&
              (v->normal = gl_texture3d_make(GL_RGBA16F, n, n, d, 1, TEX_FILTER_NEAREST, "vct.normal")) &&
              (v->radiance[0] = gl_texture3d_make(GL_RGBA16F, n, n, d, radiance_levels(p, levels), TEX_FILTER_LINEAR,
                                                  "vct.radiance"));
    if (ok && p->vct.bounces > 1)
        ok = (v->radiance[1] = gl_texture3d_make(GL_RGBA16F, n, n, d, radiance_levels(p, levels), TEX_FILTER_LINEAR,
                                                 "vct.radiance2"));
    for (int i = 0; ok && p->vct.aniso && n >= 2 && i < ANISO_AXES; i++)
        ok = (v->aniso[i] = gl_texture3d_make(GL_RGBA16F, half, half, 2 * slab * clip, levels - 1, TEX_FILTER_LINEAR,
                                              "vct.aniso")) != 0;
    ok = ok && (v->fbo = gl_fbo_empty_make(n, n, 0, 0, "vct.voxelize")) && make_low_images(v);
    ok = ok && (v->sums = gl_buffer_make(32u * (uint64_t)clip * n * n * n, NULL, GL_DYNAMIC_STORAGE_BIT,
                                         "vct.voxel_sums"));
    if (ok)
        glClearNamedBufferData(v->sums, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, NULL);
    uint64_t words = work_words(p, s);
    v->work_headers = (uint32_t)clip * (uint32_t)s->submesh_count;
    if (ok && words)
        ok = (v->work = gl_buffer_make(4u * words, NULL, GL_DYNAMIC_STORAGE_BIT, "vct.voxelize_work")) != 0;
    ok = ok && (v->opaque = gl_buffer_make(4u * (4u + (uint64_t)v->opaque_capacity), NULL, GL_DYNAMIC_STORAGE_BIT,
                                           "vct.opaque"));
    if (ok && p->vct.voxelize == VCT_VOXELIZE_COMPUTE)
        ok = (v->opaque_prev = gl_buffer_make(4u * (4u + (uint64_t)v->opaque_capacity), NULL, GL_DYNAMIC_STORAGE_BIT,
                                              "vct.opaque_prev"));
    ok = ok && (v->args = gl_buffer_make(sizeof(GLuint[4][4]), NULL, 0, "vct.dispatch_args"));
    return ok && (v->ubo = gi_ubo_make(sizeof(GpuVctParams), "vct.params"));
}

/* The parameter block, uploaded. One level: a cube around the bounds with
 * a voxel of margin each side (placed here); a clipmap is placed per frame
 * around the camera. */
static void vct_params_upload(VctGi *v)
{
    const GiParams *p = &v->params;
    int n = v->n;
    GpuVctParams *u = &v->gpu;
    float voxel = gi_grid_around(v->bmin, v->bmax, n, u->level[0]);
    u->level[0][3] = voxel;
    u->levels = v->clip;
    u->mips = v->levels;
    u->size = n;
    u->aniso = p->vct.aniso && v->aniso[0] ? 1 : 0;
    u->aniso_slab = aniso_slab(n, v->levels);
    float tan_half[VCT_MAX_CONES] = {0};
    u->cones = vct_cone_set(p->vct.cones, u->cone, tan_half);
    for (int i = 0; i < u->cones; i++)
        u->cone_aperture[i][0] = tan_half[i];
    u->step = p->vct.step;
    u->ao_range = 0.15f * voxel * (float)n;
    u->conservative = p->vct.conservative ? 1 : 0;
    u->roughness = p->vct.roughness;
    u->f0 = p->vct.f0;
    u->max_distance = sqrtf(3.f) * voxel * (float)n;
    glNamedBufferSubData(v->ubo, 0, sizeof *u, u);
}

static void *vct_create(const GiCreateInfo *ci)
{
    const GiParams *p = ci->params;
    int n = p->vct.size, clip = p->vct.levels;
    if (clip > 1 && (n & (n - 1))) {
        log_error("vct", "--vct-levels %d: the clipmap needs a power-of-two --vct-size (got %d)", clip, n);
        return NULL;
    }
    uint64_t bytes = vct_bytes(p, ci->scene), peak = bytes;
    char what[64];
    snprintf(what, sizeof what, "--vct-size %d with --vct-levels %d", n, clip);
    if (!gpu_budget_check(peak, what))
        return NULL;
    VctGi *v = calloc(1, sizeof *v);
    if (!v) {
        log_error("vct", "out of memory");
        return NULL;
    }
    v->params = *p;
    v->pc = ci->programs;
    v->n = n;
    v->clip = clip;
    v->levels = gl_mip_levels(n, n, n);
    v->bytes = bytes;
    v->opaque_capacity = opaque_capacity(n, clip);
    v->scale = p->vct.trace_scale > 1 ? p->vct.trace_scale : 1;
    v->width = ci->width;
    v->height = ci->height;
    glm_vec3_copy((float *)ci->scene->bounds_min, v->bmin);
    glm_vec3_copy((float *)ci->scene->bounds_max, v->bmax);
    if (!vct_programs(v, ci->software) || !vct_volumes(v, ci->scene)) { /* what failed logged its line */
        vct_destroy(v);
        return NULL;
    }
    vct_params_upload(v);
    return v;
}

/* Clipmap: level k has voxels of coarsest/N/2^(L-1-k), its origin snapped
 * to whole voxels around the camera; the coarsest holds the scene bounds
 * around the camera (remade 25% larger, and everything revoxelized, when
 * the camera moves so far that it no longer does). Clears `voxelized`
 * when a level moved. */
static void place_levels(VctGi *v, const Camera *cam)
{
    if (v->clip == 1)
        return;
    GpuVctParams *u = &v->gpu;
    float need = gi_clipmap_extent(v->bmin, v->bmax, cam->position, v->n);
    if (v->coarsest < need) { /* grown with a quarter to spare, so that a moving camera rarely regrows it */
        v->coarsest = 1.25f * need;
        v->voxelized = false;
    }
    for (int k = 0; k < v->clip; k++) {
        vec4 o;
        gi_clipmap_level(v->coarsest, v->n, v->clip, k, cam->position, o);
        if (memcmp(o, u->level[k], sizeof o)) {
            glm_vec4_copy(o, u->level[k]);
            v->voxelized = false;
        }
    }
    u->max_distance = sqrtf(3.f) * v->coarsest;
    glNamedBufferSubData(v->ubo, 0, sizeof *u, u);
}

/* ---- Passes -------------------------------------------------------------------- */

/* A 4×4×4-group compute pass over a side × side × depth box. */
static void dispatch_box(int side, int depth)
{
    GLuint g = (GLuint)(side + 3) / 4;
    glDispatchCompute(g, g, (GLuint)(depth + 3) / 4);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

/* The same over the n × n × n·layers stacked volume. */
static void dispatch_volume(int n, int layers) { dispatch_box(n, n * layers); }

/* The indirect dispatches of args.comp (its header), from the opaque
 * list's count and the list's before a region's revoxelization: whether a
 * list fits its capacity is known on the GPU alone. */
enum { ARGS_LIST, ARGS_VOLUME, ARGS_PREV_LIST, ARGS_PREV_VOLUME };

static void update_args(const VctGi *v)
{
    glUseProgram(v->args_prog);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VCT_OPAQUE, v->opaque);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VCT_OPAQUE_PREV, v->opaque_prev ? v->opaque_prev : v->opaque);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VCT_ARGS, v->args);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
}

/* `prog` dispatched indirectly with args.comp's dispatch `which`. */
static void dispatch_args(const VctGi *v, GLuint prog, int which)
{
    glUseProgram(prog);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, v->args);
    glDispatchComputeIndirect((GLintptr)which * 4 * sizeof(GLuint));
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
}

/* A pass over the opaque voxels: `listed` (OPAQUE_LIST, an invocation per
 * entry) when the list holds them all, else `all` over every voxel; the
 * other dispatch has no groups. */
static void dispatch_voxels(const VctGi *v, GLuint listed, GLuint all)
{
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VCT_OPAQUE, v->opaque);
    dispatch_args(v, listed, ARGS_LIST);
    dispatch_args(v, all, ARGS_VOLUME);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

/* The raster voxelization's sums: every triangle projected along its
 * dominant axis into the N×N attachment-less framebuffer
 * (voxelize.geom/.frag). */
static void voxelize_raster(VctGi *v, const GiFrame *f)
{
    GLint viewport[4];
    glGetIntegerv(GL_VIEWPORT, viewport);
    glBindFramebuffer(GL_FRAMEBUFFER, v->fbo);
    glViewport(0, 0, v->n, v->n);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    mat4 id;
    glm_mat4_identity(id);
    glProgramUniformMatrix4fv(v->voxelize, LOC_VIEW_PROJ, 1, GL_FALSE, (const float *)id);
    for (int k = 0; k < v->clip; k++) {
        glProgramUniform1i(v->voxelize, LOC_VCT_LEVEL, k);
        gpu_scene_draw(f->gpu_scene, f->scene, v->voxelize, DRAW_SKIP_EMITTERS);
    }
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
}

/* Which program voxelizes material `m` (untextured as gpu_scene's
 * untextured draws). */
static VoxelizeKind voxelize_kind(const Material *m)
{
    return m->alpha_mask ? VOXELIZE_MASKED : m->albedo_tex < 0 && m->mr_tex < 0 ? VOXELIZE_UNTEXTURED : VOXELIZE_OPAQUE;
}

/* A region of the volume: per level the voxels [lo, hi) (hi <= lo: none),
 * and the world box every triangle that can touch one of them overlaps. */
typedef struct VctRegion {
    int lo[VCT_MAX_LEVELS][3], hi[VCT_MAX_LEVELS][3];
    float wmin[3], wmax[3];
} VctRegion;

/* Whether `r` (NULL: the whole volume) holds voxels of level k. */
static bool region_has_level(const VctRegion *r, int k)
{
    return !r || (r->hi[k][0] > r->lo[k][0] && r->hi[k][1] > r->lo[k][1] && r->hi[k][2] > r->lo[k][2]);
}

/* Sets the region uniforms of `prog` for level k (stacked: z offset by k·N
 * for the resolve); none without a region. */
static void region_uniforms(const VctGi *v, GLuint prog, const VctRegion *r, int k, bool stacked)
{
    if (!r) {
        glProgramUniform4i(prog, LOC_VCT_REGION_LO, 0, 0, 0, 0);
        glProgramUniform4i(prog, LOC_VCT_REGION_HI, 0, 0, 0, 0);
        return;
    }
    int z = stacked ? k * v->n : 0;
    glProgramUniform4i(prog, LOC_VCT_REGION_LO, r->lo[k][0], r->lo[k][1], r->lo[k][2] + z, 0);
    glProgramUniform4i(prog, LOC_VCT_REGION_HI, r->hi[k][0], r->hi[k][1], r->hi[k][2] + z, 1);
}

static bool boxes_overlap(const float amin[3], const float amax[3], const float bmin[3], const float bmax[3])
{
    return amin[0] <= bmax[0] && bmin[0] <= amax[0] && amin[1] <= bmax[1] && bmin[1] <= amax[1] &&
           amin[2] <= bmax[2] && bmin[2] <= amax[2];
}

/* voxelize.comp over `count` triangles from `first` (a thread each), their
 * large ones listed under `header` from word `list` of the work buffer. */
static void dispatch_triangles(GLuint prog, uint32_t first, uint32_t count, uint32_t header, uint32_t list)
{
    glProgramUniform4ui(prog, LOC_VCT_RUN, first, count, header, list);
    GLuint groups = (count + 63) / 64, gx = groups < 65535 ? groups : 65535;
    glDispatchCompute(gx, (groups + gx - 1) / gx, 1);
}

/* The compute voxelization's sums (voxelize.comp): per clipmap level and
 * submesh a dispatch over its triangles, which list their large ones in
 * the work buffer; then per level and submesh an indirect dispatch over
 * those, in tiles of columns. With a region, only the clusters whose
 * bounds reach it are dispatched and only its voxels take samples. */
static void voxelize_compute(VctGi *v, const GiFrame *f, const VctRegion *r)
{
    const Scene *s = f->scene;
    const GpuScene *g = f->gpu_scene;
    uint32_t tris = s->index_count / 3, headers = v->work_headers;
    static const uint32_t empty[4] = {0, 0, 1, 0}; /* every header: no groups yet (z = 1), none listed */
    glClearNamedBufferSubData(v->work, GL_RGBA32UI, 0, 16 * (GLsizeiptr)headers, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                              empty);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_SCENE_VERTICES, g->vbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_SCENE_INDICES, g->ibo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VCT_WORK, v->work);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, v->work);
    for (int pass = 0; pass < 2; pass++) { /* the triangles, then the large ones' tiles */
        for (int k = 0; k < v->clip; k++) {
            if (!region_has_level(r, k))
                continue;
            for (int i = 0, c = 0; i < s->submesh_count; i++) {
                const Submesh *sm = &s->submeshes[i];
                const Material *m = &s->materials[sm->material];
                uint32_t first = sm->first_index / 3, count = sm->index_count / 3;
                int c0 = c; /* the submesh's clusters: [c0, c) */
                while (c < g->cluster_count && g->clusters[c].submesh == i)
                    c++;
                if (m->light_index >= 0 || count == 0) /* as the raster path's DRAW_SKIP_EMITTERS */
                    continue;
                bool reached = !r;
                for (int j = c0; j < c && !reached; j++)
                    reached = boxes_overlap(g->clusters[j].bounds_min, g->clusters[j].bounds_max, r->wmin, r->wmax);
                if (!reached)
                    continue;
                GLuint prog = (pass ? v->voxelize_tiles : v->voxelize_tris)[voxelize_kind(m)];
                glUseProgram(prog);
                gpu_scene_bind_material(g, m, prog);
                region_uniforms(v, prog, r, k, false);
                uint32_t header = (uint32_t)k * (uint32_t)s->submesh_count + (uint32_t)i;
                uint32_t list = 4 * headers + (uint32_t)k * tris + first;
                glProgramUniform1i(prog, LOC_VCT_LEVEL, k);
                if (pass) {
                    glProgramUniform4ui(prog, LOC_VCT_RUN, first, count, header, list);
                    glDispatchComputeIndirect(16 * (GLintptr)header);
                    continue;
                }
                if (!r)
                    dispatch_triangles(prog, first, count, header, list);
                for (int j = c0; r && j < c; j++) { /* a region: the clusters that reach it */
                    const GpuCluster *cl = &g->clusters[j];
                    if (boxes_overlap(cl->bounds_min, cl->bounds_max, r->wmin, r->wmax))
                        dispatch_triangles(prog, cl->first_index / 3, cl->index_count / 3, header, list);
                }
            }
        }
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    }
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
}

/* The region of a move's box [bmin, bmax] (world): per level the voxels
 * within one voxel of it, and their world box; `voxels` counts them. False
 * when it holds no voxel of any level. */
static bool region_of(const VctGi *v, const float bmin[3], const float bmax[3], VctRegion *r, uint64_t *voxels)
{
    bool any = false;
    *voxels = 0;
    for (int a = 0; a < 3; a++) {
        r->wmin[a] = FLT_MAX;
        r->wmax[a] = -FLT_MAX;
    }
    for (int k = 0; k < v->clip; k++) {
        const float *o = v->gpu.level[k], voxel = v->gpu.level[k][3];
        bool has = true;
        for (int a = 0; a < 3; a++) {
            float lo = floorf((bmin[a] - o[a]) / voxel) - 1.f, hi = floorf((bmax[a] - o[a]) / voxel) + 2.f;
            r->lo[k][a] = lo < 0.f ? 0 : lo > (float)v->n ? v->n : (int)lo;
            r->hi[k][a] = hi < 0.f ? 0 : hi > (float)v->n ? v->n : (int)hi;
            has = has && r->hi[k][a] > r->lo[k][a];
        }
        if (!has)
            continue;
        any = true;
        *voxels += (uint64_t)(r->hi[k][0] - r->lo[k][0]) * (uint64_t)(r->hi[k][1] - r->lo[k][1]) *
                   (uint64_t)(r->hi[k][2] - r->lo[k][2]);
        for (int a = 0; a < 3; a++) { /* the voxels' box, with room for the triangle–box test's tolerance */
            r->wmin[a] = fminf(r->wmin[a], o[a] + voxel * ((float)r->lo[k][a] - 0.01f));
            r->wmax[a] = fmaxf(r->wmax[a], o[a] + voxel * ((float)r->hi[k][a] + 0.01f));
        }
    }
    return any;
}

/* `prog` over region `r`'s box at each level it holds, 4×4×4 groups (the
 * stacked volume's coordinates, as the resolve and list.comp take them);
 * returns the voxels dispatched. */
static uint64_t dispatch_region(const VctGi *v, GLuint prog, const VctRegion *r)
{
    uint64_t voxels = 0;
    glUseProgram(prog);
    for (int k = 0; k < v->clip; k++) {
        if (!region_has_level(r, k))
            continue;
        region_uniforms(v, prog, r, k, true);
        int d[3];
        for (int a = 0; a < 3; a++)
            d[a] = r->hi[k][a] - r->lo[k][a];
        voxels += (uint64_t)d[0] * (uint64_t)d[1] * (uint64_t)d[2];
        glDispatchCompute((GLuint)(d[0] + 3) / 4, (GLuint)(d[1] + 3) / 4, (GLuint)(d[2] + 3) / 4);
    }
    return voxels;
}

/* A whole voxelization's resolve: over the opaque list the sums' first
 * samples made (the volumes cleared first: the empty voxels hold its 0),
 * or every voxel when it overflowed. */
static void resolve_whole(VctGi *v)
{
    glClearTexImage(v->albedo, 0, GL_RGBA, GL_FLOAT, NULL);
    glClearTexImage(v->normal, 0, GL_RGBA, GL_FLOAT, NULL);
    dispatch_voxels(v, v->resolve_list, v->resolve);
}

/* A region's resolve: over its boxes (its empty voxels written 0), then
 * the opaque list made again (list.comp) so that it holds every opaque
 * voxel once: the entries of the list before (opaque_prev) outside the
 * region and the region's opaque voxels, or, when the list before had
 * overflowed, every voxel's (args.comp picks on the GPU). */
static void resolve_region(VctGi *v, const VctRegion *r)
{
    v->region_voxels = dispatch_region(v, v->resolve, r);
    region_uniforms(v, v->resolve, NULL, 0, true); /* a whole voxelization's resolve shares the program */
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    const uint32_t none = 0; /* the count */
    glNamedBufferSubData(v->opaque, 0, sizeof none, &none);
    glBindTextureUnit(TEX_VCT_ALBEDO, v->albedo);
    GLint boxes[2 * VCT_MAX_LEVELS][4] = {{0}};
    for (int k = 0; k < v->clip; k++)
        for (int a = 0; a < 3; a++) {
            int z = a == 2 ? k * v->n : 0; /* stacked */
            boxes[2 * k][a] = r->lo[k][a] + z;
            boxes[2 * k + 1][a] = r->hi[k][a] + z;
        }
    glProgramUniform4iv(v->list[1], LOC_VCT_REGIONS, 2 * VCT_MAX_LEVELS, &boxes[0][0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VCT_OPAQUE_PREV, v->opaque_prev);
    dispatch_args(v, v->list[0], ARGS_PREV_VOLUME); /* the list before overflowed: every voxel */
    dispatch_args(v, v->list[1], ARGS_PREV_LIST);   /* else its entries outside the region */
    dispatch_region(v, v->list[2], r);              /* and the region's (none when it overflowed) */
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
}

/* Voxelizes the scene into the fixed-point sums (raster or compute), each
 * voxel's first sample listing it as opaque, then resolves them into the
 * albedo and normal volumes, clearing the sums behind it. With a region
 * (compute only, vct_run) only its voxels take samples, from the clusters
 * that reach them, and only they are resolved: the volumes equal a whole
 * voxelization's, the sums being exact integers whatever triangles add to
 * them in whatever order. */
static void voxelize(VctGi *v, const GiFrame *f, const VctRegion *r)
{
    /* Timed in wall time with --timings (a whole voxelization, or any with
     * synchronous timings); otherwise nothing waits for the GPU. */
    const GpuTimer *t = f->timer;
    bool timed = t && t->enabled && (t->sync || !r);
    if (timed)
        glFinish();
    double t0 = util_seconds();
    if (r) { /* the list before, kept apart: the region's first samples append to v->opaque */
        GLuint before = v->opaque;
        v->opaque = v->opaque_prev;
        v->opaque_prev = before;
    }
    const uint32_t none = 0; /* the count; args.comp makes the dispatches over the list */
    glNamedBufferSubData(v->opaque, 0, sizeof none, &none);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VCT_OPAQUE, v->opaque);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VCT_VOXELS, v->sums);
    if (v->params.vct.voxelize == VCT_VOXELIZE_COMPUTE)
        voxelize_compute(v, f, r);
    else
        voxelize_raster(v, f);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    gl_texture3d_bind_image(IMG_VCT_DST, v->albedo, 0, GL_WRITE_ONLY, GL_RGBA16F);
    gl_texture3d_bind_image(IMG_VCT_DST2, v->normal, 0, GL_WRITE_ONLY, GL_RGBA16F);
    update_args(v);
    if (r) {
        resolve_region(v, r);
        update_args(v);
    } else {
        resolve_whole(v);
    }
    if (timed) {
        glFinish();
        v->voxelize_ms = 1e3 * (util_seconds() - t0);
    }
    v->voxelizations++;
    v->region_voxelizations += r != NULL;
}

/* The injection program for one light type (LIGHT_FIXED_TYPE: the other
 * types' code and map kind drop out; llvmpipe runs both sides of a branch,
 * so each shadow tap read a cube and a 2D map), over the opaque-voxel list,
 * built on first use; the general one (every voxel) if it does not build. */
static GLuint inject_program(VctGi *v, const Scene *s, const Light *l)
{
    char defs[96];
    snprintf(defs, sizeof defs, "#define LIGHT_FIXED_TYPE %d\n#define SHADOW_FIXED_CUBE %d\n#define OPAQUE_LIST\n",
             (int)l->type, shadow_frame_is_cube(l, s->bounds_min, s->bounds_max) ? 1 : 0);
    GLuint p = program(v, "vct_inject_fixed_type", NULL, NULL, NULL, "gi/vct/inject.comp", defs);
    return p ? p : v->inject;
}

static void inject(VctGi *v, const GiFrame *f)
{
    glBindTextureUnit(TEX_VCT_ALBEDO, v->albedo);
    gl_texture3d_bind_image(IMG_VCT_DST, v->radiance[0], 0, GL_READ_WRITE, GL_RGBA16F);
    gl_texture3d_bind_image(IMG_VCT_DST2, v->normal, 0, GL_READ_WRITE, GL_RGBA16F); /* w: the lit side */
    int lights = f->lights->light_count;
    /* Over the opaque voxels alone when they fit the list; the empty ones
     * then hold the clear's 0. */
    glClearTexImage(v->radiance[0], 0, GL_RGBA, GL_FLOAT, NULL);
    for (int i = 0; i < lights; i++) {
        const Light *l = &f->scene->lights[i];
        GLuint listed = inject_program(v, f->scene, l);
        light_stage_bind_shadow(f->lights, i);
        glProgramUniform1i(listed, LOC_VCT_ACCUMULATE, i > 0);
        glProgramUniform1i(v->inject, LOC_VCT_ACCUMULATE, i > 0);
        if (listed != v->inject) { /* an overflowed list (rare): the general program over every voxel */
            dispatch_voxels(v, listed, v->inject);
        } else { /* the list's program did not build */
            glUseProgram(v->inject);
            dispatch_volume(v->n, v->clip);
        }
    }
}

/* The isotropic chain of `tex` (gi/vct/mip.comp, a dispatch per level,
 * not the driver's glGenerateMipmap: 21.9 ms on an H100, issue 46), or,
 * with the directional volumes, those from its level 0 (`tex` then has no
 * chain: radiance_levels). */
static void build_mips(VctGi *v, GLuint tex)
{
    if (!v->gpu.aniso) {
        gl_texture3d_build_mips(tex, v->mip, GL_RGBA16F, 4);
        return;
    }
    /* The first level of every axis and sign in one pass (each reads the
     * same 2×2×2 blocks of the isotropic level 0), then each axis's chain. */
    glUseProgram(v->aniso_first);
    glBindTextureUnit(TEX_VCT_NORMAL, v->normal);
    gl_texture3d_bind_image(IMG_VCT_SRC, tex, 0, GL_READ_ONLY, GL_RGBA16F);
    const GLuint units[ANISO_AXES] = {IMG_VCT_DST, IMG_VCT_DST2, IMG_VCT_DST3};
    for (int a = 0; a < ANISO_AXES; a++)
        gl_texture3d_bind_image(units[a], v->aniso[a], 0, GL_WRITE_ONLY, GL_RGBA16F);
    int half = aniso_side(v->n), slabs = v->gpu.aniso_slab * v->clip; /* one sign */
    dispatch_box(half, slabs);
    glUseProgram(v->aniso_prog);
    for (int a = 0; a < ANISO_AXES; a++) {
        glProgramUniform1i(v->aniso_prog, LOC_VCT_AXIS, a);
        for (int l = 1; l < v->levels - 1; l++) {
            glProgramUniform1i(v->aniso_prog, LOC_VCT_MIP, l);
            gl_texture3d_bind_image(IMG_VCT_SRC, v->aniso[a], l - 1, GL_READ_ONLY, GL_RGBA16F);
            gl_texture3d_bind_image(IMG_VCT_DST, v->aniso[a], l, GL_WRITE_ONLY, GL_RGBA16F);
            int s = half >> l, depth = (v->gpu.aniso_slab >> l) * 2 * v->clip; /* both signs, every level */
            dispatch_box(s > 0 ? s : 1, depth);
        }
    }
}

static void bind_volumes(const VctGi *v, GLuint radiance)
{
    glBindTextureUnit(TEX_VCT_RADIANCE, radiance);
    for (int a = 0; a < ANISO_AXES; a++)
        glBindTextureUnit(TEX_VCT_ANISO + a, v->gpu.aniso ? v->aniso[a] : radiance);
}

static bool vct_run(void *state, const GiFrame *f)
{
    VctGi *v = state;
    GpuTimer *t = f->timer;
    place_levels(v, f->camera);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_VCT, v->ubo);
    /* An object moved (animation.h): its region again (compute), or the
     * whole volume; no stale voxel stays. */
    float mmin[3], mmax[3];
    VctRegion region;
    bool moved = v->voxels_version != f->gpu_scene->version;
    bool in_region = moved && v->voxelized && v->params.vct.voxelize == VCT_VOXELIZE_COMPUTE &&
                     gpu_scene_moved_since(f->gpu_scene, v->voxels_version, mmin, mmax);
    uint64_t voxels = 0;
    if (in_region && !region_of(v, mmin, mmax, &region, &voxels)) /* moved wholly outside the volume */
        v->voxels_version = f->gpu_scene->version;
    else if (in_region && 4 * voxels <= (uint64_t)v->clip * v->n * v->n * v->n) { /* larger: the whole is cheaper */
        gpu_timer_begin(t, "vct_revoxelize");
        v->voxels_version = f->gpu_scene->version;
        voxelize(v, f, &region);
        gpu_timer_end(t);
    } else if (moved)
        v->voxelized = false;
    if (!v->voxelized) {
        gpu_timer_begin_once(t, "vct_voxelize"); /* in the warm-up frame: kept apart from the means */
        v->voxels_version = f->gpu_scene->version;
        voxelize(v, f, NULL);
        v->voxelized = true;
        gpu_timer_end(t);
    }
    /* The radiance volumes (injection, mips, the second bounce) depend on
     * the voxels and the light products alone: kept while both stand. */
    uint64_t key = util_hash_bytes(light_stage_products_key(f->lights), &v->voxelizations, sizeof v->voxelizations);
    key = util_hash_bytes(key, v->gpu.level, sizeof v->gpu.level);
    bool build = key != v->built_for;
    v->built_for = key;
    if (build) {
        v->builds++;
        gpu_timer_begin(t, "vct_inject");
        inject(v, f);
        gpu_timer_end(t);
        gpu_timer_begin(t, "vct_mips");
        build_mips(v, v->radiance[0]);
        gpu_timer_end(t);
    }
    GLuint radiance = v->params.vct.bounces > 1 ? v->radiance[1] : v->radiance[0];
    if (build && v->params.vct.bounces > 1) {
        gpu_timer_begin(t, "vct_bounce");
        /* Over the opaque voxels alone when they fit the list (as the
         * injection): the empty ones keep the direct radiance, copied. */
        bind_volumes(v, v->radiance[0]);
        glBindTextureUnit(TEX_VCT_ALBEDO, v->albedo);
        gl_texture3d_bind_image(IMG_VCT_DST, v->radiance[1], 0, GL_WRITE_ONLY, GL_RGBA16F);
        gl_texture3d_bind_image(IMG_VCT_DST2, v->normal, 0, GL_READ_WRITE, GL_RGBA16F); /* w: + the bounce's side */
        if (v->bounce_list) {
            glCopyImageSubData(v->radiance[0], GL_TEXTURE_3D, 0, 0, 0, 0, v->radiance[1], GL_TEXTURE_3D, 0, 0, 0, 0,
                               v->n, v->n, v->n * v->clip);
            dispatch_voxels(v, v->bounce_list, v->bounce);
        } else { /* the list's program did not build */
            glUseProgram(v->bounce);
            dispatch_volume(v->n, v->clip);
        }
        gpu_timer_end(t);
        gpu_timer_begin(t, "vct_mips");
        build_mips(v, v->radiance[1]);
        gpu_timer_end(t);
    }
    gpu_timer_begin(t, "vct_trace");
    glUseProgram(v->trace);
    bind_volumes(v, radiance);
    glBindTextureUnit(TEX_GB_SURFACE, f->gbuffer->surface);
    glBindTextureUnit(TEX_GB_MATERIAL, f->gbuffer->material);
    glBindTextureUnit(TEX_BRDF_ALBEDO, f->brdf_albedo);
    glProgramUniform1i(v->trace, LOC_VCT_AO_OUT, v->params.vct.ao ? 1 : 0);
    glProgramUniform1i(v->trace, LOC_VCT_SCALE, v->scale);
    bool low = v->scale > 1;
    glBindImageTexture(IMG_OUT, low ? v->low_irradiance : f->irradiance, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(IMG_OUT2, low ? v->low_specular : f->specular, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    gi_dispatch_pixels((v->width + v->scale - 1) / v->scale, (v->height + v->scale - 1) / v->scale);
    gpu_timer_end(t);
    if (!low)
        return true;
    gpu_timer_begin(t, "vct_upsample");
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glUseProgram(v->upsample);
    glProgramUniform1i(v->upsample, LOC_VCT_AO_OUT, v->params.vct.ao ? 1 : 0);
    glProgramUniform1i(v->upsample, LOC_VCT_SCALE, v->scale);
    glBindTextureUnit(TEX_INPUT, v->low_irradiance);
    glBindTextureUnit(TEX_SPECULAR, v->low_specular);
    glBindImageTexture(IMG_OUT, f->irradiance, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(IMG_OUT2, f->specular, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    gi_dispatch_pixels(v->width, v->height);
    gpu_timer_end(t);
    return true;
}

static void vct_stats(void *state, const GiFrame *f, GiStats *st)
{
    VctGi *v = state;
    st->gathered_pixels = gi_count_surfaces(f, v->pc, v->scale);
    /* As GL sizes them, like every technique's; test_vct checks it against
     * what the settings call for (v->bytes, the budget's estimate, and the
     * low-resolution images). */
    const GLuint tex[4] = {v->albedo, v->normal, v->low_irradiance, v->low_specular},
                 bufs[4] = {v->opaque, v->ubo, v->sums, v->work};
    st->gpu_bytes = gl_textures_bytes(tex, 4) + gl_textures_bytes(v->radiance, 2) +
                    gl_textures_bytes(v->aniso, ANISO_AXES) + gl_buffers_bytes(bufs, 4);
    st->voxelizations = v->voxelizations;
    st->region_voxelizations = v->region_voxelizations;
    st->region_voxels = v->region_voxels;
    st->volume_builds = v->builds;
    st->voxelize_ms = v->voxelize_ms;
}

/* ---- Hooks ------------------------------------------------------------------------ */

void vct_grid(const void *state, int *n, float origin[3], float *voxel)
{
    const VctGi *v = state;
    *n = v->n;
    for (int a = 0; a < 3; a++)
        origin[a] = v->gpu.level[0][a];
    *voxel = v->gpu.level[0][3];
}

void vct_level(const void *state, int k, float origin[3], float *voxel)
{
    const VctGi *v = state;
    for (int a = 0; a < 3; a++)
        origin[a] = v->gpu.level[k][a];
    *voxel = v->gpu.level[k][3];
}

bool vct_read_volume(void *state, VctVolume which, float *out)
{
    VctGi *v = state;
    GLuint tex = which == VCT_VOLUME_ALBEDO   ? v->albedo
                 : which == VCT_VOLUME_NORMAL ? v->normal
                                              : v->radiance[v->params.vct.bounces > 1 ? 1 : 0];
    size_t n3 = (size_t)v->n * v->n * v->n * (size_t)v->clip;
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    glGetTextureImage(tex, 0, GL_RGBA, GL_FLOAT, (GLsizei)(n3 * 4 * sizeof(float)), out);
    return true;
}

unsigned vct_opaque_voxels(const void *state, bool *listed)
{
    const VctGi *v = state;
    uint32_t count = 0; /* read back here alone: stats, tests */
    glGetNamedBufferSubData(v->opaque, 0, sizeof count, &count);
    *listed = count <= v->opaque_capacity;
    return count;
}

bool vct_read_directional(void *state, int axis, bool negative, int k, float *out)
{
    VctGi *v = state;
    if (!v->gpu.aniso || axis < 0 || axis >= ANISO_AXES || k < 0 || k >= v->clip)
        return false;
    int m = v->n / 2, slab = 2 * k + (negative ? 1 : 0);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    glGetTextureSubImage(v->aniso[axis], 0, 0, 0, slab * v->gpu.aniso_slab, m, m, m, GL_RGBA, GL_FLOAT,
                         (GLsizei)((size_t)m * m * m * 4 * sizeof(float)), out);
    return true;
}

bool vct_probe(void *state, int count, const VctProbe *probes, float (*out)[4])
{
    VctGi *v = state;
    if (count <= 0)
        return true;
    if (!v->probe) {
        const char *cones = v->params.vct.aniso && v->n >= 2 ? "#define VCT_ANISO\n" : NULL;
        v->probe = program(v, "vct_probe", NULL, NULL, NULL, "gi/vct/probe.comp", cones);
        if (!v->probe)
            return false; /* logged */
    }
    size_t bytes = (size_t)count * 16 * sizeof(float);
    float *buf = calloc((size_t)count * 16, sizeof(float));
    if (!buf) {
        log_error("vct", "out of memory");
        return false;
    }
    for (int i = 0; i < count; i++) {
        memcpy(buf + 16 * i, probes[i].x, 3 * sizeof(float));
        memcpy(buf + 16 * i + 4, probes[i].n, 3 * sizeof(float));
        memcpy(buf + 16 * i + 8, probes[i].d, 3 * sizeof(float));
        buf[16 * i + 11] = probes[i].tan_half;
    }
    GLuint ssbo = gl_buffer_make(bytes, buf, GL_DYNAMIC_STORAGE_BIT, "vct.probes");
    bool ok = ssbo != 0; /* logged */
    if (ok) {
        glUseProgram(v->probe);
        glBindBufferBase(GL_UNIFORM_BUFFER, UBO_VCT, v->ubo);
        bind_volumes(v, v->radiance[v->params.vct.bounces > 1 ? 1 : 0]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VCT_VOXELS, ssbo);
        glProgramUniform1i(v->probe, LOC_VCT_SCALE, count);
        glDispatchCompute((GLuint)(count + 63) / 64, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glGetNamedBufferSubData(ssbo, 0, (GLsizeiptr)bytes, buf);
        for (int i = 0; i < count; i++)
            memcpy(out[i], buf + 16 * i + 12, 4 * sizeof(float));
        glDeleteBuffers(1, &ssbo);
    }
    free(buf);
    return ok;
}

/* Samples along one cone: the step grows with the diameter (by the step
 * fraction), so the count is logarithmic in the volume's size. */
static double vct_samples_per_cone(const GiParams *p)
{
    double grow = 1.0 + (p->vct.step > 0.f ? p->vct.step : 0.5);
    return ceil(log((double)p->vct.size) / log(grow)) + 1.0;
}

/* Traced pixels × (diffuse cones + the specular one) × samples per cone ×
 * fetches per sample (3 of the 6 directional volumes with anisotropy), the
 * injection's 3×3 shadow taps per voxel, and with a second bounce two
 * diffuse sets from each occupied voxel: about 40 N² per level, from the
 * Cornell box's bounce pass at 128³ (~22 s on llvmpipe, conservative walls
 * two voxels thick, lanes of empty voxels in the same SIMD chunks). */
static double vct_cost(const GiCostQuery *q)
{
    const GiParams *p = q->params;
    static const int cones[] = {6, 9, 16};
    int nc = cones[p->vct.cones >= 0 && p->vct.cones < 3 ? p->vct.cones : 0];
    double fetches = p->vct.aniso ? 3.0 : 1.0, per_cone = vct_samples_per_cone(p) * fetches;
    int scale = p->vct.trace_scale > 1 ? p->vct.trace_scale : 1;
    int levels = p->vct.levels > 1 ? p->vct.levels : 1;
    double voxels = pow(p->vct.size, 3) * levels;
    double e = q->pixels / (scale * scale) * (nc + 1) * per_cone + q->pixels + voxels * 9.0;
    if (p->vct.bounces > 1)
        e += 40.0 * p->vct.size * p->vct.size * levels * 2.0 * nc * per_cone;
    return e * GI_COST_VOLUME_EVAL;
}

static void vct_print_stats(const GiStats *st, double pixels, FILE *out)
{
    (void)pixels;
    fprintf(out, "vct_voxelizations: %d\nvct_voxelize_wall_ms: %.3f\n", st->voxelizations, st->voxelize_ms);
    if (st->region_voxelizations)
        fprintf(out, "vct_region_voxelizations: %d\nvct_region_voxels: %llu\n", st->region_voxelizations,
                (unsigned long long)st->region_voxels);
}

const GiTechnique gi_vct = {
    .name = "vct",
    .paper = "Crassin et al. 2011, Interactive Indirect Illumination Using Voxel Cone Tracing",
    .summary = "voxel cone tracing: conservative voxelization, light injected with shadow maps, (anisotropic) mips, "
               "diffuse cones for irradiance, one specular cone",
    .flags = GI_HAS_SPECULAR | GI_AO,
    .needs = vct_needs,
    .create = vct_create,
    .resize = vct_resize,
    .run = vct_run,
    .stats = vct_stats,
    .destroy = vct_destroy,
    .cost = vct_cost,
    .print_stats = vct_print_stats,
};
