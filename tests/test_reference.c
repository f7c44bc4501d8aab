/* test_reference.c — the path tracer against analytic answers: the white
 * furnace, a plane under a point light; and determinism. No GL. */
#include <math.h>
#include <string.h>

#include "test_util.h"
#include "reference/pathtracer.h"
#include "core/camera.h"
#include "base/util.h"
#include <stdio.h>
#include <stdlib.h>

/* Adds a square of side a centred on c whose front face (emission side)
 * looks along unit axis-aligned normal n. */
static void add_facing_square(Scene *s, int m, const vec3 c, const vec3 n, float a)
{
    vec3 u = {0, 0, 0}, v;
    if (fabsf(n[1]) > 0.5f)
        u[0] = 1;
    else
        u[1] = 1;
    glm_vec3_cross((float *)n, u, v); /* u × v = n for v = n × u */
    vec3 p[4];
    float h = 0.5f * a;
    for (int k = 0; k < 4; k++) {
        float su = (k == 1 || k == 2) ? h : -h, sv = (k >= 2) ? h : -h;
        for (int i = 0; i < 3; i++)
            p[k][i] = c[i] + su * u[i] + sv * v[i];
    }
    /* order p0 (-,-), p1 (+,-), p2 (+,+), p3 (-,+): (p1-p0)×(p3-p0) ∝ u×v = n */
    scene_add_quad(s, m, p[0], p[1], p[2], p[3]);
}

/* A closed box [-1,1]³, every face emitting Le inward with albedo ρ. */
static void furnace_scene(Scene *s, float rho, float le)
{
    scene_init(s);
    int m = scene_add_material(s, "furnace", (vec3){rho, rho, rho});
    glm_vec3_fill(s->materials[m].emission, le);
    static const float normals[6][3] = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int f = 0; f < 6; f++) {
        vec3 c = {-normals[f][0], -normals[f][1], -normals[f][2]};
        add_facing_square(s, m, c, normals[f], 2.f);
    }
    glm_vec3_zero(s->camera.position);
    glm_vec3_copy((vec3){0.3f, 0.1f, 1.f}, s->camera.forward);
    glm_vec3_normalize(s->camera.forward);
    vec3 right;
    glm_vec3_cross(s->camera.forward, (vec3){0, 1, 0}, right);
    glm_vec3_cross(right, s->camera.forward, s->camera.up);
    glm_vec3_normalize(s->camera.up);
    s->camera.fov_y = glm_rad(90.f);
    scene_finalize(s);
}

/* Mean over the image and its standard error (pixels are independent). */
static void image_mean(const ImageF *m, const ImageF *var, double *mean, double *se)
{
    double sum = 0, vsum = 0;
    size_t n = (size_t)m->width * m->height * 3;
    for (size_t i = 0; i < n; i++) {
        sum += m->rgb[i];
        vsum += var->rgb[i];
    }
    *mean = sum / n;
    *se = sqrt(vsum) / n;
}

static void run_furnace(float rho, bool rr)
{
    const float le = 0.5f;
    Scene s;
    furnace_scene(&s, rho, le);
    PtSettings set;
    pt_settings_default(&set);
    set.width = set.height = 32;
    set.spp = 256;
    set.threads = 2;
    set.russian_roulette = rr;
    set.max_depth = rr ? 100000 : 200; /* without RR: ρ^200 truncation is < 1e-19 */
    ImageF mean, var;
    PtStats st;
    assert_true(pt_render(&s, &set, &mean, &var, &st));
    double m, se;
    image_mean(&mean, &var, &m, &se);
    double expected = le / (1.0 - rho);
    print_message("furnace rho %.1f rr %d: %.5f expected %.5f (se %.5f, %.2f%%)\n", rho, rr, m, expected, se,
                  100 * fabs(m - expected) / expected);
    /* The statistical bound must itself be tighter than 1% for the test to
     * mean anything. Without roulette every path carries exactly ρ^k, the
     * estimator has no variance, and only float rounding remains. */
    double bound = fmax(4 * se, 1e-5 * expected);
    assert_true(bound < 0.01 * expected);
    assert_true(fabs(m - expected) < bound);
    assert_true(fabs(m - expected) < 0.01 * expected);
    image_free(&mean);
    image_free(&var);
    scene_free(&s);
}

static void white_furnace_rho05(void **state) { (void)state; run_furnace(0.5f, true); run_furnace(0.5f, false); }
static void white_furnace_rho08(void **state) { (void)state; run_furnace(0.8f, true); run_furnace(0.8f, false); }

/* A 4 m plane of albedo 0.6 under a point light of intensity I; pixel
 * centres (no jitter), so each pixel sees one known point. */
