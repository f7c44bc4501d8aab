/* test_badinput.c — malformed input through `rtgi render`, `reference` and
 * `compare`: every case must exit 1 or 2 with exactly one line on stderr
 * that names the file, key or option and the problem, leave no output
 * file behind, and never crash or block (issue 9).
 *
 * The corpus is built at test time under RTGI_TEST_TMP/badinput/<case>/:
 * each case lists its input files (text, binary, FIFO, directory, symlink,
 * or a generated image) and its arguments, where "@x" names the file x in
 * the case's directory and outputs go to "@out/...". After the run the
 * "out" directory must be empty (no partial or temporary file).
 *
 * Adding a case is one row of k_cases. Unit tests of the helpers behind
 * it (atomic writes, finite checks, key checks) follow the table. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cjson/cJSON.h>

/* Rows leave trailing fields (fsize_limit, file lengths) at zero. */
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

#include "base/json_util.h"
#include "base/log.h"
#include "test_util.h"
#include "base/util.h"

typedef enum FileKind {
    K_TEXT = 0,  /* content as given (len bytes, or strlen) */
    K_FIFO,      /* a named pipe nobody writes */
    K_DIR,       /* a directory */
    K_SYMLINK,   /* a symbolic link to content (e.g. /dev/full) */
    K_PFM8,      /* a valid 8x8 PFM */
    K_PFM8_NAN,  /* 8x8 PFM with one NaN */
    K_PFM8_INF,  /* 8x8 PFM with one +Inf */
    K_PFM8_ZERO, /* 8x8 PFM, all zero (an empty mask) */
    K_PFM4,      /* a valid 4x4 PFM */
    K_PNG_HUGE,  /* PNG header claiming 17000x17000 */
    K_MANY_LIGHTS, /* scene with 33 point lights */
    K_MANY_KEYS,   /* scene with 300 keys in one object */
} FileKind;

typedef struct InFile {
    const char *name;
    FileKind kind;
    const char *content;
    size_t len; /* K_TEXT: bytes of content, 0 = strlen */
} InFile;

typedef struct Case {
    const char *name;     /* also the case's directory */
    InFile files[3];      /* inputs to create (name NULL = none) */
    const char *args[16]; /* after argv[0]; "@x" = file x in the case directory */
    int want_rc;          /* 1 (runtime error) or 2 (usage) */
    const char *want;     /* substring of the one stderr line */
    long fsize_limit;     /* > 0: RLIMIT_FSIZE for the run (a full disk) */
    double need_gib;      /* > 0: the run is refused for memory only where this is over half of the
                           * machine's: run elsewhere, it would do the work */
} Case;

#define BIN(s) s, sizeof(s) - 1
#define SCENE(json) {{"s.json", K_TEXT, json, 0}}
#define RENDER_S "render", "--scene", "@s.json", "--size", "8x8", "--out", "@out/r.pfm"
#define REF_S "reference", "--scene", "@s.json", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm"
#define CORNELL "\"builtin\": \"cornell\""
#define PLY_HEAD "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n" \
                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n"

/* One triangle in glTF: GLTF_TRI(primitive extra, buffer uri, top-level extra). */
#define GLTF_TRI(prim, uri, extra)                                                                                     \
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"             \
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}" prim "}]}],"                                      \
    "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],"          \
    "\"max\":[1,1,0]}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"buffers\":[{\"byteLength\":36,\"uri\":\"" \
    uri "\"}]" extra "}"
/* (0,0,0), (1,0,0), (0,1,0) as float32. */
#define GLTF_TRI_DATA "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"
#define GLTF_TRI_SCALE0                                                                                               \
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0,"               \
    "\"scale\":[0,0,0]}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"                          \
    "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],"          \
    "\"max\":[1,1,0]}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"buffers\":[{\"byteLength\":36,\"uri\":\"" \
    GLTF_TRI_DATA "\"}]}"

