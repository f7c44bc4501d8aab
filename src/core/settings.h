/* settings.h — the table of technique settings: one row per setting with
 * its one name, "family.field" (rsm.samples), which is at once its scene-file
 * key (the object "rsm", key "samples"), its place in Settings (.gi.rsm.samples;
 * shadow: .shadow.FIELD), and, as "--family-field", its command-line option
 * (--rsm-samples); where a GPU block holds the value, its member is
 * u_FAMILY.field, or u_gi.family_field in the shared u_gi block (a pair,
 * interleave.pattern: u_gi.interleave_pattern_n, _m). Each row
 * also has its type, range, default and help. One parser and one validator
 * serve the command line and the scene file (so the two cannot disagree),
 * `--help` is printed from the table, and tests check the guide
 * (docs/guide.md) against it. Adding a setting is adding a row (and its field
 * in its family's struct, below). The spellings of commit d364f03 (gi.samples,
 * --bias-const, ...) stay accepted: settings.c's alias list. */
#ifndef RTGI_SETTINGS_H
#define RTGI_SETTINGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <cjson/cJSON.h>

#include "base/value.h"

/* Technique parameters a scene file may set and the CLI overrides; their
 * keys, options, ranges and defaults are rows of the settings table
 * (below). */
typedef struct ShadowParams {
    int map_size;          /* 2D shadow map / cube face resolution */
    float bias_const;      /* world-space constant bias (m) */
    float bias_slope;      /* slope-scaled bias, in shadow-map texels × tanθ */
    float normal_offset;   /* receiver offset along the normal, in texels */
    int pcf_samples;       /* Poisson disk samples (≤ 64) */
    float pcf_radius;      /* PCF filter radius in texels */
    int blocker_samples;   /* PCSS blocker-search samples (≤ 64) */
    float pcss_max_radius; /* PCSS search/filter radius cap in texels */
    int filter_bias;       /* PCF/PCSS depth test: 0 receiver plane (Poisson disk), 1 legacy (slope bias × filter radius, spiral) */
    int pcf_filter;        /* ShadowPcfFilter: Poisson disk, or a grid of hardware-compare bilinear taps */
    int area_light;        /* AreaLightMode: quad lights' exact polygon irradiance, or a point at the centre */
} ShadowParams;

/* PCF's taps (ShadowParams.pcf_filter; SHADOW_FILTER_* in shared/gpu_types.h). */
typedef enum ShadowPcfFilter { SHADOW_PCF_FILTER_DISK = 0, SHADOW_PCF_FILTER_GRID = 1 } ShadowPcfFilter;

/* Visibility of the bounce (SPEC §9): how RSM and VPL gathers test it. */
typedef enum GiVisibilityMethod { GI_VISIBILITY_ISM = 0 } GiVisibilityMethod;
/* Imperfect shadow maps' texels per side (GiParams.visibility.ism_size: an index). */
typedef enum IsmSize { ISM_SIZE_16 = 0, ISM_SIZE_32 = 1, ISM_SIZE_64 = 2 } IsmSize;

typedef enum VctCones { VCT_CONES_6 = 0, VCT_CONES_9 = 1, VCT_CONES_16 = 2 } VctCones;
/* How vct voxelizes: triangles projected and rasterized, or in compute. */
typedef enum VctVoxelize { VCT_VOXELIZE_RASTER = 0, VCT_VOXELIZE_COMPUTE = 1 } VctVoxelize;
/* How the rasterizer lights with quad lights (values AREA_LIGHT_* in
 * shared/gpu_types.h). */
typedef enum AreaLightMode { AREA_LIGHT_MODE_EXACT = 0, AREA_LIGHT_MODE_POINT = 1 } AreaLightMode;

typedef enum LpvInject { LPV_INJECT_COMPUTE = 0, LPV_INJECT_POINTS = 1 } LpvInject;
/* How a propagation step moves light (shaders/gi/lpv/propagate.comp):
 * along the directions it travels in, or through the paper's 5 faces per
 * neighbour, re-emitted towards the faces' normals. */
typedef enum LpvPropagation { LPV_PROPAGATION_DIRECTIONAL = 0, LPV_PROPAGATION_FACES = 1 } LpvPropagation;

typedef enum RsmWeighting { RSM_WEIGHT_PAPER = 0, RSM_WEIGHT_UNBIASED = 1, RSM_WEIGHT_IMPORTANCE = 2 } RsmWeighting;

/* The GI settings by family (issue 45): each technique reads its family's
 * struct (and visibility, interleave where it takes them); `frame` is the
 * renderer's own (read when it composites), so changing it remakes no
 * technique. Each field is a setting's name without its family: the setting
 * lpv.size is GiParams.lpv.size. */

/* Reflective shadow maps (SPEC §3): the gathers of rsm, rsm-interp and
 * rsm-interleaved; `size` is also the RSMs' size where --vpls does not set it. */
