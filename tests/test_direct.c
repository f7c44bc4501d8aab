/* test_direct.c — the direct pass draws each light with a program built for
 * its light type, shadow mode, filter bias and PCF filter (and, without
 * glossy materials, the diffuse BRDF only), the first light of a frame
 * unblended into an uncleared target (issue 11). None of that may change
 * the image: every variant's frame equals the general program's bit for
 * bit on llvmpipe (to 1e-4 on a GPU, whose compiler treats each program's
 * arithmetic on its own), for each light type, shadow mode, filter bias and PCF filter, with
 * one and with two lights (the second blended onto the first),
 * diffuse-only and glossy. Frames without GI shade forward (no G-buffer);
 * their image equals the deferred one up to the G-buffer's quantisation. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/metrics.h"

#include "test_util.h"

/* Pixels whose channels differ at all (tol 0), or by more than tol of the
 * larger of the two values (absolute below 1e-6); *worst: the largest
 * relative difference of any channel. */
static size_t differing_pixels(const ImageF *a, const ImageF *b, double tol, double *worst)
{
    size_t n = 0;
    *worst = 0;
    for (int i = 0; i < a->width * a->height; i++) {
        bool off = false;
        for (int c = 0; c < 3; c++) {
            double x = a->rgb[3 * i + c], y = b->rgb[3 * i + c], d = fabs(x - y) / fmax(fmax(fabs(x), fabs(y)), 1e-6);
            *worst = fmax(*worst, d);
            off |= tol == 0 ? x != y : d > tol;
        }
        n += off;
    }
    return n;
}

/* The Cornell box with its light turned into `type`, optionally a second
 * (point) light and a glossy floor. */
static void make_scene(Scene *s, LightType type, bool two_lights, bool glossy)
{
    assert_true(scene_load(s, "cornell"));
    Light *l = &s->lights[0];
    l->type = type;
    if (type != LIGHT_QUAD)
        l->position[1] -= 0.1f;
    if (type == LIGHT_DIRECTIONAL) {
        glm_vec3_copy((vec3){-0.3f, -0.8f, 0.52f}, l->direction);
        glm_vec3_normalize(l->direction);
        glm_vec3_copy((vec3){1.f, 1.f, 1.f}, l->color);
        l->size = 0.02f; /* angular diameter (rad): PCSS penumbrae */
    }
    if (type == LIGHT_SPOT) {
        l->spot_inner = 0.6f;
        l->spot_outer = 0.9f;
    }
    if (two_lights) {
        Light *more = realloc(s->lights, 2 * sizeof *more);
        assert_non_null(more);
        s->lights = more;
        s->lights[1] = s->lights[0];
        s->lights[1].type = LIGHT_POINT;
        glm_vec3_copy((vec3){0.15f, 0.3f, 0.2f}, s->lights[1].position);
        glm_vec3_copy((vec3){0.05f, 0.04f, 0.03f}, s->lights[1].color);
        s->lights[1].size = 0.05f;
        s->light_count = 2;
    }
    if (glossy)
        for (int i = 0; i < s->material_count; i++)
            if (strcmp(s->materials[i].name, "floor") == 0) {
                s->materials[i].specular = 1.f;
                s->materials[i].roughness = 0.3f;
            }
}

