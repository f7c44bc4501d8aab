/* cmd_bench.c — `rtgi bench`: every listed technique (shadow × GI × settings)
 * of one scene rendered in-process with per-pass timings, measured against a
 * cached path-traced reference with the emitters masked out, written as
 * DIR/bench.json (schema in docs/measuring.md, "Benchmarks") and the self-contained
 * DIR/report.html (report_html.c). Every output is written into a staging
 * directory DIR/.bench-PID-XXXXXX and moved into DIR only when all of them
 * are written: a failed run leaves DIR as it was (a killed one leaves its
 * staging directory, which the next run removes).
 *
 * References are cached in --cache DIR (default out/ref-cache) as EXR files
 * named by a hash of what decides their pixels: the scene's content
 * (geometry, materials, textures, lights, camera), the size, the mode, the
 * samples per pixel and BENCH_REF_VERSION (raise it when the path tracer's
 * light transport changes). */
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "core/animation.h"
#include "app/cli.h"
#include "app/commands.h"
#include "app/options.h"
#include "gl/gl_context.h"
#include "io/image.h"
#include "base/log.h"
#include "version.h" /* generated: RTGI_VERSION */
#include "io/metrics.h"
#include "io/metrics_temporal.h"
#include "reference/pathtracer.h"
#include "app/render_options.h"
#include "frame/renderer.h"
#include "io/report_html.h"
#include "core/settings.h"
#include "base/util.h"

/* Raise when the reference's light transport changes: old cache entries
 * then no longer match. */
#define BENCH_REF_VERSION 1
#define BENCH_MAX_ENTRIES 64
/* --out's longest: DIR/.bench-PID-XXXXXX/images/<id>_flip.png.tmp-XXXXXX then
 * fits every path buffer of this file (1100 bytes and more). */
#define BENCH_MAX_DIR 900

static const char *const k_shadow_names[] = {"none", "hard", "pcf", "pcss", NULL};
/* Every technique of the table but the exhaustive ones (GI_EXHAUSTIVE:
 * vpl-all), comma-separated: bench's default --gi. */
static const char *default_gi_list(void)
{
    static char list[512];
    if (list[0])
        return list;
    size_t n = 0;
    for (int i = 0; gi_techniques[i]; i++)
        if (!(gi_techniques[i]->flags & GI_EXHAUSTIVE) && n < sizeof list)
            n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", n ? "," : "", gi_techniques[i]->name);
    return list;
}

/* What the command line asked for. */
typedef struct BenchArgs {
    const char *out;         /* --out DIR (required) */
    const char *scene_name;  /* --scene */
    const char *gi_list;     /* --gi: comma-separated NAME[:key=value...] */
    const char *shadow_list; /* --shadow: comma-separated */
    const char *cache;       /* --cache DIR */
    int width, height;       /* --size */
    int frames;              /* --frames: timed frames per technique */
    int ssaa;                /* --ssaa */
    float exposure;          /* --exposure of FLIP and SSIM; < 0: the scene's */
    bool markdown;           /* --markdown */
    bool animate;            /* --animate: `frames` frames of the scene's animation */
    float fps;               /* --fps (0: the frames spread over the duration) */
    PtSettings ps;           /* the reference's settings */
    Settings base;           /* the technique settings every entry starts from ... */
    bool base_given[64];     /* ... and which of them were given, by settings-table row */
} BenchArgs;

#define BA BenchArgs
static const OptionDesc k_bench_options[] = {
    OPT_WORD("--out", BA, out, "DIR", "output directory (required); images go to DIR/images/ (default: none)"),
    OPT_SCENE("--scene", BA, scene_name, "cornell, or a scene file (.json, .gltf, .obj)"),
    OPT_SIZE("--size", BA, width, height, 8192, "image size"),
    OPT_WORD("--gi", BA, gi_list, "LIST", "comma-separated techniques, each optionally with settings: NAME[:key=value[:key=value]] with settings' names (or their old gi/shadow keys), e.g. rsm:rsm.samples=100,vpl-slc:vpl.count=65536"),
    OPT_WORD("--shadow", BA, shadow_list, "LIST", "comma-separated shadow techniques"),
    OPT_INT("--spp", BA, ps.spp, 1, 1 << 20, "reference samples per pixel"),
    OPT_CHOICE("--ref-mode", BA, ps.mode, pt_mode_names, "what the reference's paths carry (rtgi reference --mode)"),
    OPT_INT("--frames", BA, frames, 1, 1000, "timed frames per technique after one warm-up frame (on a GPU, warm-up frames for 0.5 s); with --animate: the sequence's frames (at least 3)"),
    OPT_FLAG("--animate", BA, animate, "measure over the scene file's animation: every technique renders --frames frames spread over its duration (or at --fps X), each against its own cached reference; adds per-frame relMSE, flicker and a kymograph per technique (the metrics are the middle frame's)"),
    OPT_FLOAT("--fps", BA, fps, 1e-3, 1e6, "with --animate: frame i at i/X s (default: the frames spread over the duration)"),
    OPT_INT("--ssaa", BA, ssaa, 1, 8, "render every technique N x N supersampled, box-filtered to WxH (1: off), as rtgi render --ssaa"),
    OPT_FLOAT("--exposure", BA, exposure, SCENE_EXPOSURE_MIN, SCENE_EXPOSURE_MAX, "exposure of FLIP and SSIM (default: the scene's)"),
    OPT_WORD("--cache", BA, cache, "DIR", "reference cache directory"),
    OPT_INT("--threads", BA, ps.threads, 1, 1024, "reference threads (default: every core)"),
    OPT_FLAG("--markdown", BA, markdown, "also print the results as a Markdown table on stdout"),
    OPT_END,
};
#undef BA

/* The defaults, before the command line. */
static void bench_args_default(BenchArgs *args)
{
    *args = (BenchArgs){.scene_name = "cornell", .gi_list = default_gi_list(), .shadow_list = "pcss",
                        .cache = "out/ref-cache", .width = 256, .height = 256, .frames = 3, .ssaa = 1,
                        .exposure = -1.f};
    PtSettings *ps = &args->ps;
    pt_settings_default(ps);
    ps->spp = 256;
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    ps->threads = cores > 0 ? (int)cores : 1;
    settings_default(&args->base);
    const SettingDesc *vpls = settings_find_name("vpl.count");
    args->base.gi.vpl.count = 16384; /* what the benchmarks use */
    args->base_given[vpls - settings_table] = true;
}

void cmd_bench_help(void)
{
    BenchArgs def;
    bench_args_default(&def);
    printf("usage: rtgi bench --out DIR [options]\n"
           "Renders each technique with per-pass timings, compares it with a cached path-traced\n"
           "reference (emitters masked out) and writes DIR/bench.json, DIR/report.html, and\n"
           "DIR/bench.csv and DIR/bench_passes.csv (a row per technique, per technique and pass).\n");
    options_print_help(stdout, k_bench_options, &def);
    printf("  --quiet                      errors only: no progress\n"
           "  --verbose                    debug lines too\n"
           "  --OPTION VALUE               any setting of `rtgi render --help` for every technique\n"
           "                               (bench sets --vpls 16384 unless given)\n");
}

/* One technique to measure and what was measured. */
typedef struct BenchEntry {
    char *label;            /* "pcss + rsm (samples=100)" (owned) */
    char id[48];            /* file-name stem: "e03_pcss_rsm" */
    char *overrides;        /* "samples=100" or "" (owned) */
    int shadow, gi;
    Settings set;           /* settings given for this entry (over the base ones) */
    bool given[64];
    RenderSettings rs;
    double frame_ms;        /* wall time per frame (glFinish around passes) */
    double gpu_ms;          /* sum of the passes' GPU times */
    ImageF img;             /* radiance */
    float *flip_map;        /* per-pixel FLIP */
    double rmse, relmse, ssim, flip, mean_ratio;
    /* --animate: */
    double *relmse_frames;  /* relMSE of every frame against its reference (owned) */
    int frames;             /* in relmse_frames */
    double flicker;         /* metrics_temporal.h */
    double reference_flicker; /* the reference sequence's (the same for every entry) */
    ImageF kymograph;       /* the middle row of every frame */
} BenchEntry;

