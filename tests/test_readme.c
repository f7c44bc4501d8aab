/* test_readme.c — every command of the ```sh blocks of the README and of
 * the docs (guide, techniques, measuring, performance, gpu) works as
 * written (issues 15 and 43). The commands are
 * extracted from the files, so they cannot drift, and run in order in a scratch directory laid out as a
 * checkout (build/rtgi, scenes/, scripts/, shaders/, ../shared/), with the
 * documented rewriting rule (docs/developing.md, "README commands"): render, reference,
 * view and bench get --size 32x32; reference and bench --spp 2; view and
 * bench --frames 1 (bench --animate: 3). rtgi view runs under a virtual X server (Xvfb, started
 * once: test_x_display); scripts/crosscheck-cycles.sh at 16x16 and 4 spp
 * where Blender is installed; scripts/shadow-artefacts.sh at 32x32 and 4 spp
 * with two settings; scripts/frame-times.sh at 32x32, one frame, for none,
 * rsm and vct, reading a probe result made once on 64² maps (PROBE);
 * rtgi probe gets --map-size 64 and bench --lpv-iterations 8. Skipped, saying why: scripts/setup.sh and make
 * (they install and build), Sponza when ../shared has no Sponza, the Cycles
 * cross-check without Blender or the Cornell box facts. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "test_util.h"
#include "base/util.h"

#define SCRATCH RTGI_TEST_TMP "/readme"

static void sh(const char *cmd)
{
    if (system(cmd) != 0)
        fail_msg("setup failed: %s", cmd);
}

/* Replaces the value of `opt` in argv or appends "opt value". */
static void set_opt(char **argv, int *argc, const char *opt, const char *value)
{
    for (int i = 0; i + 1 < *argc; i++)
        if (!strcmp(argv[i], opt)) {
            argv[i + 1] = (char *)value;
            return;
        }
    argv[(*argc)++] = (char *)opt;
    argv[(*argc)++] = (char *)value;
    argv[*argc] = NULL;
}

