/* render_options.c — parsing of the options `render` and `view` share. */
#include "app/render_options.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/cli.h"
#include "base/log.h"
#include "gpu/probe.h"
#include "core/settings.h"
#include "app/sequence.h"
#include "frame/timings.h"
#include "gl/shader.h"
#include "base/util.h"

#define MAX_IMAGE_SIZE 16384

bool render_options_ssaa_fits(int width, int height, int ssaa)
{
    if ((long)width * ssaa <= MAX_IMAGE_SIZE && (long)height * ssaa <= MAX_IMAGE_SIZE)
        return true;
    usage_error(NULL, "--ssaa %d: %dx%d supersampled is larger than %d per side", ssaa, width * ssaa, height * ssaa,
              MAX_IMAGE_SIZE);
    return false;
}

void render_options_help(void)
{
    printf(
                "  --scene cornell|FILE.json|FILE.gltf|FILE.obj   scene (default: cornell)\n"
        "  --shadow none|hard|pcf|pcss   shadow technique (default: pcss)\n"
        "  --gi TECHNIQUE                indirect light (default: none), see below\n"
        "  --size WxH                    image size (default: 256x256, as rtgi reference; view: 512x512)\n"
        "  --exposure E                  radiance multiplier before tone mapping (default: scene's)\n"
        "  --out FILE.png|FILE.pfm|FILE.exr   output; PNG tone-mapped sRGB, PFM/EXR (OpenEXR,\n"
        "                                float32 or --half)\n"
        "                                linear radiance\n"
        "                                (default: out/render.png)\n"
        "  --half                        EXR output as half floats (default: float32)\n"
        "  --png FILE.png                also write the tone-mapped PNG (beside a .pfm/.exr --out)\n"
        "  --emitter-mask FILE.png       also write the mask of pixels that see an emitter\n"
        "                                (black; for compare --mask-emitters)\n"
        "  --out-ao FILE.pfm|FILE.png    also write the ambient visibility (1 = open) of --gi vct\n"
        "                                with --vct-ao on, at the shading size\n"
        "  --timings                     print per-pass GPU (and wall) times\n"
        "  --probe FILE|run              with --timings: the gather's fraction of this device's\n"
        "                                bound, from 'rtgi probe --json FILE' or measured now\n"
        "  --frames N                    frames to time after the warm-up (default: 3)\n"
        "  --warmup N                    untimed frames first (default: 1)\n"
        "  --animate                     render the scene file's animation: --frames N frames, spread\n"
        "                                over its duration, into --out's pattern (frame_%%04d.exr)\n"
        "  --fps F                       with --animate: frame i at i/F s\n"
        "  --time T                      render the scene's animation at T s (one image)\n"
        "  --video FILE.mp4              with --animate: also a video of the frames (needs ffmpeg)\n"
        "  --light-scale S               scale every light's emitter size (0: point lights)\n"
        "  --ssaa N                      N x N supersampling, box filter (default: 1, off)\n"
        "  --aa none|fxaa                post-process AA of the tone-mapped image\n"
        "                                (default: none for render, fxaa for view)\n"
        "  --shading auto|forward|deferred  frames without a GI technique: shade while drawing\n"
        "                                the scene or from the G-buffer, as GI frames do; auto\n"
        "                                (default): forward below 1 triangle per 64 pixels\n"
        "other:\n"
        "  --shader-dir DIR   read shaders from DIR instead of the embedded copies\n"
        "  --debug            GL debug context, KHR_debug messages logged\n"
        "  --quiet | --verbose\n");
    render_options_help_settings();
}

void render_options_help_settings(void)
{
    printf("GI techniques (--gi):\n");
    for (int i = 0; gi_techniques[i]; i++)
        printf("  %-18s %s\n", gi_techniques[i]->name, gi_techniques[i]->summary);
    printf("shadow parameters (default: the scene file's, else the value shown):\n");
    settings_print_help(stdout, "shadow");
    printf("GI parameters (default: the scene file's, else the value shown):\n");
    settings_print_help(stdout, "gi");
}

