/* test_layout.c — every block of shaders/shared/gpu_types.h has the same
 * size and field offsets in C and in the linked GLSL program (program
 * interface query), and the GLSL-only constants equal C's enums. The field
 * lists come from the header's X-macros, so nothing is listed twice. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "gpu/light_stage.h"
#include "frame/pass_direct.h"
#include "core/scene.h"
#include "gl/shader.h"
#include "shared/gpu_types.h"
#include "test_util.h"

static double fmax_d(double a, double b) { return a > b ? a : b; }

typedef struct Field {
    const char *name;
    size_t offset;
} Field;

/* C reflection of a block: its fields' names and offsetof. */
#define REFLECT_MEMBER(t, n) {#n, offsetof(REFLECTED, n)},
#define REFLECT_ARRAY(t, n, c) {#n "[0]", offsetof(REFLECTED, n)},

#define REFLECTED GpuLight
static const Field k_light[] = {GPU_LIGHT_FIELDS(REFLECT_MEMBER, REFLECT_ARRAY)};
#undef REFLECTED
#define REFLECTED GpuShadowParams
static const Field k_shadow[] = {GPU_SHADOW_PARAMS_FIELDS(REFLECT_MEMBER, REFLECT_ARRAY)};
#undef REFLECTED
#define REFLECTED GpuFrame
static const Field k_frame[] = {GPU_FRAME_FIELDS(REFLECT_MEMBER, REFLECT_ARRAY)};
#undef REFLECTED
#define REFLECTED GpuGiParams
static const Field k_gi[] = {GPU_GI_PARAMS_FIELDS(REFLECT_MEMBER, REFLECT_ARRAY)};
#undef REFLECTED
#define REFLECTED GpuVplParams
static const Field k_vpl_params[] = {GPU_VPL_PARAMS_FIELDS(REFLECT_MEMBER, REFLECT_ARRAY)};
#undef REFLECTED
#define REFLECTED GpuVpl
static const Field k_vpl[] = {GPU_VPL_FIELDS(REFLECT_MEMBER, REFLECT_ARRAY)};
#undef REFLECTED
#define REFLECTED GpuVctParams
static const Field k_vct[] = {GPU_VCT_PARAMS_FIELDS(REFLECT_MEMBER, REFLECT_ARRAY)};
#undef REFLECTED
#define REFLECTED GpuIsmParams
static const Field k_ism[] = {GPU_ISM_PARAMS_FIELDS(REFLECT_MEMBER, REFLECT_ARRAY)};
#undef REFLECTED

typedef struct Block {
    const char *glsl_block;    /* interface block name */
    const char *instance;      /* member prefix in the program ("u_light" or "vpls[0]") */
    GLenum interface;          /* GL_UNIFORM or GL_BUFFER_VARIABLE */
    const Field *fields;
    int count;
    size_t c_size;
} Block;

#define BLOCK(b, inst, iface, f, type) {b, inst, iface, f, (int)(sizeof f / sizeof f[0]), sizeof(type)}

