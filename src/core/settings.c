/* settings.c — the settings table and its one parser/validator. */
#include "core/settings.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/usage.h"
#include "base/json_util.h"
#include "base/log.h"
#include "shared/gpu_types.h"
#include "base/util.h"

static const char *const k_weightings[] = {"paper", "unbiased", "importance", NULL};
static const char *const k_filter_biases[] = {"receiver-plane", "legacy", NULL};
static const char *const k_lpv_inject[] = {"compute", "points", NULL};
static const char *const k_lpv_propagation[] = {"directional", "faces", NULL};
static const char *const k_vct_cones[] = {"6", "9", "16", NULL};
static const char *const k_vct_voxelize[] = {"raster", "compute", NULL};
static const char *const k_area_lights[] = {"exact", "point", NULL};
static const char *const k_pcf_filters[] = {"disk", "grid", NULL};
static const char *const k_visibility_methods[] = {"ism", NULL};
static const char *const k_ism_sizes[] = {"16", "32", "64", NULL};

/* A row's first fields from its family and field: the canonical name
 * "family.field", which is also its place in Settings (shadow: .shadow, the
 * GI families: .gi.FAMILY), so the name and the C field cannot differ. The
 * option is "--family-field" with '_' as '-' (test_settings checks it). */
#define SROW(field) "shadow", #field, "shadow." #field, offsetof(Settings, shadow.field), 0
#define ROW(family, field) #family, #field, #family "." #field, offsetof(Settings, gi.family.field), 0

