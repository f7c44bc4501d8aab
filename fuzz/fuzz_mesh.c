/* fuzz_mesh.c — libFuzzer target: mesh files through assimp and
 * scene_load_mesh. The first byte picks the format (OBJ, glTF, GLB, PLY);
 * the rest is the file. */
#include "fuzz_util.h"
#include "base/log.h"
#include "core/scene.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    log_set_level(LOG_QUIET);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    static const char *const names[] = {"mesh.obj", "mesh.gltf", "mesh.glb", "mesh.ply"};
    char path[512];
    if (!fuzz_write_temp(names[data[0] % 4], data + 1, size - 1, path, sizeof path))
        return 0;
    Scene s;
    scene_init(&s);
    mat4 id = GLM_MAT4_IDENTITY_INIT;
    if (scene_load_mesh(&s, path, id)) {
        scene_add_default_sun(&s);
        scene_finalize(&s);
        scene_default_camera(&s);
    }
    scene_free(&s);
    unlink(path);
    return 0;
}
