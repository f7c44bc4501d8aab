/* test_shadows.c — shadow maps on the Cornell box and PCSS vs PCF.
 * All renders at small sizes on whatever GL 4.5 is present (llvmpipe). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/log.h"
#include "io/metrics.h"
#include "test_util.h"

enum { CW = 192, CH = 192 };

static void render_cornell_filter(ShadowMode mode, float bias_const, float bias_slope, int filter, ImageF *img)
{
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    RenderSettings rs = test_settings(&s, CW, CH, mode);
    if (bias_const >= 0) {
        rs.set.shadow.bias_const = bias_const;
        rs.set.shadow.bias_slope = bias_slope;
    }
    rs.set.shadow.pcf_filter = filter;
    test_render(&s, &rs, img);
    scene_free(&s);
}

static void render_cornell(ShadowMode mode, float bias_const, float bias_slope, ImageF *img)
{
    render_cornell_filter(mode, bias_const, bias_slope, SHADOW_PCF_FILTER_DISK, img);
}

/* Floor behind the tall block as seen from the light, and a lit floor point. */
static const vec3 k_shadowed = {0.52f, 0.f, 0.35f};
static const vec3 k_lit = {0.42f, 0.f, 0.12f};

static void pixel_of(const vec3 p, int *x, int *y)
{
    Scene s;
    scene_build_cornell(&s);
    test_project(&s, CW, CH, p, x, y);
    scene_free(&s);
}

/* The floor behind the tall block is far darker than lit floor, with hard
 * shadows (no light: no GI yet) and with PCSS (inside the umbra). */
static void tall_block_casts_shadow(void **state)
{
    (void)state;
    int sx, sy, lx, ly;
    pixel_of(k_shadowed, &sx, &sy);
    pixel_of(k_lit, &lx, &ly);
    ImageF none, hard, pcss;
    render_cornell(SHADOW_MODE_NONE, -1, 0, &none);
    render_cornell(SHADOW_MODE_HARD, -1, 0, &hard);
    render_cornell(SHADOW_MODE_PCSS, -1, 0, &pcss);
    double lit = test_mean(&hard, lx, ly, 1, 3);
    double dark = test_mean(&hard, sx, sy, 1, 3);
    double unshadowed = test_mean(&none, sx, sy, 1, 3);
    print_message("lit %g, behind block %g (hard), %g (pcss), %g (no shadow)\n", lit, dark,
                  test_mean(&pcss, sx, sy, 1, 3), unshadowed);
    assert_true(lit > 0.05);
    assert_true(dark < 0.01 * lit);                          /* umbra of a point light: black */
    assert_true(test_mean(&pcss, sx, sy, 1, 3) < 0.1 * lit); /* inside PCSS umbra too */
    assert_true(unshadowed > 0.3 * lit);                     /* it is the shadow, not the geometry */
    image_free(&none);
    image_free(&hard);
    image_free(&pcss);
}

/* Acne: over a lit floor patch, hard-shadowed radiance divided by
 * unshadowed radiance should be 1 everywhere. The ratio removes the smooth
 * cosθ/d² variation, so its spread measures acne alone. Bound: mean ratio
 * ≥ 0.995 and relative standard deviation ≤ 1% (binary acne gives a large
 * fraction of black pixels, i.e. tens of percent). With zero bias the same
 * measure must see acne, which shows the measure can fail. */
static double acne_fraction(const ImageF *shadowed, const ImageF *none, int cx, int cy, int r, double *rel_std)
{
    double sum = 0, sum2 = 0;
    int n = 0, dark = 0;
    for (int y = cy - r; y <= cy + r; y++)
        for (int x = cx - r; x <= cx + r; x++) {
            double ratio = luminance(image_px(shadowed, x, y)) / luminance(image_px(none, x, y));
            sum += ratio;
            sum2 += ratio * ratio;
            dark += ratio < 0.5;
            n++;
        }
    double mean = sum / n;
    *rel_std = sqrt(fmax(sum2 / n - mean * mean, 0.0)) / mean;
    return (double)dark / n;
}