static void variants_equal_general(void **state)
{
    (void)state;
    /* The last: a point light far enough out for one fitted 2D map
     * (shadow_frame_point_fitted), a variant of its own. */
    const LightType types[] = {LIGHT_DIRECTIONAL, LIGHT_SPOT, LIGHT_POINT, LIGHT_QUAD, LIGHT_POINT};
    /* llvmpipe (CI) compiles every variant to the same arithmetic: equal bit
     * for bit. A GPU's compiler may contract and reorder each program's
     * arithmetic in its own way (GLSL leaves it free to), so there the
     * variants agree to 1e-4 of each channel but in at most 1% of the pixels
     * (a shadow test on a depth rounded the other way turns one filter tap),
     * and the images' squared difference is below 1e-8 of the image's: a
     * wrong light, BRDF term or filter is off by far more. */
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    double tol = gl_renderer_is_software(renderer) ? 0 : 1e-4, worst_all = 0;
    int frames = 0;
    for (int t = 0; t < 5; t++) {
        Scene s;
        bool two = t % 2 == 1, glossy = t >= 2;
        make_scene(&s, types[t], two, glossy);
        if (t == 4) {
            glm_vec3_copy((vec3){0.5f, 0.2f, -3.f}, s.lights[0].position);
            glm_vec3_scale(s.lights[0].color, 40.f, s.lights[0].color);
            assert_true(shadow_frame_point_fitted(&s.lights[0], s.bounds_min, s.bounds_max));
        }
        RenderSettings rs = test_settings(&s, 40, 40, SHADOW_MODE_NONE);
        rs.set.shadow.map_size = 128;
        rs.shading = t < 2 ? SHADING_FORWARD : SHADING_DEFERRED; /* each light type once per path */
        Renderer r;
        assert_true(renderer_create(&r, &s, &rs));
        assert_true(renderer_forward(&r) == (t < 2));
        for (int mode = SHADOW_MODE_NONE; mode <= SHADOW_MODE_PCSS; mode++)
            for (int variant = 0; variant < (mode == SHADOW_MODE_PCF ? 4 : 2); variant++) {
                int bias = variant % 2, filter = variant / 2;
                rs.shadow = (ShadowMode)mode;
                rs.set.shadow.filter_bias = bias;
                rs.set.shadow.pcf_filter = filter;
                assert_true(renderer_apply(&r, &rs));
                ImageF img[2];
                for (int g = 0; g < 2; g++) {
                    r.pass_direct.general = g == 1;
                    renderer_frame(&r, &s.camera);
                    assert_true(renderer_read_hdr(&r, &img[g]));
                }
                double worst;
                size_t diff = differing_pixels(&img[0], &img[1], tol, &worst);
                worst_all = fmax(worst_all, worst);
                double mean = test_image_mean(&img[0]), d2 = 0, v2 = 0;
                for (int i = 0; i < 3 * img[0].width * img[0].height; i++) {
                    d2 += (img[0].rgb[i] - img[1].rgb[i]) * (double)(img[0].rgb[i] - img[1].rgb[i]);
                    v2 += img[1].rgb[i] * (double)img[1].rgb[i];
                }
                if (diff)
                    print_message("light type %d, shadow mode %d, bias %d, filter %d, %s, %s: %zu pixels differ "
                                  "(largest relative difference %.3g)\n",
                                  types[t], mode, bias, filter, two ? "two lights" : "one light",
                                  glossy ? "glossy" : "diffuse", diff, worst);
                assert_true(mean > 0.0);
                if (tol == 0) {
                    assert_int_equal(diff, 0);
                } else {
                    assert_true(diff <= (size_t)(img[0].width * img[0].height) / 100);
                    assert_true(d2 <= 1e-8 * v2);
                }
                image_free(&img[0]);
                image_free(&img[1]);
                frames++;
            }
        renderer_destroy(&r);
        scene_free(&s);
    }
    print_message("%d light/shadow configurations on %s: variants equal the general program %s (largest relative "
                  "difference %.3g)\n",
                  frames, renderer, tol == 0 ? "bit for bit" : "to 1e-4", worst_all);
}

/* Forward and deferred frames of the same settings: the G-buffer keeps
 * positions exactly but the normal to 15 bits per octahedral coordinate
 * and the base colour to 16 bits, so the two agree to about 1e-4 of a
 * pixel's value, except where that moves a shadow test across its
 * reference. Bounds: relMSE < 1e-5 over the image, and fewer than 0.5% of
 * the lit pixels off by more than 1%. Forward frames that lose the
 * emission or the blending of the second light fail them (checked by
 * breaking each: relMSE 0.0069 and 0.26). */
static void compare_shadings(const Scene *s, RenderSettings rs, const char *what)
{
    ImageF img[2];
    for (int d = 0; d < 2; d++) {
        rs.shading = d == 1 ? SHADING_DEFERRED : SHADING_FORWARD;
        test_render(s, &rs, &img[d]);
    }
    double rel = metric_relmse(&img[0], &img[1], NULL, NULL);
    int off = 0, lit = 0;
    for (int i = 0; i < img[0].width * img[0].height; i++) {
        float a = luminance(img[0].rgb + 3 * i), b = luminance(img[1].rgb + 3 * i);
        lit += b > 0.f;
        off += fabsf(a - b) > 0.01f * fmaxf(b, 1e-3f);
    }
    print_message("%s: forward vs deferred relMSE %.2g, %d of %d lit pixels off by > 1%%\n", what, rel, off, lit);
    assert_true(lit > 0 && test_image_mean(&img[1]) > 0.0);
    assert_true(rel < 1e-5);
    assert_true(off <= lit / 200);
    image_free(&img[0]);
    image_free(&img[1]);
}