/* clang-format off */
const SettingDesc settings_table[] = {
    /* Shadow maps, PCF, PCSS (SPEC §2). */
    {SROW(map_size), "--shadow-map-size", VALUE_INT, 16, 8192, 1024, NULL,
     "shadow map resolution per side (per cube face)"},
    {SROW(bias_const), "--shadow-bias-const", VALUE_FLOAT, 0, 10, 0.0005, NULL,
     "constant depth bias (m)"},
    {SROW(bias_slope), "--shadow-bias-slope", VALUE_FLOAT, 0, 100, 1.5, NULL,
     "slope-scaled bias (shadow-map texels x tan(theta))"},
    {SROW(normal_offset), "--shadow-normal-offset", VALUE_FLOAT, 0, 100, 0, NULL,
     "receiver offset along the normal (texels)"},
    {SROW(pcf_samples), "--shadow-pcf-samples", VALUE_INT, 1, SHADOW_MAX_SAMPLES, 20, NULL,
     "PCF Poisson-disk samples"},
    {SROW(pcf_radius), "--shadow-pcf-radius", VALUE_FLOAT, 0, 256, 2, NULL,
     "PCF filter radius (texels)"},
    {SROW(blocker_samples), "--shadow-blocker-samples", VALUE_INT, 1, SHADOW_MAX_SAMPLES,
     20, NULL, "PCSS blocker-search samples"},
    {SROW(pcss_max_radius), "--shadow-pcss-max-radius", VALUE_FLOAT, 1, 256, 48, NULL,
     "PCSS search/filter radius cap (texels)"},
    {SROW(filter_bias), "--shadow-filter-bias", VALUE_CHOICE, 0, 1, 0, k_filter_biases,
     "PCF/PCSS: receiver-plane depth + 1-texel bias, Poisson disk; legacy: slope bias x filter radius, spiral"},
    {SROW(pcf_filter), "--shadow-pcf-filter", VALUE_CHOICE, 0, 1, 0, k_pcf_filters,
     "PCF taps: disk (pcf_samples depth tests on a turned Poisson disk); grid (a square of bilinear hardware-compare taps one texel apart, 2x2 for radius 1: the 3x3 tent; PCSS keeps the disk)"},
    {SROW(area_light), "--shadow-area-light", VALUE_CHOICE, 0, 1, 0, k_area_lights,
     "quad lights: exact polygon irradiance (diffuse) + 8x8 quadrature of the GGX lobe over the rectangle (specular); point: a point at the centre"},
    /* Reflective shadow maps (SPEC §3). */
    {ROW(rsm, size), "--rsm-size", VALUE_INT, 4, 4096, 512, NULL,
     "RSM texels per side, per cube face for point/quad lights"},
    {ROW(rsm, samples), "--rsm-samples", VALUE_INT, 1, LOOP_CHUNK, 400, NULL, "samples per gather"},
    {ROW(rsm, r_max), "--rsm-r-max", VALUE_FLOAT, 1e-4, 4, 0.3, NULL,
     "sampling radius (RSM widths)"},
    {ROW(rsm, weighting), "--rsm-weighting", VALUE_CHOICE, 0, 2, 2, k_weightings,
     "importance: disk + flux-importance samples; paper: xi1^2 normalised; unbiased: polar pdf"},
    {ROW(rsm, exhaustive), "--rsm-exhaustive", VALUE_FLAG, 0, 1, 0, NULL,
     "sum over every RSM texel (tests, small maps)"},
    {ROW(rsm, interp_factor), "--rsm-interp-factor", VALUE_INT, 1, 64, 4, NULL,
     "rsm-interp: gather at 1/F resolution"},
    {ROW(rsm, interp_normal), "--rsm-interp-normal", VALUE_FLOAT, -1, 1, 0.9, NULL,
     "rsm-interp/blur: min cosine between normals"},
    {ROW(rsm, interp_dist), "--rsm-interp-dist", VALUE_FLOAT, 0, 100, 0.05, NULL,
     "rsm-interp/blur: max distance, fraction of the view distance"},
    /* A pair: ROW spelled out, with the second int's offset. */
    {"interleave", "pattern", "interleave.pattern", offsetof(Settings, gi.interleave.pattern.n),
     offsetof(Settings, gi.interleave.pattern.m), "--interleave-pattern", VALUE_PAIR, 1, 16, 4, NULL,
     "interleaved techniques: sub-image pattern NxM"},
    {ROW(interleave, blur), "--interleave-blur", VALUE_BOOL, 0, 1, 1, NULL,
     "geometry-aware blur after interleaving"},
    /* Many VPLs (SPEC §4). */
    /* 4096: every VPL technique renders the Cornell box at the default
     * 256x256 in about a second or less on llvmpipe (vpl-all, the brute
     * force, in about two); the benchmarks use 16384. */
    {ROW(vpl, count), "--vpl-count", VALUE_INT, 0, 1 << 24, 4096, NULL,
     "VPLs per light (sets the RSM size; 0: the RSM size decides)"},
    {ROW(vpl, slc_emax), "--vpl-slc-emax", VALUE_FLOAT, 1e-12, 1e6, 0.0005, NULL,
     "stochastic light culling error bound e_max"},
    {ROW(vpl, near_clamp), "--vpl-near-clamp", VALUE_FLOAT, 0, 1e6, 0, NULL,
     "falloff 1/max(d^2, C), C in m^2 (notes: 0.1); 0 = off"},
    {ROW(vpl, disk), "--vpl-disk", VALUE_BOOL, 0, 1, 1, NULL,
     "VPLs fall off as disks of their surface area, 1/(d^2 + A/pi): bounded near, 1/d^2 far"},
    {ROW(vpl, range), "--vpl-range", VALUE_FLOAT, 0, 1e6, 0, NULL,
     "vpl-clamped range (m); 0 = 0.15 x scene diagonal"},
    {ROW(vpl, keep), "--vpl-keep", VALUE_FLOAT, 1e-6, 1, 1, NULL,
     "vpl-all: keep a random fraction Q of the VPLs, weighted 1/Q"},
    {ROW(vpl, seed), "--vpl-seed", VALUE_UINT, 0, 2147483647, 0, NULL,
     "seed of the VPLs' random xi (SLC culling, subsets)"},
    /* 2: a sunlit edge crossing a texel-centre grid had kept or lost whole
     * texels' flux (Sponza's nave 0.84 of the RSM's bounce at 4096 VPLs). */
    {ROW(vpl, supersample), "--vpl-supersample", VALUE_INT, 1, 4, 2, NULL,
     "VPL techniques: RSM N times finer per side, one VPL per NxN block at its flux centroid (1: one per texel)"},
    /* Visibility of the bounce (SPEC §9, docs/techniques.md: Visibility). */
    {ROW(visibility, on), "--visibility-on", VALUE_BOOL, 0, 1, 0, NULL,
     "RSM and VPL techniques: test each VPL's visibility of the shaded point (off: the papers' one-bounce-novis)"},
    {ROW(visibility, method), "--visibility-method", VALUE_CHOICE, 0, 0, 0,
     k_visibility_methods, "ism: imperfect shadow maps (Ritschel et al. 2008), one per VPL or per block of RSM texels"},
    {ROW(visibility, ism_size), "--visibility-ism-size", VALUE_CHOICE, 0, 2, 1, k_ism_sizes,
     "ism: texels per side of each paraboloid map"},
    {ROW(visibility, ism_points), "--visibility-ism-points", VALUE_INT, 64, 65536, 2048, NULL,
     "ism: scene points splatted into each map (then pull-push fills the holes)"},
    {ROW(visibility, ism_maps), "--visibility-ism-maps", VALUE_INT, 1, 65536, 4096, NULL,
     "ism: RSM gathers' maps per light, one per block of RSM texels (VPL techniques: one per VPL)"},
    /* Light propagation volumes (SPEC §5). */
    {ROW(lpv, size), "--lpv-size", VALUE_INT, 2, 256, 16, NULL,
     "lpv: cells per side of each grid"},
    {ROW(lpv, cascades), "--lpv-cascades", VALUE_INT, 1, LPV_MAX_CASCADES, 1, NULL,
     "lpv: 1 = one grid on the scene bounds; 2-3 = nested grids around the camera"},
    {ROW(lpv, iterations), "--lpv-iterations", VALUE_INT, 0, 1024, 0, NULL,
     "lpv: propagation steps; 0 = enough to cross the grid's diagonal (directional: 3 x the grid size; faces: the "
     "grid size)"},
    {ROW(lpv, occlusion), "--lpv-occlusion", VALUE_BOOL, 0, 1, 1, NULL,
     "lpv: attenuate propagation by the geometry volume"},
    {ROW(lpv, offset), "--lpv-offset", VALUE_FLOAT, 0, 2, 0.5, NULL,
     "lpv: injection offset of a VPL along its normal (cells)"},
    {ROW(lpv, gbuffer_occlusion), "--lpv-gbuffer-occlusion", VALUE_BOOL, 0, 1, 1,
     NULL, "lpv: also inject the camera's G-buffer into the geometry volume"},
    {ROW(lpv, inject), "--lpv-inject", VALUE_CHOICE, 0, 1, 0, k_lpv_inject,
     "lpv: inject light and geometry by compute (fixed-point atomics, resolve) or points (layered draws, blending)"},
    {ROW(lpv, propagation), "--lpv-propagation", VALUE_CHOICE, 0, 1, 0, k_lpv_propagation,
     "lpv: a step moves light along the directions it travels in (directional) or through the paper's 5 faces per "
     "neighbour, re-emitted towards the faces' normals (faces)"},
    {ROW(lpv, groups), "--lpv-groups", VALUE_INT, 1, 2, 2, NULL,
     "lpv: 2 = the light of surfaces facing +x/+y/+z and of those facing -x/-y/-z propagate in separate volumes (flows "
     "from facing surfaces do not merge); 1 = one volume"},
    /* Voxel cone tracing (SPEC §6). */
    {ROW(vct, size), "--vct-size", VALUE_INT, 8, 256, 128, NULL,
     "vct: voxels per side of the volume over the scene bounds"},
    {ROW(vct, levels), "--vct-levels", VALUE_INT, 1, VCT_MAX_LEVELS, 1, NULL,
     "vct: 1 = one volume over the scene bounds; 2-4 = a clipmap of nested volumes around the camera"},
    {ROW(vct, aniso), "--vct-aniso", VALUE_BOOL, 0, 1, 1, NULL,
     "vct: six directional mip volumes (anisotropic voxels) instead of one isotropic chain"},
    {ROW(vct, cones), "--vct-cones", VALUE_CHOICE, 0, 2, 1, k_vct_cones,
     "vct: diffuse cones over the hemisphere, weighted to integrate the cosine lobe"},
    {ROW(vct, bounces), "--vct-bounces", VALUE_INT, 1, 2, 1, NULL,
     "vct: 1 = direct light in the voxels; 2 = plus a cone-traced bounce between voxels"},
    {ROW(vct, step), "--vct-step", VALUE_FLOAT, 0.1, 2, 0.5, NULL,
     "vct: cone sampling step (voxels of the sampled mip, i.e. cone diameters)"},
    {ROW(vct, trace_scale), "--vct-trace-scale", VALUE_INT, 1, 4, 2, NULL,
     "vct: trace the cones at every Nth pixel per axis, then upsample by depth and normal (1 = every pixel)"},
    {ROW(vct, ao), "--vct-ao", VALUE_BOOL, 0, 1, 1, NULL,
     "vct: ambient occlusion from the diffuse cones (--out-ao)"},
    {ROW(vct, conservative), "--vct-conservative", VALUE_BOOL, 0, 1, 1, NULL,
     "vct: conservative voxelization (every voxel a triangle touches); off: fragment centres only"},
    {ROW(vct, voxelize), "--vct-voxelize", VALUE_CHOICE, 0, 1, 1, k_vct_voxelize,
     "vct: voxelize in compute (a thread per triangle, large ones split into tiles of columns) or by rasterizing "
     "each triangle along its dominant axis; the same voxels"},
    {ROW(vct, roughness), "--vct-roughness", VALUE_FLOAT, 0, 1, 0.3, NULL,
     "vct: with --vct-f0 > 0, the GGX perceptual roughness of every surface's specular cone"},
    {ROW(vct, f0), "--vct-f0", VALUE_FLOAT, 0, 1, 0, NULL,
     "vct: > 0: F0 of every surface's specular cone instead of the material's (tests); 0 = the material's"},
    /* The renderer's own (SPEC §10 for time): what it does with any technique's indirect light. */
    {ROW(frame, indirect_scale), "--frame-indirect-scale", VALUE_FLOAT, 0, 1e6, 1, NULL,
     "indirect intensity scale (1 = physical)"},
    {ROW(frame, temporal), "--frame-temporal", VALUE_BOOL, 0, 1, 0, NULL,
     "temporal accumulation of the indirect light: reprojected history, disocclusion rejection, neighbourhood clamp"},
    {ROW(frame, temporal_clamp), "--frame-temporal-clamp", VALUE_BOOL, 0, 1, 1, NULL,
     "temporal: clamp the history to this frame's 3x3 neighbourhood; off only to measure what the clamp does "
     "(a moving light's bounce then lags)"},
};
/* clang-format on */
const int settings_count = (int)(sizeof settings_table / sizeof settings_table[0]);