static void lit_floor_has_no_acne(void **state)
{
    (void)state;
    int lx, ly;
    pixel_of(k_lit, &lx, &ly);
    ImageF none, hard, nobias;
    render_cornell(SHADOW_MODE_NONE, -1, 0, &none);
    render_cornell(SHADOW_MODE_HARD, -1, 0, &hard);
    render_cornell(SHADOW_MODE_HARD, 0.f, 0.f, &nobias);
    double rs_hard, rs_nobias;
    double f_hard = acne_fraction(&hard, &none, lx, ly, 6, &rs_hard);
    double f_nobias = acne_fraction(&nobias, &none, lx, ly, 6, &rs_nobias);
    print_message("acne: biased %.3f dark, rel std %.4f; unbiased %.3f dark, rel std %.4f\n", f_hard, rs_hard,
                  f_nobias, rs_nobias);
    /* The grid PCF's taps (cube map of the quad light) on the same patch. */
    ImageF grid;
    render_cornell_filter(SHADOW_MODE_PCF, -1, 0, SHADOW_PCF_FILTER_GRID, &grid);
    double rs_grid, f_grid = acne_fraction(&grid, &none, lx, ly, 6, &rs_grid);
    print_message("acne: grid PCF %.3f dark, rel std %.4f\n", f_grid, rs_grid);
    assert_true(f_grid == 0.0 && rs_grid <= 0.01);
    image_free(&grid);
    assert_true(f_hard == 0.0);
    assert_true(rs_hard <= 0.01);
    assert_true(f_nobias > 0.1); /* the measure detects acne when there is some */
    image_free(&none);
    image_free(&hard);
    image_free(&nobias);
}

/* Acne and peter-panning as measured quantities (metric_shadow_artefacts,
 * `compare --unshadowed`) against the path tracer's direct light: on the
 * pixels the reference sees fully lit, the share the rasterizer darkens
 * (false_shadow); on those it sees fully shadowed, the share it lights
 * (false_lit). The default biases keep both near 0; no bias at all is acne
 * (measured at 128²: half the lit pixels), a slope bias of 100 texels is
 * peter-panning (a third of the umbra lit): the measure fails where it
 * should. */
static void artefacts_against_the_reference(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    ImageF ref, none, hard, pcss, nobias, overbiased;
    test_reference(&s, CW, CH, PT_DIRECT, 128, &ref);
    scene_free(&s);
    render_cornell(SHADOW_MODE_NONE, -1, 0, &none);
    render_cornell(SHADOW_MODE_HARD, -1, 0, &hard);
    render_cornell(SHADOW_MODE_PCSS, -1, 0, &pcss);
    render_cornell(SHADOW_MODE_HARD, 0.f, 0.f, &nobias);
    render_cornell(SHADOW_MODE_HARD, 0.0005f, 100.f, &overbiased);
    ShadowArtefacts h = metric_shadow_artefacts(&hard, &ref, &none, NULL);
    ShadowArtefacts p = metric_shadow_artefacts(&pcss, &ref, &none, NULL);
    ShadowArtefacts z = metric_shadow_artefacts(&nobias, &ref, &none, NULL);
    ShadowArtefacts o = metric_shadow_artefacts(&overbiased, &ref, &none, NULL);
    print_message("lit %zu, shadowed %zu pixels; false shadow / lit: hard %.4f / %.4f, pcss %.4f / %.4f, "
                  "no bias %.4f / %.4f, slope bias 100 %.4f / %.4f\n",
                  h.lit, h.shadowed, h.false_shadow, h.false_lit, p.false_shadow, p.false_lit, z.false_shadow,
                  z.false_lit, o.false_shadow, o.false_lit);
    assert_true(h.lit > 10000 && h.shadowed > 500);
    assert_true(h.false_shadow < 0.01 && h.false_lit < 0.01);
    assert_true(p.false_shadow < 0.01 && p.false_lit < 0.01);
    assert_true(z.false_shadow > 0.2);
    assert_true(o.false_lit > 0.1);
    image_free(&ref);
    image_free(&none);
    image_free(&hard);
    image_free(&pcss);
    image_free(&nobias);
    image_free(&overbiased);
}