static const char *const k_shadow_names[] = {"none", "hard", "pcf", "pcss", NULL};
static const char *const k_aa_names[] = {"none", "fxaa", NULL};
static const char *const k_shading_names[] = {"auto", "forward", "deferred", NULL};

/* --probe of the options last turned into settings (read by the timings report). */

void render_options_init(RenderOptions *o, bool view)
{
    memset(o, 0, sizeof *o);
    o->scene = "cornell";
    o->out = view ? NULL : "out/render.png";
    o->shadow = SHADOW_MODE_PCSS;
    o->width = o->height = view ? 512 : 256; /* render: as rtgi reference */
    o->exposure = -1.f;
    o->light_scale = -1.f;
    o->ssaa = 1;
    o->aa = view ? AA_FXAA : AA_NONE;
    o->frames = view ? 0 : 3;
    settings_default(&o->set);
    o->view = view;
    assert(settings_count <= (int)(sizeof o->given / sizeof o->given[0]));
    o->warmup = 1;
    o->slow_ms = 1000.0;
    o->time = -1.0;
    o->live_spp = 4096;
}

/* The options only one of the two commands takes. */
static const char *const k_render_only[] = {"--animate", "--emitter-mask", "--fps", "--out-ao", "--png", "--probe", "--time", "--timings", "--video", "--warmup", NULL};
static const char *const k_view_only[] = {"--compare", "--live-priority", "--live-reference", "--live-spp", "--live-threads", "--no-panel", "--slow-ms", "--ui-test", "--window-out", NULL};

/* The options `render` (view false) or `view` knows, the settings table's
 * included (for "did you mean"). */
static const char *const *known_options(bool view)
{
    static const char *const shared[] = {"--aa", "--debug", "--exposure", "--frames", "--gi", "--half", "--help", "--light-scale", "--out", "--quiet", "--scene", "--shader-dir", "--shading", "--shadow", "--size", "--ssaa", "--verbose", NULL};
    static const char *all[2][128];
    const char **list = all[view];
    if (!list[0]) {
        int n = 0;
        for (int i = 0; shared[i] && n < 127; i++)
            list[n++] = shared[i];
        const char *const *own = view ? k_view_only : k_render_only;
        for (int i = 0; own[i] && n < 127; i++)
            list[n++] = own[i];
        for (int i = 0; i < settings_count && n < 127; i++)
            list[n++] = settings_table[i].option;
        list[n] = NULL;
    }
    return list;
}

