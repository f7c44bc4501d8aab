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

#define SH(f) offsetof(Settings, shadow.f)
#define GI(f) offsetof(Settings, gi.f)

/* clang-format off */
const SettingDesc settings_table[] = {
    /* Shadow maps, PCF, PCSS (SPEC §2). */
    {"shadow", "map_size", "--shadow-map-size", VALUE_INT, SH(map_size), 0, 16, 8192, 1024, NULL,
     "shadow map resolution per side (per cube face)"},
    {"shadow", "bias_const", "--bias-const", VALUE_FLOAT, SH(bias_const), 0, 0, 10, 0.0005, NULL,
     "constant depth bias (m)"},
    {"shadow", "bias_slope", "--bias-slope", VALUE_FLOAT, SH(bias_slope), 0, 0, 100, 1.5, NULL,
     "slope-scaled bias (shadow-map texels x tan(theta))"},
    {"shadow", "normal_offset", "--normal-offset", VALUE_FLOAT, SH(normal_offset), 0, 0, 100, 0, NULL,
     "receiver offset along the normal (texels)"},
    {"shadow", "pcf_samples", "--pcf-samples", VALUE_INT, SH(pcf_samples), 0, 1, SHADOW_MAX_SAMPLES, 20, NULL,
     "PCF Poisson-disk samples"},
    {"shadow", "pcf_radius", "--pcf-radius", VALUE_FLOAT, SH(pcf_radius), 0, 0, 256, 2, NULL,
     "PCF filter radius (texels)"},
    {"shadow", "blocker_samples", "--blocker-samples", VALUE_INT, SH(blocker_samples), 0, 1, SHADOW_MAX_SAMPLES,
     20, NULL, "PCSS blocker-search samples"},
    {"shadow", "pcss_max_radius", "--pcss-max-radius", VALUE_FLOAT, SH(pcss_max_radius), 0, 1, 256, 48, NULL,
     "PCSS search/filter radius cap (texels)"},
    {"shadow", "filter_bias", "--filter-bias", VALUE_CHOICE, SH(filter_bias), 0, 0, 1, 0, k_filter_biases,
     "PCF/PCSS: receiver-plane depth + 1-texel bias, Poisson disk; legacy: slope bias x filter radius, spiral"},
    {"shadow", "pcf_filter", "--pcf-filter", VALUE_CHOICE, SH(pcf_filter), 0, 0, 1, 0, k_pcf_filters,
     "PCF taps: disk (pcf_samples depth tests on a turned Poisson disk); grid (a square of bilinear hardware-compare taps one texel apart, 2x2 for radius 1: the 3x3 tent; PCSS keeps the disk)"},
    {"shadow", "area_light", "--area-light", VALUE_CHOICE, SH(area_light), 0, 0, 1, 0, k_area_lights,
     "quad lights: exact polygon irradiance (diffuse) + 8x8 quadrature of the GGX lobe over the rectangle (specular); point: a point at the centre"},
    /* Reflective shadow maps (SPEC §3). */
    {"gi", "rsm_size", "--rsm-size", VALUE_INT, GI(rsm.size), 0, 4, 4096, 512, NULL,
     "RSM texels per side, per cube face for point/quad lights"},
    {"gi", "samples", "--rsm-samples", VALUE_INT, GI(rsm.samples), 0, 1, LOOP_CHUNK, 400, NULL, "samples per gather"},
    {"gi", "r_max", "--rsm-rmax", VALUE_FLOAT, GI(rsm.r_max), 0, 1e-4, 4, 0.3, NULL,
     "sampling radius (RSM widths)"},
    {"gi", "weighting", "--rsm-weighting", VALUE_CHOICE, GI(rsm.weighting), 0, 0, 2, 2, k_weightings,
     "importance: disk + flux-importance samples; paper: xi1^2 normalised; unbiased: polar pdf"},
    {"gi", "exhaustive", "--rsm-exhaustive", VALUE_FLAG, GI(rsm.exhaustive), 0, 0, 1, 0, NULL,
     "sum over every RSM texel (tests, small maps)"},
    {"gi", "interp_factor", "--interp-factor", VALUE_INT, GI(rsm.interp_factor), 0, 1, 64, 4, NULL,
     "rsm-interp: gather at 1/F resolution"},
    {"gi", "interp_normal", "--interp-normal", VALUE_FLOAT, GI(rsm.interp_normal), 0, -1, 1, 0.9, NULL,
     "rsm-interp/blur: min cosine between normals"},
    {"gi", "interp_dist", "--interp-dist", VALUE_FLOAT, GI(rsm.interp_dist), 0, 0, 100, 0.05, NULL,
     "rsm-interp/blur: max distance, fraction of the view distance"},
    {"gi", "interleave", "--interleave", VALUE_PAIR, GI(interleave.n), GI(interleave.m), 1, 16, 4, NULL,
     "interleaved techniques: sub-image pattern NxM"},
    {"gi", "interleave_blur", "--interleave-blur", VALUE_BOOL, GI(interleave.blur), 0, 0, 1, 1, NULL,
     "geometry-aware blur after interleaving"},
    {"gi", "scale", "--gi-scale", VALUE_FLOAT, GI(frame.scale), 0, 0, 1e6, 1, NULL,
     "indirect intensity scale (1 = physical)"},
    /* Many VPLs (SPEC §4). */
    /* 4096: every VPL technique renders the Cornell box at the default
     * 256x256 in about a second or less on llvmpipe (vpl-all, the brute
     * force, in about two); the benchmarks use 16384. */
    {"gi", "vpls", "--vpls", VALUE_INT, GI(vpl.count), 0, 0, 1 << 24, 4096, NULL,
     "VPLs per light (sets the RSM size; 0: the RSM size decides)"},
    {"gi", "slc_emax", "--slc-emax", VALUE_FLOAT, GI(vpl.slc_emax), 0, 1e-12, 1e6, 0.0005, NULL,
     "stochastic light culling error bound e_max"},
    {"gi", "vpl_near_clamp", "--vpl-near-clamp", VALUE_FLOAT, GI(vpl.near_clamp), 0, 0, 1e6, 0, NULL,
     "falloff 1/max(d^2, C), C in m^2 (notes: 0.1); 0 = off"},
    {"gi", "vpl_disk", "--vpl-disk", VALUE_BOOL, GI(vpl.disk), 0, 0, 1, 1, NULL,
     "VPLs fall off as disks of their surface area, 1/(d^2 + A/pi): bounded near, 1/d^2 far"},
    {"gi", "vpl_range", "--vpl-range", VALUE_FLOAT, GI(vpl.range), 0, 0, 1e6, 0, NULL,
     "vpl-clamped range (m); 0 = 0.15 x scene diagonal"},
    {"gi", "vpl_keep", "--vpl-keep", VALUE_FLOAT, GI(vpl.keep), 0, 1e-6, 1, 1, NULL,
     "vpl-all: keep a random fraction Q of the VPLs, weighted 1/Q"},
    {"gi", "vpl_seed", "--vpl-seed", VALUE_UINT, GI(vpl.seed), 0, 0, 2147483647, 0, NULL,
     "seed of the VPLs' random xi (SLC culling, subsets)"},
    /* 2: a sunlit edge crossing a texel-centre grid had kept or lost whole
     * texels' flux (Sponza's nave 0.84 of the RSM's bounce at 4096 VPLs). */
    {"gi", "vpl_supersample", "--vpl-supersample", VALUE_INT, GI(vpl.supersample), 0, 1, 4, 2, NULL,
     "VPL techniques: RSM N times finer per side, one VPL per NxN block at its flux centroid (1: one per texel)"},
    /* Visibility of the bounce (SPEC §9, docs/techniques.md: Visibility). */
    {"gi", "gi_visibility", "--gi-visibility", VALUE_BOOL, GI(visibility.on), 0, 0, 1, 0, NULL,
     "RSM and VPL techniques: test each VPL's visibility of the shaded point (off: the papers' one-bounce-novis)"},
    {"gi", "gi_visibility_method", "--gi-visibility-method", VALUE_CHOICE, GI(visibility.method), 0, 0, 0, 0,
     k_visibility_methods, "ism: imperfect shadow maps (Ritschel et al. 2008), one per VPL or per block of RSM texels"},
    {"gi", "ism_size", "--ism-size", VALUE_CHOICE, GI(visibility.ism_size), 0, 0, 2, 1, k_ism_sizes,
     "ism: texels per side of each paraboloid map"},
    {"gi", "ism_points", "--ism-points", VALUE_INT, GI(visibility.ism_points), 0, 64, 65536, 2048, NULL,
     "ism: scene points splatted into each map (then pull-push fills the holes)"},
    {"gi", "ism_maps", "--ism-maps", VALUE_INT, GI(visibility.ism_maps), 0, 1, 65536, 4096, NULL,
     "ism: RSM gathers' maps per light, one per block of RSM texels (VPL techniques: one per VPL)"},
    /* Light propagation volumes (SPEC §5). */
    {"gi", "lpv_size", "--lpv-size", VALUE_INT, GI(lpv.size), 0, 2, 256, 16, NULL,
     "lpv: cells per side of each grid"},
    {"gi", "lpv_cascades", "--lpv-cascades", VALUE_INT, GI(lpv.cascades), 0, 1, LPV_MAX_CASCADES, 1, NULL,
     "lpv: 1 = one grid on the scene bounds; 2-3 = nested grids around the camera"},
    {"gi", "lpv_iterations", "--lpv-iterations", VALUE_INT, GI(lpv.iterations), 0, 0, 1024, 0, NULL,
     "lpv: propagation steps; 0 = enough to cross the grid's diagonal (directional: 3 x the grid size; faces: the "
     "grid size)"},
    {"gi", "lpv_occlusion", "--lpv-occlusion", VALUE_BOOL, GI(lpv.occlusion), 0, 0, 1, 1, NULL,
     "lpv: attenuate propagation by the geometry volume"},
    {"gi", "lpv_offset", "--lpv-offset", VALUE_FLOAT, GI(lpv.offset), 0, 0, 2, 0.5, NULL,
     "lpv: injection offset of a VPL along its normal (cells)"},
    {"gi", "lpv_gbuffer_occlusion", "--lpv-gbuffer-occlusion", VALUE_BOOL, GI(lpv.gbuffer_occlusion), 0, 0, 1, 1,
     NULL, "lpv: also inject the camera's G-buffer into the geometry volume"},
    {"gi", "lpv_inject", "--lpv-inject", VALUE_CHOICE, GI(lpv.inject), 0, 0, 1, 0, k_lpv_inject,
     "lpv: inject light and geometry by compute (fixed-point atomics, resolve) or points (layered draws, blending)"},
    {"gi", "lpv_propagation", "--lpv-propagation", VALUE_CHOICE, GI(lpv.propagation), 0, 0, 1, 0, k_lpv_propagation,
     "lpv: a step moves light along the directions it travels in (directional) or through the paper's 5 faces per "
     "neighbour, re-emitted towards the faces' normals (faces)"},
    {"gi", "lpv_groups", "--lpv-groups", VALUE_INT, GI(lpv.groups), 0, 1, 2, 2, NULL,
     "lpv: 2 = the light of surfaces facing +x/+y/+z and of those facing -x/-y/-z propagate in separate volumes (flows "
     "from facing surfaces do not merge); 1 = one volume"},
    /* Voxel cone tracing (SPEC §6). */
    {"gi", "vct_size", "--vct-size", VALUE_INT, GI(vct.size), 0, 8, 256, 128, NULL,
     "vct: voxels per side of the volume over the scene bounds"},
    {"gi", "vct_levels", "--vct-levels", VALUE_INT, GI(vct.levels), 0, 1, VCT_MAX_LEVELS, 1, NULL,
     "vct: 1 = one volume over the scene bounds; 2-4 = a clipmap of nested volumes around the camera"},
    {"gi", "vct_aniso", "--vct-aniso", VALUE_BOOL, GI(vct.aniso), 0, 0, 1, 1, NULL,
     "vct: six directional mip volumes (anisotropic voxels) instead of one isotropic chain"},
    {"gi", "vct_cones", "--vct-cones", VALUE_CHOICE, GI(vct.cones), 0, 0, 2, 1, k_vct_cones,
     "vct: diffuse cones over the hemisphere, weighted to integrate the cosine lobe"},
    {"gi", "vct_bounces", "--vct-bounces", VALUE_INT, GI(vct.bounces), 0, 1, 2, 1, NULL,
     "vct: 1 = direct light in the voxels; 2 = plus a cone-traced bounce between voxels"},
    {"gi", "vct_step", "--vct-step", VALUE_FLOAT, GI(vct.step), 0, 0.1, 2, 0.5, NULL,
     "vct: cone sampling step (voxels of the sampled mip, i.e. cone diameters)"},
    {"gi", "vct_trace_scale", "--vct-trace-scale", VALUE_INT, GI(vct.trace_scale), 0, 1, 4, 2, NULL,
     "vct: trace the cones at every Nth pixel per axis, then upsample by depth and normal (1 = every pixel)"},
    {"gi", "vct_ao", "--vct-ao", VALUE_BOOL, GI(vct.ao), 0, 0, 1, 1, NULL,
     "vct: ambient occlusion from the diffuse cones (--out-ao)"},
    {"gi", "vct_conservative", "--vct-conservative", VALUE_BOOL, GI(vct.conservative), 0, 0, 1, 1, NULL,
     "vct: conservative voxelization (every voxel a triangle touches); off: fragment centres only"},
    {"gi", "vct_voxelize", "--vct-voxelize", VALUE_CHOICE, GI(vct.voxelize), 0, 0, 1, 1, k_vct_voxelize,
     "vct: voxelize in compute (a thread per triangle, large ones split into tiles of columns) or by rasterizing "
     "each triangle along its dominant axis; the same voxels"},
    {"gi", "vct_roughness", "--vct-roughness", VALUE_FLOAT, GI(vct.roughness), 0, 0, 1, 0.3, NULL,
     "vct: with --vct-f0 > 0, the GGX perceptual roughness of every surface's specular cone"},
    {"gi", "vct_f0", "--vct-f0", VALUE_FLOAT, GI(vct.f0), 0, 0, 1, 0, NULL,
     "vct: > 0: F0 of every surface's specular cone instead of the material's (tests); 0 = the material's"},
    /* Time (SPEC §10): temporal accumulation of any technique's indirect light. */
    {"gi", "temporal", "--temporal", VALUE_BOOL, GI(frame.temporal), 0, 0, 1, 0, NULL,
     "temporal accumulation of the indirect light: reprojected history, disocclusion rejection, neighbourhood clamp"},
    {"gi", "temporal_clamp", "--temporal-clamp", VALUE_BOOL, GI(frame.temporal_clamp), 0, 0, 1, 1, NULL,
     "temporal: clamp the history to this frame's 3x3 neighbourhood; off only to measure what the clamp does "
     "(a moving light's bounce then lags)"},
};
/* clang-format on */
const int settings_count = (int)(sizeof settings_table / sizeof settings_table[0]);

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

