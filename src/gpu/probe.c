/* probe.c — the device probe (see probe.h). */
#include "gpu/probe.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "gl/gl_resources.h"
#include "base/log.h"
#include "gl/shader.h"
#include "shared/gpu_types.h"
#include "gpu/targets.h"
#include "base/util.h"

enum { GRID = 256, SAMPLES = 64, RUNS = 5, MAPS = 4 };

/* A kernel's work is GRID² lanes per layer (each layer reads the maps in the
 * same pattern, shifted), and its timed dispatch is made of as many layers
 * as it takes to last MIN_DISPATCH_S: llvmpipe takes tens of ms over one
 * layer of a fetch kernel, a GPU microseconds, with 65,536 lanes too few to
 * fill it and its submission latency as long as the work. MAX_LAYERS
 * layers: 4 M lanes, twice a 1080p gather's. */
enum { MAX_LAYERS = 64 };
#define MIN_DISPATCH_S 4e-3

/* A map of plausible RSM data: positions near the receivers, unit normals,
 * flux (maps 0..2, RGBA32F); map 3 the same packed as RSM texels
 * (shaders/common/rsm_texel.glsl, in the unit box: position u, v, 0 at
 * 2^21 − 1 steps, normal +z, flux (1, 1, 1) in RGB9E5). */
static GLuint make_map(GLenum target, int which, int size)
{
    bool packed = which == 3;
    float *texels = util_malloc("probe", "a probe map", 4 * (size_t)size * (size_t)size, sizeof(float));
    if (!texels) /* logged */
        return 0;
    uint32_t *words = (uint32_t *)texels;
    for (int i = 0; i < size * size; i++) {
        float u = (float)(i % size) / (float)size, v = (float)(i / size) / (float)size;
        float *t = texels + 4 * i;
        if (which == 0) { t[0] = u; t[1] = v; t[2] = 0.f; t[3] = 1.f; }
        else if (which == 1) { t[0] = 0.f; t[1] = 0.f; t[2] = 1.f; t[3] = 0.f; }
        else if (which == 2) { t[0] = u; t[1] = v; t[2] = 1.f; t[3] = 1.f; }
        else {
            uint32_t qx = (uint32_t)(u * 2097151.f + 0.5f), qy = (uint32_t)(v * 2097151.f + 0.5f);
            words[4 * i + 0] = qx | (qy << 21);
            words[4 * i + 1] = (qy >> 11) | 0x80000000u; /* z = 0, a surface */
            words[4 * i + 2] = 32768u | (32768u << 16);  /* octahedral (0, 0): +z */
            words[4 * i + 3] = 256u | (256u << 9) | (256u << 18) | (16u << 27); /* 1.0 per channel */
        }
    }
    GLuint tex = gl_texture_make(target, packed ? GL_RGBA32UI : GL_RGBA32F, size, size, "probe.map");
    if (tex) {
        GLenum format = packed ? GL_RGBA_INTEGER : GL_RGBA, type = packed ? GL_UNSIGNED_INT : GL_FLOAT;
        if (target == GL_TEXTURE_CUBE_MAP) /* the faces are layers 0-5 */
            for (int f = 0; f < 6; f++)
                glTextureSubImage3D(tex, 0, 0, 0, f, size, size, 1, format, type, texels);
        else /* a 2D map takes the 2D call: the 3D one is GL_INVALID_OPERATION there, and wrote nothing */
            glTextureSubImage2D(tex, 0, 0, 0, size, size, format, type, texels);
    }
    free(texels);
    return tex;
}

/* Wall time of one dispatch of `layers` layers, finished. */
static double dispatch_seconds(int layers)
{
    glFinish();
    double t0 = util_seconds();
    glDispatchCompute(GRID / 8, GRID / 8, (GLuint)layers);
    glFinish();
    return util_seconds() - t0;
}