static void blocks_match_c(void **state)
{
    (void)state;
    GLuint prog = shader_compute_make("layout", "test/layout.comp", NULL);
    assert_true(prog != 0);
    const Block blocks[] = {
        BLOCK("LightBlock", "u_light", GL_UNIFORM, k_light, GpuLight),
        BLOCK("ShadowBlock", "u_shadow", GL_UNIFORM, k_shadow, GpuShadowParams),
        BLOCK("FrameBlock", "u_frame", GL_UNIFORM, k_frame, GpuFrame),
        BLOCK("GiBlock", "u_gi", GL_UNIFORM, k_gi, GpuGiParams),
        BLOCK("VplParamBlock", "u_vpl", GL_UNIFORM, k_vpl_params, GpuVplParams),
        BLOCK("VplBlock", "vpls[0]", GL_BUFFER_VARIABLE, k_vpl, GpuVpl),
        BLOCK("VctBlock", "u_vct", GL_UNIFORM, k_vct, GpuVctParams),
        BLOCK("IsmBlock", "u_ism", GL_UNIFORM, k_ism, GpuIsmParams),
    };
    int checked = 0;
    for (size_t b = 0; b < sizeof blocks / sizeof blocks[0]; b++) {
        const Block *bl = &blocks[b];
        GLenum block_iface = bl->interface == GL_UNIFORM ? GL_UNIFORM_BLOCK : GL_SHADER_STORAGE_BLOCK;
        GLuint bi = glGetProgramResourceIndex(prog, block_iface, bl->glsl_block);
        if (bi == GL_INVALID_INDEX)
            fail_msg("block %s not in the program", bl->glsl_block);
        GLenum size_prop = GL_BUFFER_DATA_SIZE;
        GLint gl_size = 0;
        glGetProgramResourceiv(prog, block_iface, bi, 1, &size_prop, 1, NULL, &gl_size);
        size_t rounded = (bl->c_size + 15) / 16 * 16;
        if (bl->interface == GL_UNIFORM && (size_t)gl_size != rounded)
            fail_msg("%s: GLSL block size %d, C struct %zu (rounded %zu)", bl->glsl_block, gl_size, bl->c_size,
                     rounded);
        for (int i = 0; i < bl->count; i++) {
            char name[128];
            snprintf(name, sizeof name, "%s.%s", bl->instance, bl->fields[i].name);
            GLuint ri = glGetProgramResourceIndex(prog, bl->interface, name);
            if (ri == GL_INVALID_INDEX)
                fail_msg("%s: field %s not in the program", bl->glsl_block, name);
            GLenum prop = GL_OFFSET;
            GLint off = -1;
            glGetProgramResourceiv(prog, bl->interface, ri, 1, &prop, 1, NULL, &off);
            if ((size_t)off != bl->fields[i].offset)
                fail_msg("%s: GLSL offset %d, C offset %zu", name, off, bl->fields[i].offset);
            checked++;
        }
        if (bl->interface == GL_BUFFER_VARIABLE) {
            char name[128];
            snprintf(name, sizeof name, "%s.%s", bl->instance, bl->fields[0].name);
            GLuint ri = glGetProgramResourceIndex(prog, GL_BUFFER_VARIABLE, name);
            GLenum prop = GL_TOP_LEVEL_ARRAY_STRIDE;
            GLint stride = 0;
            glGetProgramResourceiv(prog, GL_BUFFER_VARIABLE, ri, 1, &prop, 1, NULL, &stride);
            assert_int_equal((size_t)stride, bl->c_size);
        }
    }
    print_message("%d fields in 8 blocks agree between C and GLSL\n", checked);
    glDeleteProgram(prog);
}

static void constants_match_c_enums(void **state)
{
    (void)state;
    GLuint prog = shader_compute_make("layout", "test/layout.comp", NULL);
    assert_true(prog != 0);
    GLuint out, vpl;
    glCreateBuffers(1, &out);
    glNamedBufferStorage(out, 18 * sizeof(int), NULL, GL_DYNAMIC_STORAGE_BIT);
    glCreateBuffers(1, &vpl);
    glNamedBufferStorage(vpl, sizeof(GpuVpl), NULL, GL_DYNAMIC_STORAGE_BIT);
    GLuint ubo;
    glCreateBuffers(1, &ubo);
    glNamedBufferStorage(ubo, 4096, NULL, GL_DYNAMIC_STORAGE_BIT);
    const int ubos[] = {UBO_LIGHT, UBO_SHADOW, UBO_FRAME, UBO_GI, UBO_VPL};
    for (int i = 0; i < 5; i++)
        glBindBufferBase(GL_UNIFORM_BUFFER, (GLuint)ubos[i], ubo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_COUNTERS, out);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VPL, vpl);
    glUseProgram(prog);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    int v[18];
    glGetNamedBufferSubData(out, 0, sizeof v, v);
    const int want[18] = {LIGHT_DIRECTIONAL, LIGHT_SPOT, LIGHT_POINT, LIGHT_QUAD,
                          SHADOW_MODE_NONE,  SHADOW_MODE_HARD, SHADOW_MODE_PCF, SHADOW_MODE_PCSS,
                          0, SHADOW_BIAS_RECEIVER_PLANE, SHADOW_BIAS_LEGACY,
                          RSM_WEIGHT_PAPER, RSM_WEIGHT_UNBIASED, RSM_WEIGHT_IMPORTANCE,
                          AREA_LIGHT_MODE_EXACT, AREA_LIGHT_MODE_POINT,
                          SHADOW_PCF_FILTER_DISK, SHADOW_PCF_FILTER_GRID};
    for (int i = 0; i < 18; i++)
        assert_int_equal(v[i], want[i]);
    GLuint bufs[3] = {out, vpl, ubo};
    glDeleteBuffers(3, bufs);
    glDeleteProgram(prog);
}

