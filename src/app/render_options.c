/* render_options.c — parsing of the options `render` and `view` share. */
#include "app/render_options.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/cli.h"
#include "app/options.h"
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

void render_options_help_settings(void)
{
    printf("GI techniques (--gi):\n");
    for (int i = 0; gi_techniques[i]; i++)
        printf("  %-18s %s\n", gi_techniques[i]->name, gi_techniques[i]->summary);
    /* One heading per family of the settings table; each option is
     * --FAMILY-FIELD, its scene key FAMILY.FIELD. */
    const char *families[32];
    settings_families(families, 32);
    for (int i = 0; families[i]; i++) {
        printf("%s parameters (default: the scene file's, else the value shown):\n", families[i]);
        settings_print_help(stdout, families[i]);
    }
}

static const char *const k_shadow_names[] = {"none", "hard", "pcf", "pcss", NULL};
static const char *const k_aa_names[] = {"none", "fxaa", NULL};
static const char *const k_shading_names[] = {"auto", "forward", "deferred", NULL};
static const char *const k_gbuffer_names[] = {"auto", "raster", "visibility", NULL};

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

static const char *const k_live_priorities[] = {"idle", "normal", NULL};

/* The options of both commands, then those of one (a name in both of
 * the last two has a row in each, with that command's help). --gi's
 * choices are the technique table's names (set at first use). */
#define RO RenderOptions
static OptionDesc k_shared_options[] = {
    OPT_SCENE("--scene", RO, scene, "cornell, or a scene file (.json, .gltf, .obj)"),
    OPT_CHOICE("--shadow", RO, shadow, k_shadow_names, "shadow technique"),
    {"--gi", {VALUE_CHOICE, offsetof(RO, gi), 0, 0, 0, NULL, NULL}, "indirect light, see the techniques below", OPTION_NO_FLAG, NULL, "TECHNIQUE"},
    OPT_SIZE("--size", RO, width, height, MAX_IMAGE_SIZE, "image size (view: the window's image area, the panel docked beside it)"),
    OPT_FLOAT("--exposure", RO, exposure, SCENE_EXPOSURE_MIN, SCENE_EXPOSURE_MAX, "radiance multiplier before tone mapping (default: the scene's)"),
    OPT_FLOAT("--light-scale", RO, light_scale, 0, 1e3, "scale every light's emitter size, 0: point lights (default: as the scene has them)"),
    OPT_INT("--ssaa", RO, ssaa, 1, 8, "N x N supersampling, box filter (1: off)"),
    OPT_CHOICE("--aa", RO, aa, k_aa_names, "post-process AA of the tone-mapped image"),
    OPT_CHOICE("--shading", RO, shading, k_shading_names, "frames without a GI technique: shade while drawing the scene (forward) or from the G-buffer, as GI frames do; auto: forward below 1 triangle per 64 pixels"),
    OPT_CHOICE("--gbuffer", RO, gbuffer, k_gbuffer_names, "deferred frames' G-buffer: draw the scene's materials (raster) or a visibility buffer of triangle ids resolved in compute (visibility); auto: this device class's faster one"),
    OPT_FLAG("--half", RO, half, "EXR (.exr) output (render) or captures (view) as half floats (else float32)"),
    OPT_WORD("--shader-dir", RO, shader_dir, "DIR", "read shaders from DIR instead of the embedded copies (default: embedded)"),
    OPT_FLAG("--debug", RO, debug, "GL debug context, KHR_debug messages logged"),
    OPT_END,
};
static const OptionDesc k_render_only[] = {
    OPT_TEXT("--out", RO, out, "png|pfm|exr", "output: .png tone-mapped sRGB, .pfm or .exr (OpenEXR, float32 or --half) linear radiance"),
    OPT_TEXT("--png", RO, png, "png", "also the tone-mapped PNG, beside a .pfm/.exr --out (default: none)"),
    OPT_TEXT("--emitter-mask", RO, emitter_mask, "png", "also the mask of pixels that see an emitter (black; for compare --mask-emitters; default: none)"),
    OPT_TEXT("--out-ao", RO, out_ao, "png|pfm", "also the ambient visibility (1 = open) of --gi vct with --vct-ao on, at the shading size (default: none)"),
    OPT_FLAG("--timings", RO, timings, "print per-pass GPU (and wall) times"),
    OPT_WORD("--probe", RO, probe, "FILE|run", "with --timings: the gather's fraction of this device's bound, from 'rtgi probe --json FILE' or measured now (default: none)"),
    {"--frames", {VALUE_INT, offsetof(RO, frames), 0, 0, 1000000, NULL, NULL}, "frames to time after the warm-up; with --animate: the sequence's frames", offsetof(RO, frames_given), NULL, NULL},
    OPT_INT("--warmup", RO, warmup, 0, 10000, "untimed frames first"),
    OPT_FLAG("--animate", RO, animate, "render the scene file's animation: --frames N frames, spread over its duration, into --out's pattern (frame_%04d.exr)"),
    OPT_DOUBLE("--fps", RO, fps, 1e-3, 1e6, "with --animate: frame i at i/X s (default: the frames spread over the duration)"),
    OPT_DOUBLE("--time", RO, time, 0, 1e6, "render the scene's animation at X s, one image (default: as loaded)"),
    OPT_WORD("--video", RO, video, "FILE.mp4", "with --animate: also a video of the frames (needs ffmpeg; default: none)"),
    OPT_END,
};
static const OptionDesc k_view_only[] = {
    OPT_TEXT("--out", RO, out, "png|pfm|exr", "the image P saves, and with --frames the last frame: .png as shown, .pfm or .exr linear radiance (default: out/view.png)"),
    {"--frames", {VALUE_INT, offsetof(RO, frames), 0, 0, 1000000, NULL, NULL}, "exit after N frames (0: run until closed)", offsetof(RO, frames_given), NULL, NULL},
    OPT_WORD("--compare", RO, compare, "FILE", "reference image for the A/B view (split, reference, difference): .pfm or .exr radiance at the window's exposure, .png shown as it is (default: none)"),
    OPT_FLAG("--live-reference", RO, live_reference, "the reference path tracer converging in the A/B view on the window's camera (also the panel's box): a camera, light or size change restarts it; with --compare, its relMSE against that file is shown"),
    OPT_INT("--live-threads", RO, live_threads, 1, 1024, "its threads (default: every core)"),
    OPT_INT("--live-spp", RO, live_spp, 1, 1 << 24, "the samples per pixel it stops at"),
    OPT_CHOICE("--live-priority", RO, live_priority, k_live_priorities, "its threads' priority: idle (SCHED_IDLE: only the CPU time nothing else wants) or normal, as any program's"),
    OPT_TEXT("--window-out", RO, window_out, "png", "what Shift-P saves: the window, panel included; with --frames, the last frame's (default: out/window.png)"),
    OPT_DOUBLE("--slow-ms", RO, slow_ms, 1e-3, 1e9, "techniques estimated above X ms per frame need a confirming click"),
    OPT_FLAG("--no-panel", RO, no_panel, "start with the panel hidden (H shows it)"),
    OPT_WORD("--ui-test", RO, ui_test, "DIR", "run the window test's script, write its captures to DIR (default: none)"),
    OPT_END,
};
#undef RO

