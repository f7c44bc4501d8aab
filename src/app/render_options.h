/* render_options.h — the options `rtgi render` and `rtgi view` share:
 * scene, size, techniques and every parameter, parsed strictly, then
 * applied over the scene's own defaults. */
#ifndef RTGI_RENDER_OPTIONS_H
#define RTGI_RENDER_OPTIONS_H

#include <stdbool.h>

#include "gpu/probe.h"
#include "frame/renderer.h"
#include "core/scene.h"
#include "core/settings.h"

typedef struct RenderOptions {
    const char *scene;
    const char *out;   /* output image (render) or screenshot (view), may be NULL */
    const char *png;   /* render: also a tone-mapped PNG, may be NULL */
    int shadow;        /* ShadowMode */
    int gi;            /* GiMode */
    int width, height;
    float exposure;    /* < 0: scene's */
    float light_scale; /* < 0: unchanged */
    int frames;        /* render: timed frames; view: frames before exiting (0 = until closed) */
    int warmup;        /* render: untimed frames before the timed ones */
    int ssaa;          /* N×N supersampling (1: off) */
    int aa;            /* AaMode (render: none, view: fxaa) */
    int shading;       /* ShadingMode of direct-only frames (--shading; default auto) */
    int gbuffer;       /* GbufferMode of deferred frames (--gbuffer; default auto) */
    bool timings, debug;
    bool half;         /* --half: EXR output (render) or captures (view) as half floats */
    const char *probe; /* --probe FILE: a `rtgi probe --json` result for --timings */
    ProbeResult probe_file; /* --probe FILE's result, read when the options are parsed */
    bool view;         /* the options of `rtgi view` (else `rtgi render`) */
    const char *emitter_mask; /* --emitter-mask FILE.png: the pixels that see an emitter (for compare) */
    const char *out_ao; /* --out-ao FILE.pfm|FILE.png: ambient visibility of --gi vct (--vct-ao on) */
    /* `rtgi view` only (the parser refuses them for render, and render's
     * --png, --timings, --warmup, --probe, --emitter-mask for view): */
    const char *compare;    /* --compare FILE: the A/B view's reference, or NULL */
    const char *ui_test;    /* --ui-test DIR: the window test's script, or NULL */
    const char *window_out; /* --window-out FILE.png: what Shift-P saves, or NULL */
    double slow_ms;         /* --slow-ms: techniques estimated above need a click (1000) */
    /* `rtgi render` only, time (animation.h): */
    bool animate;           /* --animate: --frames N frames of the scene's animation into --out's pattern */
    bool frames_given;      /* --frames was given */
    double fps;             /* --fps F: frame i at i/F s (0: the frames spread over the duration) */
    double time;            /* --time T: the scene at T s (< 0: not given) */
    const char *video;      /* --video FILE.mp4: also a video of the frames (ffmpeg), or NULL */
    bool no_panel;          /* --no-panel: start with the panel hidden */
    bool live_reference;    /* --live-reference: the path tracer converging in the A/B view */
    int live_threads;       /* --live-threads: its threads (0: every core) */
    int live_spp;           /* --live-spp: the samples per pixel it stops at (4096) */
    bool live_ordinary;     /* --live-priority normal (else idle: SCHED_IDLE) */
    int live_priority;      /* --live-priority as parsed: 0 idle, 1 normal */
    const char *shader_dir; /* --shader-dir (applied when the options are parsed) */
    Settings set;      /* technique settings given on the command line ... */
    bool given[64];    /* ... by settings-table row */
} RenderOptions;

/* Defaults for `rtgi render` (out = out/render.png, 3 timed frames) or
 * `rtgi view` (no screenshot, runs until closed). */
void render_options_init(RenderOptions *o, bool view);
/* Parses argv. 0: go on; -1: --help was shown; else an exit status (2 for
 * usage, 1 for an output that cannot be written: cli_check_files). */
int render_options_parse(RenderOptions *o, int argc, char **argv, void (*help)(void));
/* Loads the scene the options name, with their light scale applied.
 * false after logging. */
/* The time options of `render` (--animate, --frames, --fps, --time,
 * --video) agree with each other and the rest: 0, or 2 after a usage
 * error. (Part of render_options_parse.) */
int render_options_check_time(const RenderOptions *o);
bool render_options_load_scene(const RenderOptions *o, Scene *scene);
/* Prints the options' help of `rtgi view` (view) or `rtgi render`, with
 * their defaults, then the techniques and the settings table's rows. */
void render_options_help(bool view);
/* The techniques and the settings table's rows, the tail of render's and
 * view's --help. */
void render_options_help_settings(void);
/* Render settings from the scene's defaults and the options. */
void render_options_settings(const RenderOptions *o, const Scene *scene, RenderSettings *rs);
/* Whether WxH supersampled N×N stays within the largest image per side;
 * logs the error (naming --ssaa) if not. */
bool render_options_ssaa_fits(int width, int height, int ssaa);

#endif