/* PCSS vs PCF: a spot light of diameter 0.4 m at 2.5 m over a floor, two
 * 0.4 m square blockers at heights 0.3 m and 1.2 m. PCSS's penumbra is
 * (d_r − d_b)·w/d_b: 0.055 m and 0.37 m; PCF's is fixed in texels and so
 * the same for both. Widths are measured on the image as the number of
 * pixels with visibility in (0.1, 0.9) across both edges of each shadow. */
enum { PW = 256, PH = 256 };

static void penumbra_scene(Scene *s)
{
    scene_init(s);
    strcpy(s->source, "penumbra-test");
    int floor = scene_add_material(s, "floor", (vec3){0.8f, 0.8f, 0.8f});
    int blk = scene_add_material(s, "blocker", (vec3){0.5f, 0.5f, 0.5f});
    test_add_square(s, floor, (vec3){0, 0, 0}, 6.f);
    test_add_square(s, blk, (vec3){-0.8f, 0.3f, 0}, 0.4f);
    test_add_square(s, blk, (vec3){0.8f, 1.2f, 0}, 0.4f);
    Light l = {.type = LIGHT_SPOT, .position = {0, 2.5f, 0}, .direction = {0, -1, 0}, .color = {5, 5, 5},
               .size = 0.4f, .spot_inner = glm_rad(55.f), .spot_outer = glm_rad(62.f)};
    scene_add_light(s, &l);
    glm_vec3_copy((vec3){0, 6.f, 0}, s->camera.position);
    glm_vec3_copy((vec3){0, -1, 0}, s->camera.forward);
    glm_vec3_copy((vec3){0, 0, -1}, s->camera.up);
    s->camera.fov_y = glm_rad(40.f);
    s->settings.shadow.map_size = 1024;
    scene_finalize(s);
}

/* Visibility along the image row through z = 0, averaged over 9 rows. */
static void visibility_row(const ImageF *shadowed, const ImageF *none, double *v)
{
    for (int x = 0; x < PW; x++) {
        double a = 0, b = 0;
        for (int y = PH / 2 - 4; y <= PH / 2 + 4; y++) {
            a += luminance(image_px(shadowed, x, y));
            b += luminance(image_px(none, x, y));
        }
        v[x] = b > 0 ? a / b : 1.0;
    }
}

/* Penumbra pixels (both edges) of the shadow within [x0, x1) of the row. */
static int penumbra_width(const double *v, int x0, int x1)
{
    int n = 0;
    for (int x = x0; x < x1; x++)
        n += v[x] > 0.1 && v[x] < 0.9;
    return n;
}

static void pcss_penumbra_grows_pcf_does_not(void **state)
{
    (void)state;
    Scene s;
    penumbra_scene(&s);
    ImageF none, pcf, pcss;
    RenderSettings rs = test_settings(&s, PW, PH, SHADOW_MODE_NONE);
    test_render(&s, &rs, &none);
    rs.shadow = SHADOW_MODE_PCF;
    rs.set.shadow.pcf_samples = 32;
    rs.set.shadow.pcf_radius = 6.f;
    test_render(&s, &rs, &pcf);
    rs.shadow = SHADOW_MODE_PCSS;
    rs.set.shadow.blocker_samples = 32;
    test_render(&s, &rs, &pcss);
    double v_pcf[PW], v_pcss[PW];
    visibility_row(&pcf, &none, v_pcf);
    visibility_row(&pcss, &none, v_pcss);
    /* The low blocker's shadow lies in the left half, the high one's in the right. */
    int pcf_low = penumbra_width(v_pcf, 0, PW / 2), pcf_high = penumbra_width(v_pcf, PW / 2, PW);
    int pcss_low = penumbra_width(v_pcss, 0, PW / 2), pcss_high = penumbra_width(v_pcss, PW / 2, PW);
    print_message("penumbra px: PCF low %d high %d; PCSS low %d high %d\n", pcf_low, pcf_high, pcss_low,
                  pcss_high);
    /* PCSS: ratio of predicted widths is 0.37/0.055 ≈ 6.7; ask for > 2.5. */
    assert_true(pcss_high > 2.5 * pcss_low);
    assert_true(pcss_high >= 8);
    /* PCF: the same width within a factor 1.5 (pixel quantisation). */
    assert_true(pcf_low > 0 && pcf_high > 0);
    assert_true(pcf_high <= 1.5 * pcf_low + 1 && pcf_low <= 1.5 * pcf_high + 1);
    /* Both shadows exist under PCF: visibility reaches ~0 in each half. */
    double min_l = 1, min_r = 1;
    for (int x = 0; x < PW / 2; x++)
        min_l = fmin(min_l, v_pcf[x]);
    for (int x = PW / 2; x < PW; x++)
        min_r = fmin(min_r, v_pcf[x]);
    assert_true(min_l < 0.05 && min_r < 0.05);
    image_free(&none);
    image_free(&pcf);
    image_free(&pcss);
    scene_free(&s);
}

