/* fuzz_scene.c — libFuzzer target: a scene file through the whole render
 * set-up. The input is written as a .json file, loaded by scene_load (as
 * `rtgi render --scene` does), turned into settings by the CLI's own
 * render_options code (so the file's "shadow" and "gi" values reach the
 * passes), then renderer_create at 8x8, one renderer_frame, and destroy.
 * The shadow and GI technique come from a hash of the input, so every pass
 * is exercised. One EGL context serves every input. */
#include <string.h>

#include "fuzz_util.h"
#include "gl/gl_context.h"
#include "base/log.h"
#include "app/render_options.h"
#include "frame/renderer.h"
#include "core/scene.h"

static GlContext *g_gl;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    log_set_level(LOG_QUIET);
    g_gl = gl_context_create(false);
    if (!g_gl) {
        fprintf(stderr, "fuzz_scene: no GL 4.5 context\n");
        abort();
    }
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    if (!fuzz_write_temp("scene.json", data, size, path, sizeof path))
        return 0;
    uint32_t h = 2166136261u; /* FNV-1a picks the techniques */
    for (size_t i = 0; i < size; i++)
        h = (h ^ data[i]) * 16777619u;
    static const char *const shadows[] = {"none", "hard", "pcf", "pcss"};
    char *argv[] = {"--scene", path, "--size", "8x8", "--shadow", (char *)shadows[h % 4], "--gi",
                    (char *)gi_technique_names()[(h >> 2) % GI_MODE_COUNT], NULL};
    RenderOptions o;
    render_options_init(&o, false);
    if (render_options_parse(&o, 8, argv, NULL) != 0)
        abort(); /* the harness's own arguments are valid */
    Scene scene;
    if (!render_options_load_scene(&o, &scene)) {
        unlink(path);
        return 0;
    }
    unlink(path);
    RenderSettings rs;
    render_options_settings(&o, &scene, &rs);
    /* Keep one frame cheap on llvmpipe under ASan (the defaults, a 512²
     * cube RSM of VPLs, take tens of seconds at 8x8): the sizes are
     * clamped, every other value reaches the passes as loaded. */
#define AT_MOST(v, n) ((v) = (v) > (n) ? (n) : (v))
    AT_MOST(rs.gi_params.rsm_size, 64);
    AT_MOST(rs.gi_params.vpl_count, 4096);
    AT_MOST(rs.gi_params.samples, 1024);
    AT_MOST(rs.shadow_params.map_size, 256);
    AT_MOST(rs.gi_params.lpv_size, 16);
    AT_MOST(rs.gi_params.lpv_iterations, 32);
    AT_MOST(rs.gi_params.vct_size, 16);
#undef AT_MOST
    Renderer r;
    if (renderer_create(&r, &scene, &rs))
        renderer_frame(&r, &scene.camera);
    renderer_destroy(&r);
    scene_free(&scene);
    return 0;
}
