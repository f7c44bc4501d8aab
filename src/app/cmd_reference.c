/* cmd_reference.c — `rtgi reference`: the path-traced ground truth. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/animation.h"
#include "app/cli.h"
#include "app/commands.h"
#include "app/options.h"
#include "io/image.h"
#include "base/log.h"
#include "reference/pathtracer.h"
#include "app/sequence.h"
#include "base/util.h"

/* What the command line asked for. */
typedef struct ReferenceArgs {
    PtSettings set;           /* the path tracer's settings (progress and stop: cmd_reference's) */
    const char *scene_name;   /* --scene */
    const char *out;          /* --out: the mean image */
    const char *png;          /* --png, or NULL */
    const char *var_out;      /* --variance, or NULL */
    const char *emitter_mask; /* --emitter-mask, or NULL */
    float exposure;           /* --exposure for PNG output; < 0: the scene's */
    float light_scale;        /* --light-scale; < 0: the scene's lights as they are */
    bool half;                /* --half: EXR output as half floats */
    bool animate;             /* --animate: a sequence of `frames` frames into --out's pattern */
    int frames;               /* --frames (0: not given) */
    float fps;                /* --fps (0: the frames spread over the duration) */
    float time;               /* --at (< 0: not given) */
    unsigned seed;            /* --seed (into set.seed) */
    bool no_rr, no_jitter;    /* --no-rr, --no-jitter (into set) */
    bool spp_given;           /* --spp was given */
} ReferenceArgs;

#define RA ReferenceArgs
static const OptionDesc k_reference_options[] = {
    OPT_SCENE("--scene", RA, scene_name, "cornell, or a scene file (.json, .gltf, .obj)"),
    OPT_CHOICE("--mode", RA, set.mode, pt_mode_names, "what the paths carry: every bounce, direct light, one bounce (with or without its visibility), indirect only"),
    {"--spp", {VALUE_INT, offsetof(RA, set.spp), 0, 1, 1 << 24, NULL, NULL}, "samples per pixel (with --target-relmse or --time and no --spp: as many as they need)", offsetof(RA, spp_given), NULL, NULL},
    OPT_DOUBLE("--target-relmse", RA, set.target_relmse, 1e-9, 1e3, "stop once the relMSE estimated from the per-pixel variance is at most X (after each pass, from 16 spp on; with the Sobol' sampler the real error is usually lower); 0: off"),
    OPT_DOUBLE("--time", RA, set.time_budget, 1e-3, 1e7, "stop before a pass that would end past X seconds (the first pass always runs); 0: no budget"),
    OPT_CHOICE("--sampler", RA, set.sampler, pt_sampler_names, "Owen-scrambled Sobol' or independent random numbers"),
    {"--seed", {VALUE_UINT, offsetof(RA, seed), 0, 0, 2147483647, NULL, NULL}, "random seed; the same seed gives the same image", OPTION_NO_FLAG, NULL, NULL},
    OPT_INT("--threads", RA, set.threads, 1, 1024, "worker threads (default: every core)"),
    OPT_SIZE("--size", RA, set.width, set.height, 16384, "image size, as rtgi render's"),
    OPT_TEXT("--out", RA, out, "png|pfm|exr", "the image; an EXR records the samples per pixel reached (int attribute rtgi_spp)"),
    OPT_FLAG("--half", RA, half, "EXR output as half floats (else float32)"),
    OPT_FLOAT("--exposure", RA, exposure, SCENE_EXPOSURE_MIN, SCENE_EXPOSURE_MAX, "exposure of PNG output (default: the scene's)"),
    OPT_INT("--max-depth", RA, set.max_depth, 1, 100000, "path vertices at most"),
    OPT_FLAG("--no-rr", RA, no_rr, "no Russian roulette"),
    OPT_INT("--rr-depth", RA, set.rr_depth, 0, 100000, "bounces before Russian roulette"),
    OPT_FLAG("--no-jitter", RA, no_jitter, "sample pixel centres only (no anti-aliasing)"),
    OPT_FLOAT("--light-scale", RA, light_scale, 0, 1e3, "scale every light's emitter size, 0: point lights (default: as the scene has them)"),
    OPT_TEXT("--variance", RA, var_out, "pfm|exr", "also the per-pixel variance of the mean (default: none)"),
    OPT_TEXT("--png", RA, png, "png", "also the tone-mapped PNG (default: none)"),
    OPT_TEXT("--emitter-mask", RA, emitter_mask, "png", "also the mask of pixels that see an emitter (black; render --emitter-mask writes the same one; default: none)"),
    OPT_FLOAT("--at", RA, time, 0, 1e6, "the scene file's animation at X s, one instant; --time is the time budget (default: none)"),
    OPT_FLAG("--animate", RA, animate, "the animation's --frames N frames (spread over its duration, or frame i at i/X s with --fps X) into --out's pattern (frame_%04d.exr), each at --spp with the same seed"),
    OPT_INT("--frames", RA, frames, 1, 1000000, "frames of --animate (default: none; needed with --animate)"),
    OPT_FLOAT("--fps", RA, fps, 1e-3, 1e6, "--animate: frame i at i/X s (default: the frames spread over the duration)"),
    OPT_END,
};
#undef RA

