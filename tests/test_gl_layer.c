/* test_gl_layer.c — the GL layer the volume techniques build on: geometry
 * stages, the program cache and its hot reload, 3D textures with mips as
 * layered images, attachment-less framebuffers, the live-object census and
 * the timer's debug groups. Shaders are written by the test into a scratch
 * directory that the loader reads instead of the embedded copies, so the
 * reload test can edit them. Runs on Mesa llvmpipe. */
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "gl/gl_resources.h"
#include "gl/gpu_timer.h"
#include "base/log.h"
#include "gl/shader.h"
#include "test_util.h"
#include "base/util.h"

/* Highest GL name the census looks at: far above what these tests create. */
#define MAX_NAME 4096u

static char g_dir[512]; /* scratch shader directory */

static void write_shader(const char *name, const char *text)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", g_dir, name);
    util_ensure_parent_dir(path);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* Fullscreen triangle; hands 1.5 to the next stage. */
static const char *FULLSCREEN_VERT =
    "out float v_val;\n"
    "void main() {\n"
    "    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);\n"
    "    gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);\n"
    "    v_val = 1.5;\n"
    "}\n";

/* One instance per layer of a 4-layer target; doubles the varying. */
static const char *LAYERED_GEOM =
    "layout(triangles, invocations = 4) in;\n"
    "layout(triangle_strip, max_vertices = 3) out;\n"
    "in float v_val[];\n"
    "out float g_val;\n"
    "void main() {\n"
    "    for (int i = 0; i < 3; i++) {\n"
    "        gl_Position = gl_in[i].gl_Position;\n"
    "        gl_Layer = gl_InvocationID;\n"
    "        g_val = 2.0 * v_val[i];\n"
    "        EmitVertex();\n"
    "    }\n"
    "    EndPrimitive();\n"
    "}\n";

static const char *LAYERED_FRAG =
    "in float g_val;\n"
    "layout(location = 0) out vec4 color;\n"
    "void main() { color = vec4(g_val, float(gl_Layer), 0.0, 1.0); }\n";

/* Line 4 has the error: the log must say bad.geom:4. */
static const char *BAD_GEOM =
    "layout(triangles) in;\n"
    "layout(triangle_strip, max_vertices = 3) out;\n"
    "void main() {\n"
    "    gl_Position = undefined_thing;\n"
    "    EmitVertex();\n"
    "}\n";

/* Counts fragments per layer; no colour output. */
static const char *COUNT_FRAG =
    "layout(std430, binding = 0) buffer Counts { uint n[4]; };\n"
    "void main() { atomicAdd(n[gl_Layer], 1u); }\n";

/* Level 0 of a 16³ texture: texel (x,y,z) = (x/16, y/16, z/16, (x+2y+4z) mod 7). */
static const char *FILL_COMP =
    "layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;\n"
    "layout(binding = 0, rgba16f) writeonly uniform image3D dst;\n"
    "void main() {\n"
    "    ivec3 p = ivec3(gl_GlobalInvocationID);\n"
    "    imageStore(dst, p, vec4(vec3(p) / 16.0, float((p.x + 2 * p.y + 4 * p.z) % 7)));\n"
    "}\n";

/* Writes VALUE (default 1) times SCALE into the buffer; the reload test
 * edits SCALE. */
static const char *cache_comp(int scale)
{
    static char text[512];
    snprintf(text, sizeof text,
             "layout(local_size_x = 1) in;\n"
             "#ifndef VALUE\n"
             "#define VALUE 1\n"
             "#endif\n"
             "layout(std430, binding = 0) buffer Out { uint v; };\n"
             "void main() { v = uint(VALUE * %d); }\n",
             scale);
    return text;
}

static int group_setup(void **state)
{
    snprintf(g_dir, sizeof g_dir, "%s/gl_layer_%d", RTGI_TEST_TMP, (int)getpid());
    mkdir(g_dir, 0755);
    shader_set_directory(g_dir);
    return test_gl_setup(state);
}

static int group_teardown(void **state)
{
    shader_set_directory(NULL);
    return test_gl_teardown(state);
}