/* Grid PCF (--pcf-filter grid): bilinear hardware-compare taps one texel
 * apart, r = 1 the 3×3 tent. On the penumbra scene with a 256² map
 * (3.7 cm texels on the floor, 1.7 cm pixels): a symmetric filter moves
 * no shadow edge, so the high blocker's shadow area along the row
 * (Σ 1 − v) stays the hard shadow's, within 5% (nothing random), and
 * so does its centre, within 0.6 px (measured 0.25 and 0.47: the far
 * edge's blur spans more pixels; taps shifted by half a texel move it by
 * 0.87 and 1.14 px); its
 * penumbra is wider than the hard shadow's and grows with the radius (the
 * taps span 2r + 1 texels: 3 at r = 1, 7 at r = 3). */
static void grid_pcf_keeps_the_shadow_and_widens_with_radius(void **state)
{
    (void)state;
    Scene s;
    penumbra_scene(&s);
    s.settings.shadow.map_size = 256;
    ImageF none, hard, grid1, grid3;
    RenderSettings rs = test_settings(&s, PW, PH, SHADOW_MODE_NONE);
    test_render(&s, &rs, &none);
    rs.shadow = SHADOW_MODE_HARD;
    test_render(&s, &rs, &hard);
    rs.shadow = SHADOW_MODE_PCF;
    rs.set.shadow.pcf_filter = SHADOW_PCF_FILTER_GRID;
    rs.set.shadow.pcf_radius = 1.f;
    test_render(&s, &rs, &grid1);
    rs.set.shadow.pcf_radius = 3.f;
    test_render(&s, &rs, &grid3);
    double v_hard[PW], v1[PW], v3[PW];
    visibility_row(&hard, &none, v_hard);
    visibility_row(&grid1, &none, v1);
    visibility_row(&grid3, &none, v3);
    /* The high blocker's shadow (the right half; the camera sees most of
     * the low one's hidden under its blocker). */
    int x0 = PW / 2, x1 = PW;
    double a_hard = 0, a1 = 0, a3 = 0, c_hard = 0, c1 = 0, c3 = 0;
    for (int x = x0; x < x1; x++) {
        a_hard += 1.0 - v_hard[x];
        a1 += 1.0 - v1[x];
        a3 += 1.0 - v3[x];
        c_hard += x * (1.0 - v_hard[x]);
        c1 += x * (1.0 - v1[x]);
        c3 += x * (1.0 - v3[x]);
    }
    c_hard /= a_hard;
    c1 /= a1;
    c3 /= a3;
    int w_hard = penumbra_width(v_hard, x0, x1), w1 = penumbra_width(v1, x0, x1), w3 = penumbra_width(v3, x0, x1);
    print_message("shadow area (px) hard %.1f, grid r=1 %.1f, r=3 %.1f; centre %.2f, %.2f, %.2f; penumbra px %d, %d, %d\n",
                  a_hard, a1, a3, c_hard, c1, c3, w_hard, w1, w3);
    assert_true(a_hard > 20.0);
    assert_true(fabs(c1 - c_hard) < 0.6 && fabs(c3 - c_hard) < 0.6);
    assert_true(fabs(a1 - a_hard) < 0.05 * a_hard && fabs(a3 - a_hard) < 0.05 * a_hard);
    assert_true(w1 > w_hard && w1 >= 4);
    assert_true(w3 >= 2 * w1);
    image_free(&none);
    image_free(&hard);
    image_free(&grid1);
    image_free(&grid3);
    scene_free(&s);
}

