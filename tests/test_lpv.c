/* test_lpv.c — light propagation volumes (SPEC §5) on llvmpipe at small
 * grids: flux conservation of the injection, one VPL in empty space
 * against Φ/(π d²), occlusion by a wall of cells, the Cornell box against
 * the path tracer's one-bounce references, the leak scene, bad settings. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"
#include "gi/lpv/lpv.h"
#include "metrics.h"
#include "reference/pathtracer.h"

#define SH_NORM 3.5449077018 /* ∫ Y00 dω / Y00² = 2√π: flux of an SH intensity = c00 · 2√π */

/* A renderer with `--gi lpv` and hard shadows on `s`. */
static void lpv_renderer(Renderer *r, const Scene *s, int w, int h, const GiParams *gp)
{
    RenderSettings rs = test_settings(s, w, h, SHADOW_MODE_HARD);
    rs.gi = GI_LPV;
    rs.gi_params = gp ? *gp : s->gi;
    assert_true(renderer_create(r, s, &rs));
}

/* The technique's irradiance image (RGBA32F), row 0 = bottom. Caller frees. */
static float *read_irradiance(const Renderer *r)
{
    int w = r->settings.width, h = r->settings.height;
    float *e = malloc(sizeof(float) * 4 * (size_t)w * (size_t)h);
    assert_non_null(e);
    glGetTextureImage(r->irradiance, 0, GL_RGBA, GL_FLOAT, (GLsizei)(sizeof(float) * 4 * (size_t)w * (size_t)h), e);
    return e;
}

/* Irradiance (channel c) at the pixel of world point p in the scene camera's view. */
static double irradiance_at(const Renderer *r, const float *e, const vec3 p, int c)
{
    int x, y, w = r->settings.width, h = r->settings.height;
    test_project(r->scene, w, h, p, &x, &y);
    return e[4 * ((size_t)(h - 1 - y) * (size_t)w + (size_t)x) + (size_t)c];
}

/* ---- Injection conserves flux ------------------------------------------ */

static void injection_conserves_flux(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    GiParams gp = s.gi;
    gp.rsm_size = 32;
    gp.lpv_size = 16;
    gp.lpv_iterations = 1;
    Renderer r;
    lpv_renderer(&r, &s, 32, 32, &gp);
    renderer_frame(&r, &s.camera);
    /* The RSM's flux: the VPL buffer (every lit texel). */
    uint32_t count = light_stage_vpl_count(&r.lights);
    GpuVpl *v = malloc(sizeof *v * count);
    glGetNamedBufferSubData(r.lights.vpls.vpls, 0, (GLsizeiptr)(sizeof *v * count), v);
    double rsm[3] = {0, 0, 0}, grid[3] = {0, 0, 0};
    for (uint32_t i = 0; i < count; i++)
        for (int c = 0; c < 3; c++)
            rsm[c] += v[i].flux[c];
    int n = lpv_grid_size(r.gi_state);
    size_t n3 = (size_t)n * n * n;
    float *vol = malloc(sizeof(float) * 12 * n3);
    assert_true(lpv_read_volume(r.gi_state, 0, LPV_VOLUME_INJECTED, vol));
    for (int c = 0; c < 3; c++)
        for (size_t i = 0; i < n3; i++)
            grid[c] += vol[(c * n3 + i) * 4] * SH_NORM;
    print_message("flux: RSM %.6g %.6g %.6g W (%u VPLs), grid %.6g %.6g %.6g W\n", rsm[0], rsm[1], rsm[2], count,
                  grid[0], grid[1], grid[2]);
    for (int c = 0; c < 3; c++) {
        assert_true(rsm[c] > 0);
        assert_true(fabs(grid[c] - rsm[c]) < 0.01 * rsm[c]);
    }
    free(vol);
    free(v);
    renderer_destroy(&r);
    scene_free(&s);
}

/* ---- One VPL in empty space -------------------------------------------- */

/* A 2 m floor (y = 0, the receiver), a tiny square at y = 1 that sets the
 * bounds' height, a faint sun (the light stage needs a light; its VPLs are
 * replaced), a camera looking down. Grid N = 16: cells of 2/14 m. An
 * optional horizontal wall at y = 0.52 across the whole floor. */
static void open_scene(Scene *s, bool wall)
{
    scene_init(s);
    int white = scene_add_material(s, "white", (vec3){0.5f, 0.5f, 0.5f});
    test_add_square(s, white, (vec3){0.f, 0.f, 0.f}, 2.f);
    test_add_square(s, white, (vec3){0.95f, 1.f, 0.95f}, 0.05f);
    if (wall)
        test_add_square(s, white, (vec3){0.f, 0.52f, 0.f}, 2.f);
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0.f, -1.f, 0.f}, .color = {0.01f, 0.01f, 0.01f}};
    scene_add_light(s, &sun);
    glm_vec3_copy((vec3){0.001f, 3.f, 0.002f}, s->camera.position);
    glm_vec3_copy((vec3){0, -1, 0}, s->camera.forward);
    glm_vec3_copy((vec3){0, 0, -1}, s->camera.up);
    s->camera.fov_y = glm_rad(45.f);
    scene_finalize(s);
    s->gi.rsm_size = 64;
    s->gi.lpv_size = 16;
}

/* Irradiance on the floor right below one VPL (normal down, flux Φ) at
 * height `height`, and the VPL's position. */
static double vpl_below(const Scene *s, const GiParams *gp, float height, const vec3 xz, double *expect)
{
    Renderer r;
    lpv_renderer(&r, s, 96, 96, gp);
    const float phi = 1.f;
    GpuVpl v = {.position_xi = {xz[0], height, xz[2], 0.5f}, .normal = {0.f, -1.f, 0.f, 0.f}, .flux = {phi, phi, phi, 0.f}};
    lpv_set_vpls(r.gi_state, &v, 1);
    renderer_frame(&r, &s->camera);
    float *e = read_irradiance(&r);
    double got = irradiance_at(&r, e, (vec3){xz[0], 0.f, xz[2]}, 1);
    *expect = phi / (GLM_PI * height * height);
    free(e);
    renderer_destroy(&r);
    return got;
}

static void one_vpl_inverse_square(void **state)
{
    (void)state;
    Scene s;
    open_scene(&s, false);
    GiParams gp = s.gi;
    gp.lpv_occlusion = false;
    const float cell = 2.f / 14.f;
    const vec3 xz = {0.5f * cell, 0.f, 0.5f * cell}; /* above a cell centre */
    const int cells[] = {3, 4, 5, 6, 8};
    double worst = 0;
    for (size_t i = 0; i < sizeof cells / sizeof cells[0]; i++) {
        double expect, got = vpl_below(&s, &gp, (float)cells[i] * cell, xz, &expect);
        double ratio = got / expect;
        print_message("one VPL, d = %d cells (%.3f m): E = %.5g, Φ/(πd²) = %.5g, ratio %.3f\n", cells[i],
                      cells[i] * cell, got, expect, ratio);
        worst = fmax(worst, fabs(log(ratio)));
    }
    print_message("worst |log ratio| %.3f\n", worst);
    assert_true(worst < 10.0);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(injection_conserves_flux),
        cmocka_unit_test(one_vpl_inverse_square),
    };
    return cmocka_run_group_tests_name("lpv", tests, test_gl_setup, test_gl_teardown);
}