/* FNV-1a over what decides the reference's pixels, field by field (no
 * struct padding). */
static uint64_t scene_hash(const Scene *s)
{
    uint64_t h = util_hash_bytes(1469598103934665603ull, "rtgi-ref", 8);
    int v = BENCH_REF_VERSION;
    h = util_hash_bytes(h, &v, sizeof v);
    h = util_hash_bytes(h, s->vertices, sizeof(Vertex) * s->vertex_count);
    h = util_hash_bytes(h, s->indices, sizeof(uint32_t) * s->index_count);
    for (int i = 0; i < s->submesh_count; i++) {
        const Submesh *m = &s->submeshes[i];
        h = util_hash_bytes(h, &m->first_index, sizeof m->first_index);
        h = util_hash_bytes(h, &m->index_count, sizeof m->index_count);
        h = util_hash_bytes(h, &m->material, sizeof m->material);
    }
    for (int i = 0; i < s->material_count; i++) {
        const Material *m = &s->materials[i];
        int b = m->alpha_mask;
        h = util_hash_bytes(h, m->albedo, sizeof(vec3));
        h = util_hash_bytes(h, &m->albedo_tex, sizeof m->albedo_tex);
        h = util_hash_bytes(h, &b, sizeof b);
        h = util_hash_bytes(h, &m->alpha_cutoff, sizeof m->alpha_cutoff);
        h = util_hash_bytes(h, m->emission, sizeof(vec3));
        h = util_hash_bytes(h, &m->light_index, sizeof m->light_index);
    }
    for (int i = 0; i < s->texture_count; i++) {
        const Texture *t = &s->textures[i];
        h = util_hash_bytes(h, &t->width, sizeof t->width);
        h = util_hash_bytes(h, &t->height, sizeof t->height);
        if (t->rgba)
            h = util_hash_bytes(h, t->rgba, (size_t)t->width * t->height * 4);
    }
    for (int i = 0; i < s->light_count; i++) {
        const Light *l = &s->lights[i];
        int type = l->type;
        h = util_hash_bytes(h, &type, sizeof type);
        h = util_hash_bytes(h, l->position, sizeof(vec3));
        h = util_hash_bytes(h, l->direction, sizeof(vec3));
        h = util_hash_bytes(h, l->color, sizeof(vec3));
        h = util_hash_bytes(h, &l->size, sizeof l->size);
        h = util_hash_bytes(h, &l->spot_inner, sizeof l->spot_inner);
        h = util_hash_bytes(h, &l->spot_outer, sizeof l->spot_outer);
        h = util_hash_bytes(h, l->quad_u, sizeof(vec3));
        h = util_hash_bytes(h, l->quad_v, sizeof(vec3));
    }
    const Camera *c = &s->camera;
    h = util_hash_bytes(h, c->position, sizeof(vec3));
    h = util_hash_bytes(h, c->forward, sizeof(vec3));
    h = util_hash_bytes(h, c->up, sizeof(vec3));
    h = util_hash_bytes(h, &c->fov_y, sizeof c->fov_y);
    return h;
}

/* mkdir -p for one or two levels; false after logging. */
static bool make_dir(const char *path)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = buf + 1; *p; p++)
        if (*p == '/') {
            *p = 0;
            if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
                log_error("bench", "%s: cannot create directory (%s)", buf, strerror(errno));
                return false;
            }
            *p = '/';
        }
    if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
        log_error("bench", "%s: cannot create directory (%s)", buf, strerror(errno));
        return false;
    }
    struct stat st;
    if (stat(buf, &st) != 0 || !S_ISDIR(st.st_mode)) {
        log_error("bench", "%s: not a directory", buf);
        return false;
    }
    return true;
}

typedef enum DrainMode {
    DRAIN_CHECK,  /* that no target in `to` is a directory */
    DRAIN_MOVE,   /* rename each file into `to` (one file system) */
    DRAIN_REMOVE, /* unlink each file */
} DrainMode;

/* Does `mode` to every file of `dir` (subdirectories left alone). false
 * after logging. */
static bool drain_dir(const char *dir, const char *to, DrainMode mode)
{
    DIR *d = opendir(dir);
    if (!d) {
        log_error("bench", "%s: cannot read the staging directory (%s)", dir, strerror(errno));
        return false;
    }
    bool ok = true;
    for (struct dirent *de; ok && (de = readdir(d));) {
        char src[1400], dst[1400];
        struct stat st;
        snprintf(src, sizeof src, "%s/%s", dir, de->d_name);
        if (lstat(src, &st) != 0 || S_ISDIR(st.st_mode))
            continue; /* ".", "..", images/ */
        snprintf(dst, sizeof dst, "%s/%s", to ? to : "", de->d_name);
        if (mode == DRAIN_CHECK && stat(dst, &st) == 0 && S_ISDIR(st.st_mode)) {
            log_error("bench", "%s: is a directory; no output of this run is moved into %s", dst, to);
            ok = false;
        } else if (mode == DRAIN_MOVE && rename(src, dst) != 0) {
            log_error("bench", "%s: cannot move the output into place (%s)", dst, strerror(errno));
            ok = false;
        } else if (mode == DRAIN_REMOVE) {
            unlink(src);
        }
    }
    closedir(d);
    return ok;
}

/* Removes the staging directory `stage` and what is in it. */
static void stage_remove(const char *stage)
{
    char images[1100];
    snprintf(images, sizeof images, "%s/images", stage);
    drain_dir(images, NULL, DRAIN_REMOVE);
    rmdir(images);
    drain_dir(stage, NULL, DRAIN_REMOVE);
    rmdir(stage);
}

/* Removes the staging directories DIR/.bench-PID-XXXXXX of runs that
 * ended without cleaning up (killed): those whose process is gone. A
 * running bench's own is left alone. */
static void stage_remove_stale(const char *out)
{
    DIR *d = opendir(out);
    if (!d)
        return;
    for (struct dirent *de; (de = readdir(d));) {
        int pid = 0, end = 0;
        if (sscanf(de->d_name, ".bench-%d-%*6c%n", &pid, &end) != 1 || end == 0 || de->d_name[end] || pid <= 0)
            continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH)
            continue;
        char stale[1100];
        snprintf(stale, sizeof stale, "%s/%s", out, de->d_name);
        stage_remove(stale);
        log_info("bench", "%s: removed the staging directory of an earlier run that was killed", stale);
    }
    closedir(d);
}

/* Makes the staging directory DIR/.bench-PID-XXXXXX (into `stage`) and
 * its images/: the run writes there, stage_commit moves it into DIR.
 * false after logging. */
static bool stage_open(const char *out, char *stage, size_t cap)
{
    stage_remove_stale(out);
    snprintf(stage, cap, "%s/.bench-%d-XXXXXX", out, (int)getpid());
    if (!mkdtemp(stage)) {
        log_error("bench", "%s: cannot create a staging directory there (%s)", out, strerror(errno));
        stage[0] = 0;
        return false;
    }
    char images[1100];
    snprintf(images, sizeof images, "%s/images", stage);
    if (mkdir(images, 0777) != 0) {
        log_error("bench", "%s: cannot create directory (%s)", images, strerror(errno));
        return false;
    }
    return true;
}

/* Moves every staged file into DIR and DIR/images, after checking that
 * none would land on a directory (a rename that then fails is an I/O error
 * of the same file system), and removes the emptied staging directory
 * (`stage` is then ""); a Ctrl-C or SIGTERM meanwhile waits for the whole
 * move. false after logging. */
static bool stage_commit(char *stage, const char *out)
{
    char from[1100], to[1100];
    snprintf(from, sizeof from, "%s/images", stage);
    snprintf(to, sizeof to, "%s/images", out);
    util_defer_ending_signals();
    /* DIR/images is made here, not before the run: a run killed earlier
     * leaves DIR only with its hidden staging directory. */
    bool ok = make_dir(to) && drain_dir(from, to, DRAIN_CHECK) && drain_dir(stage, out, DRAIN_CHECK) &&
              drain_dir(from, to, DRAIN_MOVE) && drain_dir(stage, out, DRAIN_MOVE);
    if (ok && rmdir(from) == 0 && rmdir(stage) == 0) {
        util_live_dir_remove(stage);
        stage[0] = 0;
    }
    util_end_deferral();
    return ok;
}