/* A wide spot light (outer 89°: its map's field of view stops at the 170°
 * cap), 0.5 m up, pointing down; a wall 3 m away facing it; a 1 m lip
 * 0.1 m under the light between 1.04 and 1.14 m out, which the map's
 * outermost texels toward the wall hold (84.5°–85° from the axis). The
 * camera looks at the wall from under the lip. */
static void wide_spot_scene(Scene *s)
{
    scene_init(s);
    strcpy(s->source, "wide-spot-test");
    int grey = scene_add_material(s, "grey", (vec3){0.8f, 0.8f, 0.8f});
    scene_add_quad(s, grey, (vec3){3, -1, -3}, (vec3){3, 1, -3}, (vec3){3, 1, 3}, (vec3){3, -1, 3});
    scene_add_quad(s, grey, (vec3){1.04f, 0.4f, -0.5f}, (vec3){1.04f, 0.4f, 0.5f}, (vec3){1.14f, 0.4f, 0.5f},
                   (vec3){1.14f, 0.4f, -0.5f});
    Light l = {.type = LIGHT_SPOT, .position = {0, 0.5f, 0}, .direction = {0, -1, 0}, .color = {100, 100, 100},
               .size = 0.01f, .spot_inner = glm_rad(80.f), .spot_outer = glm_rad(89.f)};
    scene_add_light(s, &l);
    glm_vec3_copy((vec3){0.5f, 0.3f, 0}, s->camera.position);
    glm_vec3_copy((vec3){1, 0, 0}, s->camera.forward);
    glm_vec3_copy((vec3){0, 1, 0}, s->camera.up);
    s->camera.fov_y = glm_rad(40.f);
    s->settings.shadow.map_size = 256;
    scene_finalize(s);
}

/* Whether every texel of ring k (k texels in from the edge) of light 0's
 * 2D shadow map holds the clear depth 1; `inner_drawn`: some texel of ring
 * k + 1 holds less. */
static bool ring_clear(const Renderer *r, int k, bool *inner_drawn)
{
    const ShadowMap *m = &r->lights.shadow[0];
    int n = m->size;
    float *z = malloc(sizeof(float) * (size_t)n * (size_t)n);
    assert_non_null(z);
    glGetTextureImage(m->texture, 0, GL_DEPTH_COMPONENT, GL_FLOAT, (GLsizei)(sizeof(float) * (size_t)n * (size_t)n), z);
    bool clear = true;
    *inner_drawn = false;
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            int ring = x < y ? x : y;
            ring = ring < n - 1 - x ? ring : n - 1 - x;
            ring = ring < n - 1 - y ? ring : n - 1 - y;
            if (ring == k && z[y * n + x] != 1.f)
                clear = false;
            if (ring == k + 1 && z[y * n + x] < 1.f)
                *inner_drawn = true;
        }
    free(z);
    return clear;
}

/* Off the map, lit: the grid PCF's compare sampler clamps to the map's
 * edge, whose texels are never drawn (light_stage.c, shadow_face) and so
 * read the clear depth 1 as a border would. The wide spot's wall between
 * 0.3 and 0.45 m high lies 86°–89° from its axis: inside the cone, off the
 * map; it must be lit as without shadows, where the edge texels holding
 * the lip (nearer the light) would shadow it. A directional map keeps the
 * scene two texels inside its edge (shadow_frame.c), so not drawing the
 * ring loses no blocker: checked on a 16² map of a 6 × 1 m strip seen
 * straight down, whose ends come within 0.04 m of the bounding sphere the
 * map is fitted to (they reached the outermost ring before). */
