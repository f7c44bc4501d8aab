/* test_temporal.c — measuring time (issue 50): the flicker metric on known
 * sequences, a still sequence of a deterministic technique with flicker 0,
 * and temporal accumulation on the orbiting spot light: vpl-slc flickers
 * without it, at least 3 times less with it, and its error against the
 * per-frame reference is not more than 10% higher; with a fast light, the
 * clamped history follows the bounce on the ceiling where the unclamped one
 * (--temporal-clamp off) lags. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/animation.h"
#include "io/metrics.h"
#include "io/metrics_temporal.h"
#include "frame/renderer.h"
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

enum { W = 32, H = 32, FRAMES = 12 };
#define FPS 480.0 /* the light moves 0.19 degrees a frame: its own change is smooth at this pace */
#define T0 0.5    /* the sequences' first frame (s) */

/* A sequence: technique, accumulation, and the frames' pace. */
typedef struct Run {
    GiMode gi;
    bool temporal, clamp; /* --temporal, --temporal-clamp */
    double fps;           /* frame i at T0 + i / fps; 0: every frame at T0 (still) */
} Run;

/* What a sequence measured: its flicker and, with references, the mean
 * relMSE of frames [from, FRAMES) over the whole image and over a mask. */
typedef struct Measured {
    double flicker, relmse, relmse_mask;
} Measured;

/* Renders FRAMES frames of `run` and measures them (refs, mask: may be NULL). */
static Measured sequence(Scene *s, Run run, const ImageF *refs, int from, const uint8_t *mask)
{
    RenderSettings rs = test_settings(s, W, H, SHADOW_MODE_NONE);
    rs.gi = run.gi;
    rs.set.gi = s->settings.gi;
    rs.set.gi.vpl.count = 1024;
    rs.set.gi.frame.temporal = run.temporal;
    rs.set.gi.frame.temporal_clamp = run.clamp;
    rs.cache = true;
    animation_apply(s, T0, NULL);
    Renderer r;
    assert_true(renderer_create(&r, s, &rs));
    FlickerSum f = {0};
    Measured m = {0};
    for (int i = 0; i < FRAMES; i++) {
        SceneChange c;
        animation_apply(s, run.fps > 0 ? T0 + i / run.fps : T0, &c);
        assert_true(renderer_scene_changed(&r, &c));
        renderer_frame(&r, &s->camera);
        ImageF img;
        assert_true(renderer_read_hdr(&r, &img));
        flicker_add(&f, &img, NULL);
        if (refs && i >= from) {
            m.relmse += metric_relmse(&img, &refs[i], NULL, NULL) / (FRAMES - from);
            if (mask)
                m.relmse_mask += metric_relmse(&img, &refs[i], mask, NULL) / (FRAMES - from);
        }
        image_free(&img);
    }
    assert_true(renderer_frames_whole(&r));
    renderer_destroy(&r);
    m.flicker = flicker_value(&f);
    flicker_free(&f);
    return m;
}

/* Frees the references and the scene. */
static void free_all(ImageF refs[FRAMES], Scene *s)
{
    for (int i = 0; i < FRAMES; i++)
        image_free(&refs[i]);
    scene_free(s);
}

/* The path-traced reference of each frame at `fps`, and its flicker. */
static double references(Scene *s, double fps, ImageF refs[FRAMES])
{
    FlickerSum rf = {0};
    for (int i = 0; i < FRAMES; i++) {
        animation_apply(s, T0 + i / fps, NULL);
        test_reference(s, W, H, PT_FULL, 16, &refs[i]);
        flicker_add(&rf, &refs[i], NULL);
    }
    double v = flicker_value(&rf);
    flicker_free(&rf);
    return v;
}