static void fill_gi_choices(void)
{
    for (OptionDesc *d = k_shared_options; d->name; d++)
        if (!strcmp(d->name, "--gi"))
            d->value.choices = gi_technique_names();
}

void render_options_help(bool view)
{
    fill_gi_choices();
    RenderOptions def;
    render_options_init(&def, view);
    options_print_help(stdout, k_shared_options, &def);
    options_print_help(stdout, view ? k_view_only : k_render_only, &def);
    printf("  --quiet | --verbose          errors only; debug lines too\n");
    render_options_help_settings();
}

int render_options_parse(RenderOptions *o, int argc, char **argv, void (*help)(void))
{
    fill_gi_choices();
    const OptionDesc *own = o->view ? k_view_only : k_render_only, *other = o->view ? k_render_only : k_view_only;
    OptionSet os = {.tables = (const OptionDesc *const[]){k_shared_options, own, NULL},
                    .set = &o->set,
                    .given = o->given,
                    .elsewhere = other,
                    .elsewhere_command = o->view ? "render" : "view",
                    .help = help};
    int rc = options_parse(argc, argv, &os, o);
    if (rc)
        return rc;
    o->live_ordinary = o->live_priority == 1;
    if (o->shader_dir)
        shader_set_directory(o->shader_dir);
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
    Settings set = {scene->settings.shadow, scene->settings.gi};
    for (int i = 0; i < settings_count; i++)
        if (o->given[i])
            settings_copy(&settings_table[i], &set, &o->set);
    rs->set.shadow = set.shadow;
    rs->set.gi = set.gi;
    rs->exposure = o->exposure >= 0.f ? o->exposure : scene->exposure;
    timings_use_probe(o->probe, &o->probe_file);
    rs->timings = o->timings;
    rs->timing_sync = o->timings;
    rs->ssaa = o->ssaa;
    rs->aa = (AaMode)o->aa;
    rs->shading = (ShadingMode)o->shading;
    rs->gbuffer = (GbufferMode)o->gbuffer;
}