/* Best of RUNS timed dispatches, in evaluations/s, after a warm-up dispatch
 * (llvmpipe compiles a kernel at its first) and as many doublings of the
 * layers as it takes for one to last MIN_DISPATCH_S; out->lanes keeps the
 * fewest invocations of a timed dispatch. */
static double time_kernel(GLuint program, ProbeResult *out)
{
    glUseProgram(program);
    int layers = 1;
    dispatch_seconds(layers);
    while (dispatch_seconds(layers) < MIN_DISPATCH_S && layers < MAX_LAYERS)
        layers *= 2;
    double best = 0;
    for (int run = 0; run < RUNS; run++) {
        double dt = dispatch_seconds(layers);
        double rate = (double)GRID * GRID * layers * SAMPLES / (dt > 1e-9 ? dt : 1e-9);
        if (rate > best)
            best = rate;
    }
    double lanes = (double)GRID * GRID * layers;
    if (out->lanes == 0 || lanes < out->lanes)
        out->lanes = lanes;
    return best;
}

bool probe_run(ProbeResult *out, int map_size)
{
    memset(out, 0, sizeof *out);
    int size = map_size <= 0 ? PROBE_MAP_DEFAULT : map_size < 64 ? 64 : map_size > PROBE_MAP_MAX ? PROBE_MAP_MAX : map_size;
    out->map_size = size;
    GLuint maps[2][MAPS] = {{0}};
    bool ok = true;
    for (int c = 0; c < 2 && ok; c++)
        for (int k = 0; k < MAPS && ok; k++)
            ok = (maps[c][k] = make_map(c ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D, k, size)) != 0;
    /* The kernels' sink: a layer per dispatch layer, one float per lane. */
    GLuint result = 0;
    if (ok) {
        glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &result);
        glTextureStorage3D(result, 1, GL_R32F, GRID, GRID, MAX_LAYERS);
        glObjectLabel(GL_TEXTURE, result, -1, "probe.result");
        GLint made = GL_FALSE; /* storage that could not be made leaves the texture mutable */
        glGetTextureParameteriv(result, GL_TEXTURE_IMMUTABLE_FORMAT, &made);
        ok = made == GL_TRUE;
        if (!ok)
            log_error("probe", "cannot allocate the probe's result image (%dx%dx%d R32F)", GRID, GRID, MAX_LAYERS);
    }
    ProgramCache pc;
    program_cache_create(&pc);
    for (int c = 0; c < 2 && ok; c++) {
        for (int k = 0; k < MAPS; k++)
            glBindTextureUnit((GLuint)(TEX_PROBE_MAP + k), maps[c][k]);
        glBindImageTexture(IMG_OUT, result, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R32F);
        for (int f = c ? 1 : 0; f <= 4 && ok; f++) { /* 4: one packed texel */
            char defs[128];
            snprintf(defs, sizeof defs, "#define GRID %d\n#define SAMPLES %d\n#define FETCHES %d\n%s%s", GRID, SAMPLES,
                     f > 3 ? 1 : f, c ? "#define CUBE\n" : "", f > 3 ? "#define PACKED\n" : "");
            GLuint prog = program_cache_get(&pc, &(ShaderProgramDesc){.label = "probe", .comp = "probe/probe.comp",
                                                                      .defines = defs});
            if (!prog) {
                ok = false;
                break;
            }
            double rate = time_kernel(prog, out);
            if (f > 3)
                *(c ? &out->evals_texel_cube : &out->evals_texel_2d) = rate;
            else if (c)
                out->evals_cube[f] = rate;
            else
                out->evals_2d[f] = rate;
        }
    }
    GpuVpl *data = ok ? util_calloc("probe", "the probe's VPLs", SAMPLES, sizeof(GpuVpl)) : NULL; /* logs */
    GLuint vpls = 0;
    if (data) {
        for (int k = 0; k < SAMPLES; k++) {
            gpu_vpl_set_position(&data[k], (const float[3]){(float)k / SAMPLES, 0.f, 0.f});
            data[k].surface[3] = 32768u | (32768u << 16); /* octahedral (0, 0): +z */
            data[k].normal_xi[2] = 1.f;
            data[k].flux[0] = data[k].flux[1] = data[k].flux[2] = 1.f;
        }
        vpls = gl_buffer_make(sizeof(GpuVpl) * SAMPLES, data, 0, "probe.vpls"); /* logs */
    }
    free(data);
    ok = ok && vpls;
    if (ok) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VPL, vpls);
        char defs[128];
        snprintf(defs, sizeof defs, "#define GRID %d\n#define SAMPLES %d\n#define FETCHES 0\n#define SSBO\n", GRID, SAMPLES);
        GLuint prog = program_cache_get(&pc, &(ShaderProgramDesc){.label = "probe", .comp = "probe/probe.comp",
                                                                  .defines = defs});
        ok = prog != 0;
        if (ok)
            out->evals_ssbo = time_kernel(prog, out);
    }
    glDeleteBuffers(1, &vpls);
    out->evals_cube[0] = out->evals_2d[0];
    program_cache_destroy(&pc);
    glDeleteTextures(1, &result);
    for (int c = 0; c < 2; c++)
        glDeleteTextures(MAPS, maps[c]);
    return ok;
}