/* The defaults, before the command line. */
static void reference_args_default(ReferenceArgs *args)
{
    *args = (ReferenceArgs){.scene_name = "cornell", .out = "out/reference.pfm", .exposure = -1.f,
                            .light_scale = -1.f, .time = -1.f};
    pt_settings_default(&args->set);
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    args->set.threads = cores > 0 ? (int)cores : 1;
    args->seed = (unsigned)args->set.seed;
}

void cmd_reference_help(void)
{
    ReferenceArgs def;
    reference_args_default(&def);
    printf("usage: rtgi reference [options]\n");
    options_print_help(stdout, k_reference_options, &def);
    printf("  --quiet                      errors only: no progress (else on stderr: after the first pass the\n"
           "                               time the rest will take, then samples, rays/s, time left)\n"
           "  --verbose                    debug lines too\n"
           "Prints on stdout: spp (reached), relmse_estimate, and 'stopped: target-relmse' or\n"
           "'stopped: time' when one of those ended it.\n"
           "Ctrl-C (SIGINT) finishes the current pass (a few samples per pixel) and writes the\n"
           "image with the samples reached ('spp:' line; EXR attribute rtgi_spp); a second\n"
           "Ctrl-C ends the program at once, or once the outputs being written are whole\n"
           "(all of them or none; SIGTERM likewise).\n");
}

/* Set by SIGINT: the path tracer finishes its pass and stops. */
static volatile int g_interrupted;

static void on_sigint(int sig)
{
    (void)sig;
    g_interrupted = 1;
}

/* SIGINT sets g_interrupted (once: a second one ends the program); the
 * old action into *old. */
static void catch_sigint(struct sigaction *old)
{
    struct sigaction sa = {0};
    sa.sa_handler = on_sigint;
    sa.sa_flags = SA_RESETHAND;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, old);
}

/* Writes the mean image by extension; an EXR carries the samples per pixel. */
static bool write_mean(const char *out, const ImageF *mean, float exposure, bool half, int spp, int spp_asked)
{
    if (!util_ends_with(out, ".exr"))
        return image_write(out, mean, exposure, half);
    ImageAttr attrs[2] = {{"rtgi_spp", spp}, {"rtgi_spp_requested", spp_asked}};
    return image_write_exr(out, mean, half, attrs, 2);
}

/* The time options agree: 0, or 2 after a usage error. */
static int reference_check_time(const ReferenceArgs *args)
{
    const char *single = args->png ? "--png" : args->var_out ? "--variance" : args->emitter_mask ? "--emitter-mask"
                                                                                                : NULL;
    SequenceOptions so = {.animate = args->animate, .frames_given = args->frames > 0, .frames = args->frames,
                          .frames_need_animate = true, .fps = args->fps, .time = args->time, .time_opt = "--at", .single = single,
                          .out = args->out};
    return sequence_check_options(&so);
}

/* Parses argv into *args. 0: go on; -1: --help was shown; else an exit
 * status (2 for usage, 1 for an output that cannot be written:
 * cli_check_files), after logging. */