/* Two runs into one DIR: the second's results replace the first's. Said,
 * with the run they replace (its commit and date, from its bench.json). */
static void warn_if_replacing(const char *out)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/bench.json", out);
    char *text = util_read_file(path, NULL);
    if (!text)
        return;
    cJSON *old = cJSON_Parse(text);
    free(text);
    const cJSON *commit = cJSON_GetObjectItem(old, "commit"), *date = cJSON_GetObjectItem(old, "date");
    log_warn("bench", "%s: replacing the results of an earlier run (%s, %s); give another --out to keep both", out,
             cJSON_IsString(commit) ? commit->valuestring : "commit unknown",
             cJSON_IsString(date) ? date->valuestring : "date unknown");
    cJSON_Delete(old);
}

/* true if something (even a dangling link) is at `path`. */
static bool path_exists(const char *path)
{
    struct stat st;
    return lstat(path, &st) == 0;
}

/* The cached reference, or a new one rendered and cached; the directory
 * `cache` exists (made by the caller before any output). */
static bool get_reference(const Scene *scene, const PtSettings *ps, const char *cache, ImageF *ref, char *path,
                          size_t cap, bool *reused)
{
    uint64_t h = scene_hash(scene);
    h = util_hash_bytes(h, &ps->width, sizeof ps->width);
    h = util_hash_bytes(h, &ps->height, sizeof ps->height);
    int mode = ps->mode, sampler = ps->sampler;
    h = util_hash_bytes(h, &mode, sizeof mode);
    h = util_hash_bytes(h, &sampler, sizeof sampler);
    h = util_hash_bytes(h, &ps->spp, sizeof ps->spp);
    snprintf(path, cap, "%s/ref_%dx%d_%s_%dspp_%016llx.exr", cache, ps->width, ps->height, pt_mode_names[ps->mode],
             ps->spp, (unsigned long long)h);
    *reused = false;
    if (access(path, F_OK) == 0) {
        int spp = 0;
        if (image_read_exr_attr(path, "rtgi_spp", &spp) && spp == ps->spp && image_read(path, ref) &&
            ref->width == ps->width && ref->height == ps->height) {
            *reused = true;
            log_info("bench", "reusing the cached reference %s", path);
            return true;
        }
        image_free(ref);
        log_info("bench", "%s: unusable cached reference; rendering it again", path);
    }
    if (access(cache, W_OK) != 0) { /* before minutes of rendering */
        log_error("bench", "%s: cannot write the reference there (%s)", cache, strerror(errno));
        return false;
    }
    log_info("bench", "rendering the reference (%s, %d spp, %dx%d) into %s", pt_mode_names[ps->mode], ps->spp,
             ps->width, ps->height, path);
    PtStats st = {0};
    if (!pt_render(scene, ps, ref, NULL, &st))
        return false;
    ImageAttr attrs[2] = {{"rtgi_spp", st.spp}, {"rtgi_spp_requested", ps->spp}};
    return image_write_exr(path, ref, false, attrs, 2);
}

/* The next item of a `sep`-separated list at *cursor, cut off in place
 * (an empty string for an empty item); *cursor moves past it, to NULL
 * after the last one. Unlike strtok, keeps empty items so that they can be
 * refused. */
static char *next_item(char **cursor, char sep)
{
    char *item = *cursor, *end = strchr(item, sep);
    if (end)
        *end = 0;
    *cursor = end ? end + 1 : NULL;
    return item;
}

/* Parses one "key=value" of the --gi item `item` into the entry; `over`
 * collects "key=value, ..." for the label. false after logging. */
static bool parse_gi_setting(const char *item, char *kv, BenchEntry *e, StrBuf *over)
{
    if (!*kv) {
        usage_error(NULL, "--gi: '%s': empty setting (NAME:key=value[:key=value])", item);
        return false;
    }
    char *eq = strchr(kv, '=');
    if (!eq) {
        usage_error(NULL, "--gi: '%s': settings are key=value (e.g. rsm:samples=100)", kv);
        return false;
    }
    *eq = 0;
    /* A setting's name (rsm.samples), or its old key in the scene file's
     * "gi" or "shadow" object (samples, pcf_samples). */
    const SettingDesc *d = settings_find_name(kv);
    static const char *const k_old_objects[] = {"gi", "shadow"};
    for (int i = 0; i < 2 && !d && !strchr(kv, '.'); i++) {
        char old[128];
        snprintf(old, sizeof old, "%s.%s", k_old_objects[i], kv);
        d = settings_find_name(old);
    }
    if (!d) {
        const char *keys[256];
        int n = settings_names(keys, 256);
        for (int i = 0; i < 2; i++)
            n += settings_object_keys(k_old_objects[i], keys + n, 256 - n);
        usage_error(util_nearest(kv, keys),
                    "--gi: '%s' is not a setting key (the settings table's names, e.g. rsm.samples)", kv);
        return false;
    }
    if (e->given[d - settings_table]) {
        usage_error(NULL, "--gi: '%s': the key '%s' is given twice", item, kv);
        return false;
    }
    bool on = !strcmp(eq + 1, "on") || !strcmp(eq + 1, "true") || !strcmp(eq + 1, "1");
    if (d->type == VALUE_FLAG && !on) {
        usage_error(NULL, "--gi: %s is a flag: give %s=on", kv, kv);
        return false;
    }
    if (!settings_parse_cli(d, kv, d->type == VALUE_FLAG ? NULL : eq + 1, &e->set))
        return false;
    e->given[d - settings_table] = true;
    strbuf_printf(over, "%s%s=%s", over->len ? ", " : "", kv, eq + 1);
    return true;
}

/* Splits "NAME[:key=value...]" (any length) and fills the entry's settings
 * and its overrides (owned). false after logging. */
static bool parse_gi_item(const char *item, BenchEntry *e)
{
    char *buf = util_strndup(item, strlen(item)), *cursor = buf;
    if (!buf)
        return false;
    StrBuf over = {0};
    strbuf_append(&over, "", 0);
    const char *name = next_item(&cursor, ':');
    if (!*name)
        usage_error(NULL, "--gi: '%s': no technique before the settings", item);
    bool ok = *name && (e->gi = cli_choice("--gi", name, gi_technique_names())) >= 0;
    settings_default(&e->set);
    while (ok && cursor)
        ok = parse_gi_setting(item, next_item(&cursor, ':'), e, &over);
    free(buf);
    if (ok && over.failed)
        ok = false; /* logged by strbuf */
    e->overrides = over.data;
    return ok;
}

/* "SHADOW + GI (overrides)" into e->label (owned); false after logging. */
static bool make_label(BenchEntry *e, const char *shadow)
{
    StrBuf b = {0};
    const char *o = e->overrides;
    strbuf_printf(&b, "%s + %s%s%s%s", shadow, gi_technique_names()[e->gi], o[0] ? " (" : "", o, o[0] ? ")" : "");
    e->label = b.data;
    return !b.failed;
}

/* The next item of the comma-separated list `list` of option `opt` at
 * *cursor (next_item); NULL after logging if it is empty. */
static const char *next_list_item(const char *opt, const char *list, char **cursor)
{
    const char *item = next_item(cursor, ',');
    if (!*item)
        usage_error(NULL, "%s: '%s': empty item in the list", opt, list);
    return *item ? item : NULL;
}

/* Every shadow of `shadow_list` × every item of `gi_list`, in order, into
 * entries[0..*n). false after logging a usage error; entries[0..*n) then
 * hold what was made (entries_free). */