/* Every setting as the table spelled it before issue 45 gave each one name
 * (commit d364f03): its key in the scene file's "shadow" or "gi" object, its
 * option, and the row it is now. Both old spellings stay accepted for good;
 * a setting added since has no entry. */
typedef struct SettingAlias {
    const char *key;    /* "gi.samples" */
    const char *option; /* "--rsm-samples" */
    const char *name;   /* the row's canonical name, "rsm.samples" */
} SettingAlias;

static const SettingAlias k_aliases[] = {
    {"shadow.map_size", "--shadow-map-size", "shadow.map_size"},
    {"shadow.bias_const", "--bias-const", "shadow.bias_const"},
    {"shadow.bias_slope", "--bias-slope", "shadow.bias_slope"},
    {"shadow.normal_offset", "--normal-offset", "shadow.normal_offset"},
    {"shadow.pcf_samples", "--pcf-samples", "shadow.pcf_samples"},
    {"shadow.pcf_radius", "--pcf-radius", "shadow.pcf_radius"},
    {"shadow.blocker_samples", "--blocker-samples", "shadow.blocker_samples"},
    {"shadow.pcss_max_radius", "--pcss-max-radius", "shadow.pcss_max_radius"},
    {"shadow.filter_bias", "--filter-bias", "shadow.filter_bias"},
    {"shadow.pcf_filter", "--pcf-filter", "shadow.pcf_filter"},
    {"shadow.area_light", "--area-light", "shadow.area_light"},
    {"gi.rsm_size", "--rsm-size", "rsm.size"},
    {"gi.samples", "--rsm-samples", "rsm.samples"},
    {"gi.r_max", "--rsm-rmax", "rsm.r_max"},
    {"gi.weighting", "--rsm-weighting", "rsm.weighting"},
    {"gi.exhaustive", "--rsm-exhaustive", "rsm.exhaustive"},
    {"gi.interp_factor", "--interp-factor", "rsm.interp_factor"},
    {"gi.interp_normal", "--interp-normal", "rsm.interp_normal"},
    {"gi.interp_dist", "--interp-dist", "rsm.interp_dist"},
    {"gi.interleave", "--interleave", "interleave.pattern"},
    {"gi.interleave_blur", "--interleave-blur", "interleave.blur"},
    {"gi.scale", "--gi-scale", "frame.indirect_scale"},
    {"gi.vpls", "--vpls", "vpl.count"},
    {"gi.slc_emax", "--slc-emax", "vpl.slc_emax"},
    {"gi.vpl_near_clamp", "--vpl-near-clamp", "vpl.near_clamp"},
    {"gi.vpl_disk", "--vpl-disk", "vpl.disk"},
    {"gi.vpl_range", "--vpl-range", "vpl.range"},
    {"gi.vpl_keep", "--vpl-keep", "vpl.keep"},
    {"gi.vpl_seed", "--vpl-seed", "vpl.seed"},
    {"gi.vpl_supersample", "--vpl-supersample", "vpl.supersample"},
    {"gi.gi_visibility", "--gi-visibility", "visibility.on"},
    {"gi.gi_visibility_method", "--gi-visibility-method", "visibility.method"},
    {"gi.ism_size", "--ism-size", "visibility.ism_size"},
    {"gi.ism_points", "--ism-points", "visibility.ism_points"},
    {"gi.ism_maps", "--ism-maps", "visibility.ism_maps"},
    {"gi.lpv_size", "--lpv-size", "lpv.size"},
    {"gi.lpv_cascades", "--lpv-cascades", "lpv.cascades"},
    {"gi.lpv_iterations", "--lpv-iterations", "lpv.iterations"},
    {"gi.lpv_occlusion", "--lpv-occlusion", "lpv.occlusion"},
    {"gi.lpv_offset", "--lpv-offset", "lpv.offset"},
    {"gi.lpv_gbuffer_occlusion", "--lpv-gbuffer-occlusion", "lpv.gbuffer_occlusion"},
    {"gi.lpv_inject", "--lpv-inject", "lpv.inject"},
    {"gi.lpv_propagation", "--lpv-propagation", "lpv.propagation"},
    {"gi.lpv_groups", "--lpv-groups", "lpv.groups"},
    {"gi.vct_size", "--vct-size", "vct.size"},
    {"gi.vct_levels", "--vct-levels", "vct.levels"},
    {"gi.vct_aniso", "--vct-aniso", "vct.aniso"},
    {"gi.vct_cones", "--vct-cones", "vct.cones"},
    {"gi.vct_bounces", "--vct-bounces", "vct.bounces"},
    {"gi.vct_step", "--vct-step", "vct.step"},
    {"gi.vct_trace_scale", "--vct-trace-scale", "vct.trace_scale"},
    {"gi.vct_ao", "--vct-ao", "vct.ao"},
    {"gi.vct_conservative", "--vct-conservative", "vct.conservative"},
    {"gi.vct_voxelize", "--vct-voxelize", "vct.voxelize"},
    {"gi.vct_roughness", "--vct-roughness", "vct.roughness"},
    {"gi.vct_f0", "--vct-f0", "vct.f0"},
    {"gi.temporal", "--temporal", "frame.temporal"},
    {"gi.temporal_clamp", "--temporal-clamp", "frame.temporal_clamp"},
};
enum { ALIAS_COUNT = (int)(sizeof k_aliases / sizeof k_aliases[0]) };