/* Runs `fn` with stderr going to a file; returns what it wrote (caller frees). */
static char *capture_stderr(GLuint (*fn)(void), GLuint *result)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/stderr.txt", g_dir);
    fflush(stderr);
    int saved = dup(2);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(saved >= 0 && fd >= 0);
    dup2(fd, 2);
    close(fd);
    *result = fn();
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    char *text = util_read_file(path, NULL);
    assert_non_null(text);
    return text;
}

static void read_level(GLuint tex, int level, float *out, size_t floats)
{
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    glGetTextureImage(tex, level, GL_RGBA, GL_FLOAT, (GLsizei)(floats * sizeof(float)), out);
}

/* --- live-object census --------------------------------------------------- */

static void census_sees_texture_and_buffer(void **state)
{
    (void)state;
    GlObjectCounts before = gl_count_live_objects(MAX_NAME);
    GLuint tex, buf;
    glCreateTextures(GL_TEXTURE_2D, 1, &tex);
    glCreateBuffers(1, &buf);
    GlObjectCounts during = gl_count_live_objects(MAX_NAME);
    assert_int_equal(during.textures, before.textures + 1);
    assert_int_equal(during.buffers, before.buffers + 1);
    assert_int_equal(gl_object_counts_total(&during), gl_object_counts_total(&before) + 2);
    glDeleteTextures(1, &tex);
    glDeleteBuffers(1, &buf);
    GlObjectCounts after = gl_count_live_objects(MAX_NAME);
    assert_memory_equal(&after, &before, sizeof after);
}

/* --- 3D textures ---------------------------------------------------------- */