const SettingDesc *settings_find_option(const char *option)
{
    for (int i = 0; i < settings_count; i++)
        if (!strcmp(settings_table[i].option, option))
            return &settings_table[i];
    return NULL;
}

const SettingDesc *settings_find_key(const char *group, const char *key)
{
    for (int i = 0; i < settings_count; i++)
        if (!strcmp(settings_table[i].group, group) && !strcmp(settings_table[i].key, key))
            return &settings_table[i];
    return NULL;
}

/* ---- Validation ------------------------------------------------------------- */

bool settings_parse_cli(const SettingDesc *d, const char *value, Settings *s)
{
    ValueSpec v = settings_value(d);
    return value_parse_text(&v, d->option, value, s);
}

static bool json_fail(const char *file, const char *group, const SettingDesc *d, const cJSON *v, const char *problem)
{
    char range[256], value[48] = "";
    ValueSpec spec = settings_value(d);
    value_describe(&spec, true, range, sizeof range);
    if (cJSON_IsNumber(v))
        snprintf(value, sizeof value, "%.9g ", v->valuedouble);
    log_error("scene", "%s: %s.%s: %s%s (allowed: %s)", file, group, d->key, value, problem, range);
    return false;
}

static bool json_number(const cJSON *v, const SettingDesc *d, const char *file, const char *group, double *out)
{
    if (!cJSON_IsNumber(v))
        return json_fail(file, group, d, v, "must be a number");
    ValueSpec spec = settings_value(d);
    const char *problem = value_check_number(&spec, v->valuedouble);
    if (problem)
        return json_fail(file, group, d, v, problem);
    *out = v->valuedouble;
    return true;
}