/* ---- Storage -------------------------------------------------------------- */

ValueSpec settings_value(const SettingDesc *d)
{
    return (ValueSpec){d->type, d->offset, d->offset2, d->min, d->max, d->choices, NULL};
}

static void *at(Settings *s, size_t off) { return (char *)s + off; }

void settings_default(Settings *s)
{
    memset(s, 0, sizeof *s);
    for (int i = 0; i < settings_count; i++) {
        ValueSpec v = settings_value(&settings_table[i]);
        value_store_number(&v, s, settings_table[i].def);
    }
}

void settings_copy(const SettingDesc *d, Settings *dst, const Settings *src)
{
    ValueSpec v = settings_value(d);
    value_copy(&v, dst, src);
}

void settings_format(const SettingDesc *d, const Settings *s, char *out, size_t cap)
{
    ValueSpec v = settings_value(d);
    value_format(&v, s, out, cap);
}

/* ---- Lookup ---------------------------------------------------------------- */

const SettingDesc *settings_find_name(const char *name)
{
    for (int i = 0; i < settings_count; i++)
        if (!strcmp(settings_table[i].name, name))
            return &settings_table[i];
    for (int i = 0; i < ALIAS_COUNT; i++)
        if (!strcmp(k_aliases[i].key, name))
            return settings_find_name(k_aliases[i].name);
    return NULL;
}