static void texture3d_mips_of_a_written_pattern(void **state)
{
    (void)state;
    enum { N = 16 };
    write_shader("fill.comp", FILL_COMP);
    /* VCT's isotropic chain (its own compute pass, issue 46), run per the
     * gl_texture3d_build_mips contract: the driver's box filter, checked
     * below against glGenerateMipmap's levels. */
    char *mip_text = util_read_file(RTGI_SOURCE_DIR "/shaders/gi/vct/mip.comp", NULL);
    assert_non_null(mip_text);
    write_shader("mip.comp", mip_text);
    free(mip_text);
    GlObjectCounts before = gl_count_live_objects(MAX_NAME);

    assert_int_equal(gl_mip_levels(N, N, N), 5);
    assert_int_equal(gl_mip_levels(16, 4, 1), 5);
    GLuint tex = gl_texture3d_make(GL_RGBA16F, N, N, N, 0, TEX_FILTER_LINEAR, "test.volume");
    assert_int_not_equal(tex, 0);
    GLint levels = 0, wrap = 0, min = 0;
    glGetTextureParameteriv(tex, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
    glGetTextureParameteriv(tex, GL_TEXTURE_WRAP_R, &wrap);
    glGetTextureParameteriv(tex, GL_TEXTURE_MIN_FILTER, &min);
    assert_int_equal(levels, 5);
    assert_int_equal(wrap, GL_CLAMP_TO_BORDER);
    assert_int_equal(min, GL_LINEAR_MIPMAP_LINEAR);
    int size[3];
    gl_texture_level_size(tex, 4, size);
    assert_true(size[0] == 1 && size[1] == 1 && size[2] == 1);

    GLuint fill = shader_compute_make("fill", "fill.comp", NULL);
    assert_int_not_equal(fill, 0);
    glUseProgram(fill);
    gl_texture3d_bind_image(0, tex, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glDispatchCompute(N / 4, N / 4, N / 4);
    gl_texture_generate_mips(tex);

    static float l0[N * N * N * 4];
    read_level(tex, 0, l0, N * N * N * 4);
    double mean[4] = {0};
    for (int z = 0; z < N; z++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                const float *t = &l0[4 * ((z * N + y) * N + x)];
                const float want[4] = {x / 16.f, y / 16.f, z / 16.f, (float)((x + 2 * y + 4 * z) % 7)};
                for (int c = 0; c < 4; c++) {
                    if (t[c] != want[c])
                        fail_msg("level 0 texel (%d,%d,%d).%d = %g, want %g", x, y, z, c, t[c], want[c]);
                    mean[c] += want[c] / (N * N * N);
                }
            }
    float last[4];
    read_level(tex, 4, last, 4);
    for (int c = 0; c < 4; c++)
        assert_float_equal(last[c], mean[c], 4e-3 * fmax(1.0, mean[c]));
    assert_float_equal(last[0], 7.5 / 16, 2e-3);

    /* The same chain built by compute (gi/vct/mip.comp) matches the
     * driver's box filter. */
    GLuint tex2 = gl_texture3d_make(GL_RGBA16F, N, N, N, 0, TEX_FILTER_NEAREST, "test.volume_compute_mips");
    assert_int_not_equal(tex2, 0);
    glCopyImageSubData(tex, GL_TEXTURE_3D, 0, 0, 0, 0, tex2, GL_TEXTURE_3D, 0, 0, 0, 0, N, N, N);
    GLuint mip = shader_compute_make("mip", "mip.comp", NULL);
    assert_int_not_equal(mip, 0);
    gl_texture3d_build_mips(tex2, mip, GL_RGBA16F, 4);
    static float a[8 * 8 * 8 * 4], b[8 * 8 * 8 * 4];
    read_level(tex, 1, a, 8 * 8 * 8 * 4);
    read_level(tex2, 1, b, 8 * 8 * 8 * 4);
    for (int i = 0; i < 8 * 8 * 8 * 4; i++)
        assert_float_equal(a[i], b[i], 4e-3 * fmax(1.0, fabs(a[i])));
    float last2[4];
    read_level(tex2, 4, last2, 4);
    for (int c = 0; c < 4; c++)
        assert_float_equal(last2[c], mean[c], 4e-3 * fmax(1.0, mean[c]));

    glUseProgram(0);
    glDeleteProgram(fill);
    glDeleteProgram(mip);
    gl_texture3d_destroy(&tex);
    gl_texture3d_destroy(&tex2);
    assert_int_equal(tex, 0);
    GlObjectCounts after = gl_count_live_objects(MAX_NAME);
    assert_memory_equal(&after, &before, sizeof after);
}

/* Texture and buffer sizes from GL's own answers, against sizes worked out
 * by hand for each kind rtgi makes. */
static void memory_of_textures_and_buffers(void **state)
{
    (void)state;
    GLuint t[6] = {0};
    glCreateTextures(GL_TEXTURE_2D, 1, &t[0]); /* 16² + 8² + 4² texels of 16 bytes */
    glTextureStorage2D(t[0], 3, GL_RGBA32F, 16, 16);
    glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &t[1]); /* six 8² faces of 4 bytes */
    glTextureStorage2D(t[1], 1, GL_DEPTH_COMPONENT32F, 8, 8);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t[2]); /* 3 layers of 4×2 (+ 2×1), 4 bytes */
    glTextureStorage3D(t[2], 2, GL_R32F, 4, 2, 3);
    glCreateTextures(GL_TEXTURE_2D, 1, &t[3]); /* 5×3 of 4 bytes (9+9+9 bits + a 5-bit exponent) */
    glTextureStorage2D(t[3], 1, GL_RGB9_E5, 5, 3);
    glCreateTextures(GL_TEXTURE_2D, 1, &t[4]); /* 7×5 of 4 bytes */
    glTextureStorage2D(t[4], 1, GL_SRGB8_ALPHA8, 7, 5);
    t[5] = gl_texture3d_make(GL_RGBA16F, 4, 4, 4, 0, TEX_FILTER_LINEAR, "test.memory"); /* 64 + 8 + 1 of 8 */
    const uint64_t want[6] = {(256 + 64 + 16) * 16, 6 * 64 * 4, (3 * 8 + 3 * 2) * 4, 15 * 4, 35 * 4, 73 * 8};
    uint64_t sum = 0;
    for (int i = 0; i < 6; i++) {
        print_message("texture %d: %llu bytes (want %llu)\n", i, (unsigned long long)gl_texture_bytes(t[i]),
                      (unsigned long long)want[i]);
        assert_int_equal(gl_texture_bytes(t[i]), want[i]);
        sum += want[i];
    }
    assert_int_equal(gl_textures_bytes(t, 6), sum);
    assert_int_equal(gl_texture_bytes(0), 0);
    GLuint b[2] = {0, 0};
    glCreateBuffers(2, b);
    glNamedBufferStorage(b[0], 1000, NULL, 0);
    glNamedBufferStorage(b[1], 24, NULL, GL_DYNAMIC_STORAGE_BIT);
    assert_int_equal(gl_buffer_bytes(b[0]), 1000);
    assert_int_equal(gl_buffers_bytes(b, 2), 1024);
    assert_int_equal(gl_buffer_bytes(0), 0);
    glDeleteBuffers(2, b);
    gl_texture3d_destroy(&t[5]);
    glDeleteTextures(5, t);
}