double probe_bound(const ProbeResult *r, bool vpl, bool cube, double from_list, bool texel)
{
    if (vpl)
        return r->evals_ssbo;
    double tex = texel ? (cube ? r->evals_texel_cube : r->evals_texel_2d)
                       : cube ? r->evals_cube[PROBE_RSM_FETCHES] : r->evals_2d[PROBE_RSM_FETCHES];
    if (tex <= 0)
        return 0;
    /* Time per evaluation adds up over the two kinds of sample. */
    return 1.0 / ((1.0 - from_list) / tex + from_list / r->evals_ssbo);
}

void probe_print(FILE *out, const ProbeResult *r)
{
    fprintf(out, "probe_map_size: %d\n", r->map_size);
    if (r->lanes > 0)
        fprintf(out, "probe_lanes: %.0f\n", r->lanes);
    fprintf(out, "probe_arith_evals_per_s: %.4g\n", r->evals_2d[0]);
    for (int f = 1; f <= 3; f++)
        fprintf(out, "probe_2d_fetch%d_evals_per_s: %.4g\n", f, r->evals_2d[f]);
    for (int f = 1; f <= 3; f++)
        fprintf(out, "probe_cube_fetch%d_evals_per_s: %.4g\n", f, r->evals_cube[f]);
    if (r->evals_texel_2d > 0)
        fprintf(out, "probe_2d_texel_evals_per_s: %.4g\nprobe_cube_texel_evals_per_s: %.4g\n", r->evals_texel_2d,
                r->evals_texel_cube);
    fprintf(out, "probe_ssbo_vpl_evals_per_s: %.4g\n", r->evals_ssbo);
}

bool probe_write_json(const char *path, const ProbeResult *r)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddItemToObject(o, "evals_2d", cJSON_CreateDoubleArray(r->evals_2d, 4));
    cJSON_AddItemToObject(o, "evals_cube", cJSON_CreateDoubleArray(r->evals_cube, 4));
    cJSON_AddNumberToObject(o, "evals_ssbo", r->evals_ssbo);
    cJSON_AddNumberToObject(o, "evals_texel_2d", r->evals_texel_2d);
    cJSON_AddNumberToObject(o, "evals_texel_cube", r->evals_texel_cube);
    cJSON_AddNumberToObject(o, "map_size", r->map_size);
    cJSON_AddNumberToObject(o, "lanes", r->lanes);
    char *text = cJSON_Print(o);
    cJSON_Delete(o);
    if (!text) {
        log_error("probe", "%s: cannot allocate the probe result", path);
        return false;
    }
    bool ok;
    if (!strcmp(path, "-")) {
        ok = fputs(text, stdout) >= 0 && fputc('\n', stdout) != EOF && fflush(stdout) == 0;
        if (!ok)
            log_error("probe", "cannot write the probe result to stdout");
    } else {
        /* Atomically, as every output: refuses a FIFO or a device, leaves
         * nothing behind on an error. */
        AtomicFile af;
        ok = util_atomic_open(&af, "probe", path);
        if (ok) {
            if (fputs(text, af.f) < 0)
                af.failed = true;
            ok = util_atomic_commit(&af, "probe");
        }
    }
    free(text);
    return ok;
}