static void still_deterministic_sequence_has_no_flicker(void **state)
{
    (void)state;
    Scene s;
    test_load_scene_file(&s, "cornell_orbit.json"); /* the orbiting spot light */
    double still = sequence(&s, (Run){GI_RSM, false, true, 0}, NULL, 0, NULL).flicker;
    double moving = sequence(&s, (Run){GI_RSM, false, true, FPS}, NULL, 0, NULL).flicker;
    print_message("rsm flicker: still %.3g, orbiting light %.3g\n", still, moving);
    assert_true(still == 0.0);
    assert_true(moving > 0.0); /* the same measure sees motion */
    scene_free(&s);
}

static void temporal_accumulation_lowers_vpl_slc_flicker(void **state)
{
    (void)state;
    Scene s;
    test_load_scene_file(&s, "cornell_orbit.json"); /* the orbiting spot light */
    ImageF refs[FRAMES];
    double ref_flicker = references(&s, FPS, refs);
    Measured off = sequence(&s, (Run){GI_VPL_SLC, false, true, FPS}, refs, 0, NULL);
    Measured on = sequence(&s, (Run){GI_VPL_SLC, true, true, FPS}, refs, 0, NULL);
    print_message("vpl-slc over %d frames at %g fps: flicker %.5f without, %.5f with --temporal (%.1fx lower; the "
                  "reference's %.5f); mean relMSE %.5f without, %.5f with\n",
                  FRAMES, FPS, off.flicker, on.flicker, off.flicker / on.flicker, ref_flicker, off.relmse, on.relmse);
    assert_true(off.flicker > 0.0);
    assert_true(3.0 * on.flicker <= off.flicker);
    assert_true(on.relmse <= 1.1 * off.relmse);
    free_all(refs, &s);
}

/* A fast light (the orbit at 8 fps: 11 degrees a frame): on the ceiling,
 * which only the bounce lights (the spot points down), the clamped history
 * follows the moving bounce: its error against each frame's reference
 * stays near that of no accumulation, where the history without the clamp
 * (--temporal-clamp off, the baseline) lags frames behind. */
static void temporal_accumulation_follows_a_fast_light(void **state)
{
    (void)state;
    Scene s;
    test_load_scene_file(&s, "cornell_orbit.json"); /* the orbiting spot light */
    const double fps = 8.0;
    ImageF refs[FRAMES];
    double ref_flicker = references(&s, fps, refs);
    uint8_t ceiling[W * H];
    int n = test_surface_mask(&s, W, H, "ceiling", -1, ceiling);
    const int from = 4; /* once the history has built up */
    Measured off = sequence(&s, (Run){GI_VPL_SLC, false, true, fps}, refs, from, ceiling);
    Measured on = sequence(&s, (Run){GI_VPL_SLC, true, true, fps}, refs, from, ceiling);
    Measured lag = sequence(&s, (Run){GI_VPL_SLC, true, false, fps}, refs, from, ceiling);
    print_message("vpl-slc at %g fps, frames %d-%d: ceiling (%d px) relMSE %.5f without, %.5f with --temporal, "
                  "%.5f with --temporal-clamp off; whole image %.5f, %.5f, %.5f; flicker %.5f, %.5f, %.5f (the "
                  "reference's %.5f)\n",
                  fps, from, FRAMES - 1, n, off.relmse_mask, on.relmse_mask, lag.relmse_mask, off.relmse, on.relmse,
                  lag.relmse, off.flicker, on.flicker, lag.flicker, ref_flicker);
    assert_true(n >= 40);
    assert_true(on.relmse_mask <= 1.35 * off.relmse_mask);
    assert_true(lag.relmse_mask >= 2.0 * off.relmse_mask); /* the measure sees a lagging history */
    free_all(refs, &s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(flicker_of_known_sequences),
        cmocka_unit_test(still_deterministic_sequence_has_no_flicker),
        cmocka_unit_test(temporal_accumulation_lowers_vpl_slc_flicker),
        cmocka_unit_test(temporal_accumulation_follows_a_fast_light),
    };
    return cmocka_run_group_tests_name("temporal", tests, test_gl_setup, test_gl_teardown);
}