static void texture3d_rejects_bad_requests(void **state)
{
    (void)state;
    GlObjectCounts before = gl_count_live_objects(MAX_NAME);
    log_set_level(LOG_QUIET);
    assert_int_equal(gl_texture3d_make(GL_RGBA16F, 0, 4, 4, 0, TEX_FILTER_LINEAR, "test.empty"), 0);
    assert_int_equal(gl_texture3d_make(GL_RGBA16F, 4, 4, 4, 4, TEX_FILTER_LINEAR, "test.too_many_levels"), 0);
    assert_int_equal(gl_texture3d_make(GL_RGBA, 4, 4, 4, 1, TEX_FILTER_LINEAR, "test.unsized"), 0);
    log_set_level(LOG_INFO);
    while (glGetError() != GL_NO_ERROR) /* the unsized format's INVALID_ENUM */
        ;
    GlObjectCounts after = gl_count_live_objects(MAX_NAME);
    assert_memory_equal(&after, &before, sizeof after);
}

/* --- geometry stage ----------------------------------------------------- */

static void geometry_stage_writes_every_layer(void **state)
{
    (void)state;
    enum { W = 8, LAYERS = 4 };
    write_shader("fullscreen.vert", FULLSCREEN_VERT);
    write_shader("layered.geom", LAYERED_GEOM);
    write_shader("layered.frag", LAYERED_FRAG);
    GLuint prog = shader_program_make_vgf("layered", "fullscreen.vert", "layered.geom", "layered.frag", NULL);
    assert_int_not_equal(prog, 0);

    GLuint tex, fbo, vao;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &tex);
    glTextureStorage3D(tex, 1, GL_RGBA32F, W, W, LAYERS);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0); /* layered */
    assert_int_equal(glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER), GL_FRAMEBUFFER_COMPLETE);
    glCreateVertexArrays(1, &vao);
    const float zero[4] = {0};
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, zero);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, W, W);
    glUseProgram(prog);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    static float px[W * W * LAYERS * 4];
    glGetTextureImage(tex, 0, GL_RGBA, GL_FLOAT, sizeof px, px);
    for (int l = 0; l < LAYERS; l++)
        for (int i = 0; i < W * W; i++) {
            const float *p = &px[4 * (l * W * W + i)];
            if (p[0] != 3.f || p[1] != (float)l || p[3] != 1.f)
                fail_msg("layer %d pixel %d = (%g, %g, %g, %g), want (3, %d, 0, 1)", l, i, p[0], p[1], p[2],
                         p[3], l);
        }
    glUseProgram(0);
    glDeleteProgram(prog);
    glDeleteTextures(1, &tex);
    glDeleteFramebuffers(1, &fbo);
    glDeleteVertexArrays(1, &vao);
}

static GLuint build_bad_geom(void)
{
    return shader_program_make_vgf("bad", "fullscreen.vert", "bad.geom", "layered.frag", NULL);
}

static void geometry_stage_errors_name_file_and_line(void **state)
{
    (void)state;
    write_shader("fullscreen.vert", FULLSCREEN_VERT);
    write_shader("layered.frag", LAYERED_FRAG);
    write_shader("bad.geom", BAD_GEOM);
    GlObjectCounts before = gl_count_live_objects(MAX_NAME);
    GLuint prog = 1;
    char *err = capture_stderr(build_bad_geom, &prog);
    assert_int_equal(prog, 0);
    if (!strstr(err, "bad.geom:4:") || !strstr(err, "program bad"))
        fail_msg("compile error should name bad.geom:4, got: %s", err);
    free(err);
    GlObjectCounts after = gl_count_live_objects(MAX_NAME);
    assert_memory_equal(&after, &before, sizeof after); /* no shader left behind */
}