static void plane_under_point_light(void **state)
{
    (void)state;
    Scene s;
    scene_init(&s);
    int m = scene_add_material(&s, "plane", (vec3){0.6f, 0.6f, 0.6f});
    test_add_square(&s, m, (vec3){0, 0, 0}, 4.f);
    Light l = {.type = LIGHT_POINT, .position = {0.3f, 1.1f, -0.2f}, .color = {2.f, 1.f, 3.f}};
    scene_add_light(&s, &l);
    test_camera_down(&s.camera, (vec3){0.f, 2.5f, 0.f});
    s.camera.fov_y = glm_rad(60.f);
    scene_finalize(&s);
    PtSettings set;
    pt_settings_default(&set);
    set.width = set.height = 24;
    set.spp = 4;
    set.pixel_jitter = false;
    for (int mode = PT_FULL; mode <= PT_DIRECT; mode++) {
        set.mode = (PtMode)mode;
        ImageF img;
        assert_true(pt_render(&s, &set, &img, NULL, NULL));
        for (int y = 1; y < 24; y += 5)
            for (int x = 1; x < 24; x += 5) {
                vec3 want;
                test_plane_radiance(&s, 24, 24, x, y, &l, 0.6f, want);
                for (int c = 0; c < 3; c++) {
                    float got = image_px(&img, x, y)[c];
                    if (fabsf(got - want[c]) > 0.01f * want[c])
                        fail_msg("mode %d pixel (%d,%d) c%d: %g want %g", mode, x, y, c, got, want[c]);
                }
            }
        image_free(&img);
    }
    scene_free(&s);
}

/* Same seed → identical bytes, for any thread count; another seed differs. */
static void deterministic_for_seed(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    PtSettings set;
    pt_settings_default(&set);
    set.width = set.height = 24;
    set.spp = 4;
    ImageF a, b, c, d;
    set.threads = 2;
    assert_true(pt_render(&s, &set, &a, NULL, NULL));
    assert_true(pt_render(&s, &set, &b, NULL, NULL));
    set.threads = 1;
    assert_true(pt_render(&s, &set, &c, NULL, NULL));
    set.seed = 7;
    assert_true(pt_render(&s, &set, &d, NULL, NULL));
    size_t n = sizeof(float) * 3 * 24 * 24;
    assert_memory_equal(a.rgb, b.rgb, n);
    assert_memory_equal(a.rgb, c.rgb, n);
    assert_memory_not_equal(a.rgb, d.rgb, n);
    image_free(&a);
    image_free(&b);
    image_free(&c);
    image_free(&d);
    scene_free(&s);
}

/* Through the CLI: the PFM bytes of two runs with one seed are equal. */
static void deterministic_pfm_files(void **state)
{
    (void)state;
    char p1[512], p2[512];
    snprintf(p1, sizeof p1, "%s/det1.pfm", RTGI_TEST_TMP);
    snprintf(p2, sizeof p2, "%s/det2.pfm", RTGI_TEST_TMP);
    assert_int_equal(test_run_cli(NULL, "reference", "--size", "16x16", "--spp", "4", "--seed", "3", "--threads",
                                  "2", "--out", p1, "--quiet", NULL), 0);
    assert_int_equal(test_run_cli(NULL, "reference", "--size", "16x16", "--spp", "4", "--seed", "3", "--threads",
                                  "2", "--out", p2, "--quiet", NULL), 0);
    size_t n1, n2;
    char *f1 = util_read_file(p1, &n1), *f2 = util_read_file(p2, &n2);
    assert_non_null(f1);
    assert_non_null(f2);
    assert_int_equal(n1, n2);
    assert_memory_equal(f1, f2, n1);
    free(f1);
    free(f2);
}

/* Modes split the light consistently: full = direct + indirect, and
 * one-bounce lies between direct and full (statistically). */
static void modes_add_up(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    double m[5], se[5];
    for (int mode = 0; mode < 5; mode++) {
        if (mode == PT_ONE_BOUNCE_NOVIS)
            continue;
        ImageF img, var;
        test_reference_var(&s, 16, 16, (PtMode)mode, 256, true, &img, &var);
        image_mean(&img, &var, &m[mode], &se[mode]);
        image_free(&img);
        image_free(&var);
    }
    double sum = m[PT_DIRECT] + m[PT_INDIRECT];
    double tol = 4 * sqrt(se[PT_FULL] * se[PT_FULL] + se[PT_DIRECT] * se[PT_DIRECT] + se[PT_INDIRECT] * se[PT_INDIRECT]);
    print_message("full %.5f direct %.5f indirect %.5f one-bounce %.5f (tol %.5f)\n", m[PT_FULL], m[PT_DIRECT],
                  m[PT_INDIRECT], m[PT_ONE_BOUNCE], tol);
    assert_true(fabs(m[PT_FULL] - sum) < tol);
    assert_true(m[PT_ONE_BOUNCE] > m[PT_DIRECT] + 4 * se[PT_ONE_BOUNCE]);
    assert_true(m[PT_ONE_BOUNCE] < m[PT_FULL] - 4 * se[PT_FULL]);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(white_furnace_rho05),    cmocka_unit_test(white_furnace_rho08),
        cmocka_unit_test(plane_under_point_light), cmocka_unit_test(deterministic_for_seed),
        cmocka_unit_test(deterministic_pfm_files), cmocka_unit_test(modes_add_up),
    };
    return cmocka_run_group_tests_name("reference", tests, NULL, NULL);
}