const SettingDesc *settings_find_option(const char *option)
{
    for (int i = 0; i < settings_count; i++)
        if (!strcmp(settings_table[i].option, option))
            return &settings_table[i];
    for (int i = 0; i < ALIAS_COUNT; i++)
        if (!strcmp(k_aliases[i].option, option))
            return settings_find_name(k_aliases[i].name);
    return NULL;
}

static const SettingAlias *alias_of(const SettingDesc *d)
{
    for (int i = 0; i < ALIAS_COUNT; i++)
        if (!strcmp(k_aliases[i].name, d->name))
            return &k_aliases[i];
    return NULL;
}

const char *settings_old_key(const SettingDesc *d)
{
    const SettingAlias *a = alias_of(d);
    return a && strcmp(a->key, d->name) ? a->key : NULL;
}

const char *settings_old_option(const SettingDesc *d)
{
    const SettingAlias *a = alias_of(d);
    return a && strcmp(a->option, d->option) ? a->option : NULL;
}

int settings_names(const char **out, int cap)
{
    int n = 0;
    for (int i = 0; i < settings_count && n < cap - 1; i++)
        out[n++] = settings_table[i].name;
    out[n] = NULL;
    return n;
}

int settings_families(const char **out, int cap)
{
    int n = 0;
    for (int i = 0; i < settings_count && n < cap - 1; i++) {
        bool seen = false;
        for (int k = 0; k < n && !seen; k++)
            seen = !strcmp(out[k], settings_table[i].family);
        if (!seen)
            out[n++] = settings_table[i].family;
    }
    out[n] = NULL;
    return n;
}

