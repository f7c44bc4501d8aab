/* cli.h — strict parsing of command-line values, and the one style of
 * usage errors every command shares:
 *   "<command>: <what>; did you mean '<near>'? (see rtgi <command> --help)"
 * Each parser returns false (or -1, NULL) after logging one such line that
 * names the option and the bad value; the command then exits 2. */
#ifndef RTGI_CLI_H
#define RTGI_CLI_H

#include <stdbool.h>

#include "base/usage.h"
#include "base/value.h"

/* Index of `v` in the NULL-terminated `names`, or -1 after logging (with
 * the choices and the nearest one). */
int cli_choice(const char *opt, const char *v, const char *const *names);
/* --scene's value: false after logging when it is a bare name (no '/' or
 * '.') that is no file but near a built-in scene's name ("cornel"): a
 * usage error with the suggestion. Anything else is left to scene_load. */
bool cli_scene(const char *opt, const char *v);
/* Iterates argv: cli_next returns the next option name (or NULL at the end,
 * or after logging an error: check cli_failed) and cli_value its argument
 * (NULL after logging if missing). Both "--opt value" and "--opt=value"
 * work; "=value" on an option that takes none is an error. "--" ends the
 * options: every argument after it is an operand, whatever it looks like.
 * --quiet (errors only: no info or progress lines on stderr) and --verbose
 * (debug lines too), which every command takes, are handled here: they set
 * the log level and are not returned. A command that takes operands (compare's images) sets `operands` and
 * checks cli_operand first; for the others, an operand is an error logged
 * here. */
typedef struct CliArgs {
    int argc;
    char **argv;
    bool operands;       /* the command takes operands (set by it) */
    int i;
    const char *opt;     /* current option or operand */
    const char *pending; /* the value of "--opt=value", not yet taken */
    bool is_operand;     /* opt is an operand: not an option, or after "--" */
    bool ended;          /* "--" was seen */
    bool failed;         /* cli_next stopped on an error (logged) */
    char optbuf[64];     /* the option part of "--opt=value" */
} CliArgs;
const char *cli_next(CliArgs *a);
const char *cli_value(CliArgs *a);
/* true if the iteration stopped on an error (already logged). */
static inline bool cli_failed(const CliArgs *a) { return a->failed; }
/* true if what cli_next returned is an operand, not an option. */
static inline bool cli_operand(const CliArgs *a) { return a->is_operand; }
/* Logs "<cmd>: unknown option '<opt>'; did you mean '<nearest>'? (see rtgi
 * <cmd> --help)", the nearest of the NULL-terminated `known` if one is near. */
void cli_unknown_option(const char *opt, const char *const *known);

/* Files a command reads and writes, checked before its work starts (a
 * render or a probe can take minutes): `n` options and their paths (NULL:
 * not given; "-": standard output), of which the first `outputs` are
 * written. Returns 0, or the exit status after logging one line: 2 (usage)
 * when two options name one file and either is written (the same path, or
 * one existing file); 1 when an output cannot be written, as its writer
 * would have found at the end (a directory, device or FIFO, or no
 * permission: its temporary file is made and removed here, and a missing
 * parent directory made, as the writer would). */
int cli_check_files(int n, int outputs, const char *const opts[], const char *const paths[]);

#endif