/* A count read from a probe result, `what` in `unit`s (a rate in
 * evaluations/s, a lane count in lanes): a number in [1, 1e18] (inf, 0 or
 * a denormal would print as a bound of inf or 0). `required` refuses a
 * missing key; a missing optional one reads as 0. */
static bool read_count(const char *path, const cJSON *o, const char *key, int index, bool required, const char *what,
                       const char *unit, double *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (index >= 0)
        v = cJSON_IsArray(v) && cJSON_GetArraySize(v) == 4 ? cJSON_GetArrayItem(v, index) : NULL;
    *out = 0;
    if (!v && !required)
        return true;
    char name[64];
    snprintf(name, sizeof name, index >= 0 ? "%s[%d]" : "%s", key, index);
    if (!cJSON_IsNumber(v)) {
        log_error("probe", "%s: not a probe result: %s: %s (write one with rtgi probe --json FILE)", path, name,
                  index >= 0 && !v ? "must be an array of 4 rates" : "missing or not a number");
        return false;
    }
    if (!(v->valuedouble >= 1 && v->valuedouble <= 1e18)) {
        log_error("probe", "%s: not a probe result: %s: %g is not %s (1 to 1e18 %s)", path, name, v->valuedouble,
                  what, unit);
        return false;
    }
    *out = v->valuedouble;
    return true;
}

bool probe_read_json(const char *path, ProbeResult *r)
{
    char *text = util_read_input("probe", "probe result", path, (size_t)1 << 20, NULL);
    if (!text)
        return false;
    cJSON *o = cJSON_ParseWithOpts(text, NULL, true); /* nothing after the object */
    free(text);
    if (!cJSON_IsObject(o)) {
        log_error("probe", "%s: not a probe result: not one JSON object (write one with rtgi probe --json FILE)",
                  path);
        cJSON_Delete(o);
        return false;
    }
    bool ok = true;
    for (int i = 0; ok && i < 4; i++)
        ok = read_count(path, o, "evals_2d", i, true, "a rate", "evaluations/s", &r->evals_2d[i]) &&
             read_count(path, o, "evals_cube", i, true, "a rate", "evaluations/s", &r->evals_cube[i]);
    /* Added later, so optional: an older result has no packed-texel rates
     * and lanes, and was measured on 512² maps. */
    ok = ok && read_count(path, o, "evals_ssbo", -1, true, "a rate", "evaluations/s", &r->evals_ssbo) &&
         read_count(path, o, "evals_texel_2d", -1, false, "a rate", "evaluations/s", &r->evals_texel_2d) &&
         read_count(path, o, "evals_texel_cube", -1, false, "a rate", "evaluations/s", &r->evals_texel_cube) &&
         read_count(path, o, "lanes", -1, false, "a lane count", "lanes", &r->lanes);
    const cJSON *ms = cJSON_GetObjectItemCaseSensitive(o, "map_size");
    r->map_size = PROBE_MAP_DEFAULT;
    if (ok && ms) {
        ok = cJSON_IsNumber(ms) && ms->valuedouble >= 64 && ms->valuedouble <= PROBE_MAP_MAX &&
             ms->valuedouble == (int)ms->valuedouble;
        if (ok)
            r->map_size = (int)ms->valuedouble;
        else
            log_error("probe", "%s: not a probe result: map_size: must be a whole number of texels in [64, %d]", path,
                      PROBE_MAP_MAX);
    }
    cJSON_Delete(o);
    return ok;
}