static bool parse_entries(const char *shadow_list, const char *gi_list, BenchEntry *entries, int *n)
{
    char *shadows = util_strndup(shadow_list, strlen(shadow_list)), *sc = shadows;
    bool ok = shadows != NULL;
    while (ok && sc) {
        const char *sh = next_list_item("--shadow", shadow_list, &sc);
        int shadow = sh ? cli_choice("--shadow", sh, k_shadow_names) : -1;
        char *gis = shadow >= 0 ? util_strndup(gi_list, strlen(gi_list)) : NULL, *gc = gis;
        ok = gis != NULL;
        while (ok && gc) {
            const char *gi = next_list_item("--gi", gi_list, &gc);
            if (!gi || *n == BENCH_MAX_ENTRIES) {
                if (gi)
                    usage_error(NULL, "more than %d techniques (shadows × --gi items)", BENCH_MAX_ENTRIES);
                ok = false;
                break;
            }
            BenchEntry *e = &entries[*n];
            memset(e, 0, sizeof *e);
            e->shadow = shadow;
            ok = parse_gi_item(gi, e) && make_label(e, sh);
            if (ok)
                snprintf(e->id, sizeof e->id, "e%02d_%s_%s", *n, sh, gi_technique_names()[e->gi]);
            (*n)++; /* counted either way: entries_free frees its strings */
        }
        free(gis);
    }
    free(shadows);
    return ok;
}

/* Frees what parse_entries and the measurements made of entries[0..n). */
static void entries_free(BenchEntry *entries, int n)
{
    for (int i = 0; i < n; i++) {
        free(entries[i].label);
        free(entries[i].overrides);
        image_free(&entries[i].img);
        image_free(&entries[i].kymograph);
        free(entries[i].flip_map);
        free(entries[i].relmse_frames);
        entries[i].label = entries[i].overrides = NULL;
        entries[i].flip_map = NULL;
        entries[i].relmse_frames = NULL;
    }
}

/* Adds `s` to o under `key` with the bytes that are not UTF-8 as U+FFFD,
 * as `compare --json` writes them (util_json_string): for paths and driver
 * strings, so that bench.json, bench.csv and the page stay UTF-8. false
 * after logging if memory runs out. */
static bool add_text(cJSON *o, const char *key, const char *s)
{
    char *t = util_utf8_sanitize(s);
    bool ok = t && cJSON_AddStringToObject(o, key, t);
    if (t && !ok)
        log_error("bench", "out of memory building bench.json");
    free(t);
    return ok;
}

static cJSON *json_num(double v)
{
    return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull();
}

/* What the machine is: the CPU model and its cores (the reference's device;
 * GL's renderer is recorded beside it). */
static void device_name(char *out, size_t cap)
{
    snprintf(out, cap, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, "model name", 10)) {
            char *c = strchr(line, ':');
            if (c) {
                c += 1 + (c[1] == ' ');
                c[strcspn(c, "\n")] = 0;
                snprintf(out, cap, "%s", c);
            }
            break;
        }
    if (f)
        fclose(f);
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    size_t len = strlen(out);
    snprintf(out + len, cap - len, ", %ld cores", n);
}

/* Renders one entry: warm-up, timed frames, read-back. false after logging. */
static bool bench_render(Renderer *r, bool *created, const Scene *scene, BenchEntry *e, int frames)
{
    bool ok = *created ? renderer_apply(r, &e->rs) : renderer_create(r, scene, &e->rs);
    *created = true;
    if (!ok)
        return false;
    renderer_invalidate(r);
    renderer_warm_up(r, &scene->camera, 1); /* compiles, allocates; on a GPU, raises the clocks */
    gpu_timer_reset(&r->timer);
    double t0 = util_seconds();
    for (int f = 0; f < frames; f++)
        renderer_frame(r, &scene->camera);
    e->frame_ms = 1e3 * (util_seconds() - t0) / frames;
    renderer_collect_stats(r);
    e->gpu_ms = 0;
    for (int i = 0; i < r->timer.pass_count; i++)
        e->gpu_ms += r->timer.passes[i].gpu_ms / (r->timer.frames > 0 ? r->timer.frames : 1);
    if (!renderer_frames_whole(r) || !renderer_read_hdr(r, &e->img))
        return false;
    return image_check_finite(&e->img, e->label);
}

static cJSON *entry_json(const BenchEntry *e, const Renderer *r)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "id", e->id);
    cJSON_AddStringToObject(o, "label", e->label);
    cJSON_AddStringToObject(o, "shadow", k_shadow_names[e->shadow]);
    cJSON_AddStringToObject(o, "gi", gi_technique_names()[e->gi]);
    cJSON_AddStringToObject(o, "paper", gi_techniques[e->gi]->paper);
    cJSON_AddStringToObject(o, "overrides", e->overrides);
    cJSON *set = cJSON_AddObjectToObject(o, "settings");
    Settings s = {e->rs.set.shadow, e->rs.set.gi};
    /* Every setting by its name, then again by its old key (gi.samples),
     * which scripts written before the names were unified read. */
    for (int pass = 0; pass < 2; pass++)
        for (int i = 0; i < settings_count; i++) {
            const SettingDesc *d = &settings_table[i];
            const char *key = pass ? settings_old_key(d) : d->name;
            char val[64];
            settings_format(d, &s, val, sizeof val);
            if (key)
                cJSON_AddStringToObject(set, key, val);
        }
    /* The technique's counters of the last frame, per pixel where they are. */
    const RenderStats *st = &r->stats;
    cJSON *passes = cJSON_AddArrayToObject(o, "passes");
    int frames = r->timer.frames > 0 ? r->timer.frames : 1;
    for (int i = 0; i < r->timer.pass_count; i++) {
        cJSON *p = cJSON_CreateObject();
        cJSON_AddStringToObject(p, "name", r->timer.passes[i].name);
        cJSON_AddItemToObject(p, "gpu_ms", json_num(r->timer.passes[i].gpu_ms / frames));
        cJSON_AddItemToObject(p, "wall_ms", json_num(r->timer.sync ? r->timer.passes[i].cpu_ms / frames : NAN));
        /* A gather pass's evaluations in a frame (render --timings'
         * gather_pass_NAME_evaluations): its rate is them over gpu_ms. */
        for (int g = 0; g < st->gather_pass_count; g++)
            if (!strcmp(st->gather_passes[g].name, r->timer.passes[i].name))
                cJSON_AddNumberToObject(p, "evaluations", (double)st->gather_passes[g].evaluations);
        cJSON_AddItemToArray(passes, p);
    }
    cJSON_AddItemToObject(o, "gpu_ms", json_num(e->gpu_ms));
    cJSON_AddItemToObject(o, "frame_ms", json_num(e->frame_ms));
    double px = (double)e->rs.width * e->rs.height;
    cJSON *sj = cJSON_AddObjectToObject(o, "stats");
    cJSON_AddNumberToObject(sj, "vpl_count", st->vpl_count);
    cJSON_AddNumberToObject(sj, "vpl_evaluations_per_pixel", (double)st->vpl_evaluations / px);
    cJSON_AddNumberToObject(sj, "vpl_candidates_per_pixel", (double)st->vpl_candidates / px);
    cJSON_AddNumberToObject(sj, "gather_evaluations_per_pixel", (double)st->gather_evaluations / px);
    cJSON_AddNumberToObject(sj, "gathered_pixels", st->gathered_pixels);
    /* GPU memory the technique counts as its own (render's gi_memory_mib);
     * null where it counts none. */
    cJSON_AddItemToObject(sj, "gi_memory_mib", st->gpu_bytes ? json_num(render_mib(st->gpu_bytes))
                                                              : cJSON_CreateNull());
    /* --gi-visibility's share of gi_memory_mib (null without it). */
    cJSON_AddItemToObject(sj, "visibility_memory_mib", st->visibility_bytes ? json_num(render_mib(st->visibility_bytes))
                                                                            : cJSON_CreateNull());
    /* All of the frame's GPU memory by owner (render --timings' *_memory_mib). */
    RenderMemory mem = renderer_gpu_memory(r);
    cJSON_AddNumberToObject(sj, "light_memory_mib", render_mib(mem.lights));
    cJSON_AddNumberToObject(sj, "frame_memory_mib", render_mib(mem.frame));
    cJSON_AddNumberToObject(sj, "scene_memory_mib", render_mib(mem.scene));
    cJSON_AddNumberToObject(sj, "gpu_memory_mib", render_mib(render_memory_total(&mem)));
    cJSON *m = cJSON_AddObjectToObject(o, "metrics");
    cJSON_AddItemToObject(m, "rmse", json_num(e->rmse));
    cJSON_AddItemToObject(m, "relmse", json_num(e->relmse));
    cJSON_AddItemToObject(m, "ssim", json_num(e->ssim));
    cJSON_AddItemToObject(m, "flip", json_num(e->flip));
    cJSON_AddItemToObject(m, "mean_ratio", json_num(e->mean_ratio));
    cJSON *img = cJSON_AddObjectToObject(o, "images");
    char p[96];
    snprintf(p, sizeof p, "images/%s.png", e->id);
    cJSON_AddStringToObject(img, "png", p);
    snprintf(p, sizeof p, "images/%s.exr", e->id);
    cJSON_AddStringToObject(img, "exr", p);
    snprintf(p, sizeof p, "images/%s_flip.png", e->id);
    cJSON_AddStringToObject(img, "flip_png", p);
    if (e->relmse_frames) { /* --animate */
        cJSON *tj = cJSON_AddObjectToObject(o, "temporal");
        cJSON *per = cJSON_AddArrayToObject(tj, "relmse_per_frame");
        double mean = 0;
        for (int i = 0; i < e->frames; i++) {
            cJSON_AddItemToArray(per, json_num(e->relmse_frames[i]));
            mean += e->relmse_frames[i] / e->frames;
        }
        cJSON_AddItemToObject(tj, "relmse_mean", json_num(mean));
        cJSON_AddItemToObject(tj, "flicker", json_num(e->flicker));
        cJSON_AddItemToObject(tj, "reference_flicker", json_num(e->reference_flicker));
        snprintf(p, sizeof p, "images/%s_kymograph.png", e->id);
        cJSON_AddStringToObject(tj, "kymograph", p);
    }
    return o;
}

