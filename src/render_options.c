/* render_options.c — parsing of the options `render` and `view` share. */
#include "render_options.h"

#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "log.h"
#include "shader.h"
#include "util.h"

#define MAX_IMAGE_SIZE 16384

void render_options_help(void)
{
    printf(
                "  --scene cornell|FILE.json|FILE.gltf|FILE.obj   scene (default: cornell)\n"
        "  --shadow none|hard|pcf|pcss   shadow technique (default: pcss)\n"
        "  --gi TECHNIQUE                indirect light (default: none): none, rsm, rsm-interp,\n"
        "                                rsm-interleaved, vpl-all, vpl-clamped, vpl-slc,\n"
        "                                vpl-interleaved, vpl-metalights\n"
        "  --size WxH                    image size (default: 512x512)\n"
        "  --exposure E                  radiance multiplier before tone mapping (default: scene's)\n"
        "  --out FILE.png|FILE.pfm       output; PNG tone-mapped sRGB, PFM linear radiance\n"
        "                                (default: out/render.png)\n"
        "  --png FILE.png                also write the tone-mapped PNG (beside a .pfm --out)\n"
        "  --timings                     print per-pass GPU (and wall) times\n"
        "  --frames N                    frames to time after the warm-up (default: 3)\n"
        "  --warmup N                    untimed frames first (default: 1)\n"
        "  --light-scale S               scale every light's emitter size (0: point lights)\n"
        "shadow parameters (default: scene file's, else built-in):\n"
        "  --shadow-map-size N  --bias-const M  --bias-slope S  --normal-offset T\n"
        "  --pcf-samples N  --pcf-radius T  --blocker-samples N  --pcss-max-radius T\n"
        "  (M in metres, T in shadow-map texels, S in texels x tan(theta))\n"
        "GI parameters (reflective shadow maps):\n"
        "  --rsm-size N         RSM texels per side, per cube face for point/quad lights (512)\n"
        "  --rsm-samples N      samples per gather (400)\n"
        "  --rsm-rmax R         sampling radius in RSM widths (0.3)\n"
        "  --rsm-weighting paper|unbiased   xi1^2 normalised, or unbiased for the polar pdf\n"
        "  --rsm-exhaustive     sum over every RSM texel (tests, small maps)\n"
        "  --interp-factor F    rsm-interp: gather at 1/F resolution (4)\n"
        "  --interp-normal C    rsm-interp/blur: min cosine between normals (0.9)\n"
        "  --interp-dist D      rsm-interp/blur: max distance, fraction of view distance (0.05)\n"
        "  --interleave NxM     rsm-interleaved: sub-image pattern (4x4)\n"
        "  --interleave-blur on|off   geometry-aware blur after reassembly (on)\n"
        "  --gi-scale S         indirect intensity scale (1 = physical)\n"
        "many-VPL parameters (vpl-*):\n"
        "  --vpls N             VPLs per light (sets the RSM size; e.g. 4096 .. 1048576)\n"
        "  --slc-emax E         stochastic light culling error bound e_max (0.0005)\n"
        "  --vpl-near-clamp C   falloff 1/max(d^2, C), C in m^2 (notes: 0.1); default off\n"
        "  --vpl-range R        vpl-clamped range in metres (default 0.15 x scene diagonal)\n"
        "  --vpl-keep Q         vpl-all: keep a random fraction Q of the VPLs, weighted 1/Q\n"
        "  --vpl-seed S         seed of the VPLs' random xi (SLC culling, subsets)\n"
        "other:\n"
        "  --shader-dir DIR   read shaders from DIR instead of the embedded copies\n"
        "  --debug            GL debug context, KHR_debug messages logged\n"
        "  --quiet | --verbose\n");
}

enum { GP_SIZE = 1, GP_N = 2, GP_RMAX = 4, GP_W = 8, GP_EXH = 16, GP_IF = 32, GP_IN = 64, GP_ID = 128,
       GP_IL = 256, GP_BLUR = 512, GP_SCALE = 1024, GP_VPLS = 2048, GP_EMAX = 4096, GP_NEAR = 8192,
       GP_RANGE = 16384, GP_KEEP = 32768, GP_SEED = 65536 };
static const char *const k_weightings[] = {"paper", "unbiased", NULL};
static const char *const k_on_off[] = {"off", "on", NULL};