/* --- attachment-less framebuffer ------------------------------------------ */

/* Draws a fullscreen triangle with `prog` into `fbo` and returns the four
 * per-layer fragment counts. */
static void count_fragments(GLuint prog, GLuint fbo, int size, GLuint out[4])
{
    GLuint buf, vao;
    const GLuint zero[4] = {0};
    glCreateBuffers(1, &buf);
    glNamedBufferStorage(buf, sizeof zero, zero, 0);
    glCreateVertexArrays(1, &vao);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, size, size);
    glUseProgram(prog);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buf, 0, 4 * sizeof(GLuint), out);
    glUseProgram(0);
    glDeleteBuffers(1, &buf);
    glDeleteVertexArrays(1, &vao);
}

static void empty_framebuffer_rasterizes_every_pixel(void **state)
{
    (void)state;
    write_shader("fullscreen.vert", FULLSCREEN_VERT);
    write_shader("layered.geom", LAYERED_GEOM);
    write_shader("count.frag", COUNT_FRAG);
    GlObjectCounts before = gl_count_live_objects(MAX_NAME);
    GLuint flat = shader_program_make("count", "fullscreen.vert", "count.frag", NULL);
    GLuint layered = shader_program_make_vgf("count_layered", "fullscreen.vert", "layered.geom", "count.frag", NULL);
    assert_true(flat && layered);

    GLuint fbo = gl_fbo_empty_make(32, 32, 0, 0, "test.empty_fbo");
    assert_int_not_equal(fbo, 0);
    GLint w = 0;
    glGetNamedFramebufferParameteriv(fbo, GL_FRAMEBUFFER_DEFAULT_WIDTH, &w);
    assert_int_equal(w, 32);
    GLuint n[4];
    count_fragments(flat, fbo, 32, n);
    assert_int_equal(n[0], 1024);
    assert_int_equal(n[1] + n[2] + n[3], 0);
    gl_fbo_destroy(&fbo);
    assert_int_equal(fbo, 0);

    /* Layered: the geometry stage sends the triangle to each of 4 layers. */
    fbo = gl_fbo_empty_make(32, 32, 4, 0, "test.empty_fbo_layered");
    assert_int_not_equal(fbo, 0);
    count_fragments(layered, fbo, 32, n);
    for (int l = 0; l < 4; l++)
        assert_int_equal(n[l], 1024);
    gl_fbo_destroy(&fbo);

    /* Multisampled: the rasterizer sees 4 samples. Every pixel is covered,
     * so at least 1024 invocations; llvmpipe runs one extra row or column
     * (1056), so the count is not checked exactly. */
    fbo = gl_fbo_empty_make(32, 32, 0, 4, "test.empty_fbo_msaa");
    assert_int_not_equal(fbo, 0);
    count_fragments(flat, fbo, 32, n);
    GLint samples = 0, dsamples = 0;
    glGetNamedFramebufferParameteriv(fbo, GL_SAMPLES, &samples);
    glGetNamedFramebufferParameteriv(fbo, GL_FRAMEBUFFER_DEFAULT_SAMPLES, &dsamples);
    assert_int_equal(samples, 4);
    assert_int_equal(dsamples, 4);
    assert_in_range(n[0], 1024, 33 * 33);
    gl_fbo_destroy(&fbo);

    log_set_level(LOG_QUIET);
    assert_int_equal(gl_fbo_empty_make(0, 32, 0, 0, "test.bad_fbo"), 0);
    assert_int_equal(gl_fbo_empty_make(32, 32, 0, 1 << 20, "test.bad_fbo"), 0);
    log_set_level(LOG_INFO);

    glDeleteProgram(flat);
    glDeleteProgram(layered);
    GlObjectCounts after = gl_count_live_objects(MAX_NAME);
    assert_memory_equal(&after, &before, sizeof after);
}

