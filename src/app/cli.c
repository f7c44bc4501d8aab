#include "app/cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/log.h"
#include "core/scene.h"
#include "base/util.h"

/* The options every command takes, handled by cli_next (log_option). */
static const char *const k_common_options[] = {"--quiet", "--verbose", NULL};

/* --quiet: errors only (no info or progress lines); --verbose: debug lines. */
static void log_option(const char *opt)
{
    log_set_level(!strcmp(opt, "--quiet") ? LOG_ERROR : LOG_DEBUG);
}

int cli_choice(const char *opt, const char *v, const char *const *names)
{
    int index = -1;
    ValueSpec spec = {VALUE_CHOICE, 0, 0, 0, 0, names, NULL};
    return value_parse_text(&spec, opt, v, &index) ? index : -1;
}

bool cli_scene(const char *opt, const char *v)
{
    const char *near = scene_builtin_near(v);
    if (near)
        usage_error(near, "%s: '%s' is no file and no built-in scene", opt, v);
    return near == NULL;
}

void cli_unknown_option(const char *opt, const char *const *known)
{
    const char *near = known ? util_nearest(opt, known) : NULL;
    const char *common = util_nearest(opt, k_common_options);
    if (common && (!near || util_edit_distance(opt, common) < util_edit_distance(opt, near)))
        near = common;
    usage_error(near, "unknown option '%s'", opt);
}

const char *cli_next(CliArgs *a)
{
    for (;;) {
        if (a->pending) {
            usage_error(NULL, "%s takes no value, given '%s'", a->opt, a->pending);
            a->failed = true;
            return NULL;
        }
        if (!a->ended && a->i < a->argc && !strcmp(a->argv[a->i], "--")) {
            a->ended = true; /* the end of the options */
            a->i++;
        }
        if (a->failed || a->i >= a->argc)
            return NULL;
        a->opt = a->argv[a->i++];
        a->is_operand = a->ended || a->opt[0] != '-' || !a->opt[1];
        if (a->is_operand) {
            if (a->operands)
                return a->opt;
            usage_error(NULL, "unexpected argument '%s': options start with --", a->opt);
            a->failed = true;
            return NULL;
        }
        const char *eq = strncmp(a->opt, "--", 2) == 0 ? strchr(a->opt, '=') : NULL;
        if (eq) {
            size_t n = (size_t)(eq - a->opt);
            if (n >= sizeof a->optbuf) {
                usage_error(NULL, "'%.40s...': option name too long", a->opt);
                a->failed = true;
                return NULL;
            }
            memcpy(a->optbuf, a->opt, n);
            a->optbuf[n] = 0;
            a->pending = eq + 1;
            a->opt = a->optbuf;
        }
        if (strcmp(a->opt, "--quiet") && strcmp(a->opt, "--verbose"))
            return a->opt;
        if (!a->pending) /* --quiet, --verbose: taken here */
            log_option(a->opt);
    }
}

const char *cli_value(CliArgs *a)
{
    if (a->pending) {
        const char *v = a->pending;
        a->pending = NULL;
        return v;
    }
    if (a->i >= a->argc) {
        usage_error(NULL, "%s needs a value", a->opt);
        return NULL;
    }
    return a->argv[a->i++];
}

/* Whether a and b name one file: the same string, or one existing file. */
static bool same_file(const char *a, const char *b)
{
    if (strcmp(a, b) == 0)
        return true;
    struct stat sa, sb;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int cli_check_files(int n, int outputs, const char *const opts[], const char *const paths[])
{
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            if (paths[i] && paths[j] && strcmp(paths[i], "-") && (i < outputs || j < outputs) &&
                same_file(paths[i], paths[j])) {
                usage_error(NULL, "%s and %s name the same file, %s", opts[i], opts[j], paths[j]);
                return 2;
            }
    for (int i = 0; i < outputs; i++) {
        if (!paths[i] || !strcmp(paths[i], "-")) /* -: standard output */
            continue;
        /* The writers' own temporary file, created and removed: what the
         * write will meet, permissions as the kernel applies them (root
         * included); directories, devices and FIFOs refused. */
        AtomicFile af; /* tagged with the command: it is the output's problem, not the command line's */
        if (!util_atomic_open(&af, usage_command(), paths[i]))
            return 1;
        util_atomic_abort(&af);
    }
    return 0;
}