enum { SP_MAP = 1, SP_BC = 2, SP_BS = 4, SP_NO = 8, SP_PS = 16, SP_PR = 32, SP_BL = 64, SP_MR = 128 };

static const char *const k_shadow_names[] = {"none", "hard", "pcf", "pcss", NULL};

static void apply_gi_overrides(const RenderOptions *o, GiParams *p)
{
    if (o->gp_set & GP_SIZE) p->rsm_size = o->gp.rsm_size;
    if (o->gp_set & GP_N) p->samples = o->gp.samples;
    if (o->gp_set & GP_RMAX) p->r_max = o->gp.r_max;
    if (o->gp_set & GP_W) p->weighting = o->gp.weighting;
    if (o->gp_set & GP_EXH) p->exhaustive = o->gp.exhaustive;
    if (o->gp_set & GP_IF) p->interp_factor = o->gp.interp_factor;
    if (o->gp_set & GP_IN) p->interp_normal = o->gp.interp_normal;
    if (o->gp_set & GP_ID) p->interp_dist = o->gp.interp_dist;
    if (o->gp_set & GP_IL) {
        p->interleave_n = o->gp.interleave_n;
        p->interleave_m = o->gp.interleave_m;
    }
    if (o->gp_set & GP_BLUR) p->interleave_blur = o->gp.interleave_blur;
    if (o->gp_set & GP_SCALE) p->scale = o->gp.scale;
    if (o->gp_set & GP_VPLS) p->vpl_count = o->gp.vpl_count;
    if (o->gp_set & GP_EMAX) p->slc_emax = o->gp.slc_emax;
    if (o->gp_set & GP_NEAR) p->vpl_near_clamp = o->gp.vpl_near_clamp;
    if (o->gp_set & GP_RANGE) p->vpl_range = o->gp.vpl_range;
    if (o->gp_set & GP_KEEP) p->vpl_keep = o->gp.vpl_keep;
    if (o->gp_set & GP_SEED) p->vpl_seed = o->gp.vpl_seed;
}

void render_options_init(RenderOptions *o, bool view)
{
    memset(o, 0, sizeof *o);
    o->scene = "cornell";
    o->out = view ? NULL : "out/render.png";
    o->shadow = SHADOW_MODE_PCSS;
    o->width = o->height = 512;
    o->exposure = -1.f;
    o->light_scale = -1.f;
    o->frames = view ? 0 : 3;
    o->warmup = 1;
}