static int run(char **argv, char **out)
{
    char log[600];
    snprintf(log, sizeof log, "%s/readme_cmd.log", RTGI_TEST_TMP);
    pid_t pid = fork();
    if (pid == 0) {
        if (chdir(SCRATCH "/repo") != 0 || !freopen(log, "w", stdout) || dup2(fileno(stdout), 2) < 0)
            _exit(127);
        /* Under `make test-asan`, LeakSanitizer's tracer sometimes crashes
         * at the exit of a long multi-threaded run ("Tracer caught signal
         * 11", exit 1, no leak reported); this test checks that the README's
         * commands work, the other tests check leaks, so its children skip
         * the leak check. */
        const char *asan = getenv("ASAN_OPTIONS");
        if (asan) {
            static char opts[1024];
            snprintf(opts, sizeof opts, "%s:detect_leaks=0", asan);
            setenv("ASAN_OPTIONS", opts, 1);
        }
        execv(argv[0], argv);
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    *out = util_read_file(log, NULL);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

static void readme_commands_work(void **state)
{
    (void)state;
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "rm -rf '%s' && mkdir -p '%s/repo/build' && ln -s '%s' '%s/repo/build/rtgi' && "
             "for d in scenes scripts shaders; do ln -s '%s/'$d '%s/repo/'$d; done",
             SCRATCH, SCRATCH, RTGI_BINARY, SCRATCH, RTGI_SOURCE_DIR, SCRATCH);
    sh(cmd);
    struct stat st;
    if (stat(RTGI_SHARED_DIR, &st) == 0) {
        snprintf(cmd, sizeof cmd, "ln -s \"$(realpath '%s')\" '%s/shared'", RTGI_SHARED_DIR, SCRATCH);
        sh(cmd);
    }
    /* frame-times.sh's gathers read this instead of a probe run each (10 s
     * at the default 512² maps) */
    snprintf(cmd, sizeof cmd, "'%s' probe --map-size 64 --json '%s/probe64.json' --quiet", RTGI_BINARY, SCRATCH);
    sh(cmd);
    bool sponza = stat(SCRATCH "/shared/assets/sponza/Sponza.gltf", &st) == 0;
    bool cornell_facts = stat(SCRATCH "/shared/assets/cornell/cornell_box_facts.json", &st) == 0;

    /* In this order: measuring.md compares the guide's out/render.pfm. */
    static const char *const files[] = {"README.md",          "docs/guide.md",       "docs/techniques.md",
                                        "docs/measuring.md",  "docs/performance.md", "docs/gpu.md"};
    int ran = 0, skipped = 0, failed = 0;
    for (size_t f = 0; f < sizeof files / sizeof files[0]; f++) {
        char path[600];
        snprintf(path, sizeof path, "%s/%s", RTGI_SOURCE_DIR, files[f]);
        char *text = util_read_file(path, NULL);
        assert_non_null(text);
        print_message("== %s\n", files[f]);
        bool in_block = false;
        for (char *save = NULL, *line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
            if (!strncmp(line, "```", 3)) {
                in_block = !in_block && !strncmp(line, "```sh", 5);
                continue;
            }
            if (!in_block)
                continue;
            char *hash = strstr(line, " #");
            if (hash)
                *hash = 0;
            char shown[1024];
            snprintf(shown, sizeof shown, "%s", line);
            char *argv[64];
            int argc = 0;
            for (char *s2 = NULL, *tok = strtok_r(line, " \t", &s2); tok && argc < 56; tok = strtok_r(NULL, " \t", &s2))
                argv[argc++] = tok;
            argv[argc] = NULL;
            if (argc == 0)
                continue;
            const char *why = NULL;
            if (!strcmp(argv[0], "scripts/setup.sh") || !strcmp(argv[0], "make"))
                why = "installs and builds (this suite is that build)";
            else if (strstr(shown, "sponza") && !sponza)
                why = "../shared/assets/sponza is absent";
            else if (!strcmp(argv[0], "scripts/crosscheck-cycles.sh") && system("command -v blender >/dev/null 2>&1") != 0)
                why = "Blender is not installed (an optional tool: apt install blender)";
            else if (!strcmp(argv[0], "scripts/crosscheck-cycles.sh") && !cornell_facts)
                why = "../shared/assets/cornell/cornell_box_facts.json is absent";
            else if (!strcmp(argv[0], "scripts/crosscheck-cycles.sh") && argc == 4) {
                argv[2] = "16x16"; /* the rewriting rule: seconds, not minutes */
                argv[3] = "4";
            } else if (!strcmp(argv[0], "scripts/shadow-artefacts.sh")) {
                static const char *const defaults[] = {"cornell", "32x32", "4"}; /* the rewriting rule */
                for (int k = 1; k <= 3; k++)
                    argv[k] = (char *)(k == 1 && argc > 1 ? argv[1] : defaults[k - 1]);
                argc = argc > 4 ? argc : 4;
                argv[argc] = NULL;
                setenv("SETTINGS", "--shadow hard --bias-slope 0;--shadow pcss", 1); /* two rows, not eleven */
            } else if (!strcmp(argv[0], "scripts/frame-times.sh")) {
                static const char *const defaults[] = {"cornell", "32x32", "pcss", "1"}; /* the rewriting rule */
                for (int k = 1; k <= 4; k++)
                    argv[k] = (char *)(k == 1 && argc > 1 ? argv[1] : k == 3 && argc > 3 ? argv[3] : defaults[k - 1]);
                argc = argc > 5 ? argc : 5;
                argv[argc] = NULL;
                setenv("GI", "none rsm vct", 1); /* three rows, not eleven */
                setenv("PROBE", SCRATCH "/probe64.json", 1);
            } else if (strcmp(argv[0], "build/rtgi") != 0)
                fail_msg("%s command '%s': the test knows no rule for it (add one to tests/test_readme.c)", files[f], shown);
            if (why) {
                print_message("SKIP %s  (%s)\n", shown, why);
                skipped++;
                continue;
            }
            const char *sub = argc > 1 ? argv[1] : "";
            bool view = !strcmp(sub, "view");
            if (!strcmp(sub, "render") || !strcmp(sub, "reference") || !strcmp(sub, "bench") || view)
                set_opt(argv, &argc, "--size", "32x32");
            if (!strcmp(sub, "reference") || !strcmp(sub, "bench"))
                set_opt(argv, &argc, "--spp", "2");
            bool animate = false; /* bench --animate: flicker needs 3 frames */
            for (int k = 1; k < argc; k++)
                animate = animate || !strcmp(argv[k], "--animate");
            if (!strcmp(sub, "bench") || view)
                set_opt(argv, &argc, "--frames", animate ? "3" : "1");
            if (!strcmp(sub, "bench")) { /* Sponza's three 32³ cascades: 96 steps took 10 s a frame */
                set_opt(argv, &argc, "--lpv-iterations", "8");
                set_opt(argv, &argc, "--vct-size", "64"); /* the nave's 256³ volumes: 1 GB and 5 s of a 12 s bench */
            }
            if (!strcmp(sub, "probe"))
                set_opt(argv, &argc, "--map-size", "64");
            if (view)
                test_x_display(); /* a window: under Xvfb */
            char *out = NULL;
            double t0 = util_seconds();
            int rc = run(argv, &out);
            double took = util_seconds() - t0;
            unsetenv("SETTINGS");
            unsetenv("GI");
            unsetenv("PROBE");
            print_message("%s %5.1f s  %s\n", rc == 0 ? "ok  " : "FAIL", took, shown);
            if (rc != 0) {
                print_message("  exit %d:\n%s\n", rc, out ? out : "");
                failed++;
            }
            free(out);
            ran++;
        }
        free(text);
    }
    print_message("%d commands ran, %d skipped, %d failed\n", ran, skipped, failed);
    assert_int_equal(failed, 0);
    assert_true(ran >= 10);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(readme_commands_work),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