static bool parse_json_value(const cJSON *v, const SettingDesc *d, const char *file, const char *group, Settings *s)
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
            return json_fail(file, group, d, v, "must be true or false");
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
        return json_fail(file, group, d, v, "must be one of the choices");
    }
    case VALUE_PAIR:
        if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
            return json_fail(file, group, d, v, "must be [n, m]");
        if (!json_number(cJSON_GetArrayItem(v, 0), d, file, group, &x) ||
            !json_number(cJSON_GetArrayItem(v, 1), d, file, group, &y))
            return false;
        *(int *)at(s, d->offset) = (int)x;
        *(int *)at(s, d->offset2) = (int)y;
        return true;
    default:
        if (!json_number(v, d, file, group, &x))
            return false;
        ValueSpec spec = settings_value(d);
        value_store_number(&spec, s, x);
        return true;
    }
}

int settings_keys(const char *group, const char **out, int cap)
{
    int n = 0;
    for (int i = 0; i < settings_count && n < cap - 1; i++)
        if (!group || !strcmp(settings_table[i].group, group))
            out[n++] = settings_table[i].key;
    out[n] = NULL;
    return n;
}

bool settings_parse_json(const cJSON *obj, const char *group, const char *file, Settings *s)
{
    if (!cJSON_IsObject(obj)) {
        log_error("scene", "%s: %s: must be an object", file, group);
        return false;
    }
    /* Unknown keys (an error naming the nearest, or a warning with
     * --lenient) and duplicates: the scene file's one key check. */
    const char *known[128];
    settings_keys(group, known, 128);
    if (!json_check_keys(obj, known, file, group))
        return false;
    for (const cJSON *a = obj->child; a; a = a->next) {
        const SettingDesc *d = settings_find_key(group, a->string ? a->string : "");
        if (d && !parse_json_value(a, d, file, group, s))
            return false;
    }
    return true;
}

/* ---- Help ------------------------------------------------------------------- */

void settings_print_help(FILE *f, const char *group)
{
    Settings def;
    settings_default(&def);
    for (int i = 0; i < settings_count; i++) {
        const SettingDesc *d = &settings_table[i];
        if (strcmp(d->group, group))
            continue;
        char arg[160], value[64], range[160], placeholder[96];
        settings_format(d, &def, value, sizeof value);
        ValueSpec v = settings_value(d);
        value_placeholder(&v, placeholder, sizeof placeholder);
        snprintf(arg, sizeof arg, "%s%s%s", d->option, placeholder[0] ? " " : "", placeholder);
        if (d->type == VALUE_FLOAT || d->type == VALUE_INT || d->type == VALUE_UINT || d->type == VALUE_PAIR)
            snprintf(range, sizeof range, " [%.10g..%.10g]", d->min, d->max);
        else
            range[0] = 0;
        fprintf(f, "  %-32s %s (default %s%s; scene key %s.%s)\n", arg, d->help, value, range, d->group, d->key);
    }
}
