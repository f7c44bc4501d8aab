/* test_temporal.c — measuring time (issue 50): the flicker metric on known
 * sequences, a still sequence of a deterministic technique with flicker 0,
 * and temporal accumulation on the orbiting spot light: vpl-slc flickers
 * without it, at least 3 times less with it, and its error against the
 * per-frame reference is not more than 10% higher (its history does not
 * lag behind the moving light's bounce). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "animation.h"
#include "metrics.h"
#include "metrics_temporal.h"
#include "renderer.h"
#include "test_util.h"

/* A w×h image of one value. */
static void flat(ImageF *img, int w, int h, float v)
{
    assert_true(image_alloc(img, w, h));
    for (size_t i = 0; i < 3 * (size_t)w * h; i++)
        img->rgb[i] = v;
}

static void flicker_of_known_sequences(void **state)
{
    (void)state;
    ImageF a, b;
    flat(&a, 2, 2, 1.f);
    flat(&b, 2, 2, 2.f);
    /* Equal frames: 0. */
    FlickerSum f = {0};
    for (int i = 0; i < 4; i++)
        flicker_add(&f, &a, NULL);
    assert_true(flicker_value(&f) == 0.0);
    flicker_free(&f);
    /* 1, 2, 1: the middle frame's second difference is 1, the mean
     * radiance 4/3: 0.75. */
    flicker_add(&f, &a, NULL);
    flicker_add(&f, &b, NULL);
    flicker_add(&f, &a, NULL);
    assert_float_equal(flicker_value(&f), 0.75, 1e-12);
    flicker_free(&f);
    /* A steady ramp 1, 2, 3 has none (motion at a constant pace). */
    ImageF c;
    flat(&c, 2, 2, 3.f);
    flicker_add(&f, &a, NULL);
    flicker_add(&f, &b, NULL);
    flicker_add(&f, &c, NULL);
    assert_true(flicker_value(&f) == 0.0);
    flicker_free(&f);
    /* Two frames: not defined. */
    flicker_add(&f, &a, NULL);
    flicker_add(&f, &b, NULL);
    assert_true(isnan(flicker_value(&f)));
    flicker_free(&f);
    /* Masked pixels do not count. */
    uint8_t mask[4] = {1, 0, 0, 0};
    ImageF d;
    flat(&d, 2, 2, 1.f);
    d.rgb[3] = 5.f; /* pixel 1, masked out */
    flicker_add(&f, &a, mask);
    flicker_add(&f, &d, mask);
    flicker_add(&f, &a, mask);
    assert_true(flicker_value(&f) == 0.0);
    flicker_free(&f);
    image_free(&a);
    image_free(&b);
    image_free(&c);
    image_free(&d);
}

/* The orbiting spot light of scenes/cornell_orbit.json. */
static void load_orbit(Scene *s)
{
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/cornell_orbit.json", RTGI_SOURCE_DIR);
    assert_true(scene_load(s, path));
}

enum { W = 32, H = 32, FRAMES = 12 };
#define FPS 480.0 /* the light moves 0.19 degrees a frame: its own change is smooth at this pace */

/* Renders `frames` frames at times i/FPS (still: all at t = 0.5 s) with
 * technique gi, returning their flicker and (with refs) the mean relMSE
 * against refs[i]. */
static double sequence(Scene *s, GiMode gi, bool temporal, bool still, const ImageF *refs, double *mean_relmse)
{
    RenderSettings rs = test_settings(s, W, H, SHADOW_MODE_NONE);
    rs.gi = gi;
    rs.gi_params = s->gi;
    rs.gi_params.vpl_count = 1024;
    rs.gi_params.temporal = temporal;
    rs.cache = true;
    animation_apply(s, 0.5, NULL);
    Renderer r;
    assert_true(renderer_create(&r, s, &rs));
    FlickerSum f = {0};
    double sum = 0;
    for (int i = 0; i < FRAMES; i++) {
        SceneChange c;
        animation_apply(s, still ? 0.5 : 0.5 + i / FPS, &c);
        assert_true(renderer_scene_changed(&r, &c));
        renderer_frame(&r, &s->camera);
        ImageF img;
        assert_true(renderer_read_hdr(&r, &img));
        flicker_add(&f, &img, NULL);
        if (refs)
            sum += metric_relmse(&img, &refs[i], NULL, NULL);
        image_free(&img);
    }
    assert_true(renderer_frames_whole(&r));
    renderer_destroy(&r);
    double v = flicker_value(&f);
    flicker_free(&f);
    if (mean_relmse)
        *mean_relmse = sum / FRAMES;
    return v;
}

static void still_deterministic_sequence_has_no_flicker(void **state)
{
    (void)state;
    Scene s;
    load_orbit(&s);
    double still = sequence(&s, GI_RSM, false, true, NULL, NULL);
    double moving = sequence(&s, GI_RSM, false, false, NULL, NULL);
    print_message("rsm flicker: still %.3g, orbiting light %.3g\n", still, moving);
    assert_true(still == 0.0);
    assert_true(moving > 0.0); /* the same measure sees motion */
    scene_free(&s);
}

static void temporal_accumulation_lowers_vpl_slc_flicker(void **state)
{
    (void)state;
    Scene s;
    load_orbit(&s);
    ImageF refs[FRAMES];
    for (int i = 0; i < FRAMES; i++) {
        animation_apply(&s, 0.5 + i / FPS, NULL);
        test_reference(&s, W, H, PT_FULL, 16, &refs[i]);
    }
    FlickerSum rf = {0};
    for (int i = 0; i < FRAMES; i++)
        flicker_add(&rf, &refs[i], NULL);
    double e_off, e_on;
    double off = sequence(&s, GI_VPL_SLC, false, false, refs, &e_off);
    double on = sequence(&s, GI_VPL_SLC, true, false, refs, &e_on);
    print_message("vpl-slc over %d frames at %g fps: flicker %.5f without, %.5f with --temporal (%.1fx lower; the "
                  "reference's %.5f); mean relMSE %.5f without, %.5f with\n",
                  FRAMES, FPS, off, on, off / on, flicker_value(&rf), e_off, e_on);
    assert_true(off > 0.0);
    assert_true(3.0 * on <= off);
    assert_true(e_on <= 1.1 * e_off);
    flicker_free(&rf);
    for (int i = 0; i < FRAMES; i++)
        image_free(&refs[i]);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(flicker_of_known_sequences),
        cmocka_unit_test(still_deterministic_sequence_has_no_flicker),
        cmocka_unit_test(temporal_accumulation_lowers_vpl_slc_flicker),
    };
    return cmocka_run_group_tests_name("temporal", tests, test_gl_setup, test_gl_teardown);
}