typedef struct RsmParams {
    int size;              /* RSM texels per side (per cube face for point/quad lights) */
    int samples;           /* N samples per gather (paper: ~400) */
    float r_max;           /* sampling radius, in RSM widths (cube: face widths) */
    RsmWeighting weighting;/* paper's ξ1² normalised, unbiased for the polar pdf, or importance
                              sampling of the whole map by flux */
    bool exhaustive;       /* sum over every RSM texel instead of sampling */
    int interp_factor;     /* screen-space interpolation: low-res = full / factor */
    float interp_normal;   /* min cosine between normals for a usable low-res sample */
    float interp_dist;     /* max world distance, as a fraction of the view distance */
    /* Diagnostic, no scene key: the RSM gathers' twin for `render --timings
     * --probe run`, which reads every sample and evaluates none (the image
     * is meaningless); its rate is the limit of the gather's own reads. */
    bool reads_only;
} RsmParams;

/* Interleaved sampling and shading (rsm-interleaved, vpl-interleaved, vpl-metalights). */
typedef struct InterleaveParams {
    struct {
        int n, m;
    } pattern;             /* the sub-image pattern n×m */
    bool blur;             /* geometry-aware blur after reassembly */
} InterleaveParams;

/* Many-VPL techniques (SPEC §4). */
typedef struct VplParams {
    int count;             /* VPLs per light wanted (sets the RSM size); 0: the RSM size decides */
    float slc_emax;        /* stochastic light culling error bound e_max (0.0005) */
    float near_clamp;      /* falloff 1/max(d², c) with c in m²; 0 = off (the notes use 0.1) */
    bool disk;             /* VPLs fall off as disks of their texel's area: 1/(d² + A/π) */
    float range;           /* clamped-range baseline, metres; 0 = 0.15 × scene diagonal */
    float keep;            /* vpl-all: fraction q of VPLs kept (uniform subsampling, weight 1/q) */
    unsigned seed;         /* seed of the VPLs' fixed random ξ */
    int supersample;       /* the VPLs' RSM this many times finer per side, one VPL per block (1: per texel) */
} VplParams;

/* Visibility of the bounce (SPEC §9, src/gi/visibility/). */
typedef struct VisibilityParams {
    bool on;               /* RSM and VPL gathers test whether each VPL (sample) sees the shaded point */
    int method;            /* GiVisibilityMethod */
    int ism_size;          /* IsmSize: texels per side of each imperfect shadow map */
    int ism_points;        /* scene points splatted into each map */
    int ism_maps;          /* RSM gathers: maps per light, one per block of RSM texels */
} VisibilityParams;

/* Light propagation volumes (SPEC §5). */
typedef struct LpvParams {
    int size;              /* cells per side of each grid */
    int cascades;          /* 1: one grid fitted to the scene; 2–3: nested grids centred on the camera */
    int iterations;        /* propagation steps; 0: the grid size (enough to cross it) */
    bool occlusion;        /* attenuate propagation by the geometry volume */
    float offset;          /* VPLs move this many cells along their normal before injection (0.5) */
    bool gbuffer_occlusion;/* also inject the camera's G-buffer into the geometry volume */
    int inject;            /* LpvInject: compute with fixed-point atomics, or points into 3D-texture layers with blending */
    int propagation;       /* LpvPropagation: directional (light keeps its direction) or the paper's faces */
    int groups;            /* 1, or 2: the light of surfaces facing +x/+y/+z and of those facing away propagated apart */
} LpvParams;

/* Voxel cone tracing (SPEC §6). */
typedef struct VctParams {
    int size;          /* voxels per side of the volume over the scene bounds (of each clipmap level) */
    int levels;        /* 1: one volume over the bounds; 2–4: a clipmap centred on the camera */
    bool aniso;        /* six directional mip volumes (Crassin's anisotropic voxels) */
    int cones;         /* VctCones: the diffuse cone set (6, 9 or 16 cones) */
    int bounces;       /* 1: direct light in the voxels; 2: plus one cone-traced bounce */
    float step;        /* cone sampling step, in units of the cone's current diameter */
    int trace_scale;   /* cones traced at every Nth pixel per axis, upsampled by depth and normal */
    bool ao;           /* ambient occlusion from the diffuse cones (irradiance alpha, --out-ao) */
    bool conservative; /* conservative voxelization (off: one voxel per fragment centre; tests) */
    int voxelize;      /* VctVoxelize: compute (a thread per triangle, large ones in tiles of columns) or raster */
    float roughness;   /* with vct_f0 > 0: GGX perceptual roughness of every surface's specular cone */
    float f0;          /* > 0: F0 of every surface's specular cone instead of the material's (tests); 0: the material's */
} VctParams;