static double num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItem(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* The results as a Markdown table (what scripts/bench-*.sh print). */
static void print_markdown(const cJSON *doc)
{
    const cJSON *ref = cJSON_GetObjectItem(doc, "reference");
    int ssaa = (int)num(doc, "ssaa");
    char aa[32] = "";
    if (ssaa > 1)
        snprintf(aa, sizeof aa, ", ssaa %d", ssaa);
    printf("%s, %dx%d%s, reference %s %d spp, %s, %s\n\n", cJSON_GetObjectItem(doc, "scene")->valuestring,
           (int)num(doc, "width"), (int)num(doc, "height"), aa, cJSON_GetObjectItem(ref, "mode")->valuestring,
           (int)num(ref, "spp"), cJSON_GetObjectItem(doc, "gl_renderer")->valuestring,
           cJSON_GetObjectItem(doc, "commit")->valuestring);
    printf("| technique | GPU ms per pass | GPU ms | ms/frame | VPLs | evaluations/pixel | RMSE | relMSE | FLIP | "
           "mean ÷ ref |\n|---|---|---|---|---|---|---|---|---|---|\n");
    const cJSON *e;
    cJSON_ArrayForEach(e, cJSON_GetObjectItem(doc, "techniques")) {
        printf("| %s | ", cJSON_GetObjectItem(e, "label")->valuestring);
        const cJSON *p;
        bool first = true;
        cJSON_ArrayForEach(p, cJSON_GetObjectItem(e, "passes")) {
            printf("%s%s %.1f", first ? "" : ", ", cJSON_GetObjectItem(p, "name")->valuestring, num(p, "gpu_ms"));
            first = false;
        }
        const cJSON *st = cJSON_GetObjectItem(e, "stats"), *m = cJSON_GetObjectItem(e, "metrics");
        double ev = num(st, "vpl_evaluations_per_pixel");
        if (!(ev > 0))
            ev = num(st, "gather_evaluations_per_pixel");
        printf(" | %.1f | %.1f | %.0f | %.0f | %.5f | %.5f | %.4f | %.3f |\n", num(e, "gpu_ms"), num(e, "frame_ms"),
               num(st, "vpl_count"), ev, num(m, "rmse"), num(m, "relmse"), num(m, "flip"), num(m, "mean_ratio"));
    }
    const cJSON *anim = cJSON_GetObjectItem(doc, "animation");
    if (!anim)
        return;
    printf("\nOver the animation's %d frames (the metrics above are its middle frame's):\n\n"
           "| technique | mean relMSE | flicker | reference flicker | ms/frame |\n|---|---|---|---|---|\n",
           (int)num(anim, "frames"));
    cJSON_ArrayForEach(e, cJSON_GetObjectItem(doc, "techniques")) {
        const cJSON *t = cJSON_GetObjectItem(e, "temporal");
        printf("| %s | %.5f | %.5f | %.5f | %.1f |\n", cJSON_GetObjectItem(e, "label")->valuestring,
               num(t, "relmse_mean"), num(t, "flicker"), num(t, "reference_flicker"), num(e, "frame_ms"));
    }
}

/* Writes `text` atomically to DIR/name. */
static bool write_text(const char *dir, const char *name, const char *text)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    AtomicFile af;
    if (!util_atomic_open(&af, "bench", path))
        return false;
    if (fputs(text, af.f) == EOF)
        af.failed = true;
    return util_atomic_commit(&af, "bench");
}

/* CSV (RFC 4180): every text field quoted, its quotes doubled; numbers as
 * %.9g, empty where bench.json has null. Each file's columns are a table
 * of where in bench.json a field comes from, so a header and its rows are
 * one list. */
typedef enum CsvFrom { FROM_DOC, FROM_REFERENCE, FROM_TECHNIQUE, FROM_STATS, FROM_METRICS, FROM_TEMPORAL, FROM_PASS } CsvFrom;

typedef struct CsvColumn {
    const char *name;
    CsvFrom from;
    const char *key; /* NULL: the name */
    bool text;
} CsvColumn;

static const CsvColumn k_csv_techniques[] = {
    {"commit", FROM_DOC, NULL, true},
    {"scene", FROM_DOC, NULL, true},
    {"width", FROM_DOC, NULL, false},
    {"height", FROM_DOC, NULL, false},
    {"ssaa", FROM_DOC, NULL, false},
    {"reference_mode", FROM_REFERENCE, "mode", true},
    {"reference_spp", FROM_REFERENCE, "spp", false},
    {"gl_renderer", FROM_DOC, NULL, true},
    {"id", FROM_TECHNIQUE, NULL, true},
    {"label", FROM_TECHNIQUE, NULL, true},
    {"shadow", FROM_TECHNIQUE, NULL, true},
    {"gi", FROM_TECHNIQUE, NULL, true},
    {"overrides", FROM_TECHNIQUE, NULL, true},
    {"gpu_ms", FROM_TECHNIQUE, NULL, false},
    {"frame_ms", FROM_TECHNIQUE, NULL, false},
    {"vpl_count", FROM_STATS, NULL, false},
    {"vpl_evaluations_per_pixel", FROM_STATS, NULL, false},
    {"gather_evaluations_per_pixel", FROM_STATS, NULL, false},
    {"gi_memory_mib", FROM_STATS, NULL, false},
    {"light_memory_mib", FROM_STATS, NULL, false},
    {"frame_memory_mib", FROM_STATS, NULL, false},
    {"scene_memory_mib", FROM_STATS, NULL, false},
    {"gpu_memory_mib", FROM_STATS, NULL, false},
    {"rmse", FROM_METRICS, NULL, false},
    {"relmse", FROM_METRICS, NULL, false},
    {"ssim", FROM_METRICS, NULL, false},
    {"flip", FROM_METRICS, NULL, false},
    {"mean_ratio", FROM_METRICS, NULL, false},
    {"relmse_mean", FROM_TEMPORAL, NULL, false}, /* --animate: empty without it */
    {"flicker", FROM_TEMPORAL, NULL, false},
    {"reference_flicker", FROM_TEMPORAL, NULL, false},
};

static const CsvColumn k_csv_passes[] = {
    {"id", FROM_TECHNIQUE, NULL, true},
    {"label", FROM_TECHNIQUE, NULL, true},
    {"pass", FROM_PASS, "name", true},
    {"gpu_ms", FROM_PASS, NULL, false},
    {"wall_ms", FROM_PASS, NULL, false},
};