/* --- program cache -------------------------------------------------------- */

static GLuint run_value(GLuint prog)
{
    GLuint buf, v = 0xdeadbeef;
    glCreateBuffers(1, &buf);
    glNamedBufferStorage(buf, sizeof v, &v, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf);
    glUseProgram(prog);
    glDispatchCompute(1, 1, 1);
    glUseProgram(0);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buf, 0, sizeof v, &v);
    glDeleteBuffers(1, &buf);
    return v;
}

static bool g_reload_ok;
static ProgramCache *g_reload_cache;
static GLuint reload_captured(void)
{
    g_reload_ok = program_cache_reload(g_reload_cache);
    return 0;
}

static void program_cache_builds_once_and_reloads(void **state)
{
    (void)state;
    write_shader("cache.comp", cache_comp(1));
    write_shader("fullscreen.vert", FULLSCREEN_VERT);
    write_shader("layered.geom", LAYERED_GEOM);
    write_shader("layered.frag", LAYERED_FRAG);
    write_shader("count.frag", COUNT_FRAG);
    GlObjectCounts before = gl_count_live_objects(MAX_NAME);

    ProgramCache pc;
    program_cache_create(&pc);
    const ShaderProgramDesc one = {.label = "cache_one", .comp = "cache.comp"};
    const ShaderProgramDesc two = {.label = "cache_two", .comp = "cache.comp", .defines = "#define VALUE 2\n"};
    GLuint p1 = program_cache_get(&pc, &one);
    assert_int_not_equal(p1, 0);
    /* Same key (no defines == empty defines; label not part of the key). */
    assert_int_equal(program_cache_get(&pc, &(ShaderProgramDesc){.label = "other", .comp = "cache.comp",
                                                                   .defines = ""}),
                     p1);
    GLuint p2 = program_cache_get(&pc, &two);
    assert_true(p2 != 0 && p2 != p1);
    assert_int_equal(program_cache_get(&pc, &two), p2);
    /* Graphics programs are keyed by all their stages, geometry included. */
    const ShaderProgramDesc g3 = {.vert = "fullscreen.vert", .geom = "layered.geom", .frag = "layered.frag"};
    const ShaderProgramDesc g4 = {.vert = "fullscreen.vert", .geom = "layered.geom", .frag = "count.frag"};
    const ShaderProgramDesc g5 = {.vert = "fullscreen.vert", .frag = "count.frag"};
    GLuint p3 = program_cache_get(&pc, &g3), p4 = program_cache_get(&pc, &g4), p5 = program_cache_get(&pc, &g5);
    assert_true(p3 && p4 && p5 && p3 != p4 && p4 != p5 && p3 != p1 && p3 != p2);
    assert_int_equal(program_cache_get(&pc, &g4), p4);
    assert_int_equal(program_cache_count(&pc), 5);
    assert_int_equal(run_value(p1), 1);
    assert_int_equal(run_value(p2), 2);

    /* Edited source: rebuilt under the same names. */
    write_shader("cache.comp", cache_comp(10));
    assert_true(program_cache_reload(&pc));
    assert_int_equal(program_cache_get(&pc, &one), p1);
    assert_int_equal(program_cache_get(&pc, &two), p2);
    assert_int_equal(program_cache_get(&pc, &g3), p3);
    assert_int_equal(run_value(p1), 10);
    assert_int_equal(run_value(p2), 20);

    /* Broken source: reload fails, names the error, keeps the old builds. */
    write_shader("cache.comp", "layout(local_size_x = 1) in;\nvoid main() { oops; }\n");
    g_reload_cache = &pc;
    GLuint unused;
    char *err = capture_stderr(reload_captured, &unused);
    assert_false(g_reload_ok);
    if (!strstr(err, "cache.comp:2:"))
        fail_msg("reload error should name cache.comp:2, got: %s", err);
    free(err);
    assert_int_equal(program_cache_get(&pc, &one), p1);
    assert_int_equal(run_value(p1), 10);
    assert_int_equal(run_value(p2), 20);

    /* A key that fails to build gives 0 until a reload succeeds. */
    write_shader("late.comp", "void main() { nope; }\n");
    const ShaderProgramDesc late = {.comp = "late.comp"};
    log_set_level(LOG_QUIET);
    assert_int_equal(program_cache_get(&pc, &late), 0);
    log_set_level(LOG_INFO);
    assert_int_equal(program_cache_get(&pc, &late), 0); /* remembered, not rebuilt */
    assert_int_equal(program_cache_count(&pc), 6);
    write_shader("cache.comp", cache_comp(100));
    write_shader("late.comp", cache_comp(7));
    assert_true(program_cache_reload(&pc));
    GLuint p6 = program_cache_get(&pc, &late);
    assert_int_not_equal(p6, 0);
    assert_int_equal(run_value(p6), 7);
    assert_int_equal(run_value(p1), 100);

    GlObjectCounts during = gl_count_live_objects(MAX_NAME);
    assert_int_equal(during.programs, before.programs + 6);
    program_cache_destroy(&pc);
    assert_int_equal(program_cache_count(&pc), 0);
    GlObjectCounts after = gl_count_live_objects(MAX_NAME);
    assert_memory_equal(&after, &before, sizeof after); /* programs and their shaders */
}