void settings_scene_keys(const char **out, int *n, int cap)
{
    const char *fam[32];
    settings_families(fam, 32);
    for (int i = 0; fam[i] && *n < cap - 2; i++)
        out[(*n)++] = fam[i];
    if (*n < cap - 1)
        out[(*n)++] = "gi";
    out[*n] = NULL;
}

/* ---- Validation ------------------------------------------------------------- */

bool settings_parse_cli(const SettingDesc *d, const char *as_written, const char *value, Settings *s)
{
    ValueSpec v = settings_value(d);
    return value_parse_text(&v, as_written ? as_written : d->option, value, s);
}

/* `where` is the key as the scene file spells it: "rsm.samples", "gi.samples". */
static bool json_fail(const char *file, const char *where, const SettingDesc *d, const cJSON *v, const char *problem)
{
    char range[256], value[48] = "";
    ValueSpec spec = settings_value(d);
    value_describe(&spec, true, range, sizeof range);
    if (cJSON_IsNumber(v))
        snprintf(value, sizeof value, "%.9g ", v->valuedouble);
    log_error("scene", "%s: %s: %s%s (allowed: %s)", file, where, value, problem, range);
    return false;
}

static bool json_number(const cJSON *v, const SettingDesc *d, const char *file, const char *where, double *out)
{
    if (!cJSON_IsNumber(v))
        return json_fail(file, where, d, v, "must be a number");
    ValueSpec spec = settings_value(d);
    const char *problem = value_check_number(&spec, v->valuedouble);
    if (problem)
        return json_fail(file, where, d, v, problem);
    *out = v->valuedouble;
    return true;
}