static int reference_parse_args(int argc, char **argv, ReferenceArgs *args)
{
    reference_args_default(args);
    PtSettings *set = &args->set;
    int rc = options_parse(argc, argv, &(OptionSet){.tables = (const OptionDesc *const[]){k_reference_options, NULL}, .help = cmd_reference_help}, args);
    if (rc)
        return rc;
    set->seed = args->seed;
    set->russian_roulette = !args->no_rr;
    set->pixel_jitter = !args->no_jitter;
    /* A target or a budget without --spp: the samples are what they need. */
    if (!args->spp_given && (set->target_relmse > 0.0 || set->time_budget > 0.0))
        set->spp = 1 << 24;
    rc = reference_check_time(args);
    if (rc)
        return rc;
    char first[UTIL_PATH_MAX]; /* a sequence's frames are checked as its first */
    if (args->animate)
        sequence_path(args->out, 0, first, sizeof first);
    const char *const opts[] = {"--out", "--png", "--variance", "--emitter-mask", "--scene"};
    const char *const paths[] = {args->animate ? first : args->out, args->png, args->var_out, args->emitter_mask,
                                 args->scene_name};
    return cli_check_files(5, 4, opts, paths);
}

/* Writes --out, --png, --variance and --emitter-mask: all of them or none
 * (a failure removes the ones written before it). false after logging. */
static bool reference_write_outputs(const ReferenceArgs *args, const Scene *scene, const ImageF *mean,
                                    const ImageF *var, const PtStats *st)
{
    const PtSettings *set = &args->set;
    float e = args->exposure >= 0.f ? args->exposure : scene->exposure;
    image_warn_if_black(mean, "reference", args->out);
    const char *written[3];
    int n = 0;
    bool ok = write_mean(args->out, mean, e, args->half, st->spp, set->spp);
    if (ok)
        written[n++] = args->out;
    if (ok && args->png && (ok = image_write_png(args->png, mean, e)))
        written[n++] = args->png;
    if (ok && args->var_out && (ok = write_mean(args->var_out, var, 1.f, false, st->spp, set->spp)))
        written[n++] = args->var_out;
    if (ok && args->emitter_mask)
        ok = pt_write_emitter_mask(scene, set->width, set->height, args->emitter_mask);
    for (int i = 0; !ok && i < n; i++)
        remove(written[i]);
    return ok;
}

/* The result lines on stdout (scripts read them). */
static void reference_print(const ReferenceArgs *args, const Scene *scene, const PtStats *st, double cpu_s)
{
    const PtSettings *set = &args->set;
    printf("reference: %s, mode %s, %dx%d, %d spp, %d threads, seed %llu\n", scene->source,
           pt_mode_names[set->mode], set->width, set->height, st->spp, set->threads,
           (unsigned long long)set->seed);
    printf("spp: %d\n", st->spp);
    if (st->stopped == PT_STOP_INTERRUPTED)
        printf("interrupted: %d of %d spp\n", st->spp, set->spp);
    else if (st->stopped == PT_STOP_TARGET)
        printf("stopped: target-relmse %g reached at %d spp\n", set->target_relmse, st->spp);
    else if (st->stopped == PT_STOP_TIME)
        printf("stopped: time %g s reached at %d spp\n", set->time_budget, st->spp);
    printf("relmse_estimate: %.6g\n", st->relmse_estimate);
    printf("sampler: %s\n", pt_sampler_names[set->sampler]);
    printf("time_s: %.3f\n", st->seconds);
    printf("cpu_s: %.3f\n", cpu_s);
    printf("rays: %llu\n", (unsigned long long)st->rays);
    printf("rays_per_s: %.0f\n", st->seconds > 0 ? st->rays / st->seconds : 0.0);
    log_info("reference", "wrote %s", args->out);
}

/* --animate: each frame of the sequence path-traced at --spp with the
 * same seed (a frame's image depends on the scene at its time alone) and
 * written as it is done. Ctrl-C finishes the frame being traced with the
 * samples reached, writes it, and ends the sequence there; the frames
 * before it stay. Returns the exit status. */
