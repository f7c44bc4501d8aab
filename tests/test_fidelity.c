/* test_fidelity.c — where each GI technique's light lands on the Cornell
 * box, surface by surface, against the path tracer. A whole-image error
 * can hide light in the wrong place (LPV once passed one while darker than
 * no GI on the ceiling and 2.6× too bright on the back wall), so each row
 * checks the indirect ratio (test_util.h: the light the technique adds over
 * --gi none, over the light one bounce adds in the reference) of every
 * surface the camera sees: each wall, the floor, the ceiling and each face
 * of the blocks, as the path tracer's primary hits name them
 * (pt_surface_map). --gi none's ratio is 0 everywhere, so a lower bound
 * above 0 is one that no GI fails.
 *
 * The references (direct, one-bounce, one-bounce-novis) are rendered once
 * for the whole program. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"
#include "io/metrics.h"

#define W 128
#define H 128
#define SPP 256
#define MIN_PIXELS 40 /* a surface seen by fewer (eroded) pixels is not checked */

typedef struct Fixture {
    Scene scene;
    ImageF none;                   /* the rasterizer without GI */
    ImageF ref[PT_INDIRECT + 1];   /* by PtMode: direct, one-bounce, one-bounce-novis rendered */
    uint8_t *keep;                 /* 1 where a pixel and its neighbours see no emitter (test_emitter_mask) */
} Fixture;

static int setup(void **state)
{
    if (test_gl_setup(state) != 0)
        return -1;
    Fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    scene_build_cornell(&f->scene);
    scene_finalize(&f->scene);
    test_render_gi(&f->scene, W, H, GI_NONE, NULL, &f->none);
    const PtMode modes[] = {PT_DIRECT, PT_ONE_BOUNCE, PT_ONE_BOUNCE_NOVIS};
    for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++)
        test_reference(&f->scene, W, H, modes[i], SPP, &f->ref[modes[i]]);
    int32_t *ids = malloc(sizeof *ids * W * H);
    f->keep = malloc(W * H);
    assert_true(ids && f->keep && pt_surface_map(&f->scene, W, H, ids));
    test_emitter_mask(&f->scene, W, H, ids, f->keep);
    free(ids);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    Fixture *f = *state;
    image_free(&f->none);
    free(f->keep);
    for (int m = 0; m <= PT_INDIRECT; m++)
        image_free(&f->ref[m]);
    scene_free(&f->scene);
    free(f);
    *state = NULL;
    return test_gl_teardown(state);
}

static const char *const k_face_names[] = {"+x", "-x", "+y", "-y", "+z", "-z"};

/* Renders technique `gi` (settings gp; NULL: the scene's) and checks the
 * indirect ratio against the reference `mode` on every surface seen by
 * MIN_PIXELS or more: within [lo, hi]. Returns the whole image's ratio;
 * with `region`, the ratio over its pixels into *region_ratio. */
static double check_region_with(const Fixture *f, GiMode gi, const GiParams *gp, PtMode mode, double lo, double hi,
                                const uint8_t *region, double *region_ratio)
{
    ImageF img;
    test_render_gi(&f->scene, W, H, gi, gp, &img);
    const ImageF *ref = &f->ref[mode], *direct = &f->ref[PT_DIRECT];
    uint8_t *mask = malloc((size_t)W * H);
    assert_non_null(mask);
    double whole = test_indirect_ratio(&img, &f->none, ref, direct, NULL);
    if (region)
        *region_ratio = test_indirect_ratio(&img, &f->none, ref, direct, region);
    print_message("%s%s against %s: whole image %.3f\n", gi_technique_names()[gi],
                  gp && gp->visibility.on ? " with visibility" : "", pt_mode_names[mode], whole);
    int checked = 0, bad = 0;
    for (int m = 0; m < f->scene.material_count; m++) {
        const Material *mat = &f->scene.materials[m];
        if (mat->emission[0] > 0 || mat->emission[1] > 0 || mat->emission[2] > 0)
            continue;
        for (int face = 0; face < 6; face++) {
            int n = test_surface_mask(&f->scene, W, H, mat->name, face, mask);
            if (n < MIN_PIXELS)
                continue;
            double r = test_indirect_ratio(&img, &f->none, ref, direct, mask);
            bool ok = r >= lo && r <= hi;
            print_message("  %-12s %s %5d px  ratio %.3f%s\n", mat->name, k_face_names[face], n, r,
                          ok ? "" : "  <- outside the bounds");
            checked++;
            bad += !ok;
        }
    }
    print_message("  %d surfaces, %d outside [%.2f, %.2f]\n", checked, bad, lo, hi);
    assert_true(checked >= 8); /* 5 walls and the blocks' faces */
    assert_int_equal(bad, 0);
    free(mask);
    image_free(&img);
    return whole;
}