int render_options_parse(RenderOptions *o, int argc, char **argv, void (*help)(void))
{
    CliArgs a = {.argc = argc, .argv = argv};
    const char *opt, *v = NULL;
    const SettingDesc *setting;
    while ((opt = cli_next(&a))) {
        if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            help();
            return -1;
        } else if (cli_in_list(opt, o->view ? k_render_only : k_view_only)) {
            usage_error(NULL, "%s is an option of 'rtgi %s'", opt, o->view ? "render" : "view");
            return 2;
        } else if (!strcmp(opt, "--compare")) {
            CLI_VALUE(&a, v);
            o->compare = v;
        } else if (!strcmp(opt, "--ui-test")) {
            CLI_VALUE(&a, v);
            o->ui_test = v;
        } else if (!strcmp(opt, "--window-out")) {
            CLI_VALUE(&a, v);
            if (!util_ends_with(v, ".png")) {
                usage_error(NULL, "--window-out: '%s' must end in .png", v);
                return 2;
            }
            o->window_out = v;
        } else if (!strcmp(opt, "--slow-ms")) {
            CLI_VALUE(&a, v);
            char *end;
            o->slow_ms = strtod(v, &end);
            if (*end || !(o->slow_ms > 0) || !isfinite(o->slow_ms)) {
                usage_error(NULL, "--slow-ms: '%s' is not a positive number of milliseconds", v);
                return 2;
            }
        } else if (!strcmp(opt, "--no-panel")) {
            o->no_panel = true;
        } else if (!strcmp(opt, "--live-reference")) {
            o->live_reference = true;
        } else if (!strcmp(opt, "--live-threads")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 1024, &o->live_threads))
                return 2;
        } else if (!strcmp(opt, "--live-priority")) {
            CLI_VALUE(&a, v);
            if (strcmp(v, "idle") && strcmp(v, "normal")) {
                usage_error(NULL, "--live-priority: '%s' is not idle or normal", v);
                return 2;
            }
            o->live_ordinary = !strcmp(v, "normal");
        } else if (!strcmp(opt, "--live-spp")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 1 << 24, &o->live_spp))
                return 2;
        } else if (!strcmp(opt, "--scene")) {
            CLI_VALUE(&a, v);
            if (!cli_scene(opt, v))
                return 2;
            o->scene = v;
        } else if (!strcmp(opt, "--out")) {
            CLI_VALUE(&a, v);
            o->out = v;
            if (!util_ends_with(v, ".png") && !util_ends_with(v, ".pfm") && !util_ends_with(v, ".exr")) {
                usage_error(NULL, "--out: '%s' must end in .png, .pfm or .exr", v);
                return 2;
            }
        } else if (!strcmp(opt, "--png")) {
            CLI_VALUE(&a, v);
            o->png = v;
            if (!util_ends_with(v, ".png")) {
                usage_error(NULL, "--png: '%s' must end in .png", v);
                return 2;
            }
        } else if (!strcmp(opt, "--shadow")) {
            CLI_VALUE(&a, v);
            if ((o->shadow = cli_choice(opt, v, k_shadow_names)) < 0)
                return 2;
        } else if (!strcmp(opt, "--gi")) {
            CLI_VALUE(&a, v);
            if ((o->gi = cli_choice(opt, v, gi_technique_names())) < 0)
                return 2;
        } else if (!strcmp(opt, "--size")) {
            CLI_VALUE(&a, v);
            if (!cli_size(opt, v, MAX_IMAGE_SIZE, &o->width, &o->height))
                return 2;
        } else if (!strcmp(opt, "--exposure")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, SCENE_EXPOSURE_MIN, SCENE_EXPOSURE_MAX, &o->exposure))
                return 2;
        } else if (!strcmp(opt, "--light-scale")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 1e3f, &o->light_scale))
                return 2;
        } else if (!strcmp(opt, "--ssaa")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 8, &o->ssaa))
                return 2;
        } else if (!strcmp(opt, "--aa")) {
            CLI_VALUE(&a, v);
            if ((o->aa = cli_choice(opt, v, k_aa_names)) < 0)
                return 2;
        } else if (!strcmp(opt, "--shading")) {
            CLI_VALUE(&a, v);
            if ((o->shading = cli_choice(opt, v, k_shading_names)) < 0)
                return 2;
        } else if (!strcmp(opt, "--frames")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 0, 1000000, &o->frames))
                return 2;
            o->frames_given = true;
        } else if (!strcmp(opt, "--animate")) {
            o->animate = true;
        } else if (!strcmp(opt, "--fps") || !strcmp(opt, "--time")) {
            CLI_VALUE(&a, v);
            float f;
            if (!cli_float(opt, v, opt[2] == 'f' ? 1e-3f : 0.f, 1e6f, &f))
                return 2;
            *(opt[2] == 'f' ? &o->fps : &o->time) = f;
        } else if (!strcmp(opt, "--video")) {
            CLI_VALUE(&a, v);
            o->video = v;
        } else if (!strcmp(opt, "--warmup")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 0, 10000, &o->warmup))
                return 2;
        } else if (!strcmp(opt, "--half")) {
            o->half = true;
        } else if (!strcmp(opt, "--timings")) {
            o->timings = true;
        } else if (!strcmp(opt, "--probe")) {
            CLI_VALUE(&a, v);
            o->probe = v;
        } else if (!strcmp(opt, "--emitter-mask")) {
            CLI_VALUE(&a, v);
            if (!util_ends_with(v, ".png")) {
                usage_error(NULL, "--emitter-mask: '%s' must end in .png", v);
                return 2;
            }
            o->emitter_mask = v;
        } else if (!strcmp(opt, "--out-ao")) {
            CLI_VALUE(&a, v);
            if (!util_ends_with(v, ".png") && !util_ends_with(v, ".pfm")) {
                usage_error(NULL, "--out-ao: '%s' must end in .png or .pfm", v);
                return 2;
            }
            o->out_ao = v;
        } else if (!strcmp(opt, "--debug")) {
            o->debug = true;
        } else if (!strcmp(opt, "--shader-dir")) {
            CLI_VALUE(&a, v);
            shader_set_directory(v);
        } else if ((setting = settings_find_option(opt))) {
            if (setting->type != VALUE_FLAG)
                CLI_VALUE(&a, v);
            if (!settings_parse_cli(setting, setting->type == VALUE_FLAG ? NULL : v, &o->set))
                return 2;
            o->given[setting - settings_table] = true;
        } else {
            cli_unknown_option(opt, known_options(o->view));
            return 2;
        }
    }
    if (cli_failed(&a))
        return 2;
    int time_rc = render_options_check_time(o);
    if (time_rc)
        return time_rc;
    /* A sequence's frames are checked as its first frame's file. */
    char first_frame[UTIL_PATH_MAX];
    if (o->animate)
        sequence_path(o->out, 0, first_frame, sizeof first_frame);
    const char *const opts[] = {"--out", "--png", "--emitter-mask", "--out-ao", "--window-out", "--video", "--scene",
                                "--probe", "--compare"};
    const char *const paths[] = {o->animate ? first_frame : o->out, o->png, o->emitter_mask, o->out_ao, o->window_out,
                                 o->video, o->scene, o->probe && strcmp(o->probe, "run") ? o->probe : NULL,
                                 o->compare};
    int files = cli_check_files(9, 6, opts, paths);
    if (files)
        return files;
    if (o->probe) {
        /* Read now, not after the frames it would have judged. */
        if (!o->timings) {
            usage_error(NULL, "--probe: needs --timings (the fractions are part of the timings report)");
            return 2;
        }
        if (strcmp(o->probe, "run") && !probe_read_json(o->probe, &o->probe_file))
            return 2;
    }
    return render_options_ssaa_fits(o->width, o->height, o->ssaa) ? 0 : 2;
}

