/* main.c — rtgi's entry point: dispatches subcommands; the only place that
 * exits. */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "base/json_util.h"
#include "base/log.h"
#include "base/util.h"
#include "version.h" /* generated: RTGI_VERSION */

static void usage(FILE *f)
{
    fprintf(f,
            "rtgi — real-time global illumination renderer and its reference\n"
            "usage: rtgi <command> [options]\n"
            "commands:\n"
            "  render      rasterize a scene (shadows, GI) to PNG, PFM or OpenEXR\n"
            "  view        the renderer in a window, with a camera and toggles\n"
            "  reference   path-trace the same scene on the CPU (Embree): ground truth\n"
            "  compare     error metrics between two images, PFM, EXR or PNG (RMSE, relMSE, SSIM, FLIP)\n"
            "  probe       this device's throughput on gather-shaped work (evaluations/s)\n"
            "  bench       time and measure a list of techniques against the reference:\n"
            "              DIR/bench.json, DIR/bench.csv and a self-contained DIR/report.html\n"
            "run 'rtgi <command> --help' for a command's options, 'rtgi --version' for the version;\n"
            "options take their value as '--opt value' or '--opt=value'\n"
            "every command also takes --quiet (errors only on stderr), --verbose (debug lines)\n"
            "and --lenient (unknown keys in a scene file are warnings instead of errors);\n"
            "'--' ends the options\n");
}

/* A command's results on stdout (compare's metrics, --timings' lines) are
 * its output: a failed write there (a full disk, a closed pipe) fails the
 * command, as a failed output file does. */
static int check_stdout(int rc)
{
    if (fflush(stdout) == 0 && !ferror(stdout))
        return rc;
    log_error("cli", "standard output: write failed (%s)", strerror(errno ? errno : EIO));
    return rc ? rc : 1;
}

int main(int argc, char **argv)
{
    /* outside `reference`'s render loop, which finishes its pass first */
    util_handle_ending_signals();
    /* --lenient applies to every command's scene loading: take it out here
     * (before or after the command name) so that the commands' option
     * parsers need not know it. */
    int n = 1;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--lenient") == 0)
            json_set_lenient(true);
        else
            argv[n++] = argv[i];
    }
    argc = n;
    argv[argc] = NULL;
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "--version")) {
        printf("rtgi %s\n", RTGI_VERSION);
        return 0;
    }
    if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) {
        usage(stdout);
        return 0;
    }
    static const struct {
        const char *name;
        int (*run)(int argc, char **argv);
    } commands[] = {{"render", cmd_render},       {"view", cmd_view},   {"reference", cmd_reference},
                    {"compare", cmd_compare},     {"probe", cmd_probe}, {"bench", cmd_bench}};
    enum { N = sizeof commands / sizeof commands[0] };
    const char *names[N + 1] = {NULL};
    for (int i = 0; i < N; i++) {
        if (!strcmp(cmd, commands[i].name)) {
            usage_set_command(cmd); /* usage errors name it */
            return check_stdout(commands[i].run(argc - 2, argv + 2));
        }
        names[i] = commands[i].name;
    }
    usage_error(util_nearest(cmd, names), "unknown command '%s'", cmd);
    return 2;
}