/* The relMSE of technique `gi` against one-bounce without the pixels that
 * see the emitter and their neighbours (the rasterizer draws the quad
 * light's face, the path tracer its emission: both unrelated to GI, and
 * they would dominate). */
static double relmse_one_bounce(const Fixture *f, GiMode gi)
{
    ImageF img;
    if (gi != GI_NONE)
        test_render_gi(&f->scene, W, H, gi, NULL, &img);
    double r = metric_relmse(gi != GI_NONE ? &img : &f->none, &f->ref[PT_ONE_BOUNCE], f->keep, NULL);
    if (gi != GI_NONE)
        image_free(&img);
    return r;
}

static double check_surfaces(const Fixture *f, GiMode gi, PtMode mode, double lo, double hi)
{
    return check_region_with(f, gi, NULL, mode, lo, hi, NULL, NULL);
}

/* The control: RSM computes exactly one-bounce-novis up to its sampling,
 * so every surface must sit near 1 against it. */
static void rsm_against_one_bounce_novis(void **state)
{
    const Fixture *f = *state;
    double whole = check_surfaces(f, GI_RSM, PT_ONE_BOUNCE_NOVIS, 0.85, 1.15);
    assert_true(whole > 0.9 && whole < 1.1);
}

/* The back wall's pixels (−z face) in the image columns of the tall
 * block, above it: the strip whose bounce from the floor in front of the
 * block the block hides. Into mask; returns the count. */
static int strip_behind_tall_block(const Fixture *f, uint8_t *mask)
{
    uint8_t *block = malloc((size_t)W * H);
    assert_non_null(block);
    test_surface_mask(&f->scene, W, H, "tall_block", -1, block);
    int x0 = W, x1 = -1;
    for (int i = 0; i < W * H; i++)
        if (block[i]) {
            x0 = i % W < x0 ? i % W : x0;
            x1 = i % W > x1 ? i % W : x1;
        }
    test_surface_mask(&f->scene, W, H, "back_wall", PT_FACE_NEG_Z, mask);
    int n = 0;
    for (int i = 0; i < W * H; i++) {
        mask[i] = mask[i] && i % W >= x0 && i % W <= x1;
        n += mask[i];
    }
    free(block);
    return n;
}

/* Issue 47: with the visibility of the bounce (imperfect shadow maps) RSM
 * and VPL gathers compute one-bounce itself. Without it they compute
 * one-bounce-novis, the baseline every bound here is set against (measured
 * with it, 128²: whole image rsm 1.125, vpl-slc 1.116; the floor 1.92 and
 * 1.84, the left wall 1.37 and 1.34, the strip 1.15 and 1.14). With it:
 * whole 0.973 and 0.959, every surface 0.91-1.10, the strip 0.988 and
 * 0.977 (the maps' widened silhouettes read a few percent low). vpl-slc
 * had read 0.932 with visibility (1.093 without: VPLs at texel centres,
 * --vpl-supersample 1, and splats reaching along their planes), under
 * a bound of 0.92. */
static void visibility_against_one_bounce(void **state)
{
    const Fixture *f = *state;
    GiParams gp = f->scene.settings.gi;
    gp.visibility.on = true;
    uint8_t *strip = malloc((size_t)W * H);
    assert_non_null(strip);
    int n = strip_behind_tall_block(f, strip);
    assert_true(n >= MIN_PIXELS);
    const GiMode modes[] = {GI_RSM, GI_VPL_SLC};
    const double whole_lo[] = {0.95, 0.95};
    for (int k = 0; k < 2; k++) {
        double s_off, s_on;
        double off = check_region_with(f, modes[k], NULL, PT_ONE_BOUNCE, 0.0, 100.0, strip, &s_off);
        double on = check_region_with(f, modes[k], &gp, PT_ONE_BOUNCE, 0.85, 1.2, strip, &s_on);
        print_message("%s: whole image off %.3f, on %.3f; back wall behind the tall block (%d px) off %.3f, on %.3f\n",
                      gi_technique_names()[modes[k]], off, on, n, s_off, s_on);
        assert_true(off > 1.05 && s_off > 1.1); /* the baseline fails the bounds below */
        assert_true(on >= whole_lo[k] && on <= 1.05);
        assert_true(s_on >= 0.9 && s_on <= 1.1);
    }
    free(strip);
}

/* Light propagation volumes (the defaults: 16³, directional propagation, two
 * light groups, G-buffer occlusion) against one-bounce, whose occluded
 * bounce the geometry volume stands for: every surface within [0.67, 1.5]
 * (issue 44), and the whole image's relMSE under half --gi none's.
 * Measured at 256² (PCSS, jittered reference; scripts/gi-regions.sh):
 * 0.89-1.31 on the 10 surfaces, relMSE 0.0029 (none 0.0332); the paper's
 * faces at 32³ had read the floor 6.0, the ceiling 0.07, the back wall 2.7. */