static bool parse_json_value(const cJSON *v, const SettingDesc *d, const char *file, const char *where, Settings *s)
{
    double x, y;
    switch (d->type) {
    case VALUE_BOOL:
    case VALUE_FLAG: {
        /* A switch may also be written as on the command line. */
        bool word = d->type == VALUE_BOOL && cJSON_IsString(v);
        if (word && (!strcmp(v->valuestring, "on") || !strcmp(v->valuestring, "off"))) {
            *(bool *)at(s, d->offset) = !strcmp(v->valuestring, "on");
            return true;
        }
        if (!cJSON_IsBool(v))
            return json_fail(file, where, d, v, "must be true or false");
        *(bool *)at(s, d->offset) = cJSON_IsTrue(v);
        return true;
    }
    case VALUE_CHOICE: {
        /* A choice that is a number ("16") may also be given as one. */
        char num[32] = "";
        if (cJSON_IsNumber(v))
            snprintf(num, sizeof num, "%.10g", v->valuedouble);
        const char *name = cJSON_IsString(v) ? v->valuestring : num;
        for (int i = 0; *name && d->choices[i]; i++)
            if (!strcmp(name, d->choices[i])) {
                *(int *)at(s, d->offset) = i;
                return true;
            }
        return json_fail(file, where, d, v, "must be one of the choices");
    }
    case VALUE_PAIR:
        if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
            return json_fail(file, where, d, v, "must be [n, m]");
        if (!json_number(cJSON_GetArrayItem(v, 0), d, file, where, &x) ||
            !json_number(cJSON_GetArrayItem(v, 1), d, file, where, &y))
            return false;
        *(int *)at(s, d->offset) = (int)x;
        *(int *)at(s, d->offset2) = (int)y;
        return true;
    default:
        if (!json_number(v, d, file, where, &x))
            return false;
        ValueSpec spec = settings_value(d);
        value_store_number(&spec, s, x);
        return true;
    }
}

