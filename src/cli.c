#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"

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
    log_error("cli", "%s: unknown value '%s' (one of %s)", opt, v, list);
    return -1;
}

const char *cli_next(CliArgs *a)
{
    if (a->i >= a->argc)
        return NULL;
    a->opt = a->argv[a->i++];
    return a->opt;
}

const char *cli_value(CliArgs *a)
{
    if (a->i >= a->argc) {
        log_error("cli", "%s needs a value", a->opt);
        return NULL;
    }
    return a->argv[a->i++];
}