static void csv_header(StrBuf *b, const CsvColumn *cols, int n)
{
    for (int i = 0; i < n; i++)
        strbuf_printf(b, "%s%s", cols[i].name, i + 1 < n ? "," : "\r\n");
}

/* One row; `objects` indexed by CsvFrom. */
static void csv_row(StrBuf *b, const CsvColumn *cols, int n, const cJSON *const objects[])
{
    for (int i = 0; i < n; i++) {
        const cJSON *v = cJSON_GetObjectItem(objects[cols[i].from], cols[i].key ? cols[i].key : cols[i].name);
        if (cols[i].text) {
            strbuf_append(b, "\"", 1);
            for (const char *p = cJSON_IsString(v) ? v->valuestring : ""; *p; p++)
                if (*p == '"')
                    strbuf_append(b, "\"\"", 2);
                else
                    strbuf_append(b, p, 1);
            strbuf_append(b, "\"", 1);
        } else if (cJSON_IsNumber(v)) {
            strbuf_printf(b, "%.9g", v->valuedouble);
        }
        strbuf_append(b, i + 1 < n ? "," : "\r\n", i + 1 < n ? 1 : 2);
    }
}

/* bench.csv: one row per technique, the run's facts repeated on each so
 * that runs concatenate; bench_passes.csv: one row per technique and pass. */
static bool write_csv(const char *dir, const cJSON *doc)
{
    enum { NT = sizeof k_csv_techniques / sizeof k_csv_techniques[0], NP = sizeof k_csv_passes / sizeof k_csv_passes[0] };
    StrBuf t = {0}, p = {0};
    csv_header(&t, k_csv_techniques, NT);
    csv_header(&p, k_csv_passes, NP);
    const cJSON *e, *pass;
    cJSON_ArrayForEach(e, cJSON_GetObjectItem(doc, "techniques")) {
        const cJSON *objects[] = {doc, cJSON_GetObjectItem(doc, "reference"), e, cJSON_GetObjectItem(e, "stats"),
                                  cJSON_GetObjectItem(e, "metrics"), cJSON_GetObjectItem(e, "temporal"), NULL};
        csv_row(&t, k_csv_techniques, NT, objects);
        cJSON_ArrayForEach(pass, cJSON_GetObjectItem(e, "passes")) {
            objects[FROM_PASS] = pass;
            csv_row(&p, k_csv_passes, NP, objects);
        }
    }
    bool ok = !t.failed && !p.failed && write_text(dir, "bench.csv", t.data) &&
              write_text(dir, "bench_passes.csv", p.data);
    free(t.data);
    free(p.data);
    return ok;
}


/* Parses argv into *args. 0: go on; -1: --help was shown; else an exit
 * status (2 for usage), after logging. */
static int bench_parse_args(int argc, char **argv, BenchArgs *args)
{
    bench_args_default(args);
    int rc = options_parse(argc, argv,
                           &(OptionSet){.tables = (const OptionDesc *const[]){k_bench_options, NULL},
                                        .set = &args->base, .given = args->base_given, .help = cmd_bench_help},
                           args);
    if (rc)
        return rc;
    if (!args->out) {
        usage_error(NULL, "--out DIR is required");
        return 2;
    }
    if (args->fps > 0 && !args->animate) {
        usage_error(NULL, "--fps: needs --animate");
        return 2;
    }
    if (args->animate && args->frames < 3) {
        usage_error(NULL, "--animate --frames %d: flicker needs at least 3 frames", args->frames);
        return 2;
    }
    if (strlen(args->out) > BENCH_MAX_DIR) {
        usage_error(NULL, "--out: DIR is longer than %d bytes", BENCH_MAX_DIR);
        return 2;
    }
    if (!render_options_ssaa_fits(args->width, args->height, args->ssaa))
        return 2;
    args->ps.width = args->width;
    args->ps.height = args->height;
    args->ps.progress = log_get_level() <= LOG_INFO;
    return 0;
}

/* What every entry is measured against (bench_reference_free frees it). */
typedef struct BenchReference {
    ImageF img;              /* the path-traced reference */
    char path[1400];         /* its file in the cache */
    bool reused;             /* read from the cache, not rendered */
    uint8_t *mask;           /* a byte per pixel, non-zero where no emitter is seen: the pixels measured */
    size_t masked;           /* pixels left out (they see an emitter) */
    float metric_exposure;   /* of FLIP and SSIM */
    double display_exposure; /* of the PNGs and the page */
    /* --animate: the sequence (img and mask above are its middle frame's). */
    int frames;              /* 0 without --animate */
    ImageF *seq;             /* [frames] the reference of every frame */
    uint8_t **seq_mask;      /* [frames] the pixels measured in each (no emitter seen) */
    int mid;                 /* the middle frame */
    int kymograph_row;       /* the row the kymographs show */
    double flicker;          /* the reference's own (its noise: the floor) */
    ImageF kymograph;
} BenchReference;

static void bench_reference_free(BenchReference *ref)
{
    image_free(&ref->img);
    free(ref->mask);
    ref->mask = NULL;
    for (int i = 0; i < ref->frames; i++) {
        if (ref->seq)
            image_free(&ref->seq[i]);
        if (ref->seq_mask)
            free(ref->seq_mask[i]);
    }
    free(ref->seq);
    free(ref->seq_mask);
    ref->seq = NULL;
    ref->seq_mask = NULL;
    ref->frames = 0;
    image_free(&ref->kymograph);
}

/* ---- --animate (issue 50): the reference of every frame ---------------- */

/* The time of frame i. */
static double frame_time(const BenchArgs *args, const Scene *scene, int i)
{
    return animation_frame_time(scene, i, args->frames, args->fps);
}

/* Every frame's reference (cached per frame: the cache key is the scene's
 * state), its emitter mask, the reference's flicker and kymograph, and its
 * kymograph PNG into images_dir; the scene is left at the middle frame,
 * whose reference bench_prepare_reference then reads back as the one the
 * still metrics use. false after logging. */
static bool bench_prepare_sequence(const BenchArgs *args, Scene *scene, const char *images_dir, BenchReference *ref)
{
    int n = args->frames;
    size_t np = (size_t)args->width * args->height;
    if (!animation_check_frames(scene, n, args->fps, "--animate"))
        return false;
    ref->seq = util_calloc("bench", "the reference sequence", (size_t)n, sizeof(ImageF));
    ref->seq_mask = util_calloc("bench", "the reference sequence", (size_t)n, sizeof(uint8_t *));
    if (!ref->seq || !ref->seq_mask)
        return false;
    ref->frames = n;
    ref->mid = n / 2;
    ref->kymograph_row = args->height / 2;
    if (!image_alloc(&ref->kymograph, args->width, n))
        return false;
    FlickerSum fl = {0};
    bool ok = true, all_reused = true;
    for (int i = 0; i < n && ok; i++) {
        animation_apply(scene, frame_time(args, scene, i), NULL);
        char path[1400];
        bool reused = false;
        log_info("bench", "reference frame %d of %d (t = %.4g s)", i + 1, n, frame_time(args, scene, i));
        ok = get_reference(scene, &args->ps, args->cache, &ref->seq[i], path, sizeof path, &reused) &&
             (ref->seq_mask[i] = util_malloc("bench", "the emitter mask", np, 1)) != NULL &&
             pt_emitter_mask(scene, args->width, args->height, ref->seq_mask[i]);
        all_reused = all_reused && reused;
        if (ok) {
            flicker_add(&fl, &ref->seq[i], ref->seq_mask[i]);
            kymograph_add(&ref->kymograph, i, &ref->seq[i], ref->kymograph_row);
        }
    }
    ref->flicker = flicker_value(&fl);
    flicker_free(&fl);
    animation_apply(scene, frame_time(args, scene, ref->mid), NULL);
    if (!ok)
        return false;
    log_info("bench", "reference flicker %.5f over %d frames%s", ref->flicker, n,
             all_reused ? " (every frame from the cache)" : "");
    return true;
}