int render_options_parse(RenderOptions *o, int argc, char **argv, void (*help)(void))
{
    CliArgs a = {argc, argv, 0, NULL};
    const char *opt, *v;
    while ((opt = cli_next(&a))) {
        if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            help();
            return -1;
        } else if (!strcmp(opt, "--scene")) {
            CLI_VALUE(&a, v);
            o->scene = v;
        } else if (!strcmp(opt, "--out")) {
            CLI_VALUE(&a, v);
            o->out = v;
            if (!util_ends_with(v, ".png") && !util_ends_with(v, ".pfm")) {
                log_error("cli", "--out: '%s' must end in .png or .pfm", v);
                return 2;
            }
        } else if (!strcmp(opt, "--png")) {
            CLI_VALUE(&a, v);
            o->png = v;
            if (!util_ends_with(v, ".png")) {
                log_error("cli", "--png: '%s' must end in .png", v);
                return 2;
            }
        } else if (!strcmp(opt, "--shadow")) {
            CLI_VALUE(&a, v);
            if ((o->shadow = cli_choice(opt, v, k_shadow_names)) < 0)
                return 2;
        } else if (!strcmp(opt, "--gi")) {
            CLI_VALUE(&a, v);
            if ((o->gi = cli_choice(opt, v, gi_technique_names)) < 0)
                return 2;
        } else if (!strcmp(opt, "--size")) {
            CLI_VALUE(&a, v);
            if (!cli_size(opt, v, MAX_IMAGE_SIZE, &o->width, &o->height))
                return 2;
        } else if (!strcmp(opt, "--exposure")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 1e9f, &o->exposure))
                return 2;
        } else if (!strcmp(opt, "--light-scale")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 1e3f, &o->light_scale))
                return 2;
        } else if (!strcmp(opt, "--frames")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 0, 1000000, &o->frames))
                return 2;
        } else if (!strcmp(opt, "--warmup")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 0, 10000, &o->warmup))
                return 2;
        } else if (!strcmp(opt, "--timings")) {
            o->timings = true;
        } else if (!strcmp(opt, "--debug")) {
            o->debug = true;
        } else if (!strcmp(opt, "--quiet")) {
            log_set_level(LOG_ERROR);
        } else if (!strcmp(opt, "--verbose")) {
            log_set_level(LOG_DEBUG);
        } else if (!strcmp(opt, "--shader-dir")) {
            CLI_VALUE(&a, v);
            shader_set_directory(v);
        } else if (!strcmp(opt, "--shadow-map-size")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 16, 8192, &o->sp.map_size))
                return 2;
            o->sp_set |= SP_MAP;
        } else if (!strcmp(opt, "--bias-const")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 10.f, &o->sp.bias_const))
                return 2;
            o->sp_set |= SP_BC;
        } else if (!strcmp(opt, "--bias-slope")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 100.f, &o->sp.bias_slope))
                return 2;
            o->sp_set |= SP_BS;
        } else if (!strcmp(opt, "--normal-offset")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 100.f, &o->sp.normal_offset))
                return 2;
            o->sp_set |= SP_NO;
        } else if (!strcmp(opt, "--pcf-samples")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 64, &o->sp.pcf_samples))
                return 2;
            o->sp_set |= SP_PS;
        } else if (!strcmp(opt, "--pcf-radius")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 256.f, &o->sp.pcf_radius))
                return 2;
            o->sp_set |= SP_PR;
        } else if (!strcmp(opt, "--blocker-samples")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 64, &o->sp.blocker_samples))
                return 2;
            o->sp_set |= SP_BL;
        } else if (!strcmp(opt, "--pcss-max-radius")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 1.f, 256.f, &o->sp.pcss_max_radius))
                return 2;
            o->sp_set |= SP_MR;
        } else if (!strcmp(opt, "--rsm-size")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 4, 4096, &o->gp.rsm_size))
                return 2;
            o->gp_set |= GP_SIZE;
        } else if (!strcmp(opt, "--rsm-samples")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 65536, &o->gp.samples))
                return 2;
            o->gp_set |= GP_N;
        } else if (!strcmp(opt, "--rsm-rmax")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 1e-4f, 4.f, &o->gp.r_max))
                return 2;
            o->gp_set |= GP_RMAX;
        } else if (!strcmp(opt, "--rsm-weighting")) {
            CLI_VALUE(&a, v);
            int w = cli_choice(opt, v, k_weightings);
            if (w < 0)
                return 2;
            o->gp.weighting = (RsmWeighting)w;
            o->gp_set |= GP_W;
        } else if (!strcmp(opt, "--rsm-exhaustive")) {
            o->gp.exhaustive = true;
            o->gp_set |= GP_EXH;
        } else if (!strcmp(opt, "--interp-factor")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 64, &o->gp.interp_factor))
                return 2;
            o->gp_set |= GP_IF;
        } else if (!strcmp(opt, "--interp-normal")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, -1.f, 1.f, &o->gp.interp_normal))
                return 2;
            o->gp_set |= GP_IN;
        } else if (!strcmp(opt, "--interp-dist")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 100.f, &o->gp.interp_dist))
                return 2;
            o->gp_set |= GP_ID;
        } else if (!strcmp(opt, "--interleave")) {
            CLI_VALUE(&a, v);
            if (!cli_size(opt, v, 16, &o->gp.interleave_n, &o->gp.interleave_m))
                return 2;
            o->gp_set |= GP_IL;
        } else if (!strcmp(opt, "--interleave-blur")) {
            CLI_VALUE(&a, v);
            int b = cli_choice(opt, v, k_on_off);
            if (b < 0)
                return 2;
            o->gp.interleave_blur = b == 1;
            o->gp_set |= GP_BLUR;
        } else if (!strcmp(opt, "--vpls")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 1 << 24, &o->gp.vpl_count))
                return 2;
            o->gp_set |= GP_VPLS;
        } else if (!strcmp(opt, "--slc-emax")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 1e-12f, 1e6f, &o->gp.slc_emax))
                return 2;
            o->gp_set |= GP_EMAX;
        } else if (!strcmp(opt, "--vpl-near-clamp")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 1e6f, &o->gp.vpl_near_clamp))
                return 2;
            o->gp_set |= GP_NEAR;
        } else if (!strcmp(opt, "--vpl-range")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 1e-6f, 1e6f, &o->gp.vpl_range))
                return 2;
            o->gp_set |= GP_RANGE;
        } else if (!strcmp(opt, "--vpl-keep")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 1e-6f, 1.f, &o->gp.vpl_keep))
                return 2;
            o->gp_set |= GP_KEEP;
        } else if (!strcmp(opt, "--vpl-seed")) {
            CLI_VALUE(&a, v);
            int seed;
            if (!cli_int(opt, v, 0, 2147483647, &seed))
                return 2;
            o->gp.vpl_seed = (unsigned)seed;
            o->gp_set |= GP_SEED;
        } else if (!strcmp(opt, "--gi-scale")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 1e6f, &o->gp.scale))
                return 2;
            o->gp_set |= GP_SCALE;
        } else {
            log_error("cli", "unknown option '%s' (see --help)", opt);
            return 2;
        }
    }
    return 0;
}