static void off_the_map_is_lit(void **state)
{
    (void)state;
    Scene s;
    wide_spot_scene(&s);
    RenderSettings rs = test_settings(&s, PW, PH, SHADOW_MODE_NONE);
    ImageF none, grid;
    test_render(&s, &rs, &none);
    rs.shadow = SHADOW_MODE_PCF;
    rs.set.shadow.pcf_filter = SHADOW_PCF_FILTER_GRID;
    rs.set.shadow.pcf_radius = 1.f;
    Renderer r;
    assert_true(renderer_create(&r, &s, &rs));
    renderer_frame(&r, &s.camera);
    assert_true(renderer_read_hdr(&r, &grid));
    double lit = 0, unshadowed = 0;
    int count = 0;
    for (int j = 0; j <= 15; j++)
        for (int i = 0; i <= 20; i++) {
            int x, y;
            test_project(&s, PW, PH, (vec3){2.999f, 0.3f + 0.01f * (float)j, -0.5f + 0.05f * (float)i}, &x, &y);
            if (x < 0 || y < 0 || x >= PW || y >= PH)
                continue;
            lit += grid.rgb[3 * (y * PW + x)];
            unshadowed += none.rgb[3 * (y * PW + x)];
            count++;
        }
    print_message("wall beyond the spot map (%d points): grid PCF %g of the unshadowed radiance\n", count,
                  lit / unshadowed);
    assert_true(count == 16 * 21 && unshadowed > 0.0);
    assert_true(fabs(lit / unshadowed - 1.0) < 1e-6);
    bool inner_drawn;
    assert_true(ring_clear(&r, 0, &inner_drawn));
    assert_true(inner_drawn); /* the lip reaches the map's edge */
    renderer_destroy(&r);
    image_free(&none);
    image_free(&grid);
    scene_free(&s);

    scene_init(&s);
    strcpy(s.source, "sun-ring-test");
    int floor = scene_add_material(&s, "floor", (vec3){0.8f, 0.8f, 0.8f});
    scene_add_quad(&s, floor, (vec3){-3, 0, -0.5f}, (vec3){-3, 0, 0.5f}, (vec3){3, 0, 0.5f}, (vec3){3, 0, -0.5f});
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0, -1, 0}, .color = {1, 1, 1}, .size = glm_rad(0.5f)};
    scene_add_light(&s, &sun);
    test_camera_down(&s.camera, (vec3){0.f, 10.f, 0.f});
    s.camera.fov_y = glm_rad(40.f);
    s.settings.shadow.map_size = 16;
    scene_finalize(&s);
    rs = test_settings(&s, 32, 32, SHADOW_MODE_PCF);
    rs.set.shadow.pcf_filter = SHADOW_PCF_FILTER_GRID;
    assert_true(renderer_create(&r, &s, &rs));
    renderer_frame(&r, &s.camera);
    assert_true(ring_clear(&r, 0, &inner_drawn) && ring_clear(&r, 1, &inner_drawn));
    assert_true(inner_drawn); /* the strip reaches ring 2 */
    renderer_destroy(&r);
    scene_free(&s);
}

/* A point light far outside the scene gets one perspective map fitted to
 * the scene's bounding sphere (shadow_frame_point_fitted) instead of a cube
 * whose 90° faces spread the scene over a few texels.
 *  - 3 m in front of the Cornell box (6 bounding radii), low and to one
 *    side: the hard shadows against the direct reference, as
 *    artefacts_against_the_reference counts them. Fitted: false shadow
 *    0.0016, false lit 0; the cube map (texels 1.7× as wide): false lit
 *    0.11 (checked by turning the fitting off).
 *  - 170 m behind its closed back, top and side (the reference is black):
 *    the share of the pixels it reaches unshadowed that the hard shadows
 *    still light above 1% of that. Fitted: 0.6%, a line along the seam of
 *    the floor and a wall (the bias's contact leak); the cube map (a texel
 *    0.33 m wide there) lit all of them. */
static void far_point_light_scene(Scene *s, const vec3 at, float intensity)
{
    scene_build_cornell(s);
    Light *l = &s->lights[0];
    l->type = LIGHT_POINT;
    glm_vec3_copy((float *)at, l->position);
    glm_vec3_fill(l->color, intensity);
    l->size = 0.02f;
    scene_finalize(s);
}

static void count_light_errors(LogLevel level, const char *tag, const char *message, void *user)
{
    if (level == LOG_ERROR && !strcmp(tag, "lights") && strstr(message, "moved across the bound"))
        ++*(int *)user;
}