/* The reference (cached or rendered), the emitter mask and the exposures
 * into *ref, and the reference's EXR and PNG into images_dir. false after
 * logging; *ref then holds what was made (bench_reference_free). */
static bool bench_prepare_reference(const BenchArgs *args, const Scene *scene, const char *images_dir,
                                    BenchReference *ref)
{
    if (!get_reference(scene, &args->ps, args->cache, &ref->img, ref->path, sizeof ref->path, &ref->reused))
        return false;
    size_t np = (size_t)args->width * args->height;
    if (!(ref->mask = util_malloc("bench", "the emitter mask", np, 1)) ||
        !pt_emitter_mask(scene, args->width, args->height, ref->mask))
        return false;
    size_t selected = 0;
    for (size_t i = 0; i < np; i++)
        selected += ref->mask[i] != 0;
    if (!selected) {
        log_error("bench", "%s: every pixel sees an emitter: nothing to measure", scene->source);
        return false;
    }
    ref->masked = np - selected;
    ref->metric_exposure = args->exposure >= 0.f ? args->exposure : scene->exposure;
    ref->display_exposure = report_display_exposure(&ref->img, ref->mask);
    if (!(ref->display_exposure > 0))
        ref->display_exposure = ref->metric_exposure;
    char p[1400];
    snprintf(p, sizeof p, "%s/reference.exr", images_dir);
    if (!image_write_exr(p, &ref->img, false, NULL, 0))
        return false;
    snprintf(p, sizeof p, "%s/reference.png", images_dir);
    if (!image_write_png(p, &ref->img, (float)ref->display_exposure))
        return false;
    snprintf(p, sizeof p, "%s/reference_kymograph.png", images_dir);
    return !ref->frames || image_write_png(p, &ref->kymograph, (float)ref->display_exposure);
}

/* The entry's render settings: the scene's, the command line's base
 * settings over them, the entry's own over those. */
static void entry_render_settings(const BenchArgs *args, const Scene *scene, BenchEntry *e)
{
    RenderOptions o;
    render_options_init(&o, false);
    o.width = args->width;
    o.height = args->height;
    o.ssaa = args->ssaa;
    o.shadow = e->shadow;
    o.gi = e->gi;
    o.timings = true;
    o.set = args->base;
    memcpy(o.given, args->base_given, sizeof o.given);
    for (int k = 0; k < settings_count; k++)
        if (e->given[k]) {
            settings_copy(&settings_table[k], &o.set, &e->set);
            o.given[k] = true;
        }
    render_options_settings(&o, scene, &e->rs);
}

/* Renders one entry (bench_render), measures it against the reference and
 * writes its EXR, PNG and FLIP map into images_dir. false after logging. */
/* --animate: renders the entry over the sequence, light products cached
 * (what a moved light or object invalidates is redrawn, the rest kept, as
 * in the window): one warm-up frame at the first frame's time, then every
 * frame timed (wall time with glFinish), read back and measured against
 * its reference; e->img is the middle frame. false after logging. */
static bool bench_render_sequence(Renderer *r, bool *created, const BenchArgs *args, Scene *scene,
                                  const BenchReference *ref, BenchEntry *e)
{
    int n = args->frames;
    e->rs.cache = true;
    SceneChange c;
    animation_apply(scene, frame_time(args, scene, 0), &c);
    if (*created && !renderer_scene_changed(r, &c))
        return false;
    bool ok = *created ? renderer_apply(r, &e->rs) : renderer_create(r, scene, &e->rs);
    *created = true;
    e->frames = n;
    if (!ok || !(e->relmse_frames = util_calloc("bench", "the per-frame errors", (size_t)n, sizeof(double))) ||
        !image_alloc(&e->kymograph, args->width, n))
        return false;
    renderer_invalidate(r);
    renderer_warm_up(r, &scene->camera, 1); /* compiles, allocates; on a GPU, raises the clocks */
    pass_temporal_reset(&r->pass_temporal); /* the sequence starts without history */
    gpu_timer_reset(&r->timer);
    FlickerSum fl = {0};
    double wall = 0;
    ImageF img = {0};
    for (int i = 0; i < n && ok; i++) {
        animation_apply(scene, frame_time(args, scene, i), &c);
        double t0 = util_seconds();
        ok = renderer_scene_changed(r, &c);
        if (ok)
            renderer_frame(r, &scene->camera);
        glFinish();
        wall += util_seconds() - t0;
        ok = ok && renderer_frames_whole(r) && renderer_read_hdr(r, &img) && image_check_finite(&img, e->label);
        if (!ok)
            break;
        e->relmse_frames[i] = metric_relmse(&img, &ref->seq[i], ref->seq_mask[i], NULL);
        flicker_add(&fl, &img, ref->seq_mask[i]);
        kymograph_add(&e->kymograph, i, &img, ref->kymograph_row);
        if (i == ref->mid) {
            e->img = img; /* kept: the still metrics' image */
            img = (ImageF){0};
        }
        image_free(&img);
    }
    image_free(&img);
    e->flicker = flicker_value(&fl);
    flicker_free(&fl);
    if (!ok)
        return false;
    e->frame_ms = 1e3 * wall / n;
    renderer_collect_stats(r);
    e->gpu_ms = 0;
    for (int i = 0; i < r->timer.pass_count; i++)
        e->gpu_ms += r->timer.passes[i].gpu_ms / (r->timer.frames > 0 ? r->timer.frames : 1);
    return true;
}

static bool bench_run_entry(Renderer *r, bool *created, const BenchArgs *args, Scene *scene,
                            const BenchReference *ref, const char *images_dir, BenchEntry *e)
{
    size_t np = (size_t)args->width * args->height;
    const uint8_t *mask = ref->mask;
    entry_render_settings(args, scene, e);
    if (!(args->animate ? bench_render_sequence(r, created, args, scene, ref, e)
                        : bench_render(r, created, scene, e, args->frames)))
        return false;
    if (!(e->flip_map = util_malloc("bench", "the FLIP map", np, sizeof(float))))
        return false;
    e->rmse = metric_rmse(&e->img, &ref->img, mask, NULL);
    e->relmse = metric_relmse(&e->img, &ref->img, mask, NULL);
    e->ssim = metric_ssim(&e->img, &ref->img, ref->metric_exposure, mask, NULL);
    e->flip = metric_flip(&e->img, &ref->img, ref->metric_exposure, FLIP_DEFAULT_PPD, mask, e->flip_map);
    e->mean_ratio = metric_mean_ratio(&e->img, &ref->img, mask, NULL);
    if (metric_alloc_failures())
        return false;
    for (size_t k = 0; k < np; k++) /* the masked pixels show as zero error */
        if (!mask[k])
            e->flip_map[k] = 0.f;
    char p[1400];
    snprintf(p, sizeof p, "%s/%s.exr", images_dir, e->id);
    if (!image_write_exr(p, &e->img, false, NULL, 0))
        return false;
    snprintf(p, sizeof p, "%s/%s.png", images_dir, e->id);
    if (!image_write_png(p, &e->img, (float)ref->display_exposure))
        return false;
    snprintf(p, sizeof p, "%s/%s_flip.png", images_dir, e->id);
    if (!metric_write_heatmap(p, e->flip_map, args->width, args->height))
        return false;
    log_info("bench", "  %.2f ms/frame (GPU %.2f ms), relmse %.5f, flip %.4f, mean ratio %.3f", e->frame_ms,
             e->gpu_ms, e->relmse, e->flip, e->mean_ratio);
    if (!args->animate)
        return true;
    double mean = 0;
    for (int i = 0; i < args->frames; i++)
        mean += e->relmse_frames[i] / args->frames;
    e->reference_flicker = ref->flicker;
    log_info("bench", "  over %d frames: mean relmse %.5f, flicker %.5f (reference %.5f)", args->frames, mean,
             e->flicker, ref->flicker);
    snprintf(p, sizeof p, "%s/%s_kymograph.png", images_dir, e->id);
    return image_write_png(p, &e->kymograph, (float)ref->display_exposure);
}

/* bench.json's facts of the run, with an empty "techniques" array for
 * entry_json's objects. NULL after logging. */
