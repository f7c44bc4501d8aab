/* cmd_probe.c — `rtgi probe`: this device's throughput on gather-shaped
 * work (probe.h). */
#include <stdio.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "gl/gl_context.h"
#include "base/log.h"
#include "gpu/probe.h"

void cmd_probe_help(void)
{
    printf("usage: rtgi probe [--json FILE] [--map-size N] [--quiet | --verbose]\n"
           "Measures evaluations per second of the VPL irradiance arithmetic with 0-3 texture\n"
           "fetches per sample from 2D and cube maps, with one packed RSM texel per sample (as\n"
           "the RSM gathers read them), and with one VPL per sample from a storage buffer\n"
           "(shaders/probe/probe.comp), best of 5.\n"
           "  --json FILE   also write the result (for render --timings --probe FILE); -: stdout, the text to stderr\n"
           "  --map-size N  the maps' side in texels, 64..2048 (default 512): a gather's rate depends on\n"
           "                the size of the map it reads; render --probe run uses the gather's RSM size\n"
           "  --quiet       errors only on stderr; --verbose: debug lines too\n");
}

/* The options this command knows (for "did you mean"). */
static const char *const k_probe_options[] = {"--help", "--json", "--map-size", NULL};

int cmd_probe(int argc, char **argv)
{
    const char *json = NULL, *opt, *v;
    int map_size = PROBE_MAP_DEFAULT;
    CliArgs a = {.argc = argc, .argv = argv};
    while ((opt = cli_next(&a))) {
        if (!strcmp(opt, "--help") || !strcmp(opt, "-h")) {
            cmd_probe_help();
            return 0;
        } else if (!strcmp(opt, "--json")) {
            CLI_VALUE(&a, v);
            json = v;
        } else if (!strcmp(opt, "--map-size")) {
            CLI_VALUE(&a, v);
            if (!cli_int(opt, v, 64, PROBE_MAP_MAX, &map_size))
                return 2;
        } else {
            cli_unknown_option(opt, k_probe_options);
            return 2;
        }
    }
    if (cli_failed(&a))
        return 2;
    int files = cli_check_files(1, 1, (const char *const[]){"--json"}, (const char *const[]){json});
    if (files)
        return files;
    GlContext *gl = gl_context_create(false);
    if (!gl)
        return 1;
    ProbeResult r;
    bool ok = probe_run(&r, map_size);
    if (ok) {
        /* `--json -`: the JSON alone on stdout, the text on stderr. */
        FILE *text = json && !strcmp(json, "-") ? stderr : stdout;
        fprintf(text, "renderer: %s\n", gl_context_renderer(gl));
        probe_print(text, &r);
        if (json)
            ok = probe_write_json(json, &r);
    }
    gl_context_destroy(gl);
    return ok ? 0 : 1;
}