/* The G-buffer's packed surfel (shaders/common/surfel.glsl) gives positions
 * back exactly and normals within 1e-3 rad (measured: < 1e-4), over random
 * directions and the octahedron's folds (poles, axes, the equator). */
static void surfel_round_trips(void **state)
{
    (void)state;
    enum { N = 4096 };
    GLuint prog = shader_compute_make("surfel", "test/surfel.comp", NULL);
    assert_true(prog != 0);
    static GpuVpl v[N], back[N];
    uint32_t rng = 12345u;
    for (int i = 0; i < N; i++) {
        float n[3];
        if (i < 26) { /* the 26 directions of the cube's faces, edges and corners */
            int c = i < 13 ? i : i + 1;
            n[0] = (float)(c % 3 - 1), n[1] = (float)(c / 3 % 3 - 1), n[2] = (float)(c / 9 - 1);
        } else {
            for (int k = 0; k < 3; k++) {
                rng = rng * 1664525u + 1013904223u;
                n[k] = (float)(rng >> 8) / 16777216.f * 2.f - 1.f;
            }
        }
        float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len < 1e-3f)
            n[0] = 1.f, n[1] = n[2] = 0.f, len = 1.f;
        float pos[3];
        for (int k = 0; k < 3; k++) {
            v[i].normal_xi[k] = n[k] / len;
            rng = rng * 1664525u + 1013904223u;
            pos[k] = ((float)(rng >> 8) / 16777216.f - 0.5f) * 1e3f * (float)(i % 7);
        }
        gpu_vpl_set_position(&v[i], pos);
    }
    GLuint buf;
    glCreateBuffers(1, &buf);
    glNamedBufferStorage(buf, sizeof v, v, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VPL, buf);
    glUseProgram(prog);
    glDispatchCompute(N / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buf, 0, sizeof back, back);
    double worst = 0.0;
    for (int i = 0; i < N; i++) {
        assert_memory_equal(back[i].surface, v[i].surface, 3 * sizeof(float));
        assert_true(back[i].normal_xi[3] == 1.f);
        double d2 = 0.0; /* angle from the chord: acos is blind near 0 */
        for (int k = 0; k < 3; k++)
            d2 += ((double)back[i].normal_xi[k] - v[i].normal_xi[k]) * ((double)back[i].normal_xi[k] - v[i].normal_xi[k]);
        double angle = 2.0 * asin(sqrt(d2) / 2.0);
        worst = angle > worst ? angle : worst;
    }
    print_message("surfel: worst normal error %.3g rad over %d directions\n", worst, N);
    assert_true(worst < 1e-3);
    glDeleteBuffers(1, &buf);
    glDeleteProgram(prog);
}

/* Random unit vector, or one of the 26 directions of the cube's faces,
 * edges and corners for i < 26 (the octahedron's folds). */
static void test_direction(int i, uint32_t *rng, float n[3])
{
    if (i < 26) {
        int c = i < 13 ? i : i + 1;
        n[0] = (float)(c % 3 - 1), n[1] = (float)(c / 3 % 3 - 1), n[2] = (float)(c / 9 - 1);
    } else {
        for (int k = 0; k < 3; k++) {
            *rng = *rng * 1664525u + 1013904223u;
            n[k] = (float)(*rng >> 8) / 16777216.f * 2.f - 1.f;
        }
    }
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len < 1e-3f)
        n[0] = 1.f, n[1] = n[2] = 0.f, len = 1.f;
    for (int k = 0; k < 3; k++)
        n[k] /= len;
}

static float test_uniform(uint32_t *rng)
{
    *rng = *rng * 1664525u + 1013904223u;
    return (float)(*rng >> 8) / 16777216.f;
}