static const Case k_cases[] = {
    /* ---- scene numbers: finite, in range ---- */
    {"cam_pos_inf", SCENE("{" CORNELL ", \"camera\": {\"position\": [1e400, 0, 0], \"target\": [0, 0, 0]}}"),
     {REF_S}, 1, "camera.position[0]"},
    {"light_pos_inf", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0, 1e400, 0], \"intensity\": 1}]}"),
     {REF_S}, 1, "lights[0].position[1]"},
    {"light_dir_inf", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"directional\", \"direction\": [0, -1e400, 0], \"irradiance\": 1}]}"),
     {REF_S}, 1, "lights[0].direction[1]"},
    {"quad_vertex_inf", SCENE("{\"quads\": [{\"vertices\": [[0,0,0],[1,0,0],[1,1e400,0],[0,1,0]]}]}"),
     {REF_S}, 1, "quads[0].vertices[2][1]"},
    {"intensity_1e39", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0.2, 0.4, 0.2], \"intensity\": 1e39}]}"),
     {RENDER_S}, 1, "lights[0].intensity: 1e+39 is not a finite 32-bit float"},
    {"intensity_1e400", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0.2, 0.4, 0.2], \"intensity\": [1, 1e400, 1]}]}"),
     {REF_S}, 1, "lights[0].intensity[1]"},
    {"intensity_1e31", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0.2, 0.4, 0.2], \"intensity\": 1e31}]}"),
     {RENDER_S}, 1, "lights[0].intensity: 1e+31 is outside [0, 1e+30]"},
    {"intensity_negative", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0.2, 0.4, 0.2], \"intensity\": [1, -1, 1]}]}"),
     {RENDER_S}, 1, "lights[0].intensity: -1 is outside"},
    {"irradiance_minus_inf", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"directional\", \"direction\": [0, -1, 0], \"irradiance\": -1e400}]}"),
     {RENDER_S}, 1, "lights[0].irradiance"},
    {"irradiance_string", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"directional\", \"direction\": [0, -1, 0], \"irradiance\": \"bright\"}]}"),
     {RENDER_S}, 1, "lights[0].irradiance: must be an array of 3 numbers"},
    {"quad_u_1e30", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"quad\", \"position\": [0.28, 0.5, 0.28], \"direction\": [0, -1, 0], "
                          "\"radiance\": 1, \"u\": [1e30, 0, 0], \"v\": [0, 0, 0.1]}]}"),
     {RENDER_S}, 1, "lights[0].u: 1e+30 is beyond the limit"},
    {"quad_v_1e30", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"quad\", \"position\": [0.28, 0.5, 0.28], \"direction\": [0, -1, 0], "
                          "\"radiance\": 1, \"u\": [0.1, 0, 0], \"v\": [0, 0, 1e30]}]}"),
     {REF_S}, 1, "lights[0].v: 1e+30 is beyond the limit"},
    {"quad_light_power", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"quad\", \"position\": [0.28, 0.5, 0.28], \"direction\": [0, -1, 0], "
                               "\"radiance\": 1e29, \"u\": [1000, 0, 0], \"v\": [0, 0, 1000]}]}"),
     {RENDER_S}, 1, "exceeds the limit"},
    {"quad_light_degenerate", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"quad\", \"position\": [0.28, 0.5, 0.28], \"direction\": [0, -1, 0], "
                                    "\"radiance\": 1, \"u\": [0.1, 0, 0], \"v\": [0.2, 0, 0]}]}"),
     {RENDER_S}, 1, "lights[0]: u and v span no area"},
    {"quad_light_tiny_size", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"quad\", \"position\": [0.28, 0.5, 0.28], \"direction\": [0, -1, 0], "
                                   "\"radiance\": 1e20, \"u\": [0.1, 0, 0], \"v\": [0, 0, 0.1], \"size\": 1e-10}]}"),
     {RENDER_S}, 1, "lights[0].size"},
    {"quad_light_size_negative", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"quad\", \"position\": [0.28, 0.5, 0.28], \"direction\": [0, -1, 0], "
                                       "\"radiance\": 1, \"u\": [0.1, 0, 0], \"v\": [0, 0, 0.1], \"size\": -1}]}"),
     {RENDER_S}, 1, "lights[0].size: -1 is outside"},
    {"light_dir_zero", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 0], \"irradiance\": 1}]}"),
     {RENDER_S}, 1, "lights[0].direction: is zero"},
    {"spot_dir_zero", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"spot\", \"position\": [0.2, 0.4, 0.2], \"direction\": [0, 0, 0], \"intensity\": 1}]}"),
     {RENDER_S}, 1, "lights[0].direction: is zero"},
    {"spot_cone_inverted", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"spot\", \"position\": [0.2, 0.4, 0.2], \"direction\": [0, -1, 0], "
                                 "\"intensity\": 1, \"inner_deg\": 40, \"outer_deg\": 30}]}"),
     {RENDER_S}, 1, "inner_deg < outer_deg"},
    {"spot_cone_wide", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"spot\", \"position\": [0.2, 0.4, 0.2], \"direction\": [0, -1, 0], "
                             "\"intensity\": 1, \"outer_deg\": 95}]}"),
     {RENDER_S}, 1, "outer_deg < 90"},
    {"diameter_negative", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0.2, 0.4, 0.2], \"intensity\": 1, \"diameter\": -1}]}"),
     {RENDER_S}, 1, "lights[0].diameter: -1 is outside"},
    {"sun_diameter_100", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"directional\", \"direction\": [0, -1, 0], \"irradiance\": 1, "
                               "\"angular_diameter_deg\": 100}]}"),
     {RENDER_S}, 1, "lights[0].angular_diameter_deg: 100 is outside"},
    {"light_pos_far", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [2e6, 0, 0], \"intensity\": 1}]}"),
     {RENDER_S}, 1, "lights[0].position: 2e+06 is beyond the limit"},
    {"light_dir_tiny", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"directional\", \"direction\": [1e-30, 0, 0], \"irradiance\": 1}]}"),
     {RENDER_S}, 1, "lights[0].direction: is zero"},
    {"light_pos_four", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0, 0, 0, 0], \"intensity\": 1}]}"),
     {REF_S}, 1, "lights[0].position: must be an array of 3 numbers"},
    {"spot_inner_negative", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"spot\", \"position\": [0.2, 0.4, 0.2], \"direction\": [0, -1, 0], "
                                  "\"intensity\": 1, \"inner_deg\": -5}]}"),
     {RENDER_S}, 1, "0 <= inner_deg"},
    {"spot_outer_inf", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"spot\", \"position\": [0.2, 0.4, 0.2], \"direction\": [0, -1, 0], "
                             "\"intensity\": 1, \"outer_deg\": 1e400}]}"),
     {RENDER_S}, 1, "lights[0].outer_deg: inf is not a finite"},
    /* ---- camera ---- */
    {"cam_near_zero", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.28, 0.27, -0.8], \"target\": [0.28, 0.27, 0], \"near\": 0}}"),
     {RENDER_S}, 1, "camera.near: 0 is outside (0"},
    {"cam_near_negative", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.28, 0.27, -0.8], \"target\": [0.28, 0.27, 0], \"near\": -1}}"),
     {RENDER_S}, 1, "camera.near"},
    {"cam_far_negative", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.28, 0.27, -0.8], \"target\": [0.28, 0.27, 0], \"far\": -5}}"),
     {RENDER_S}, 1, "camera.far"},
    {"cam_far_below_near", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.28, 0.27, -0.8], \"target\": [0.28, 0.27, 0], \"near\": 2, \"far\": 1}}"),
     {RENDER_S}, 1, "camera: need 0 < near < far"},
    {"cam_fov_zero", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.28, 0.27, -0.8], \"target\": [0.28, 0.27, 0], \"fov_y_deg\": 0}}"),
     {RENDER_S}, 1, "camera.fov_y_deg"},
    {"cam_fov_180", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.28, 0.27, -0.8], \"target\": [0.28, 0.27, 0], \"fov_y_deg\": 180}}"),
     {RENDER_S}, 1, "camera.fov_y_deg"},
    {"cam_target_is_position", SCENE("{" CORNELL ", \"camera\": {\"position\": [1, 1, 1], \"target\": [1, 1, 1]}}"),
     {RENDER_S}, 1, "position equals target"},
    {"cam_up_parallel", SCENE("{" CORNELL ", \"camera\": {\"position\": [0, 0, 0], \"target\": [0, 5, 0], \"up\": [0, 1, 0]}}"),
     {RENDER_S}, 1, "camera.up: is parallel"},
    {"cam_up_zero", SCENE("{" CORNELL ", \"camera\": {\"position\": [0, 0, 0], \"target\": [0, 0, 1], \"up\": [0, 0, 0]}}"),
     {RENDER_S}, 1, "camera.up: is zero"},
    {"cam_target_and_forward", SCENE("{" CORNELL ", \"camera\": {\"position\": [0, 0, 0], \"target\": [0, 0, 1], \"forward\": [0, 0, 1]}}"),
     {RENDER_S}, 1, "not both"},
    {"cam_not_object", SCENE("{" CORNELL ", \"camera\": [0, 0, 0]}"), {RENDER_S}, 1, "camera: must be an object"},
    {"cam_position_missing", SCENE("{" CORNELL ", \"camera\": {\"target\": [0, 0, 1]}}"), {RENDER_S}, 1,
     "camera.position: missing"},
    {"cam_position_string", SCENE("{" CORNELL ", \"camera\": {\"position\": \"here\", \"target\": [0, 0, 1]}}"),
     {RENDER_S}, 1, "camera.position: must be an array of 3 numbers"},
    {"cam_position_two", SCENE("{" CORNELL ", \"camera\": {\"position\": [0, 0], \"target\": [0, 0, 1]}}"),
     {RENDER_S}, 1, "camera.position: must be an array of 3 numbers"},
    {"cam_position_null", SCENE("{" CORNELL ", \"camera\": {\"position\": [0, null, 0], \"target\": [0, 0, 1]}}"),
     {RENDER_S}, 1, "camera.position[1]: is not a number"},
    {"cam_near_inf", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.28, 0.27, -0.8], \"target\": [0.28, 0.27, 0], \"near\": 1e400}}"),
     {RENDER_S}, 1, "camera.near: inf is not a finite"},
    {"cam_fov_string", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.28, 0.27, -0.8], \"target\": [0.28, 0.27, 0], \"fov_y_deg\": \"60\"}}"),
     {RENDER_S}, 1, "camera.fov_y_deg: must be a number"},
    {"cam_forward_zero", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.28, 0.27, -0.8], \"forward\": [0, 0, 0]}}"),
     {REF_S}, 1, "camera.forward: is zero"},
    /* ---- quads ---- */
    {"quads_object", SCENE("{\"quads\": {\"vertices\": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}}"), {RENDER_S}, 1,
     "quads: must be an array"},
    {"quads_number", SCENE("{\"quads\": [3]}"), {RENDER_S}, 1, "quads[0]: must be an object"},
    {"quad_degenerate", SCENE("{\"quads\": [{\"vertices\": [[0,0,0],[0,0,0],[0,0,0],[0,0,0]]}]}"), {RENDER_S}, 1,
     "quads[0].vertices: the quad is degenerate"},
    {"quad_collinear", SCENE("{\"quads\": [{\"vertices\": [[0,0,0],[1,0,0],[2,0,0],[3,0,0]]}]}"), {REF_S}, 1,
     "degenerate"},
    {"quad_three_vertices", SCENE("{\"quads\": [{\"vertices\": [[0,0,0],[1,0,0],[1,1,0]]}]}"), {RENDER_S}, 1,
     "quads[0].vertices: must hold 4 points"},
    {"quad_vertex_two_coords", SCENE("{\"quads\": [{\"vertices\": [[0,0,0],[1,0],[1,1,0],[0,1,0]]}]}"), {RENDER_S}, 1,
     "vertex 1 is not 3 numbers"},
    {"quad_albedo_2", SCENE("{\"quads\": [{\"albedo\": 2, \"vertices\": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}]}"),
     {RENDER_S}, 1, "quads[0].albedo: 2 is outside [0, 1]"},
    {"quad_albedo_negative", SCENE("{\"quads\": [{\"albedo\": [0.5, -0.1, 0.5], \"vertices\": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}]}"),
     {RENDER_S}, 1, "quads[0].albedo"},
    {"quad_vertex_far", SCENE("{\"quads\": [{\"vertices\": [[0,0,0],[1e7,0,0],[1,1,0],[0,1,0]]}]}"), {RENDER_S}, 1,
     "beyond the limit"},
    {"quad_albedo_two", SCENE("{\"quads\": [{\"albedo\": [1, 1], \"vertices\": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}]}"), {RENDER_S}, 1,
     "quads[0].albedo: must be an array of 3 numbers"},
    {"quads_empty", SCENE("{\"quads\": []}"), {RENDER_S}, 1, "no geometry"},
    /* ---- top level ---- */
    {"mesh_scale_zero", SCENE("{\"mesh\": \"m.obj\", \"mesh_scale\": 0}"), {RENDER_S}, 1, "mesh_scale: 0 is outside (0"},
    {"mesh_scale_negative", SCENE("{\"mesh\": \"m.obj\", \"mesh_scale\": -2}"), {RENDER_S}, 1, "mesh_scale"},
    {"mesh_scale_without_mesh", SCENE("{" CORNELL ", \"mesh_scale\": 2}"), {RENDER_S}, 1, "given without \"mesh\""},
    {"mesh_translate_inf", SCENE("{\"mesh\": \"m.obj\", \"mesh_translate\": [0, 1e400, 0]}"), {RENDER_S}, 1,
     "mesh_translate[1]"},
    /* ---- views that see nothing, lights inside surfaces ---- */
    {"camera_far_before_scene", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.278, 0.273, -0.8], "
                                      "\"target\": [0.278, 0.273, 0.28], \"far\": 0.5}}"),
     {RENDER_S}, 1, "camera.far 0.5 ends before the scene, whose nearest point is 0.8 m from the camera"},
    {"camera_near_past_scene", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.278, 0.273, -0.8], "
                                     "\"target\": [0.278, 0.273, 0.28], \"near\": 5, \"far\": 10}}"),
     {REF_S}, 1, "camera.near 5 starts past the scene"},
    {"camera_looks_away", SCENE("{" CORNELL ", \"camera\": {\"position\": [0.278, 0.273, -0.8], "
                                "\"target\": [0.278, 0.273, -2]}}"),
     {RENDER_S}, 1, "the camera sees none of the scene: all of it lies behind the camera"},
    {"point_light_in_surfaces", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0.278, 0.45, 0.2795], "
                                      "\"intensity\": 0.2, \"diameter\": 10}]}"),
     {REF_S}, 1, "lights[0]: the point light's sphere (diameter 10 m) reaches into the scene's surfaces"},
    {"point_light_in_surfaces_scaled", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0.278, 0.45, 0.2795], "
                                             "\"intensity\": 0.2, \"diameter\": 0.05}]}"),
     {RENDER_S, "--light-scale", "10"}, 1, "(diameter 0.5 m, after --light-scale) reaches into"},
    /* A quad light too small to draw or sample in float (the Cornell light,
     * 0.13 × 0.105 m, scaled by 1e-6): render had been 1e5× too bright,
     * the reference black. */
    {"quad_light_tiny_scaled", SCENE("{" CORNELL "}"), {RENDER_S, "--light-scale", "1e-6"}, 1,
     "lights[0]: the quad light's shorter side is 1.05e-07 m (size 1e-06, after --light-scale), under 1e-05 of the "
     "scene's size"},
    {"quad_light_tiny_reference", SCENE("{" CORNELL "}"), {REF_S, "--light-scale", "1e-12"}, 1,
     "or size 0 for a point light"},
    {"quad_light_tiny_size", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"quad\", \"position\": [0.278, 0.548, 0.2795], "
                                   "\"direction\": [0, -1, 0], \"radiance\": [10, 10, 10], \"u\": [0.13, 0, 0], "
                                   "\"v\": [0, 0, 0.105], \"size\": 1e-7}]}"),
     {RENDER_S}, 1, "lights[0]: the quad light's shorter side is 1.05e-08 m (size 1e-07), under 1e-05"},
    {"exposure_negative", SCENE("{" CORNELL ", \"exposure\": -1}"), {RENDER_S}, 1, "exposure: -1 is outside [1e-09, 1e+09]"},
    {"exposure_zero", SCENE("{" CORNELL ", \"exposure\": 0}"), {RENDER_S}, 1, "exposure: 0 is outside [1e-09, 1e+09]"},
    {"exposure_inf", SCENE("{" CORNELL ", \"exposure\": 1e400}"), {RENDER_S}, 1, "exposure: inf is not a finite"},
    {"exposure_string", SCENE("{" CORNELL ", \"exposure\": \"bright\"}"), {RENDER_S}, 1, "exposure: must be a number"},
    {"unknown_key_top", SCENE("{" CORNELL ", \"camrea\": {}}"), {RENDER_S}, 1,
     "unknown key \"camrea\"; did you mean \"camera\"?"},
    {"unknown_key_camera", SCENE("{" CORNELL ", \"camera\": {\"positon\": [0, 0, 0], \"target\": [0, 0, 1]}}"),
     {RENDER_S}, 1, "unknown key \"camera.positon\"; did you mean \"position\"?"},
    {"unknown_key_light", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0.2, 0.4, 0.2], \"intesity\": 1}]}"),
     {RENDER_S}, 1, "unknown key \"lights[0].intesity\"; did you mean \"intensity\"?"},
    {"unknown_key_far", SCENE("{" CORNELL ", \"zzzzzzzz\": 1}"), {RENDER_S}, 1, "unknown key \"zzzzzzzz\"; known keys:"},
    {"spot_key_on_point", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0.2, 0.4, 0.2], \"intensity\": 1, \"inner_deg\": 5}]}"),
     {RENDER_S}, 1, "unknown key \"lights[0].inner_deg\""},
    {"unknown_key_quad", SCENE("{\"quads\": [{\"albdeo\": 1, \"vertices\": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}]}"), {RENDER_S}, 1,
     "did you mean \"albedo\"?"},
    {"duplicate_key_top", SCENE("{" CORNELL ", \"exposure\": 1, \"exposure\": 2}"), {RENDER_S}, 1,
     "duplicate key \"exposure\""},
    {"duplicate_key_camera", SCENE("{" CORNELL ", \"camera\": {\"position\": [0, 0, 0], \"position\": [1, 0, 0], \"target\": [0, 0, 1]}}"),
     {RENDER_S}, 1, "duplicate key \"camera.position\""},
    {"too_many_keys", {{"s.json", K_MANY_KEYS}}, {RENDER_S}, 1, "more than 256 keys"},
    {"exposure_bool", SCENE("{" CORNELL ", \"exposure\": true}"), {RENDER_S}, 1, "exposure: must be a number"},
    {"mesh_scale_string", SCENE("{\"mesh\": \"m.obj\", \"mesh_scale\": \"big\"}"), {RENDER_S}, 1, "mesh_scale: must be a number"},
    {"mesh_translate_short", SCENE("{\"mesh\": \"m.obj\", \"mesh_translate\": [0, 0]}"), {RENDER_S}, 1,
     "mesh_translate: must be an array of 3 numbers"},
    {"duplicate_key_lenient", SCENE("{" CORNELL ", \"exposure\": 1, \"exposure\": 2}"), {"render", "--lenient", "--scene", "@s.json",
     "--size", "8x8", "--out", "@out/r.pfm"}, 1, "duplicate key \"exposure\""},
    {"duplicate_key_light", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"type\": \"spot\", \"position\": [0.2, 0.4, 0.2], \"intensity\": 1}]}"),
     {REF_S}, 1, "duplicate key \"lights[0].type\""},
    {"lights_object", SCENE("{" CORNELL ", \"lights\": {\"type\": \"point\"}}"), {RENDER_S}, 1, "lights: must be an array"},
    {"light_number", SCENE("{" CORNELL ", \"lights\": [7]}"), {RENDER_S}, 1, "lights[0]: must be an object"},
    {"light_type_missing", SCENE("{" CORNELL ", \"lights\": [{\"position\": [0, 0, 0]}]}"), {RENDER_S}, 1,
     "lights[0].type: missing"},
    {"light_type_number", SCENE("{" CORNELL ", \"lights\": [{\"type\": 3}]}"), {RENDER_S}, 1,
     "lights[0].type: must be a string"},
    {"light_type_unknown", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"laser\"}]}"), {REF_S}, 1,
     "unknown light type \"laser\""},
    {"light_missing_intensity", SCENE("{" CORNELL ", \"lights\": [{\"type\": \"point\", \"position\": [0.2, 0.4, 0.2]}]}"),
     {RENDER_S}, 1, "lights[0].intensity: missing"},
    {"too_many_lights", {{"s.json", K_MANY_LIGHTS}}, {RENDER_S}, 1, "33 lights is more than the limit of 32"},
    {"builtin_number", SCENE("{\"builtin\": 1}"), {RENDER_S}, 1, "builtin: must be a string"},
    {"builtin_unknown", SCENE("{\"builtin\": \"sponza\"}"), {RENDER_S}, 1, "unknown builtin scene \"sponza\""},
    {"material_unknown", SCENE("{\"builtin\": \"cornell\", \"materials\": {\"tal_block\": {\"metallic\": 1}}}"),
     {RENDER_S}, 1, "materials.tal_block: no material of that name"},
    {"material_metallic_range", SCENE("{\"builtin\": \"cornell\", \"materials\": {\"floor\": {\"metallic\": 2}}}"),
     {RENDER_S}, 1, "materials.floor.metallic: 2 is outside [0, 1]"},
    {"material_unknown_key", SCENE("{\"builtin\": \"cornell\", \"materials\": {\"floor\": {\"roughnes\": 0.5}}}"),
     {RENDER_S}, 1, "roughnes"},
    {"materials_array", SCENE("{\"builtin\": \"cornell\", \"materials\": [1]}"), {RENDER_S}, 1,
     "materials: must be an object"},
    {"mesh_number", SCENE("{\"mesh\": 5}"), {RENDER_S}, 1, "mesh: must be a file path"},
    {"no_geometry", SCENE("{\"exposure\": 1}"), {RENDER_S}, 1, "no geometry"},
    {"top_level_array", SCENE("[1, 2]"), {RENDER_S}, 1, "top level must be a JSON object"},
    {"malformed_json", SCENE("{\"builtin\": \"cornell\",, }"), {RENDER_S}, 1, "s.json:1:"},
    /* what broke it, the mistakes made by hand (issue 43): cJSON alone said "malformed JSON" */
    {"json_trailing_comma", SCENE("{\n  \"builtin\": \"cornell\",\n  \"exposure\": 2,\n}\n"), {RENDER_S}, 1,
     "s.json:3:16: malformed JSON: a comma before '}' (JSON allows no trailing comma)"},
    {"json_trailing_comma_array", SCENE("{\"builtin\": \"cornell\", \"camera\": {\"position\": [0, 1, 2,]}}"),
     {RENDER_S}, 1, "a comma before ']' (JSON allows no trailing comma)"},
    {"json_missing_comma", SCENE("{\"builtin\": \"cornell\"\n \"exposure\": 2}"), {RENDER_S}, 1,
     "s.json:2:2: malformed JSON: a ',' is missing before this member"},
    {"json_single_quotes", SCENE("{'builtin': 'cornell'}"), {RENDER_S}, 1,
     "s.json:1:2: malformed JSON: strings take double quotes"},
    {"json_comment", SCENE("{\"builtin\": \"cornell\" // the box\n}"), {RENDER_S}, 1, "JSON has no comments"},
    {"json_unclosed", SCENE("{\"builtin\": \"cornell\", \"exposure\": [1, 2"), {RENDER_S}, 1,
     "the file ends inside a value (a '}', ']' or '\"' is missing)"},
    {"empty_file", SCENE(""), {RENDER_S}, 1, "malformed JSON"},
    {"binary_file", {{"s.json", K_TEXT, BIN("\x00\x01\x02\xff{")}}, {RENDER_S}, 1, "malformed JSON"},
    {"shadow_not_object", SCENE("{" CORNELL ", \"shadow\": 5}"), {RENDER_S}, 1, "shadow: must be an object"},
    {"gi_not_object", SCENE("{" CORNELL ", \"gi\": \"rsm\"}"), {RENDER_S}, 1, "gi: must be an object"},
    {"shadow_value_inf", SCENE("{" CORNELL ", \"shadow\": {\"bias_const\": 1e400}}"), {RENDER_S}, 1,
     "shadow.bias_const: inf is not a finite"},
    {"gi_value_huge_int", SCENE("{" CORNELL ", \"gi\": {\"samples\": 1e20}}"), {RENDER_S}, 1,
     "gi.samples: 1e+20 is out of range"},
    /* ---- input files: regular files only, never block ---- */
    {"scene_fifo", {{"s.json", K_FIFO}}, {RENDER_S}, 1, "s.json: scene file is a FIFO, not a regular file"},
    {"scene_fifo_reference", {{"s.json", K_FIFO}}, {REF_S}, 1, "is a FIFO"},
    {"scene_directory", {{"s.json", K_DIR}}, {RENDER_S}, 1, "s.json: scene file is a directory"},
    {"scene_device", {{0}}, {"render", "--scene", "/dev/null", "--size", "8x8", "--out", "@out/r.pfm"}, 1,
     "/dev/null: mesh file is a character device"},
    {"scene_missing", {{0}}, {"render", "--scene", "@nope.json", "--size", "8x8", "--out", "@out/r.pfm"}, 1,
     "nope.json: cannot read scene file: it does not exist"},
    {"mesh_fifo", {{"m.obj", K_FIFO}}, {"render", "--scene", "@m.obj", "--size", "8x8", "--out", "@out/r.pfm"}, 1,
     "m.obj: mesh file is a FIFO"},
    {"mesh_directory", {{"m.gltf", K_DIR}}, {"render", "--scene", "@m.gltf", "--size", "8x8", "--out", "@out/r.pfm"},
     1, "m.gltf: mesh file is a directory"},
    {"mesh_fifo_from_scene", {{"s.json", K_TEXT, "{\"mesh\": \"m.obj\"}"}, {"m.obj", K_FIFO}}, {REF_S}, 1,
     "m.obj: mesh file is a FIFO"},
    {"mesh_missing_from_scene", SCENE("{\"mesh\": \"m.obj\"}"), {RENDER_S}, 1, "m.obj: cannot read mesh file: it does not exist"},
    {"ply_index_out_of_range", {{"m.ply", K_TEXT, PLY_HEAD "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"}},
     {"render", "--scene", "@m.ply", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "out of range"},
    {"ply_index_out_of_range_ref", {{"m.ply", K_TEXT, PLY_HEAD "0 0 0\n1 0 0\n0 1 0\n3 0 1 70000\n"}},
     {"reference", "--scene", "@m.ply", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm"}, 1, "m.ply"},
    {"ply_bad_property", {{"m.ply", K_TEXT, BIN("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                                "property float y\nproperty \xeb\xeb y float z\nelement face 1\n"
                                                "property list uchar int vertex_indices\nend_header\n"
                                                "\0\0\0\0\0\0\0\0\0\0\0\0\0\0\x80\x3f\0\0\0\0\0\0\0\0\0\0\0\0\0\0\x80\x3f"
                                                "\0\0\0\0\x03\0\0\0\0\x01\0\0\0\x02\0\0\0")}},
     {"render", "--scene", "@m.ply", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "m.ply"},
    /* assimp 5.2's PLY reader crashed (SEGV) on this header; found by fuzz_mesh */
    {"ply_malformed_header", {{"m.ply", K_TEXT, BIN(
                                               "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\npv 0 1 1\nvn 0 0 1\nvt 0 0"
                                               "\nvt 1 1\nf 1 2 3 4\nf 5 6 7 8\nf 1/1/1 5/2uchar int vertex_indices\nend_hea\x9c\x9a\x8d\xf5\x00\x00"
                                               "\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00")}},
     {"render", "--scene", "@m.ply", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "m.ply: malformed PLY file"},
    /* A binary glTF's lengths taken on trust cost assimp 4.2 GB and 12 s
     * before it failed (found by fuzz_mesh): a chunk, then the header,
     * claiming more than the file holds. */
    {"glb_chunk_past_end", {{"m.glb", K_TEXT, BIN("glTF\x02\0\0\0\x2f\0\0\0\0\xff\xff\xff" "JSON"
                                                 "{\"asset\":{\"version\":\"2.0\"}}")}},
     {"render", "--scene", "@m.glb", "--size", "8x8", "--out", "@out/r.pfm"}, 1,
     "m.glb: malformed binary glTF: a chunk's length"},
    {"glb_header_past_end", {{"m.glb", K_TEXT, BIN("glTF\x02\0\0\0\xf0\xff\xff\xff\x1b\0\0\0" "JSON"
                                                  "{\"asset\":{\"version\":\"2.0\"}}")}},
     {"reference", "--scene", "@m.glb", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm"}, 1,
     "m.glb: malformed binary glTF: its header's length"},
    {"obj_garbage", {{"m.obj", K_TEXT, "garbage here\nmore\n"}},
     {"render", "--scene", "@m.obj", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "m.obj: cannot import mesh"},
    {"obj_nan_vertex", {{"m.obj", K_TEXT, "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}},
     {"reference", "--scene", "@m.obj", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm"}, 1, "m.obj: vertex 0"},
    {"obj_inf_vertex", {{"m.obj", K_TEXT, "v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}},
     {"render", "--scene", "@m.obj", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "not finite"},
    {"obj_no_faces", {{"m.obj", K_TEXT, "v 0 0 0\nv 1 0 0\n"}},
     {"render", "--scene", "@m.obj", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "m.obj"},
    {"mesh_scaled_too_far", {{"s.json", K_TEXT, "{\"mesh\": \"m.obj\", \"mesh_scale\": 1e6}"},
                             {"m.obj", K_TEXT, "v 0 0 0\nv 10 0 0\nv 0 10 0\nf 1 2 3\n"}},
     {RENDER_S}, 1, "beyond the limit of 1e6 m"},
    {"texture_missing", {{"m.obj", K_TEXT, "mtllib m.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n"},
                         {"m.mtl", K_TEXT, "newmtl a\nmap_Kd missing.png\n"}},
     {"render", "--scene", "@m.obj", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "missing.png: cannot read texture"},
    {"texture_fifo", {{"m.obj", K_TEXT, "mtllib m.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n"},
                      {"m.mtl", K_TEXT, "newmtl a\nmap_Kd t.png\n"}, {"t.png", K_FIFO}},
     {"render", "--scene", "@m.obj", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "t.png: texture is a FIFO"},
    /* Files a mesh names are opened through rtgi's own file system for
     * assimp (scene_load.c): a FIFO would block the import for ever. */
    {"mtllib_fifo", {{"m.obj", K_TEXT, "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}, {"m.mtl", K_FIFO}},
     {"render", "--scene", "@m.obj", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "m.mtl, is a FIFO, not a regular file"},
    {"gltf_buffer_fifo", {{"m.gltf", K_TEXT, GLTF_TRI("", "b.bin", "")}, {"b.bin", K_FIFO}},
     {"reference", "--scene", "@m.gltf", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm"}, 1,
     "b.bin, is a FIFO, not a regular file"},
    /* A mesh file's material values, checked as the scene file's are. */
    {"mtl_kd_nan", {{"m.obj", K_TEXT, "mtllib m.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
                    {"m.mtl", K_TEXT, "newmtl a\nKd nan nan nan\n"}},
     {"render", "--scene", "@m.obj", "--size", "8x8", "--gi", "rsm", "--out", "@out/r.pfm"}, 1,
     "m.obj: material 'a': diffuse colour (Kd) component 0 is nan, not in [0, 1]"},
    {"mtl_kd_negative", {{"m.obj", K_TEXT, "mtllib m.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
                         {"m.mtl", K_TEXT, "newmtl a\nKd 0.5 -1 0.5\n"}},
     {"reference", "--scene", "@m.obj", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm"}, 1,
     "component 1 is -1, not in [0, 1]"},
    {"gltf_base_color_huge", {{"m.gltf", K_TEXT, GLTF_TRI(",\"material\":0", GLTF_TRI_DATA,
                                                           ",\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[1e39,0,0,1]}}]")}},
     {"render", "--scene", "@m.gltf", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "baseColorFactor component 0 is inf"},
    {"gltf_metallic_negative", {{"m.gltf", K_TEXT, GLTF_TRI(",\"material\":0", GLTF_TRI_DATA,
                                                             ",\"materials\":[{\"pbrMetallicRoughness\":{\"metallicFactor\":-3}}]")}},
     {"render", "--scene", "@m.gltf", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "metallicFactor is -3, not in [0, 1]"},
    {"gltf_emissive_negative", {{"m.gltf", K_TEXT, GLTF_TRI(",\"material\":0", GLTF_TRI_DATA,
                                                        ",\"materials\":[{\"emissiveFactor\":[-5,0,0]}]")}},
     {"render", "--scene", "@m.gltf", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "emissiveFactor component 0 is -5"},
    /* Only zero-area triangles: nothing to draw, where it had rendered black. */
    {"obj_zero_area", {{"m.obj", K_TEXT, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"}},
     {"render", "--scene", "@m.obj", "--size", "8x8", "--out", "@out/r.pfm"}, 1, "all 1 triangles have zero area"},
    {"gltf_zero_scale", {{"m.gltf", K_TEXT, GLTF_TRI_SCALE0}},
     {"reference", "--scene", "@m.gltf", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm"}, 1, "have zero area"},
    /* ---- options checked before any work ---- */
    {"probe_without_timings", {{0}}, {"render", "--size", "8x8", "--probe", "run", "--out", "@out/r.pfm"}, 2,
     "--probe: needs --timings"},
    {"probe_file_missing", {{0}}, {"render", "--size", "8x8", "--timings", "--probe", "@nope.json", "--out", "@out/r.pfm"}, 2,
     "nope.json: cannot read probe result: it does not exist"},
    {"probe_file_not_a_result", {{"p.json", K_TEXT, "{\"evals_2d\": 1}"}},
     {"render", "--size", "8x8", "--timings", "--probe", "@p.json", "--out", "@out/r.pfm"}, 2, "p.json: not a probe result"},
    /* Rates that would print as a bound of inf or 0, and text after the
     * object, had been taken. */
    {"probe_file_infinite_rate", {{"p.json", K_TEXT, "{\"evals_2d\": [1e999, 1, 1, 1], \"evals_cube\": [1, 1, 1, 1], \"evals_ssbo\": 1}"}},
     {"render", "--size", "8x8", "--timings", "--probe", "@p.json", "--out", "@out/r.pfm"}, 2,
     "p.json: not a probe result: evals_2d[0]: inf is not a rate (1 to 1e18 evaluations/s)"},
    {"probe_file_denormal_rate", {{"p.json", K_TEXT, "{\"evals_2d\": [1, 1, 1, 1], \"evals_cube\": [1, 1, 1, 1], \"evals_ssbo\": 1e-320}"}},
     {"render", "--size", "8x8", "--timings", "--probe", "@p.json", "--out", "@out/r.pfm"}, 2,
     "evals_ssbo: 9.99989e-321 is not a rate"},
    {"probe_file_trailing_text", {{"p.json", K_TEXT, "{\"evals_2d\": [1, 1, 1, 1], \"evals_cube\": [1, 1, 1, 1], \"evals_ssbo\": 1} x"}},
     {"render", "--size", "8x8", "--timings", "--probe", "@p.json", "--out", "@out/r.pfm"}, 2,
     "p.json: not a probe result: not one JSON object"},
    {"probe_json_fifo", {{"p.json", K_FIFO}}, {"probe", "--map-size", "64", "--json", "@p.json"}, 1,
     "p.json: output is a FIFO, not a regular file"},
    {"compare_exposure_zero", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm", "--exposure", "0"}, 2,
     "--exposure: '0' is out of range"},
    /* strtod's other forms: hex, blanks, inf (settings had taken 0x10 as 16,
     * where --spp refused it) */
    {"setting_hex", {{0}}, {"render", "--size", "8x8", "--rsm-samples", "0x10", "--out", "@out/r.png"}, 2,
     "--rsm-samples: '0x10' is not a number"},
    {"setting_blank", {{0}}, {"render", "--size", "8x8", "--rsm-samples", " 7", "--out", "@out/r.png"}, 2,
     "--rsm-samples: ' 7' is not a number"},
    {"exposure_hex_float", {{0}}, {"render", "--size", "8x8", "--exposure", "0x1p1", "--out", "@out/r.png"}, 2,
     "--exposure: '0x1p1' is not a number"},
    {"render_exposure_zero", {{0}}, {"render", "--size", "8x8", "--exposure", "0", "--out", "@out/r.png"}, 2,
     "--exposure: '0' is out of range"},
    /* ---- compare inputs ---- */
    /* ---- outputs that name one file, or an input ---- */
    {"render_out_is_png", {{NULL}}, {"render", "--size", "8x8", "--out", "@out/r.png", "--png", "@out/r.png"}, 2,
     "--out and --png name the same file"},
    {"reference_out_is_variance", {{NULL}}, {"reference", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm",
                                             "--variance", "@out/r.pfm"}, 2, "--out and --variance name the same file"},
    {"compare_heatmap_is_input", {{"a.png", K_TEXT, "x"}, {"b.pfm", K_PFM8}}, {"compare", "@a.png", "@b.pfm", "--heatmap", "@a.png"}, 2,
     "--heatmap and TEST name the same file"},
    {"compare_heatmap_not_png", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm", "--heatmap", "@out/h.pfm"}, 2,
     "--heatmap: '"},
    {"probe_json_directory", {{"p.json", K_DIR}}, {"probe", "--map-size", "64", "--json", "@p.json"}, 1,
     "p.json: output is a directory"},
    {"compare_fifo", {{"a.pfm", K_FIFO}, {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm"}, 1,
     "a.pfm: image is a FIFO"},
    {"compare_fifo_png", {{"a.pfm", K_PFM8}, {"b.png", K_FIFO}}, {"compare", "@a.pfm", "@b.png"}, 1,
     "b.png: image is a FIFO"},
    {"compare_directory", {{"a.pfm", K_DIR}, {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm"}, 1,
     "a.pfm: image is a directory"},
    {"compare_device", {{"b.pfm", K_PFM8}}, {"compare", "/dev/zero", "@b.pfm"}, 1, "/dev/zero: image is a character device"},
    {"compare_mask_fifo", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8}, {"m.png", K_FIFO}},
     {"compare", "@a.pfm", "@b.pfm", "--mask", "@m.png"}, 1, "m.png: image is a FIFO"},
    {"compare_nan", {{"a.pfm", K_PFM8_NAN}, {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm", "--json", "@out/j.json"},
     1, "a.pfm: 1 of 64 pixels are NaN or infinite (first at x=3 y=2); --allow-nonfinite"},
    {"compare_inf_reference", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8_INF}}, {"compare", "@a.pfm", "@b.pfm"}, 1,
     "b.pfm: 1 of 64 pixels are NaN or infinite"},
    {"compare_empty_mask", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8}, {"m.pfm", K_PFM8_ZERO}},
     {"compare", "@a.pfm", "@b.pfm", "--mask", "@m.pfm", "--json", "@out/j.json", "--heatmap", "@out/h.png"}, 1,
     "m.pfm: the mask selects no pixel"},
    {"compare_mask_size", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8}, {"m.pfm", K_PFM4}},
     {"compare", "@a.pfm", "@b.pfm", "--mask", "@m.pfm"}, 1, "m.pfm: mask is 4x4, images are 8x8"},
    {"compare_size_mismatch", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM4}}, {"compare", "@a.pfm", "@b.pfm"}, 1,
     "sizes must match"},
    {"pfm_header_huge", {{"a.pfm", K_TEXT, "PF\n65536 65536\n-1.0\n"}, {"b.pfm", K_PFM8}},
     {"compare", "@a.pfm", "@b.pfm"}, 1, "a.pfm: PFM data truncated"},
    {"pfm_too_wide", {{"a.pfm", K_TEXT, "PF\n70000 1\n-1.0\n"}, {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm"}, 1,
     "a.pfm: not an RGB PFM file"},
    {"pfm_negative_size", {{"a.pfm", K_TEXT, "PF\n-8 8\n-1.0\n"}, {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm"}, 1,
     "not an RGB PFM file"},
    {"pfm_grey", {{"a.pfm", K_TEXT, "Pf\n1 1\n-1.0\n\0\0\0\0"}, {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm"}, 1,
     "a.pfm: not an RGB PFM file"},
    {"pfm_scale_nan", {{"a.pfm", K_TEXT, "PF\n1 1\nnan\n"}, {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm"}, 1,
     "not an RGB PFM file"},
    {"pfm_big_endian", {{"a.pfm", K_TEXT, BIN("PF\n1 1\n1.0\n\0\0\0\0\0\0\0\0\0\0\0\0")}, {"b.pfm", K_PFM8}},
     {"compare", "@a.pfm", "@b.pfm"}, 1, "big-endian PFM is not supported"},
    {"pfm_empty", {{"a.pfm", K_TEXT, ""}, {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm"}, 1, "a.pfm: not an RGB PFM"},
    /* sscanf's %d had wrapped 4294967297 to 1 and read a 1x1 image */
    {"pfm_width_overflow", {{"a.pfm", K_TEXT, BIN("PF\n4294967297 1\n-1.0\n\0\0\x80?\0\0\x80?\0\0\x80?")},
                            {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm"}, 1, "a.pfm: not an RGB PFM file"},
    {"pfm_trailing_bytes", {{"a.pfm", K_TEXT, BIN("PF\n1 1\n-1.0\n\0\0\x80?\0\0\x80?\0\0\x80?\0\0\0\0")},
                            {"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm"}, 1,
     "a.pfm: 4 bytes after the PFM's 1x1 pixels (a wrong size in its header?)"},
    {"png_garbage", {{"a.png", K_TEXT, "not a png"}, {"b.pfm", K_PFM8}}, {"compare", "@a.png", "@b.pfm"}, 1,
     "a.png: cannot read image"},
    {"png_huge", {{"a.png", K_PNG_HUGE}, {"b.pfm", K_PFM8}}, {"compare", "@a.png", "@b.pfm"}, 1,
     "a.png: image is 17000x17000, more than the limit"},
    /* stb_image read these 20 bytes as a TGA of 2^27 pixels (fuzz_image timeout) */
    {"image_headerless_bomb", {{"a.png", K_TEXT, BIN("\x00\x00\x0b\x0b\x96\x0b\x0b\x0b\x0b\x0b\x0b\xf5\x7b\xf4\xfc\x0b\x0f\x0b\x96")},
                               {"b.pfm", K_PFM8}}, {"compare", "@a.png", "@b.pfm"}, 1, "a.png: cannot read image (not a PNG or JPEG"},
    /* a PNG cut after its signature and IHDR's start: stb_image's own reason
     * ("IDA", "") had been all the line said */
    {"png_truncated", {{"a.png", K_TEXT, BIN("\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x08")}, {"b.pfm", K_PFM8}},
     {"compare", "@a.png", "@b.pfm"}, 1, "a.png: cannot read image (corrupt or truncated PNG data; stb_image: "},
    /* a newline in a path is escaped: one error, one line (it had split
     * the line and could forge another) */
    {"out_name_with_newline", {{"f", K_TEXT, "x"}}, {"render", "--size", "8x8", "--out", "@f/a\nrtgi: info b.pfm"}, 1,
     "f/a\\nrtgi: info b.pfm: cannot create output file (Not a directory)"},
    {"compare_missing", {{"b.pfm", K_PFM8}}, {"compare", "@a.pfm", "@b.pfm"}, 1, "a.pfm: cannot read image: it does not exist"},
    /* ---- outputs: never partial, never "wrote" after a failure ---- */
    {"render_out_full_device", {{"full.pfm", K_SYMLINK, "/dev/full"}},
     {"render", "--size", "8x8", "--out", "@full.pfm"}, 1, "full.pfm: output is a character device"},
    {"render_out_fifo", {{"o.pfm", K_FIFO}}, {"render", "--size", "8x8", "--out", "@o.pfm"}, 1,
     "o.pfm: output is a FIFO"},
    {"render_out_directory", {{"o.png", K_DIR}}, {"render", "--size", "8x8", "--out", "@o.png"}, 1,
     "o.png: output is a directory"},
    {"render_out_no_parent", {{0}}, {"render", "--size", "8x8", "--out", "@out/a/b/r.pfm"}, 1,
     "r.pfm: cannot create output file"},
    {"render_disk_full_pfm", {{0}}, {"render", "--size", "8x8", "--out", "@out/r.pfm"}, 1,
     "r.pfm: write failed (File too large)", 200},
    {"render_disk_full_png", {{0}}, {"render", "--size", "64x64", "--out", "@out/r.png"}, 1,
     "r.png: write failed", 100},
    {"render_png_fails_removes_out", {{"p.png", K_FIFO}},
     {"render", "--size", "8x8", "--out", "@out/r.pfm", "--png", "@p.png"}, 1, "p.png: output is a FIFO"},
    {"reference_disk_full", {{0}}, {"reference", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm"}, 1,
     "r.pfm: write failed (File too large)", 200},
    {"reference_variance_fails", {{"v.pfm", K_DIR}},
     {"reference", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm", "--png", "@out/r.png", "--variance", "@v.pfm"},
     1, "v.pfm: output is a directory"},
    {"reference_png_fails", {{"p.png", K_SYMLINK, "/dev/full"}},
     {"reference", "--size", "8x8", "--spp", "1", "--out", "@out/r.pfm", "--png", "@p.png"}, 1,
     "p.png: output is a character device"},
    {"compare_json_directory", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8}, {"j.json", K_DIR}},
     {"compare", "@a.pfm", "@b.pfm", "--json", "@j.json", "--heatmap", "@out/h.png"}, 1, "j.json: output is a directory"},
    {"compare_heatmap_fifo", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8}, {"h.png", K_FIFO}},
     {"compare", "@a.pfm", "@b.pfm", "--heatmap", "@h.png"}, 1, "h.png: output is a FIFO"},
    {"compare_disk_full", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8}},
     {"compare", "@a.pfm", "@b.pfm", "--heatmap", "@out/h.png", "--json", "@out/j.json"}, 1, "h.png: write failed", 60},
    {"compare_heatmap_full_device", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8}, {"h.png", K_SYMLINK, "/dev/full"}},
     {"compare", "@a.pfm", "@b.pfm", "--heatmap", "@h.png", "--json", "@out/j.json"}, 1, "h.png: output is a character device"},
    {"compare_json_disk_full", {{"a.pfm", K_PFM8}, {"b.pfm", K_PFM8}},
     {"compare", "@a.pfm", "@b.pfm", "--json", "@out/j.json"}, 1, "j.json: write failed", 20},
    /* ---- sizes and allocations ---- */
    /* 16384² (the largest --size) needs 15 GiB of buffers: refused on a
     * machine of less than 30 GiB (CI's 24), path-traced on more (an hour
     * of a 128 GiB GPU machine's 16 cores). */
    {"reference_size_huge", {{0}}, {"reference", "--size", "16384x16384", "--out", "@out/r.pfm"}, 1,
     "--size 16384x16384: the reference needs", 0, 15.0},
    {"reference_variance_png", {{0}}, {"reference", "--size", "8x8", "--variance", "@out/v.png"}, 2,
     "--variance: '"},
};

/* ------------------------------------------------------------ harness */

static char g_root[600];

static void write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
}

static void write_pfm(const char *path, int w, int h, float fill, float special)
{
    char head[64];
    int n = snprintf(head, sizeof head, "PF\n%d %d\n-1.0\n", w, h);
    size_t count = (size_t)w * h * 3;
    float *px = malloc(count * sizeof(float));
    assert_non_null(px);
    for (size_t i = 0; i < count; i++)
        px[i] = fill * (float)(i % 7) / 7.f;
    if (special != 0.f) /* pixel x=3, y=2 from the top: file row h-1-2 */
        px[3 * ((size_t)(h - 1 - 2) * w + 3) + 1] = special;
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fwrite(head, 1, (size_t)n, f);
    fwrite(px, sizeof(float), count, f);
    fclose(f);
    free(px);
}

static void make_file(const char *dir, const InFile *in)
{
    char path[800];
    assert_true(snprintf(path, sizeof path, "%s/%s", dir, in->name) < (int)sizeof path);
    switch (in->kind) {
    case K_TEXT:
        write_bytes(path, in->content, in->len ? in->len : strlen(in->content));
        break;
    case K_FIFO:
        assert_int_equal(mkfifo(path, 0600), 0);
        break;
    case K_DIR:
        assert_int_equal(mkdir(path, 0700), 0);
        break;
    case K_SYMLINK:
        assert_int_equal(symlink(in->content, path), 0);
        break;
    case K_PFM8:
        write_pfm(path, 8, 8, 1.f, 0.f);
        break;
    case K_PFM8_NAN:
        write_pfm(path, 8, 8, 1.f, NAN);
        break;
    case K_PFM8_INF:
        write_pfm(path, 8, 8, 1.f, INFINITY);
        break;
    case K_PFM8_ZERO:
        write_pfm(path, 8, 8, 0.f, 0.f);
        break;
    case K_PFM4:
        write_pfm(path, 4, 4, 1.f, 0.f);
        break;
    case K_PNG_HUGE: { /* signature and IHDR only: 17000x17000 RGB, under stb's own limit */
        static const unsigned char png[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D',
                                            'R', 0, 0, 0x42, 0x68, 0, 0, 0x42, 0x68, 8, 2, 0, 0, 0, 0, 0, 0, 0};
        write_bytes(path, png, sizeof png);
        break;
    }
    case K_MANY_LIGHTS:
    case K_MANY_KEYS: {
        StrBuf b = {0};
        strbuf_printf(&b, "{\"builtin\": \"cornell\"");
        if (in->kind == K_MANY_LIGHTS) {
            strbuf_printf(&b, ", \"lights\": [");
            for (int i = 0; i < 33; i++)
                strbuf_printf(&b, "%s{\"type\": \"point\", \"position\": [0.2, 0.4, 0.2], \"intensity\": 0.01}",
                              i ? ", " : "");
            strbuf_printf(&b, "]}");
        } else {
            strbuf_printf(&b, ", \"camera\": {");
            for (int i = 0; i < 300; i++)
                strbuf_printf(&b, "%s\"k%d\": %d", i ? ", " : "", i, i);
            strbuf_printf(&b, "}}");
        }
        write_bytes(path, b.data, b.len);
        free(b.data);
        break;
    }
    }
}

static void remove_tree(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0)
        return;
    if (S_ISDIR(st.st_mode)) {
        DIR *d = opendir(path);
        struct dirent *e;
        while (d && (e = readdir(d))) {
            if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
                continue;
            char sub[1200];
            snprintf(sub, sizeof sub, "%s/%s", path, e->d_name);
            remove_tree(sub);
        }
        if (d)
            closedir(d);
        rmdir(path);
    } else {
        unlink(path);
    }
}

/* Names of the entries of `dir` (comma-separated into buf); their count. */
static int list_dir(const char *dir, char *buf, size_t cap)
{
    buf[0] = 0;
    int n = 0;
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d && (e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        strncat(buf, e->d_name, cap - strlen(buf) - 1);
        strncat(buf, " ", cap - strlen(buf) - 1);
        n++;
    }
    if (d)
        closedir(d);
    return n;
}

/* Runs rtgi with argv and returns its exit status, stderr in *err (caller
 * frees). stderr goes through a pipe, which RLIMIT_FSIZE does not limit; a
 * watchdog alarm turns a hang into a failure (exit 128 + SIGALRM). */
static int run_case(const char *const *argv, long fsize_limit, char **err)
{
    int fds[2];
    assert_int_equal(pipe(fds), 0);
    pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        if (dup2(fds[1], 2) < 0 || !freopen("/dev/null", "w", stdout))
            _exit(127);
        if (fsize_limit > 0) {
            struct rlimit rl = {(rlim_t)fsize_limit, (rlim_t)fsize_limit};
            signal(SIGXFSZ, SIG_IGN); /* writes then fail with EFBIG */
            setrlimit(RLIMIT_FSIZE, &rl);
        }
        alarm(120);
        execv(RTGI_BINARY, (char *const *)argv);
        _exit(127);
    }
    close(fds[1]);
    StrBuf b = {0};
    strbuf_append(&b, "", 0);
    char chunk[4096];
    ssize_t r;
    while ((r = read(fds[0], chunk, sizeof chunk)) != 0) {
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0)
            break;
        strbuf_append(&b, chunk, (size_t)r);
    }
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    *err = b.data;
    if (WIFSIGNALED(status))
        return 128 + WTERMSIG(status);
    return WEXITSTATUS(status);
}

static void bad_input_case(void **state)
{
    const Case *c = *state;
    double half_gib = (double)util_physical_memory() / 2 / 1073741824.0;
    if (c->need_gib > 0 && half_gib > 0 && c->need_gib <= half_gib) {
        print_message("%s: not a refusal on this machine (%.1f GiB needed, half its memory is %.1f GiB)\n", c->name,
                      c->need_gib, half_gib);
        return;
    }
    char dir[800], out[900];
    snprintf(dir, sizeof dir, "%s/%s", g_root, c->name);
    remove_tree(dir);
    assert_int_equal(mkdir(dir, 0700), 0);
    snprintf(out, sizeof out, "%s/out", dir);
    assert_int_equal(mkdir(out, 0700), 0);
    for (int i = 0; i < 3 && c->files[i].name; i++)
        make_file(dir, &c->files[i]);

    char argbuf[16][900];
    const char *argv[18];
    int n = 0;
    argv[n++] = RTGI_BINARY;
    for (int i = 0; i < 16 && c->args[i]; i++) {
        if (c->args[i][0] == '@') {
            snprintf(argbuf[i], sizeof argbuf[i], "%s/%s", dir, c->args[i] + 1);
            argv[n++] = argbuf[i];
        } else {
            argv[n++] = c->args[i];
        }
    }
    argv[n] = NULL;
    char *err = NULL;
    int rc = run_case(argv, c->fsize_limit, &err);
    const char *e = err ? err : "";
    char left[512];
    int nleft = list_dir(out, left, sizeof left);
    size_t lines = 0;
    for (const char *p = e; *p; p++)
        lines += *p == '\n';
    bool ok = rc == c->want_rc && lines == 1 && strstr(e, c->want) && strncmp(e, "rtgi: error [", 13) == 0 &&
              nleft == 0 && !strstr(e, "wrote");
    if (!ok)
        fail_msg("case %s: exit %d (want %d), %zu stderr lines (want 1), stderr: %s(want '%s'), left in out/: [%s]",
                 c->name, rc, c->want_rc, lines, e, c->want, left);
    free(err);
    remove_tree(dir);
}

/* ------------------------------------------------ behaviour that passes */

/* --lenient: an unknown key is a warning and the render succeeds. */
static void lenient_unknown_key_is_warning(void **state)
{
    (void)state;
    char path[700], out[700];
    snprintf(path, sizeof path, "%s/lenient.json", g_root);
    snprintf(out, sizeof out, "%s/lenient.pfm", g_root);
    write_bytes(path, "{\"builtin\": \"cornell\", \"camrea\": 1}", 35);
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--lenient", "--scene", path, "--size", "8x8", "--out", out, NULL);
    if (rc != 0 || !err || !strstr(err, "warning [scene]") || !strstr(err, "camrea"))
        fail_msg("exit %d, stderr: %s", rc, err ? err : "");
    free(err);
    unlink(out);
    unlink(path);
}

/* A black image is written (a camera may rightly see nothing lit) but
 * never silently: render and reference warn, naming the file. The scene: a
 * spot light in front of the Cornell box, turned away from it. A flat scene's
 * default camera looks down on it rather than along it (one quad, lit by
 * the default sun): no warning, a lit image. */
static void black_image_is_reported(void **state)
{
    (void)state;
    char scene[700], flat[700], out[700];
    snprintf(scene, sizeof scene, "%s/black.json", g_root);
    snprintf(flat, sizeof flat, "%s/flat.json", g_root);
    snprintf(out, sizeof out, "%s/black.pfm", g_root);
    const char *json = "{\"builtin\": \"cornell\", \"lights\": [{\"type\": \"spot\", \"position\": [0.278, 0.3, -0.5], "
                       "\"direction\": [0, 0, -1], \"intensity\": 1, \"inner_deg\": 20, \"outer_deg\": 30}]}";
    write_bytes(scene, json, strlen(json));
    const char *cmds[2][12] = {
        {"render", "--scene", scene, "--size", "16x16", "--gi", "none", "--shadow", "hard", "--out", out, NULL},
        {"reference", "--scene", scene, "--size", "16x16", "--spp", "1", "--out", out, NULL}};
    for (int k = 0; k < 2; k++) {
        char *err = NULL;
        int rc = test_run_cli(&err, cmds[k][0], cmds[k][1], cmds[k][2], cmds[k][3], cmds[k][4], cmds[k][5],
                              cmds[k][6], cmds[k][7], cmds[k][8], cmds[k][9], cmds[k][10], NULL);
        if (rc != 0 || !err || !strstr(err, "warning [") || !strstr(err, "black.pfm: the image is black"))
            fail_msg("%s: exit %d, stderr: %s", cmds[k][0], rc, err ? err : "");
        free(err);
        ImageF img = {0};
        assert_true(image_read_pfm(out, &img));
        assert_true(test_image_mean(&img) == 0.0);
        image_free(&img);
        unlink(out);
    }
    json = "{\"quads\": [{\"vertices\": [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]]}]}";
    write_bytes(flat, json, strlen(json));
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--scene", flat, "--size", "16x16", "--out", out, NULL);
    if (rc != 0 || (err && strstr(err, "the image is black")))
        fail_msg("flat scene: exit %d, stderr: %s", rc, err ? err : "");
    free(err);
    ImageF img = {0};
    assert_true(image_read_pfm(out, &img));
    double mean = test_image_mean(&img);
    print_message("one flat quad from the default camera: mean radiance %g\n", mean);
    assert_true(mean > 0.1);
    image_free(&img);
    unlink(out);
    unlink(scene);
    unlink(flat);
}

/* compare --allow-nonfinite: the metrics may be NaN; --json is still valid
 * JSON (null for them) and escapes a file name with quotes. */
static void compare_json_is_valid(void **state)
{
    (void)state;
    char a[700], b[700], json[700];
    snprintf(a, sizeof a, "%s/we \"quote\" \\ it.pfm", g_root);
    snprintf(b, sizeof b, "%s/ref.pfm", g_root);
    snprintf(json, sizeof json, "%s/out.json", g_root);
    write_pfm(a, 8, 8, 1.f, NAN);
    write_pfm(b, 8, 8, 1.f, 0.f);
    char *err = NULL;
    int rc = test_run_cli(&err, "compare", a, b, "--allow-nonfinite", "--json", json, NULL);
    if (rc != 0)
        fail_msg("exit %d, stderr: %s", rc, err ? err : "");
    free(err);
    char *text = util_read_file(json, NULL);
    assert_non_null(text);
    cJSON *root = cJSON_Parse(text);
    if (!root)
        fail_msg("not JSON: %s", text);
    assert_string_equal(cJSON_GetObjectItem(root, "test")->valuestring, a);
    assert_true(cJSON_IsNull(cJSON_GetObjectItem(root, "rmse")));
    cJSON_Delete(root);
    free(text);
    unlink(a);
    unlink(b);
    unlink(json);
}

/* ---------------------------------------------- the helpers, in-process */

/* util_utf8_sanitize keeps valid UTF-8 and replaces what util_json_string
 * writes as \ufffd (a stray or truncated sequence, one U+FFFD a byte). */
static void utf8_sanitize(void **state)
{
    (void)state;
    static const char *const cases[][2] = {
        {"plain/path.json", "plain/path.json"},
        {"caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80", "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80"},
        {"na\xffme", "na\xef\xbf\xbdme"},
        {"\xc3", "\xef\xbf\xbd"},
        {"\xe2\x82x", "\xef\xbf\xbd\xef\xbf\xbdx"},
        {"\xc0\xaf", "\xef\xbf\xbd\xef\xbf\xbd"}, /* overlong '/' */
        {"", ""},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *t = util_utf8_sanitize(cases[i][0]);
        assert_non_null(t);
        assert_string_equal(t, cases[i][1]);
        free(t);
    }
}

static void writers_refuse_nonfinite(void **state)
{
    (void)state;
    ImageF img;
    assert_true(image_alloc(&img, 4, 4));
    image_px(&img, 1, 2)[0] = NAN;
    char path[700];
    snprintf(path, sizeof path, "%s/nan.pfm", g_root);
    LogLevel lv = log_get_level();
    log_set_level(LOG_QUIET);
    assert_false(image_write_pfm(path, &img));
    assert_int_equal(access(path, F_OK), -1);
    snprintf(path, sizeof path, "%s/nan.png", g_root);
    assert_false(image_write_png(path, &img, 1.f));
    assert_int_equal(access(path, F_OK), -1);
    image_px(&img, 1, 2)[0] = 0.f;
    assert_true(image_write_png(path, &img, 1.f));
    assert_int_equal(access(path, F_OK), 0);
    unlink(path);
    assert_int_equal(image_count_nonfinite(&img, NULL, NULL), 0);
    image_free(&img);
    ImageF big;
    assert_false(image_alloc(&big, 1 << 15, 1 << 15)); /* over IMAGE_MAX_PIXELS: refused, not attempted */
    assert_null(big.rgb);
    log_set_level(lv);
}

static void atomic_abort_leaves_nothing(void **state)
{
    (void)state;
    char path[700];
    snprintf(path, sizeof path, "%s/atomic.txt", g_root);
    write_bytes(path, "old", 3);
    AtomicFile af;
    assert_true(util_atomic_open(&af, "test", path));
    fputs("new", af.f);
    util_atomic_abort(&af);
    char *text = util_read_file(path, NULL);
    assert_string_equal(text, "old"); /* untouched */
    free(text);
    assert_true(util_atomic_open(&af, "test", path));
    fputs("new", af.f);
    assert_true(util_atomic_commit(&af, "test"));
    text = util_read_file(path, NULL);
    assert_string_equal(text, "new");
    free(text);
    unlink(path);
}

static void nearest_and_keys(void **state)
{
    (void)state;
    static const char *const names[] = {"position", "target", "fov_y_deg", NULL};
    assert_int_equal(util_edit_distance("kitten", "sitting"), 3);
    assert_int_equal(util_edit_distance("", "abc"), 3);
    /* Optimal string alignment: a swapped pair is one edit (Levenshtein:
     * two), but a swapped pair is not edited again ("ca" -> "abc" is 3,
     * unrestricted Damerau-Levenshtein 2). */
    assert_int_equal(util_edit_distance("pfc", "pcf"), 1);
    assert_int_equal(util_edit_distance("ab", "ba"), 1);
    assert_int_equal(util_edit_distance("ca", "abc"), 3);
    static const char *const shadows[] = {"none", "hard", "pcf", "pcss", NULL};
    assert_string_equal(util_nearest("pfc", shadows), "pcf");
    assert_string_equal(util_nearest("positon", names), "position");
    assert_string_equal(util_nearest("fov_y_dg", names), "fov_y_deg");
    assert_null(util_nearest("zzzzzzzzz", names));
    cJSON *ok = cJSON_Parse("{\"position\": 1, \"target\": 2}");
    cJSON *dup = cJSON_Parse("{\"position\": 1, \"position\": 2}");
    cJSON *unk = cJSON_Parse("{\"positon\": 1}");
    LogLevel lv = log_get_level();
    log_set_level(LOG_QUIET);
    assert_true(json_check_keys(ok, names, "f.json", "camera"));
    assert_false(json_check_keys(dup, names, "f.json", "camera"));
    assert_false(json_check_keys(unk, names, "f.json", "camera"));
    json_set_lenient(true);
    assert_true(json_check_keys(unk, names, "f.json", "camera"));
    assert_false(json_check_keys(dup, names, "f.json", "camera")); /* duplicates stay errors */
    json_set_lenient(false);
    log_set_level(lv);
    cJSON_Delete(ok);
    cJSON_Delete(dup);
    cJSON_Delete(unk);
}

/* A well-formed binary glTF passes mesh_check_glb: one triangle, its
 * JSON and BIN chunks padded to 4 bytes as the format asks. */
static void valid_glb_loads(void **state)
{
    (void)state;
    static const char js[] = "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
                             "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":"
                             "{\"POSITION\":0}}]}],\"buffers\":[{\"byteLength\":36}],\"bufferViews\":"
                             "[{\"buffer\":0,\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,"
                             "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],"
                             "\"max\":[1,1,0]}]}";
    const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t jlen = (uint32_t)((sizeof js - 1 + 3) / 4 * 4), total = 12 + 8 + jlen + 8 + 36;
    uint8_t glb[1024] = {0};
    assert_true(total <= sizeof glb);
    uint32_t head[5] = {0x46546c67u, 2, total, jlen, 0x4e4f534au}; /* "glTF", 2, length; JSON chunk */
    memcpy(glb, head, sizeof head);
    memset(glb + 20, ' ', jlen);
    memcpy(glb + 20, js, sizeof js - 1);
    uint32_t bin[2] = {36, 0x004e4942u}; /* BIN chunk */
    memcpy(glb + 20 + jlen, bin, sizeof bin);
    memcpy(glb + 28 + jlen, tri, sizeof tri);
    char path[800];
    snprintf(path, sizeof path, "%s/valid.glb", g_root);
    write_bytes(path, glb, total);
    Scene s;
    scene_init(&s);
    mat4 id = GLM_MAT4_IDENTITY_INIT;
    assert_true(scene_load_mesh(&s, path, id));
    assert_int_equal(s.index_count, 3);
    scene_free(&s);
    unlink(path);
}

int main(void)
{
    snprintf(g_root, sizeof g_root, "%s/badinput", RTGI_TEST_TMP);
    remove_tree(g_root);
    mkdir(g_root, 0700);
    enum { N = sizeof k_cases / sizeof k_cases[0] };
    struct CMUnitTest tests[N + 8];
    for (int i = 0; i < N; i++)
        tests[i] = (struct CMUnitTest){k_cases[i].name, bad_input_case, NULL, NULL, (void *)&k_cases[i]};
    tests[N + 0] = (struct CMUnitTest)cmocka_unit_test(lenient_unknown_key_is_warning);
    tests[N + 1] = (struct CMUnitTest)cmocka_unit_test(compare_json_is_valid);
    tests[N + 2] = (struct CMUnitTest)cmocka_unit_test(writers_refuse_nonfinite);
    tests[N + 3] = (struct CMUnitTest)cmocka_unit_test(atomic_abort_leaves_nothing);
    tests[N + 4] = (struct CMUnitTest)cmocka_unit_test(nearest_and_keys);
    tests[N + 5] = (struct CMUnitTest)cmocka_unit_test(valid_glb_loads);
    tests[N + 6] = (struct CMUnitTest)cmocka_unit_test(black_image_is_reported);
    tests[N + 7] = (struct CMUnitTest)cmocka_unit_test(utf8_sanitize);
    int failed = _cmocka_run_group_tests("badinput", tests, N + 8, NULL, NULL);
    if (!failed)
        remove_tree(g_root);
    return failed;
}