static void apply_shadow_overrides(const RenderOptions *o, ShadowParams *p)
{
    if (o->sp_set & SP_MAP) p->map_size = o->sp.map_size;
    if (o->sp_set & SP_BC) p->bias_const = o->sp.bias_const;
    if (o->sp_set & SP_BS) p->bias_slope = o->sp.bias_slope;
    if (o->sp_set & SP_NO) p->normal_offset = o->sp.normal_offset;
    if (o->sp_set & SP_PS) p->pcf_samples = o->sp.pcf_samples;
    if (o->sp_set & SP_PR) p->pcf_radius = o->sp.pcf_radius;
    if (o->sp_set & SP_BL) p->blocker_samples = o->sp.blocker_samples;
    if (o->sp_set & SP_MR) p->pcss_max_radius = o->sp.pcss_max_radius;
}


bool render_options_load_scene(const RenderOptions *o, Scene *scene)
{
    if (!scene_load(scene, o->scene))
        return false;
    if (o->light_scale >= 0.f)
        scene_rescale_lights(scene, o->light_scale);
    return true;
}

void render_options_settings(const RenderOptions *o, const Scene *scene, RenderSettings *rs)
{
    memset(rs, 0, sizeof *rs);
    rs->width = o->width;
    rs->height = o->height;
    rs->shadow = (ShadowMode)o->shadow;
    rs->gi = (GiMode)o->gi;
    rs->gi_params = scene->gi;
    apply_gi_overrides(o, &rs->gi_params);
    rs->exposure = o->exposure >= 0.f ? o->exposure : scene->exposure;
    rs->shadow_params = scene->shadow;
    apply_shadow_overrides(o, &rs->shadow_params);
    rs->timings = o->timings;
    rs->timing_sync = o->timings;
}

void render_options_print_timings(Renderer *r, const char *gl_renderer, double frame_ms)
{
    const RenderSettings *rs = &r->settings;
    printf("renderer: %s\n", gl_renderer);
    gpu_timer_print(&r->timer, stdout);
    printf("frame_wall_ms: %.3f\n", frame_ms);
    if (rs->gi == GI_NONE)
        return;
    const RenderStats *st = renderer_collect_stats(r);
    double pixels = (double)rs->width * rs->height;
    printf("gathered_pixels: %u\n", st->gathered_pixels);
    if (rs->gi == GI_RSM_INTERP)
        printf("rsm_full_gather_fraction: %.4f\n", (double)st->full_gathers / pixels);
    if (rs->gi >= GI_VPL_ALL) {
        printf("vpl_count: %u\n", st->vpl_count);
        printf("vpl_evaluations: %llu\n", (unsigned long long)st->vpl_evaluations);
        printf("vpl_evaluations_per_pixel: %.1f\n", (double)st->vpl_evaluations / pixels);
        printf("vpl_candidates: %llu\n", (unsigned long long)st->vpl_candidates);
        if (st->tile_overflow)
            printf("vpl_tile_overflow: %u\n", st->tile_overflow);
    }
}
