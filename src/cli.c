#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "util.h"

bool cli_float(const char *opt, const char *v, float lo, float hi, float *out)
{
    char *end = NULL;
    errno = 0;
    double d = strtod(v, &end);
    if (end == v || *end || errno || !isfinite(d)) {
        log_error("cli", "%s: '%s' is not a number", opt, v);
        return false;
    }
    if (d < lo || d > hi) {
        log_error("cli", "%s: %s is out of range [%g, %g]", opt, v, (double)lo, (double)hi);
        return false;
    }
    *out = (float)d;
    return true;
}

bool cli_int(const char *opt, const char *v, int lo, int hi, int *out)
{
    char *end = NULL;
    errno = 0;
    long n = strtol(v, &end, 10);
    if (end == v || *end || errno) {
        log_error("cli", "%s: '%s' is not an integer", opt, v);
        return false;
    }
    if (n < lo || n > hi) {
        log_error("cli", "%s: %s is out of range [%d, %d]", opt, v, lo, hi);
        return false;
    }
    *out = (int)n;
    return true;
}

bool cli_size(const char *opt, const char *v, int max, int *w, int *h)
{
    char *end = NULL;
    long a = strtol(v, &end, 10);
    long b = (end && (*end == 'x' || *end == 'X')) ? strtol(end + 1, &end, 10) : -1;
    if (b < 0 || *end) {
        log_error("cli", "%s: '%s' is not a size WxH (e.g. 512x512)", opt, v);
        return false;
    }
    if (a < 1 || b < 1 || a > max || b > max) {
        log_error("cli", "%s: %s: width and height must be between 1 and %d", opt, v, max);
        return false;
    }
    *w = (int)a;
    *h = (int)b;
    return true;
}

int cli_choice(const char *opt, const char *v, const char *const *names)
{
    for (int i = 0; names[i]; i++)
        if (strcmp(v, names[i]) == 0)
            return i;
    char list[256] = "";
    for (int i = 0; names[i]; i++) {
        strncat(list, names[i], sizeof list - strlen(list) - 1);
        if (names[i + 1])
            strncat(list, "|", sizeof list - strlen(list) - 1);
    }
    const char *near = util_nearest(v, names);
    if (near)
        log_error("cli", "%s: unknown value '%s'; did you mean '%s'? (one of %s)", opt, v, near, list);
    else
        log_error("cli", "%s: unknown value '%s' (one of %s)", opt, v, list);
    return -1;
}

void cli_unknown_option(const char *cmd, const char *opt, const char *const *known)
{
    const char *near = known ? util_nearest(opt, known) : NULL;
    if (near)
        log_error("cli", "%s: unknown option '%s'; did you mean '%s'? (see rtgi %s --help)", cmd, opt, near, cmd);
    else
        log_error("cli", "%s: unknown option '%s' (see rtgi %s --help)", cmd, opt, cmd);
}

const char *cli_next(CliArgs *a)
{
    if (a->pending) {
        log_error("cli", "%s takes no value (given '%s')", a->opt, a->pending);
        a->failed = true;
        return NULL;
    }
    if (a->failed || a->i >= a->argc)
        return NULL;
    a->opt = a->argv[a->i++];
    const char *eq = strncmp(a->opt, "--", 2) == 0 ? strchr(a->opt, '=') : NULL;
    if (eq) {
        size_t n = (size_t)(eq - a->opt);
        if (n >= sizeof a->optbuf) {
            log_error("cli", "'%.40s...': option name too long", a->opt);
            a->failed = true;
            return NULL;
        }
        memcpy(a->optbuf, a->opt, n);
        a->optbuf[n] = 0;
        a->pending = eq + 1;
        a->opt = a->optbuf;
    }
    return a->opt;
}

const char *cli_value(CliArgs *a)
{
    if (a->pending) {
        const char *v = a->pending;
        a->pending = NULL;
        return v;
    }
    if (a->i >= a->argc) {
        log_error("cli", "%s needs a value", a->opt);
        return NULL;
    }
    return a->argv[a->i++];
}