static void forward_equals_deferred(void **state)
{
    (void)state;
    const LightType types[] = {LIGHT_DIRECTIONAL, LIGHT_SPOT, LIGHT_POINT, LIGHT_QUAD};
    const char *names[] = {"sun", "spot", "point", "quad"};
    for (int t = 0; t < 4; t++) {
        Scene s;
        bool two = t % 2 == 1, glossy = t >= 2;
        make_scene(&s, types[t], two, glossy);
        for (int mode = SHADOW_MODE_NONE; mode <= SHADOW_MODE_PCSS; mode++)
            for (int filter = 0; filter < (mode == SHADOW_MODE_PCF ? 2 : 1); filter++) {
                RenderSettings rs = test_settings(&s, 48, 48, (ShadowMode)mode);
                rs.set.shadow.map_size = 256;
                rs.set.shadow.pcf_filter = filter;
                char what[96];
                snprintf(what, sizeof what, "%s%s%s, shadow mode %d%s", names[t], two ? " + point" : "",
                         glossy ? ", glossy" : "", mode, filter ? " (grid)" : "");
                compare_shadings(&s, rs, what);
            }
        /* Supersampled: both shade at 2x the size. */
        RenderSettings rs = test_settings(&s, 24, 24, SHADOW_MODE_PCF);
        rs.ssaa = 2;
        compare_shadings(&s, rs, "supersampled x2");
        scene_free(&s);
    }
}

/* An alpha-masked leaf (a quad whose texture is transparent on its x > 0
 * half) over a floor, lit from above: forward shading draws masked
 * materials with their discard, so the floor shows through the hole, lit
 * through it, as in the G-buffer. */
static void forward_masked_materials(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, test_masked_leaf_obj("direct_masked")));
    int masked = 0;
    for (int i = 0; i < s.material_count; i++)
        masked += s.materials[i].alpha_mask;
    assert_int_equal(masked, 1);
    test_camera_down(&s.camera, (vec3){0.f, 4.f, 0.f});
    s.camera.fov_y = glm_rad(40.f);
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0, -1, 0}, .color = {2, 2, 2}};
    free(s.lights);
    s.lights = NULL;
    s.light_count = 0;
    scene_add_light(&s, &sun);
    RenderSettings rs = test_settings(&s, 64, 64, SHADOW_MODE_PCF);
    compare_shadings(&s, rs, "alpha-masked leaf");
    /* The hole shows the lit floor: ρ/π·E = 0.8/π·2 beside the leaf's centre. */
    ImageF img;
    test_render(&s, &rs, &img);
    float hole = luminance(image_px(&img, 40, 32)), leaf = luminance(image_px(&img, 24, 32));
    print_message("masked leaf: hole %.4f (lit floor %.4f), leaf %.4f\n", hole, 0.8 / GLM_PI * 2.0, leaf);
    assert_float_equal(hole, 0.8 / GLM_PI * 2.0, 0.01);
    assert_true(fabsf(leaf - hole) > 0.1f);
    image_free(&img);
    scene_free(&s);
}

/* --shading auto: forward where the scene has fewer triangles than shading
 * pixels / 64, deferred otherwise and always with a GI technique (it reads
 * the G-buffer), whatever the mode asks. */
/* Largest difference (in 8-bit steps) between r's final image and its
 * radiance tone-mapped on the CPU (× exposure, clamped, sRGB-encoded);
 * counts the pixels the clamp reaches in *clamped. */
static int display_error(Renderer *r, float exposure, int *clamped)
{
    ImageF hdr;
    assert_true(renderer_read_hdr(r, &hdr));
    uint8_t *ldr = renderer_read_ldr(r);
    assert_non_null(ldr);
    int worst = 0;
    *clamped = 0;
    for (int i = 0; i < 3 * hdr.width * hdr.height; i++) {
        float c = hdr.rgb[i] * exposure;
        *clamped += c > 1.f;
        int want = (int)lroundf(255.f * srgb_encode(fminf(fmaxf(c, 0.f), 1.f)));
        worst = abs(want - (int)ldr[i]) > worst ? abs(want - (int)ldr[i]) : worst;
    }
    free(ldr);
    image_free(&hdr);
    return worst;
}