/* The map kind is fixed with the products (light_stage_run): a light moved
 * across the fitting bound is reported once, not drawn wrong in silence. */
static void moved_across_the_fitting_bound_is_reported(void **state)
{
    (void)state;
    Scene s;
    far_point_light_scene(&s, (vec3){0.278f, 0.4f, 0.28f}, 0.2f);
    RenderSettings rs = test_settings(&s, 16, 16, SHADOW_MODE_HARD);
    Renderer r;
    assert_true(renderer_create(&r, &s, &rs));
    int errors = 0;
    log_set_hook(count_light_errors, &errors);
    renderer_frame(&r, &s.camera);
    assert_int_equal(errors, 0);
    glm_vec3_copy((vec3){0.5f, 0.2f, -3.f}, s.lights[0].position);
    renderer_frame(&r, &s.camera);
    renderer_frame(&r, &s.camera);
    log_set_hook(NULL, NULL);
    assert_int_equal(errors, 1);
    renderer_destroy(&r);
    scene_free(&s);
}

static void far_point_light_gets_a_fitted_map(void **state)
{
    (void)state;
    Scene s;
    far_point_light_scene(&s, (vec3){0.5f, 0.2f, -3.f}, 10.f);
    assert_true(shadow_frame_point_fitted(&s.lights[0], s.bounds_min, s.bounds_max));
    ShadowFrame f;
    shadow_frame_compute(&s.lights[0], s.bounds_min, s.bounds_max, 1024, 2, &f);
    assert_false(f.cube);
    assert_true(f.texel_k < 0.65f * 2.f / 1024.f);
    ImageF ref, none, hard;
    test_reference(&s, CW, CH, PT_DIRECT, 128, &ref);
    RenderSettings rs = test_settings(&s, CW, CH, SHADOW_MODE_NONE);
    test_render(&s, &rs, &none);
    rs.shadow = SHADOW_MODE_HARD;
    test_render(&s, &rs, &hard);
    ShadowArtefacts h = metric_shadow_artefacts(&hard, &ref, &none, NULL);
    print_message("light 3 m in front: lit %zu, shadowed %zu pixels; false shadow %.4f, false lit %.4f\n", h.lit,
                  h.shadowed, h.false_shadow, h.false_lit);
    assert_true(h.lit > 10000 && h.shadowed > 200);
    assert_true(h.false_shadow < 0.01 && h.false_lit < 0.02);
    image_free(&ref);
    image_free(&none);
    image_free(&hard);
    scene_free(&s);

    far_point_light_scene(&s, (vec3){100.f, 100.f, 100.f}, 3e4f);
    assert_true(shadow_frame_point_fitted(&s.lights[0], s.bounds_min, s.bounds_max));
    rs = test_settings(&s, CW, CH, SHADOW_MODE_NONE);
    test_render(&s, &rs, &none);
    rs.shadow = SHADOW_MODE_HARD;
    test_render(&s, &rs, &hard);
    size_t lit = 0, reached = 0;
    for (int i = 0; i < CW * CH; i++) {
        float u = none.rgb[3 * i + 1], v = hard.rgb[3 * i + 1];
        reached += u > 0.f;
        lit += u > 0.f && v > 0.01f * u;
    }
    print_message("light 170 m behind the closed walls: %zu of %zu pixels it reaches unshadowed stay lit\n", lit,
                  reached);
    assert_true(reached > 5000);
    assert_true((double)lit < 0.02 * (double)reached);
    image_free(&none);
    image_free(&hard);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(grid_pcf_keeps_the_shadow_and_widens_with_radius),
        cmocka_unit_test(tall_block_casts_shadow),
        cmocka_unit_test(lit_floor_has_no_acne),
        cmocka_unit_test(artefacts_against_the_reference),
        cmocka_unit_test(pcss_penumbra_grows_pcf_does_not),
        cmocka_unit_test(off_the_map_is_lit),
        cmocka_unit_test(far_point_light_gets_a_fitted_map),
        cmocka_unit_test(moved_across_the_fitting_bound_is_reported),
    };
    return cmocka_run_group_tests_name("shadows", tests, test_gl_setup, test_gl_teardown);
}
