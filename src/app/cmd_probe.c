/* cmd_probe.c — `rtgi probe`: this device's throughput on gather-shaped
 * work (probe.h). */
#include <stdio.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "app/options.h"
#include "gl/gl_context.h"
#include "base/log.h"
#include "gpu/probe.h"

typedef struct ProbeArgs {
    const char *json; /* --json FILE or "-", or NULL */
    int map_size;     /* --map-size */
} ProbeArgs;

static const OptionDesc k_probe_options[] = {
    OPT_WORD("--json", ProbeArgs, json, "FILE", "also write the result (for render --timings --probe FILE); -: stdout, the text to stderr (default: none)"),
    OPT_INT("--map-size", ProbeArgs, map_size, 64, PROBE_MAP_MAX, "the maps' side in texels: a gather's rate depends on the size of the map it reads; render --probe run uses the gather's RSM size"),
    OPT_END,
};

void cmd_probe_help(void)
{
    ProbeArgs def = {NULL, PROBE_MAP_DEFAULT};
    printf("usage: rtgi probe [--json FILE] [--map-size N] [--quiet | --verbose]\n"
           "Measures evaluations per second of the VPL irradiance arithmetic with 0-3 texture\n"
           "fetches per sample from 2D and cube maps, with one packed RSM texel per sample (as\n"
           "the RSM gathers read them), and with one VPL per sample from a storage buffer\n"
           "(shaders/probe/probe.comp), best of 5.\n");
    options_print_help(stdout, k_probe_options, &def);
    printf("  --quiet | --verbose          errors only on stderr | debug lines too\n");
}

int cmd_probe(int argc, char **argv)
{
    ProbeArgs args = {NULL, PROBE_MAP_DEFAULT};
    int rc = options_parse(argc, argv, &(OptionSet){.tables = (const OptionDesc *const[]){k_probe_options, NULL}, .help = cmd_probe_help}, &args);
    if (rc)
        return rc < 0 ? 0 : rc;
    const char *json = args.json;
    int map_size = args.map_size;
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