int settings_object_keys(const char *object, const char **out, int cap)
{
    int n = 0;
    for (int i = 0; i < settings_count && n < cap - 1; i++)
        if (!strcmp(settings_table[i].family, object))
            out[n++] = settings_table[i].field;
    size_t len = strlen(object);
    for (int i = 0; i < ALIAS_COUNT && n < cap - 1; i++) {
        const char *k = k_aliases[i].key;
        if (strncmp(k, object, len) || k[len] != '.')
            continue;
        bool seen = false;
        for (int j = 0; j < n && !seen; j++)
            seen = !strcmp(out[j], k + len + 1);
        if (!seen)
            out[n++] = k + len + 1;
    }
    out[n] = NULL;
    return n;
}

/* Reads the scene object `object` (a family's, or "gi") into `s`; given[]
 * marks each row read, and a row already read (through another object) is
 * an error. */
static bool parse_object(const cJSON *obj, const char *object, const char *file, Settings *s, const char **given)
{
    if (!cJSON_IsObject(obj)) {
        log_error("scene", "%s: %s: must be an object", file, object);
        return false;
    }
    /* Unknown keys (an error naming the nearest, or a warning with
     * --lenient) and duplicates: the scene file's one key check. */
    const char *known[128];
    settings_object_keys(object, known, 128);
    if (!json_check_keys(obj, known, file, object))
        return false;
    for (const cJSON *a = obj->child; a; a = a->next) {
        char where[128];
        snprintf(where, sizeof where, "%s.%s", object, a->string ? a->string : "");
        const SettingDesc *d = settings_find_name(where);
        if (!d)
            continue; /* unknown, and --lenient: warned */
        const char **was = &given[d - settings_table];
        if (*was) {
            log_error("scene", "%s: %s: the setting %s is also given in the object \"%s\"", file, where, d->name,
                      *was);
            return false;
        }
        *was = object;
        if (!parse_json_value(a, d, file, where, s))
            return false;
    }
    return true;
}

bool settings_parse_scene(const cJSON *root, const char *file, Settings *s)
{
    const char *keys[40];
    int n = 0;
    settings_scene_keys(keys, &n, 40);
    enum { MAX_ROWS = 256 };
    const char *given[MAX_ROWS] = {0}; /* the object each row was read from */
    if (settings_count > MAX_ROWS) {
        log_error("scene", "%s: the settings table has more than %d rows", file, MAX_ROWS);
        return false;
    }
    for (int i = 0; keys[i]; i++) {
        const cJSON *obj = cJSON_GetObjectItemCaseSensitive(root, keys[i]);
        if (obj && !parse_object(obj, keys[i], file, s, given))
            return false;
    }
    return true;
}

/* ---- Help ------------------------------------------------------------------- */

void settings_print_help(FILE *f, const char *family)
{
    Settings def;
    settings_default(&def);
    for (int i = 0; i < settings_count; i++) {
        const SettingDesc *d = &settings_table[i];
        if (strcmp(d->family, family))
            continue;
        char arg[160], value[64], range[160], placeholder[96], was[160] = "";
        settings_format(d, &def, value, sizeof value);
        ValueSpec v = settings_value(d);
        value_placeholder(&v, placeholder, sizeof placeholder);
        snprintf(arg, sizeof arg, "%s%s%s", d->option, placeholder[0] ? " " : "", placeholder);
        if (d->type == VALUE_FLOAT || d->type == VALUE_INT || d->type == VALUE_UINT || d->type == VALUE_PAIR)
            snprintf(range, sizeof range, " [%.10g..%.10g]", d->min, d->max);
        else
            range[0] = 0;
        const char *old_option = settings_old_option(d), *old_key = settings_old_key(d);
        if (old_option || old_key)
            snprintf(was, sizeof was, "; also %s%s%s", old_option ? old_option : "",
                     old_option && old_key ? ", " : "", old_key ? old_key : "");
        fprintf(f, "  %-32s %s (default %s%s; scene key %s%s)\n", arg, d->help, value, range, d->name, was);
    }
}
