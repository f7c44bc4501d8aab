/* cmd_reference.c — `rtgi reference`: the path-traced ground truth. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/animation.h"
#include "app/cli.h"
#include "app/commands.h"
#include "io/image.h"
#include "base/log.h"
#include "reference/pathtracer.h"
#include "app/sequence.h"
#include "base/util.h"

void cmd_reference_help(void)
{
    printf("usage: rtgi reference [options]\n"
           "  --scene cornell|FILE.json|FILE.gltf|FILE.obj   scene (default: cornell)\n"
           "  --mode full|direct|one-bounce|one-bounce-novis|indirect   (default: full)\n"
           "  --spp N            samples per pixel (default: 64; with --target-relmse or --time\n"
           "                     and no --spp, at most 16777216)\n"
           "  --target-relmse E  stop once the relMSE estimated from the per-pixel variance is at\n"
           "                     most E (checked after each pass, from 16 spp on; with the default\n"
           "                     Sobol' sampler the real error is usually lower than the estimate)\n"
           "  --time T           stop before a pass that would end past T seconds of rendering\n"
           "                     (the first pass always runs)\n"
           "  --sampler sobol|independent   Owen-scrambled Sobol' or independent random numbers (default: sobol)\n"
           "  --seed S           random seed (default: 1); same seed → same image\n"
           "  --threads T        worker threads (default: all cores)\n"
           "  --size WxH         image size (default: 256x256, as rtgi render)\n"
           "  --out FILE.pfm|FILE.exr|FILE.png   (default: out/reference.pfm); an EXR records the\n"
           "                     samples per pixel reached in its header (int attribute rtgi_spp)\n"
           "  --half             EXR output as half floats (default: float32)\n"
           "  --exposure E       for PNG output (default: scene's)\n"
           "  --max-depth N      path vertices at most (default: 64)\n"
           "  --no-rr            disable Russian roulette\n"
           "  --rr-depth N       bounces before Russian roulette (default: 3)\n"
           "  --no-jitter        sample pixel centres only (no anti-aliasing)\n"
           "  --light-scale S    scale every light's emitter size (0: point lights)\n"
           "  --variance FILE.pfm  also write the per-pixel variance of the mean\n"
           "  --png FILE.png     also write the tone-mapped PNG\n"
           "  --emitter-mask FILE.png   also write the mask of pixels that see an emitter\n"
           "                     (black; render --emitter-mask writes the same one)\n"
           "  --at T             the scene file's animation at T s (one instant; --time is the\n"
           "                     time budget)\n"
           "  --animate          the animation's --frames N frames (spread over its duration, or\n"
           "                     frame i at i/F s with --fps F) into --out's pattern (frame_%%04d.exr),\n"
           "                     each at --spp with the same seed\n"
           "  --quiet            errors only: no progress (else on stderr: after the first pass the\n"
           "                     time the rest will take, then samples, rays/s, time left)\n"
           "  --verbose          debug lines too\n"
           "Prints on stdout: spp (reached), relmse_estimate, and 'stopped: target-relmse' or\n"
           "'stopped: time' when one of those ended it.\n"
           "Ctrl-C (SIGINT) finishes the current pass (a few samples per pixel) and writes the\n"
           "image with the samples reached ('spp:' line; EXR attribute rtgi_spp); a second\n"
           "Ctrl-C ends the program at once, or once the outputs being written are whole\n"
           "(all of them or none; SIGTERM likewise).\n");
}

/* The options this command knows (for "did you mean"). */
static const char *const k_reference_options[] = {"--animate", "--at", "--emitter-mask", "--exposure", "--fps", "--frames", "--half", "--help", "--light-scale", "--max-depth", "--mode", "--no-jitter", "--no-rr", "--out", "--png", "--rr-depth", "--sampler", "--scene", "--seed", "--size", "--spp", "--target-relmse", "--threads", "--time", "--variance", NULL};

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
} ReferenceArgs;

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
    *args = (ReferenceArgs){.scene_name = "cornell", .out = "out/reference.pfm", .exposure = -1.f,
                            .light_scale = -1.f, .time = -1.f};
    PtSettings *set = &args->set;
    pt_settings_default(set);
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    set->threads = cores > 0 ? (int)cores : 1;
    CliArgs a = {.argc = argc, .argv = argv};
    const char *opt, *v;
    bool spp_given = false;
    while ((opt = cli_next(&a))) {
        if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            cmd_reference_help();
            return -1;
        } else if (!strcmp(opt, "--scene")) {
            CLI_VALUE(&a, v);
            if (!cli_scene(opt, v))
                return 2;
            args->scene_name = v;
        } else if (!strcmp(opt, "--mode")) {
            CLI_VALUE(&a, v);
            int m = cli_choice(opt, v, pt_mode_names);
            if (m < 0)
                return 2;
            set->mode = (PtMode)m;
        } else if (!strcmp(opt, "--sampler")) {
            CLI_VALUE(&a, v);
            int k = cli_choice(opt, v, pt_sampler_names);
            if (k < 0)
                return 2;
            set->sampler = (PtSampler)k;
        } else if (!strcmp(opt, "--spp")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 1 << 24, &set->spp))
                return 2;
            spp_given = true;
        } else if (!strcmp(opt, "--target-relmse")) {
            CLI_VALUE(&a, v);
            float e;
            if (!cli_float(opt, v, 1e-9f, 1e3f, &e))
                return 2;
            set->target_relmse = e;
        } else if (!strcmp(opt, "--time")) {
            CLI_VALUE(&a, v);
            float t;
            if (!cli_float(opt, v, 1e-3f, 1e7f, &t))
                return 2;
            set->time_budget = t;
        } else if (!strcmp(opt, "--seed")) {
            CLI_VALUE(&a, v);
            int s;
            if (!cli_int(opt, v, 0, 2147483647, &s))
                return 2;
            set->seed = (uint64_t)s;
        } else if (!strcmp(opt, "--threads")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 1024, &set->threads))
                return 2;
        } else if (!strcmp(opt, "--size")) {
            CLI_VALUE(&a, v);
            if (!cli_size(opt, v, 16384, &set->width, &set->height))
                return 2;
        } else if (!strcmp(opt, "--out")) {
            CLI_VALUE(&a, v);
            args->out = v;
            if (!util_ends_with(v, ".png") && !util_ends_with(v, ".pfm") && !util_ends_with(v, ".exr")) {
                usage_error(NULL, "--out: '%s' must end in .png, .pfm or .exr", v);
                return 2;
            }
        } else if (!strcmp(opt, "--png")) {
            CLI_VALUE(&a, v);
            args->png = v;
            if (!util_ends_with(v, ".png")) {
                usage_error(NULL, "--png: '%s' must end in .png", v);
                return 2;
            }
        } else if (!strcmp(opt, "--emitter-mask")) {
            CLI_VALUE(&a, v);
            args->emitter_mask = v;
            if (!util_ends_with(v, ".png")) {
                usage_error(NULL, "--emitter-mask: '%s' must end in .png", v);
                return 2;
            }
        } else if (!strcmp(opt, "--variance")) {
            CLI_VALUE(&a, v);
            args->var_out = v;
            if (!util_ends_with(v, ".pfm") && !util_ends_with(v, ".exr")) {
                usage_error(NULL, "--variance: '%s' must end in .pfm or .exr", v);
                return 2;
            }
        } else if (!strcmp(opt, "--exposure")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, SCENE_EXPOSURE_MIN, SCENE_EXPOSURE_MAX, &args->exposure))
                return 2;
        } else if (!strcmp(opt, "--light-scale")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 1e3f, &args->light_scale))
                return 2;
        } else if (!strcmp(opt, "--max-depth")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 100000, &set->max_depth))
                return 2;
        } else if (!strcmp(opt, "--rr-depth")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 0, 100000, &set->rr_depth))
                return 2;
        } else if (!strcmp(opt, "--half")) {
            args->half = true;
        } else if (!strcmp(opt, "--no-rr")) {
            set->russian_roulette = false;
        } else if (!strcmp(opt, "--no-jitter")) {
            set->pixel_jitter = false;
        } else if (!strcmp(opt, "--animate")) {
            args->animate = true;
        } else if (!strcmp(opt, "--frames")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 1, 1000000, &args->frames))
                return 2;
        } else if (!strcmp(opt, "--fps")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 1e-3f, 1e6f, &args->fps))
                return 2;
        } else if (!strcmp(opt, "--at")) {
            CLI_VALUE(&a, v);
            if (!cli_float(opt, v, 0.f, 1e6f, &args->time))
                return 2;
        } else {
            cli_unknown_option(opt, k_reference_options);
            return 2;
        }
    }
    if (cli_failed(&a))
        return 2;
    /* A target or a budget without --spp: the samples are what they need. */
    if (!spp_given && (set->target_relmse > 0.0 || set->time_budget > 0.0))
        set->spp = 1 << 24;
    int rc = reference_check_time(args);
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