static int reference_sequence(ReferenceArgs *args, Scene *scene)
{
    PtSettings *set = &args->set;
    struct sigaction old_sa;
    catch_sigint(&old_sa);
    float e = args->exposure >= 0.f ? args->exposure : scene->exposure;
    int done = 0;
    bool ok = true;
    double seconds = 0;
    for (int i = 0; i < args->frames && ok && !g_interrupted; i++) {
        double t = animation_frame_time(scene, i, args->frames, args->fps);
        animation_apply(scene, t, NULL);
        if (set->progress)
            log_progress("reference: frame %d of %d (t = %.4g s)", i + 1, args->frames, t);
        ImageF mean = {0};
        PtStats st = {0};
        char path[UTIL_PATH_MAX];
        sequence_path(args->out, i, path, sizeof path);
        ok = pt_render(scene, set, &mean, NULL, &st);
        util_defer_ending_signals();
        ok = ok && write_mean(path, &mean, e, args->half, st.spp, set->spp);
        util_end_deferral();
        image_free(&mean);
        seconds += st.seconds;
        done += ok;
    }
    sigaction(SIGINT, &old_sa, NULL);
    if (!ok) {
        sequence_remove(args->out, done); /* all frames or none */
        return 1;
    }
    printf("reference: %s, mode %s, %dx%d, %d spp, %d threads, seed %llu\n", scene->source,
           pt_mode_names[set->mode], set->width, set->height, set->spp, set->threads,
           (unsigned long long)set->seed);
    printf("frames: %d\n", done);
    if (done < args->frames)
        printf("interrupted: %d of %d frames\n", done, args->frames);
    printf("time_s: %.3f\n", seconds);
    char first[UTIL_PATH_MAX];
    sequence_path(args->out, 0, first, sizeof first);
    log_info("reference", "wrote %d frames from %s", done, first);
    return 0;
}

int cmd_reference(int argc, char **argv)
{
    ReferenceArgs args;
    int rc = reference_parse_args(argc, argv, &args);
    if (rc != 0)
        return rc < 0 ? 0 : rc;
    PtSettings *set = &args.set;
    set->progress = log_get_level() <= LOG_INFO; /* --quiet: none */
    set->stop = &g_interrupted;

    /* The path tracer holds two double sums per channel and pixel, the mean
     * and the variance images: check that they fit before it allocates. */
    size_t npix = (size_t)set->width * (size_t)set->height;
    size_t need = npix * 3 * (2 * sizeof(double) + (args.var_out ? 2 : 1) * sizeof(float));
    size_t phys = util_physical_memory();
    if (npix > IMAGE_MAX_PIXELS || (phys && need > phys / 2)) {
        log_error("cli", "--size %dx%d: the reference needs %.1f GiB for its image buffers; the limit is %zu "
                  "pixels and %.1f GiB (half of this machine's memory)", set->width, set->height,
                  need / 1073741824.0, (size_t)IMAGE_MAX_PIXELS, phys / 2 / 1073741824.0);
        return 1;
    }

    Scene scene;
    if (!scene_load_scaled(&scene, args.scene_name, args.light_scale))
        return 1;
    bool timed = args.time >= 0 ? animation_check_time(&scene, args.time, "--at")
               : args.animate   ? animation_check_frames(&scene, args.frames, args.fps, "--animate")
                                : true;
    if (!timed) {
        scene_free(&scene);
        return 1;
    }
    if (args.animate) {
        rc = reference_sequence(&args, &scene);
        scene_free(&scene);
        return rc;
    }
    ImageF mean = {0}, var = {0};
    PtStats st = {0};
    /* Ctrl-C: finish the pass, write what was reached; a second one kills. */
    struct sigaction old_sa;
    catch_sigint(&old_sa);
    double cpu0 = util_cpu_seconds();
    bool rendered = pt_render(&scene, set, &mean, args.var_out ? &var : NULL, &st);
    double cpu_s = util_cpu_seconds() - cpu0; /* BVH build and render, every thread */
    sigaction(SIGINT, &old_sa, NULL);
    if (rendered && st.stopped == PT_STOP_INTERRUPTED)
        log_info("reference", "interrupted: writing the partial image with %d of %d spp", st.spp, set->spp);
    /* All outputs or none, also under a second Ctrl-C or a SIGTERM: the
     * signal waits until every file is written (ms to seconds). */
    util_defer_ending_signals();
    rc = 1;
    if (rendered && reference_write_outputs(&args, &scene, &mean, &var, &st)) {
        reference_print(&args, &scene, &st, cpu_s);
        rc = 0;
    }
    util_end_deferral();
    image_free(&mean);
    image_free(&var);
    scene_free(&scene);
    return rc;
}