/* What the renderer does with any technique's light (no technique reads it). */
typedef struct FrameParams {
    float indirect_scale;  /* indirect intensity scale (1 = physical) */
    bool temporal;         /* temporal accumulation of the indirect light (frame/pass_temporal.h) */
    bool temporal_clamp;   /* its neighbourhood clamp (off: the history lags a moving light; for measuring) */
} FrameParams;

/* Every GI family; `frame` last (renderer_apply compares what precedes it). */
typedef struct GiParams {
    RsmParams rsm;
    InterleaveParams interleave;
    VplParams vpl;
    VisibilityParams visibility;
    LpvParams lpv;
    VctParams vct;
    FrameParams frame;
} GiParams;
_Static_assert(offsetof(GiParams, frame) + sizeof(FrameParams) == sizeof(GiParams),
               "frame is GiParams' last member: renderer_apply compares the families before it");

/* Everything the table stores. */
typedef struct Settings {
    ShadowParams shadow;
    GiParams gi;
} Settings;


typedef struct SettingDesc {
    const char *family;          /* "shadow", "rsm", "interleave", "vpl", "visibility", "lpv", "vct", "frame" */
    const char *field;           /* its field in the family's struct, and its key in the family's scene object */
    const char *name;            /* "family.field": the one name */
    size_t offset;               /* in Settings */
    size_t offset2;              /* VALUE_PAIR: the second int */
    const char *option;          /* command-line option, "--family-field" */
    ValueType type;              /* base/value.h */
    double min, max;             /* inclusive range (pairs: each; enum/bool: unused) */
    double def;                  /* default (pairs: both values) */
    const char *const *choices;  /* VALUE_CHOICE: names, index = stored value; NULL-terminated */
    const char *help;            /* one line, with its unit */
} SettingDesc;

extern const SettingDesc settings_table[];
extern const int settings_count;

/* Every setting at its default. */
void settings_default(Settings *s);
/* The row whose option is `option` ("--shadow-pcf-samples", or its old
 * spelling "--pcf-samples"), or NULL. */
const SettingDesc *settings_find_option(const char *option);
/* The row named `name` ("rsm.samples", or its old scene key "gi.samples"),
 * or NULL. */
const SettingDesc *settings_find_name(const char *name);
/* Row `d`'s spellings before its one name (commit d364f03), or NULL where
 * they were the same or the row is newer: its scene key ("gi.samples"), its
 * option ("--bias-const"). */
const char *settings_old_key(const SettingDesc *d);
const char *settings_old_option(const SettingDesc *d);

/* The rows' names into out[0..cap-1], NULL-terminated (for "did you mean");
 * returns how many. */
int settings_names(const char **out, int cap);
/* The keys the scene file's object `object` may hold into out[0..cap-1],
 * NULL-terminated: a family's fields, and for "gi" (and "shadow", whose old
 * keys are its fields) the old keys of that object. Returns how many. */
int settings_object_keys(const char *object, const char **out, int cap);
/* The families in table order into out[0..cap-1], NULL-terminated; returns
 * how many. */
int settings_families(const char **out, int cap);
/* The scene file's top-level keys that hold settings: each family's object,
 * and "gi", the object of the old keys (gi.samples); NULL-terminated
 * (appended at out[*n], *n advanced). */
void settings_scene_keys(const char **out, int *n, int cap);

/* Parses a command-line value (NULL for VALUE_FLAG) into `s`, range
 * checked; `as_written` is the option as the user gave it (an old spelling;
 * NULL: d->option). false after logging a usage error (usage_error)
 * "<option>: '<value>' <problem> (allowed: <range>)", with the nearest
 * choice of an enum. */
bool settings_parse_cli(const SettingDesc *d, const char *as_written, const char *value, Settings *s);
/* Reads the settings of a scene file's root object into `s`: each family's
 * object ("rsm": {"samples": 100}) and the old "gi" object ("gi":
 * {"samples": 100}); "shadow" is both. Every key must be a field of its
 * object's rows (unknown keys are an error naming the nearest), no key
 * twice, no setting both in its family's object and in "gi", each value of
 * the row's type and in its range. false after logging "<file>:
 * <object>.<key>: <problem>" as the file spells it. */
bool settings_parse_scene(const cJSON *root, const char *file, Settings *s);
/* Row `d` as the value it stores in a Settings (value.h). */
ValueSpec settings_value(const SettingDesc *d);
/* Copies the value of row `d` from `src` to `dst`. */
void settings_copy(const SettingDesc *d, Settings *dst, const Settings *src);
/* The value of row `d` in `s` as text ("20", "0.0005", "4x4", "paper", "on"). */
void settings_format(const SettingDesc *d, const Settings *s, char *out, size_t cap);
/* Prints the option help of one family, from the table. */
void settings_print_help(FILE *f, const char *family);

#endif