/* --- timer debug groups --------------------------------------------------- */

static GLint debug_depth(void)
{
    GLint d = 0;
    glGetIntegerv(GL_DEBUG_GROUP_STACK_DEPTH, &d);
    return d;
}

static void timer_pushes_debug_groups(void **state)
{
    (void)state;
    GlObjectCounts before = gl_count_live_objects(MAX_NAME);
    GpuTimer t;
    gpu_timer_create(&t, false, false);
    GlObjectCounts created = gl_count_live_objects(MAX_NAME);
    assert_int_equal(created.queries, before.queries); /* disabled: no queries */

    /* The pushed group shows in the debug log with the pass name. */
    glEnable(GL_DEBUG_OUTPUT);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, NULL, GL_TRUE);
    while (glGetDebugMessageLog(1, 0, NULL, NULL, NULL, NULL, NULL, NULL) > 0)
        ;
    assert_int_equal(debug_depth(), 1);
    gpu_timer_begin(&t, "lpv_inject");
    assert_int_equal(debug_depth(), 2);
    gpu_timer_end(&t);
    assert_int_equal(debug_depth(), 1);
    gpu_timer_end(&t); /* unmatched: no stack underflow */
    assert_int_equal(debug_depth(), 1);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    char msg[256];
    GLenum type = 0;
    bool seen = false;
    while (glGetDebugMessageLog(1, sizeof msg, NULL, &type, NULL, NULL, NULL, msg) > 0)
        seen |= type == GL_DEBUG_TYPE_PUSH_GROUP && strcmp(msg, "lpv_inject") == 0;
    glDisable(GL_DEBUG_OUTPUT);
    assert_true(seen);
    gpu_timer_end_frame(&t);
    assert_int_equal(t.frames, 0); /* nothing read back */
    gpu_timer_destroy(&t);

    /* Enabled: groups and timings together. */
    gpu_timer_create(&t, true, false);
    gpu_timer_begin(&t, "vct_trace");
    assert_int_equal(debug_depth(), 2);
    gpu_timer_end(&t);
    assert_int_equal(debug_depth(), 1);
    gpu_timer_end_frame(&t);
    assert_true(gpu_timer_mean_ms(&t, "vct_trace", false) >= 0.0);
    gpu_timer_destroy(&t);
    GlObjectCounts after = gl_count_live_objects(MAX_NAME);
    assert_memory_equal(&after, &before, sizeof after);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(census_sees_texture_and_buffer),
        cmocka_unit_test(texture3d_mips_of_a_written_pattern),
        cmocka_unit_test(texture3d_rejects_bad_requests),
        cmocka_unit_test(memory_of_textures_and_buffers),
        cmocka_unit_test(geometry_stage_writes_every_layer),
        cmocka_unit_test(geometry_stage_errors_name_file_and_line),
        cmocka_unit_test(empty_framebuffer_rasterizes_every_pixel),
        cmocka_unit_test(program_cache_builds_once_and_reloads),
        cmocka_unit_test(timer_pushes_debug_groups),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