static cJSON *bench_doc_create(const BenchArgs *args, const Scene *scene, const GlContext *gl,
                               const BenchReference *ref)
{
    cJSON *doc = cJSON_CreateObject();
    cJSON_AddNumberToObject(doc, "schema", 1);
    cJSON_AddStringToObject(doc, "commit", RTGI_VERSION);
    char date[64];
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", gmtime(&now));
    cJSON_AddStringToObject(doc, "date", date);
    char dev[256];
    device_name(dev, sizeof dev);
    if (!add_text(doc, "device", dev) || !add_text(doc, "gl_renderer", gl_context_renderer(gl)) ||
        !add_text(doc, "scene", scene->source)) {
        cJSON_Delete(doc);
        return NULL;
    }
    cJSON_AddNumberToObject(doc, "width", args->width);
    cJSON_AddNumberToObject(doc, "height", args->height);
    cJSON_AddNumberToObject(doc, "frames", args->frames);
    cJSON_AddNumberToObject(doc, "ssaa", args->ssaa);
    cJSON *rj = cJSON_AddObjectToObject(doc, "reference");
    cJSON_AddStringToObject(rj, "mode", pt_mode_names[args->ps.mode]);
    cJSON_AddNumberToObject(rj, "spp", args->ps.spp);
    if (!add_text(rj, "cache", ref->path)) {
        cJSON_Delete(doc);
        return NULL;
    }
    cJSON_AddBoolToObject(rj, "reused", ref->reused);
    cJSON_AddStringToObject(rj, "png", "images/reference.png");
    cJSON_AddStringToObject(rj, "exr", "images/reference.exr");
    cJSON_AddNumberToObject(doc, "spp", args->ps.spp);
    cJSON_AddNumberToObject(doc, "metric_exposure", ref->metric_exposure);
    cJSON_AddNumberToObject(doc, "display_exposure", ref->display_exposure);
    cJSON_AddNumberToObject(doc, "masked_pixels", (double)ref->masked);
    if (ref->frames) { /* --animate */
        cJSON *aj = cJSON_AddObjectToObject(doc, "animation");
        cJSON_AddNumberToObject(aj, "frames", ref->frames);
        cJSON_AddItemToObject(aj, "fps", args->fps > 0 ? cJSON_CreateNumber(args->fps) : cJSON_CreateNull());
        cJSON_AddNumberToObject(aj, "duration", animation_duration(scene));
        cJSON *times = cJSON_AddArrayToObject(aj, "times");
        for (int i = 0; i < ref->frames; i++)
            cJSON_AddItemToArray(times, cJSON_CreateNumber(frame_time(args, scene, i)));
        cJSON_AddNumberToObject(aj, "middle_frame", ref->mid);
        cJSON_AddItemToObject(aj, "reference_flicker", json_num(ref->flicker));
        cJSON_AddNumberToObject(aj, "kymograph_row", ref->kymograph_row);
        cJSON_AddStringToObject(aj, "reference_kymograph", "images/reference_kymograph.png");
    }
    cJSON_AddStringToObject(doc, "timing",
                            "gpu_ms: timer queries; wall_ms: glFinish around each pass; frame_ms: wall "
                            "time per frame; means over the timed frames after one warm-up frame");
    cJSON_AddArrayToObject(doc, "techniques");
    return doc;
}

/* bench.json, bench.csv, bench_passes.csv and report.html into the
 * staging directory `stage`. false after logging. */
static bool bench_write_outputs(const char *stage, const cJSON *doc, const BenchReference *ref,
                                const BenchEntry *entries, int n)
{
    char *text = cJSON_Print(doc);
    bool ok = text && write_text(stage, "bench.json", text) && write_csv(stage, doc);
    free(text);
    if (!ok)
        return false;
    ReportImage imgs[2 * (BENCH_MAX_ENTRIES + 1)];
    char kymo_ids[BENCH_MAX_ENTRIES][64];
    int k = 0;
    imgs[k++] = (ReportImage){"reference", &ref->img, NULL};
    for (int i = 0; i < n; i++)
        imgs[k++] = (ReportImage){entries[i].id, &entries[i].img, entries[i].flip_map};
    if (ref->frames) { /* --animate: the kymographs, "<id>_kymograph" */
        imgs[k++] = (ReportImage){"reference_kymograph", &ref->kymograph, NULL};
        for (int i = 0; i < n; i++) {
            snprintf(kymo_ids[i], sizeof kymo_ids[i], "%s_kymograph", entries[i].id);
            imgs[k++] = (ReportImage){kymo_ids[i], &entries[i].kymograph, NULL};
        }
    }
    char p[1400];
    snprintf(p, sizeof p, "%s/report.html", stage);
    return report_html_write(p, doc, imgs, k);
}

int cmd_bench(int argc, char **argv)
{
    BenchArgs args;
    int rc = bench_parse_args(argc, argv, &args);
    if (rc != 0)
        return rc < 0 ? 0 : rc;
    /* The entries: every shadow × every GI item. */
    static BenchEntry entries[BENCH_MAX_ENTRIES];
    int n = 0;
    if (!parse_entries(args.shadow_list, args.gi_list, entries, &n)) {
        entries_free(entries, n);
        return 2;
    }
    Scene scene;
    if (!scene_load_scaled(&scene, args.scene_name, -1.f)) {
        entries_free(entries, n);
        return 1;
    }
    /* DIR/images, what is written into the staging directory, and whether
     * this run made DIR and DIR/images (a failed one removes them). */
    const char *out = args.out;
    char out_images[1100], stage[1100] = "", images_dir[1100];
    snprintf(out_images, sizeof out_images, "%s/images", out);
    bool made_out = !path_exists(out), made_images = !path_exists(out_images);
    rc = 1;
    BenchReference ref = {0};
    GlContext *gl = NULL;
    Renderer r;
    bool created = false;
    cJSON *doc = NULL;
    /* Ctrl-C or SIGTERM before the outputs are moved into DIR leaves no
     * staging directory behind, nor a DIR that this run made: one that
     * comes while they are made waits until they are registered. */
    util_defer_ending_signals();
    bool staged = make_dir(args.cache) && make_dir(out) && stage_open(out, stage, sizeof stage);
    if (made_out && path_exists(out))
        util_live_dir_add(out, false);
    if (stage[0])
        util_live_dir_add(stage, true);
    util_end_deferral();
    if (!staged)
        goto done; /* a bad --cache leaves no DIR */
    snprintf(images_dir, sizeof images_dir, "%s/images", stage);
    if ((args.animate && !bench_prepare_sequence(&args, &scene, images_dir, &ref)) ||
        !bench_prepare_reference(&args, &scene, images_dir, &ref) || !(gl = gl_context_create(false)) ||
        !(doc = bench_doc_create(&args, &scene, gl, &ref)))
        goto done;
    for (int i = 0; i < n; i++) {
        log_info("bench", "[%d/%d] %s", i + 1, n, entries[i].label);
        if (!bench_run_entry(&r, &created, &args, &scene, &ref, images_dir, &entries[i]))
            goto done;
        /* The timings of this entry go into the JSON now: the renderer's
         * timer is reset by the next one. */
        cJSON_AddItemToArray(cJSON_GetObjectItem(doc, "techniques"), entry_json(&entries[i], &r));
    }
    if (!bench_write_outputs(stage, doc, &ref, entries, n))
        goto done;
    warn_if_replacing(out);
    if (!stage_commit(stage, out))
        goto done;
    if (args.markdown)
        print_markdown(doc);
    rc = 0;
    log_info("bench", "wrote %s/bench.json, %s/report.html and %s/bench.csv (%d techniques)", out, out, out, n);
done:
    util_live_dir_remove(stage);
    util_live_dir_remove(out);
    if (stage[0])
        stage_remove(stage);
    if (rc != 0 && made_images)
        rmdir(out_images);
    if (rc != 0 && made_out)
        rmdir(out);
    if (created)
        renderer_destroy(&r);
    gl_context_destroy(gl);
    entries_free(entries, n);
    cJSON_Delete(doc);
    bench_reference_free(&ref);
    scene_free(&scene);
    return rc;
}