/* The final image is the radiance tone-mapped, whether a tone-mapping pass
 * makes it (deferred frames, forward frames of two lights) or the forward
 * draw of a one-light frame writes it as it shades: within one 8-bit step
 * (the shaders' sRGB encoding is a fit, srgb_encode_matches_the_standard) of the CPU's, at two exposures in one
 * renderer (an exposure change remakes nothing and must reach both). A
 * one-light forward frame that left the final image unwritten, or wrote
 * it without the exposure or the sRGB encoding, fails (checked by breaking
 * each: errors of 255, 118 and 73 steps). */
static void display_image_is_tone_mapped_radiance(void **state)
{
    (void)state;
    for (int c = 0; c < 3; c++) {
        Scene s;
        make_scene(&s, LIGHT_SPOT, c == 2, false);
        RenderSettings rs = test_settings(&s, 48, 40, SHADOW_MODE_PCF);
        rs.set.shadow.map_size = 256;
        rs.shading = c == 1 ? SHADING_DEFERRED : SHADING_FORWARD;
        Renderer r;
        assert_true(renderer_create(&r, &s, &rs));
        const float exposures[2] = {4.f, 0.7f};
        for (int e = 0; e < 2; e++) {
            rs.exposure = exposures[e];
            assert_true(renderer_apply(&r, &rs));
            renderer_frame(&r, &s.camera);
            int clamped, worst = display_error(&r, rs.exposure, &clamped);
            print_message("%s, exposure %.1f: largest difference %d of 255, %d channels clamped\n",
                          c == 0 ? "forward, one light" : c == 1 ? "deferred" : "forward, two lights", rs.exposure,
                          worst, clamped);
            assert_true(worst <= 1);
            if (e == 0)
                assert_true(clamped > 0);
        }
        renderer_destroy(&r);
        scene_free(&s);
    }
}

/* A display-only frame (RenderSettings.display_only: render's PNG output)
 * keeps no radiance: its final image is the one a frame that keeps it
 * writes, bit for bit; renderer_read_hdr refuses it; and radiance that is
 * not finite still shows: renderer_count_nonfinite finds the same pixels
 * (and the same first one) from the final image's alpha as from the
 * radiance of a frame that keeps it, here with a NaN in the light's colour.
 * Without the alpha mark the display-only count is 0. */
static void display_only_frames(void **state)
{
    (void)state;
    Scene s;
    make_scene(&s, LIGHT_SPOT, false, false);
    RenderSettings rs = test_settings(&s, 48, 40, SHADOW_MODE_PCF);
    rs.set.shadow.map_size = 256;
    rs.shading = SHADING_FORWARD;
    Renderer r;
    assert_true(renderer_create(&r, &s, &rs));
    for (int nan = 0; nan < 2; nan++) {
        if (nan)
            s.lights[0].color[1] = NAN; /* past the loader's checks: the renderer must still notice */
        uint8_t *ldr[2];
        size_t bad[2];
        int x[2], y[2];
        for (int k = 0; k < 2; k++) {
            rs.display_only = k == 1;
            assert_true(renderer_apply(&r, &rs));
            renderer_frame(&r, &s.camera);
            ldr[k] = renderer_read_ldr(&r);
            assert_non_null(ldr[k]);
            assert_true(renderer_count_nonfinite(&r, &bad[k], &x[k], &y[k]));
        }
        ImageF hdr;
        assert_false(renderer_read_hdr(&r, &hdr)); /* the last frame was display-only */
        print_message("%s: non-finite pixels %zu (radiance kept) and %zu (display only), first at (%d, %d) and (%d, %d)\n",
                      nan ? "NaN light" : "finite", bad[0], bad[1], x[0], y[0], x[1], y[1]);
        if (nan) {
            assert_true(bad[0] > 0);
        } else {
            assert_int_equal(bad[0], 0);
            assert_memory_equal(ldr[0], ldr[1], 3 * 48 * 40);
        }
        assert_int_equal(bad[1], bad[0]);
        assert_int_equal(x[1], x[0]);
        assert_int_equal(y[1], y[0]);
        free(ldr[0]);
        free(ldr[1]);
    }
    renderer_destroy(&r);
    scene_free(&s);
}

