/* cli.h — strict parsing of command-line values. Each returns false after
 * logging one line that names the option and the bad value. */
#ifndef RTGI_CLI_H
#define RTGI_CLI_H

#include <stdbool.h>

bool cli_float(const char *opt, const char *v, float lo, float hi, float *out);
bool cli_int(const char *opt, const char *v, int lo, int hi, int *out);
/* "WxH", each in [1, max]. */
bool cli_size(const char *opt, const char *v, int max, int *w, int *h);
/* Index of `v` in the NULL-terminated `names`, or -1 after logging. */
int cli_choice(const char *opt, const char *v, const char *const *names);

/* Iterates argv: cli_next returns the next option name (or NULL at the end,
 * or after logging an error: check cli_failed) and cli_value its argument
 * (NULL after logging if missing). Both "--opt value" and "--opt=value"
 * work; "=value" on an option that takes none is an error. */
typedef struct CliArgs {
    int argc;
    char **argv;
    int i;
    const char *opt;     /* current option */
    const char *pending; /* the value of "--opt=value", not yet taken */
    bool failed;         /* cli_next stopped on an error (logged) */
    char optbuf[64];     /* the option part of "--opt=value" */
} CliArgs;
const char *cli_next(CliArgs *a);
const char *cli_value(CliArgs *a);
/* true if the iteration stopped on an error (already logged). */
static inline bool cli_failed(const CliArgs *a) { return a->failed; }
/* Logs "<cmd>: unknown option '<opt>'; did you mean '<nearest>'? (see rtgi
 * <cmd> --help)", the nearest of the NULL-terminated `known` if one is near. */
void cli_unknown_option(const char *cmd, const char *opt, const char *const *known);

/* Inside an option loop: fetch the option's value into `v`, or return 2
 * (usage error, already logged) from the enclosing function. */
#define CLI_VALUE(args, v)            \
    if (!((v) = cli_value(args)))     \
        return 2;

#endif