/* The RSM texel (shaders/common/rsm_texel.glsl), packed and unpacked in the
 * frame light_stage_rsm_texel_frame gives a light, over a Sponza-sized box
 * and each kind of light (cube, spot, directional): positions within 1e-5
 * of the scene's size, normals within 1e-3 rad, flux within 1% of each
 * channel at or above a quarter of the texel's largest (and 2^-9 of the
 * largest for every channel: RGB9E5 shares one exponent), flux spanning six
 * decades; the area the unpacking derives equals light/rsm.frag's former
 * stored one, a·cos³·d²/max(n·l, 0.05) (ortho: A/max(n·l, 0.05)), within 1%;
 * a cleared texel reads as empty with flux and area 0. */
static void rsm_texel_round_trips(void **state)
{
    (void)state;
    enum { N = 4096 };
    GLuint prog = shader_compute_make("rsm_texel", "test/rsm_texel.comp", NULL);
    assert_true(prog != 0);
    const vec3 bmin = {-19.f, -0.1f, -8.f}, bmax = {18.f, 15.6f, 7.5f};
    const float extent = 37.f;
    static GpuVpl v[N], back[N];
    GLuint buf, ubo;
    glCreateBuffers(1, &buf);
    glNamedBufferStorage(buf, sizeof v, NULL, GL_DYNAMIC_STORAGE_BIT);
    glCreateBuffers(1, &ubo);
    glNamedBufferStorage(ubo, sizeof(GpuLight), NULL, GL_DYNAMIC_STORAGE_BIT);
    for (int kind = 0; kind < 3; kind++) { /* point (cube), spot, directional */
        GpuLight g = {0};
        const float light[3] = {0.5f, 14.f, -0.3f}, axis[3] = {0.f, -1.f, 0.f};
        const float sun[3] = {0.3f / 1.0295630f, -0.9f / 1.0295630f, 0.4f / 1.0295630f}; /* unit */
        const float *dir = kind == 2 ? sun : axis;
        memcpy(g.position_type, light, sizeof light);
        g.position_type[3] = (float)(kind == 0 ? LIGHT_POINT : kind == 1 ? LIGHT_SPOT : LIGHT_DIRECTIONAL);
        memcpy(g.direction_width, dir, 3 * sizeof(float));
        g.color[0] = 40.f, g.color[1] = 30.f, g.color[2] = 10.f;
        g.shadow_info[1] = kind == 2 ? 60.f / 2048.f : 2.f / 512.f; /* texel_k */
        g.shadow_info[3] = kind == 0 ? 1.f : 0.f;
        light_stage_rsm_texel_frame(bmin, bmax, &g);
        const float most = 16384.f * g.rsm_box_min[3]; /* the most a texel receives */
        uint32_t rng = 777u + (uint32_t)kind;
        for (int i = 0; i < N; i++) {
            float n[3], pos[3];
            test_direction(i, &rng, n);
            for (int k = 0; k < 3; k++)
                pos[k] = bmin[k] + (bmax[k] - bmin[k]) * test_uniform(&rng);
            gpu_vpl_set_position(&v[i], pos);
            /* the lit side: facing the light (as rsm.frag flips it) */
            float to_light[3], tl = 0.f, dot = 0.f;
            for (int k = 0; k < 3; k++) {
                to_light[k] = kind == 2 ? -dir[k] : light[k] - pos[k];
                tl += to_light[k] * to_light[k];
            }
            for (int k = 0; k < 3; k++)
                dot += n[k] * to_light[k];
            for (int k = 0; k < 3; k++)
                v[i].normal_xi[k] = dot < 0.f ? -n[k] : n[k];
            float mag = most * powf(10.f, -6.f * test_uniform(&rng));
            for (int k = 0; k < 3; k++)
                v[i].flux[k] = mag * (k == (i % 3) ? 1.f : test_uniform(&rng));
            v[i].normal_xi[3] = i == N - 1 ? -1.f : 0.f; /* the last: a cleared texel */
        }
        glNamedBufferSubData(buf, 0, sizeof v, v);
        glNamedBufferSubData(ubo, 0, sizeof g, &g);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VPL, buf);
        glBindBufferBase(GL_UNIFORM_BUFFER, UBO_LIGHT, ubo);
        glUseProgram(prog);
        glDispatchCompute(N / 64, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glGetNamedBufferSubData(buf, 0, sizeof back, back);
        double worst_p = 0, worst_n = 0, worst_f = 0, worst_fmax = 0, worst_a = 0;
        for (int i = 0; i < N - 1; i++) {
            assert_true(back[i].normal_xi[3] == 1.f); /* 2: the record's packed and unpacked normals differ */
            double d2 = 0.0, fmax = 0.0;
            float pos[3], bpos[3];
            gpu_vpl_position(&v[i], pos);
            gpu_vpl_position(&back[i], bpos);
            for (int k = 0; k < 3; k++) {
                worst_p = fmax_d(worst_p, fabs((double)bpos[k] - pos[k]) / extent);
                d2 += ((double)back[i].normal_xi[k] - v[i].normal_xi[k]) * ((double)back[i].normal_xi[k] - v[i].normal_xi[k]);
                fmax = fmax_d(fmax, v[i].flux[k]);
            }
            worst_n = fmax_d(worst_n, 2.0 * asin(sqrt(d2) / 2.0)); /* the angle from the chord */
            for (int k = 0; k < 3; k++) {
                double err = fabs((double)back[i].flux[k] - v[i].flux[k]);
                worst_fmax = fmax_d(worst_fmax, err / fmax);
                if (v[i].flux[k] >= 0.25 * fmax)
                    worst_f = fmax_d(worst_f, err / v[i].flux[k]);
            }
            /* rsm.frag's former area, from the exact position and normal */
            double d[3], dd = 0, h, cos_s = 0;
            for (int k = 0; k < 3; k++) {
                d[k] = kind == 2 ? dir[k] : (double)pos[k] - light[k];
                dd += d[k] * d[k];
            }
            for (int k = 0; k < 3; k++)
                cos_s -= v[i].normal_xi[k] * d[k] / sqrt(dd);
            cos_s = fmax_d(cos_s, 0.05);
            double a = (double)g.shadow_info[1] * g.shadow_info[1];
            if (kind == 2) {
                h = 1.0;
            } else if (kind == 1) {
                h = fabs(d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2]) / sqrt(dd);
            } else {
                h = fmax_d(fabs(d[0]), fmax_d(fabs(d[1]), fabs(d[2]))) / sqrt(dd);
            }
            double area = kind == 2 ? a / cos_s : a * h * h * h * dd / cos_s;
            worst_a = fmax_d(worst_a, fabs(back[i].flux[3] - area) / area);
        }
        print_message("rsm texel (%s): worst position error %.3g of the scene, normal %.3g rad, flux %.3g "
                      "(channels >= max/4), %.3g of the largest, area %.3g\n",
                      kind == 0 ? "cube" : kind == 1 ? "spot" : "directional", worst_p, worst_n, worst_f, worst_fmax,
                      worst_a);
        assert_true(worst_p < 1e-5);
        assert_true(worst_n < 1e-3);
        assert_true(worst_f < 0.01);
        assert_true(worst_fmax <= 1.0 / 512.0 + 1e-6);
        assert_true(worst_a < 0.01);
        const GpuVpl *e = &back[N - 1];
        assert_true(e->normal_xi[3] == 0.f && e->flux[0] == 0.f && e->flux[1] == 0.f && e->flux[2] == 0.f &&
                    e->flux[3] == 0.f);
    }
    glDeleteBuffers(1, &buf);
    glDeleteBuffers(1, &ubo);
    glDeleteProgram(prog);
}

/* Texture units past the 32 a fragment stage may use at once are still
 * valid bindings below GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS (GL 4.5: ≥ 80). */
static void texture_units_exist(void **state)
{
    (void)state;
    GLint units = 0;
    glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &units);
    print_message("GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS = %d\n", units);
    const int used[] = {TEX_LDR, TEX_GB_MATERIAL, TEX_MATERIAL_MR, TEX_LPV_OUTER + 5};
    for (size_t i = 0; i < sizeof used / sizeof used[0]; i++)
        assert_true(used[i] < units);
    assert_true(TEX_MATERIAL_MR > TEX_LDR);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(blocks_match_c),
        cmocka_unit_test(texture_units_exist),
        cmocka_unit_test(constants_match_c_enums),
        cmocka_unit_test(surfel_round_trips),
        cmocka_unit_test(rsm_texel_round_trips),
    };
    return cmocka_run_group_tests_name("layout", tests, test_gl_setup, test_gl_teardown);
}