int render_options_check_time(const RenderOptions *o)
{
    const char *single = o->png ? "--png" : o->emitter_mask ? "--emitter-mask" : o->out_ao ? "--out-ao"
                       : o->timings                          ? "--timings"
                       : o->probe                            ? "--probe"
                                                             : NULL;
    SequenceOptions so = {.animate = o->animate, .frames_given = o->frames_given, .frames = o->frames,
                          .fps = o->fps, .time = o->time, .time_opt = "--time", .video = o->video, .single = single, .out = o->out};
    return sequence_check_options(&so);
}

bool render_options_load_scene(const RenderOptions *o, Scene *scene)
{
    return scene_load_scaled(scene, o->scene, o->light_scale);
}

void render_options_settings(const RenderOptions *o, const Scene *scene, RenderSettings *rs)
{
    memset(rs, 0, sizeof *rs);
    rs->width = o->width;
    rs->height = o->height;
    rs->shadow = (ShadowMode)o->shadow;
    rs->gi = (GiMode)o->gi;
    /* The scene's settings, then the command line's over them. */
    Settings set = {scene->shadow, scene->gi};
    for (int i = 0; i < settings_count; i++)
        if (o->given[i])
            settings_copy(&settings_table[i], &set, &o->set);
    rs->shadow_params = set.shadow;
    rs->gi_params = set.gi;
    rs->exposure = o->exposure >= 0.f ? o->exposure : scene->exposure;
    timings_use_probe(o->probe, &o->probe_file);
    rs->timings = o->timings;
    rs->timing_sync = o->timings;
    rs->ssaa = o->ssaa;
    rs->aa = (AaMode)o->aa;
    rs->shading = (ShadingMode)o->shading;
}