static void lpv_against_one_bounce(void **state)
{
    const Fixture *f = *state;
    double whole = check_surfaces(f, GI_LPV, PT_ONE_BOUNCE, 0.67, 1.5);
    assert_true(whole > 0.8 && whole < 1.25);
    double lpv = relmse_one_bounce(f, GI_LPV), none = relmse_one_bounce(f, GI_NONE);
    print_message("relMSE against one-bounce, emitter pixels left out: lpv %.4f, none %.4f\n", lpv, none);
    assert_true(lpv < 0.5 * none);
}

/* Voxel cone tracing (the defaults: 128³, directional volumes, 9 cones)
 * against one-bounce: every surface within [0.75, 1.33] (issue 44).
 * Measured at 256² (scripts/gi-regions.sh): 0.89-1.28 on the 10 surfaces,
 * whole 1.04; the code before (opacity mips, every voxel sending its light
 * every way, samples lifted one diameter along n) read the floor 3.2, the
 * back wall 1.8, the ceiling 0.54 and the tall block's +x face 0.42. */
static void vct_against_one_bounce(void **state)
{
    const Fixture *f = *state;
    double whole = check_surfaces(f, GI_VCT, PT_ONE_BOUNCE, 0.75, 1.33);
    assert_true(whole > 0.8 && whole < 1.25);
    /* relMSE under 2.5× rsm's (issue 44; 256²: 0.0029 against rsm's
     * 0.0022, the code before 0.0108). */
    double vct = relmse_one_bounce(f, GI_VCT), rsm = relmse_one_bounce(f, GI_RSM);
    print_message("relMSE against one-bounce, emitter pixels left out: vct %.4f, rsm %.4f\n", vct, rsm);
    assert_true(vct < 2.5 * rsm);
}

/* The short block's top at 256², where the issue measures it: at 128² it
 * has 37 eroded pixels (under MIN_PIXELS) and reads higher (6 cones 1.42,
 * 9 cones 1.35; scripts/gi-regions.sh, gi_regions --min-pixels 10), so the
 * fixture's check above does not see it. Its own references at 256², 64
 * spp. Measured (9 cones, the default): 1.322 against these references
 * (1.315 against 256 spp); the 6-cone set, the default before, reads 1.375
 * (1.369): its ring cones, narrowed near the surface by the mip cap
 * (gi/vct/cone.glsl, vct_mip_cap), read the radiance along their axes,
 * and on the block's top the 6-cone set's axes point at brighter wall
 * than their cells hold on average (tests/vct_probe: cone 1 reads 2.4×
 * its cell's ray cast, the narrow cones over the whole hemisphere 0.96).
 * The bound is the issue's [0.75, 1.33]; the 6-cone set must fail it. */
static void vct_block_top_256(void **state)
{
    (void)state;
    enum { W2 = 256, SPP2 = 64 };
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    ImageF none, ob, direct, img[2];
    test_render_gi(&s, W2, W2, GI_NONE, NULL, &none);
    test_reference(&s, W2, W2, PT_ONE_BOUNCE, SPP2, &ob);
    test_reference(&s, W2, W2, PT_DIRECT, SPP2, &direct);
    uint8_t *mask = malloc((size_t)W2 * W2);
    assert_non_null(mask);
    int n = test_surface_mask(&s, W2, W2, "short_block", PT_FACE_POS_Y, mask);
    assert_true(n >= 200);
    double r[2];
    for (int k = 0; k < 2; k++) {
        GiParams gp = s.settings.gi;
        if (k == 1)
            gp.vct.cones = VCT_CONES_6;
        test_render_gi(&s, W2, W2, GI_VCT, &gp, &img[k]);
        r[k] = test_indirect_ratio(&img[k], &none, &ob, &direct, mask);
        image_free(&img[k]);
    }
    print_message("short block's top at 256x256 (%d px): vct %.3f, with 6 cones %.3f\n", n, r[0], r[1]);
    assert_true(r[0] >= 0.75 && r[0] <= 1.33);
    assert_true(r[1] > 1.33); /* the baseline fails the bound */
    free(mask);
    image_free(&none);
    image_free(&ob);
    image_free(&direct);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(visibility_against_one_bounce),
        cmocka_unit_test(rsm_against_one_bounce_novis),
        cmocka_unit_test(lpv_against_one_bounce),
        cmocka_unit_test(vct_against_one_bounce),
        cmocka_unit_test(vct_block_top_256),
    };
    return cmocka_run_group_tests_name("fidelity", tests, setup, teardown);
}