/* The shaders' sRGB encoding (common/tonemap.glsl's fit) against the
 * standard's formula (image.c's srgb_encode) on 2^16 + 1 values spread over
 * [0, 1] and squeezed toward the branch at 0.0031308: within 0.06 of an
 * 8-bit step (the fit's own bound is 0.052), so the final image's bytes are
 * the exact encoding's or one step off where it lies that near a rounding
 * boundary. A plain 1/2.2 gamma is 8.5 steps off, the fit without its
 * constant term 8.8 (both measured). */
static void srgb_encode_matches_the_standard(void **state)
{
    (void)state;
    enum { N = 65537 };
    float(*v)[4] = malloc(sizeof(float) * 4 * N);
    assert_non_null(v);
    for (int i = 0; i < N; i++) {
        double t = (double)i / (N - 1);
        v[i][0] = (float)t;
        v[i][1] = (float)(t * t * t); /* dense near the knee */
        v[i][2] = (float)(0.0031308 * (1.0 + 0.02 * (t - 0.5)));
        v[i][3] = 0.f;
    }
    GLuint prog = shader_compute_make("test_srgb", "test/srgb.comp", NULL);
    assert_true(prog != 0);
    GLuint buf;
    glCreateBuffers(1, &buf);
    glNamedBufferStorage(buf, (GLsizeiptr)(sizeof(float) * 4 * N), v, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_SAMPLES, buf);
    glUseProgram(prog);
    glDispatchCompute((N + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    float(*got)[4] = malloc(sizeof(float) * 4 * N);
    assert_non_null(got);
    glGetNamedBufferSubData(buf, 0, (GLsizeiptr)(sizeof(float) * 4 * N), got);
    double worst = 0.0;
    float at = 0.f;
    for (int i = 0; i < N; i++)
        for (int c = 0; c < 3; c++) {
            double e = 255.0 * fabs((double)got[i][c] - (double)srgb_encode(v[i][c]));
            if (e > worst) {
                worst = e;
                at = v[i][c];
            }
        }
    print_message("srgb_encode: largest error %.4f of an 8-bit step (at %.6g)\n", worst, at);
    assert_true(worst < 0.06);
    glDeleteBuffers(1, &buf);
    glDeleteProgram(prog);
    free(got);
    free(v);
}

static void auto_shading_follows_triangle_density(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, "cornell"));
    int triangles = (int)(s.index_count / 3);
    struct {
        int w, h, ssaa;
        GiMode gi;
        ShadingMode shading;
        bool forward;
    } cases[] = {
        {256, 256, 1, GI_NONE, SHADING_AUTO, triangles * 64 < 256 * 256},
        {8, 8, 1, GI_NONE, SHADING_AUTO, false},
        {8, 8, 4, GI_NONE, SHADING_AUTO, triangles * 64 < 32 * 32},
        {8, 8, 1, GI_NONE, SHADING_FORWARD, true},
        {256, 256, 1, GI_NONE, SHADING_DEFERRED, false},
        {64, 64, 1, GI_RSM, SHADING_FORWARD, false},
    };
    assert_true(cases[0].forward && !cases[2].forward); /* the box's 36-odd triangles at these sizes */
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        RenderSettings rs = test_settings(&s, cases[i].w, cases[i].h, SHADOW_MODE_HARD);
        rs.ssaa = cases[i].ssaa;
        rs.gi = cases[i].gi;
        rs.set.gi = s.settings.gi;
        rs.set.gi.rsm.size = 32;
        rs.shading = cases[i].shading;
        Renderer r;
        assert_true(renderer_create(&r, &s, &rs));
        assert_true(renderer_forward(&r) == cases[i].forward);
        renderer_destroy(&r);
    }
    print_message("Cornell box (%d triangles): forward at 256x256, deferred at 8x8 and 32x32 shading pixels\n",
                  triangles);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(variants_equal_general),
        cmocka_unit_test(forward_equals_deferred),
        cmocka_unit_test(forward_masked_materials),
        cmocka_unit_test(auto_shading_follows_triangle_density),
        cmocka_unit_test(display_image_is_tone_mapped_radiance),
        cmocka_unit_test(srgb_encode_matches_the_standard),
        cmocka_unit_test(display_only_frames),
    };
    return cmocka_run_group_tests_name("direct", tests, test_gl_setup, test_gl_teardown);
}
