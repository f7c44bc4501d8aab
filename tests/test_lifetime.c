/* test_lifetime.c — the window's path: one renderer whose technique, size
 * and exposure change through renderer_apply gives the same images as a
 * fresh renderer, and releases what the old technique created (live GL
 * objects counted by name). */
#include <string.h>

#include "gl/gl_resources.h"
#include "io/metrics.h"
#include "frame/renderer.h"
#include "test_util.h"

enum { W = 40, H = 32, MAX_NAME = 8192 };

static RenderSettings settings_for(const Scene *s, GiMode gi, int w, int h)
{
    RenderSettings rs = test_settings(s, w, h, SHADOW_MODE_PCF);
    rs.gi = gi;
    rs.set.gi = s->settings.gi;
    rs.set.gi.rsm.size = 32;
    rs.set.gi.rsm.samples = 64;
    rs.set.gi.vpl.count = 1024;
    rs.set.shadow.map_size = 64;
    return rs;
}

static void fresh_image(const Scene *s, const RenderSettings *rs, ImageF *out)
{
    Renderer r;
    assert_true(renderer_create(&r, s, rs));
    renderer_frame(&r, &s->camera);
    assert_true(renderer_read_hdr(&r, out));
    renderer_destroy(&r);
}

/* Live objects other than programs and shaders (those belong to the
 * renderer's program cache, which keeps them for later switches). */
static int resources(const GlObjectCounts *c)
{
    return c->textures + c->buffers + c->framebuffers + c->renderbuffers + c->vertex_arrays + c->queries +
           c->samplers;
}

static void switching_matches_fresh_and_releases(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, "cornell"));
    const GiMode order[] = {GI_RSM, GI_VPL_SLC, GI_RSM_INTERLEAVED, GI_VPL_METALIGHTS, GI_RSM_INTERP, GI_NONE};
    const int n = (int)(sizeof order / sizeof order[0]);
    ImageF fresh[6];
    for (int i = 0; i < n; i++) {
        RenderSettings rs = settings_for(&s, order[i], W, H);
        fresh_image(&s, &rs, &fresh[i]);
    }

    GlObjectCounts before = gl_count_live_objects(MAX_NAME);
    Renderer r;
    RenderSettings rs = settings_for(&s, GI_NONE, W, H);
    assert_true(renderer_create(&r, &s, &rs));
    renderer_frame(&r, &s.camera);
    GlObjectCounts base = gl_count_live_objects(MAX_NAME);
    for (int i = 0; i < n; i++) {
        rs = settings_for(&s, order[i], W, H);
        assert_true(renderer_apply(&r, &rs));
        renderer_frame(&r, &s.camera);
        ImageF img;
        assert_true(renderer_read_hdr(&r, &img));
        double e = metric_relmse(&img, &fresh[i], NULL, NULL);
        print_message("%-16s switched vs fresh: relMSE %.3g\n", gi_techniques[order[i]]->name, e);
        assert_true(e < 1e-10);
        image_free(&img);
    }
    /* Back at "none": the techniques' textures, buffers and the light
     * stage's RSMs and VPL buffer are gone. */
    GlObjectCounts back = gl_count_live_objects(MAX_NAME);
    print_message("live resources: none %d, after 6 switches back to none %d; cached programs %d\n",
                  resources(&base), resources(&back), r.programs.count);
    assert_int_equal(resources(&back), resources(&base));
    assert_true(back.programs <= base.programs + r.programs.count);
    renderer_destroy(&r);
    GlObjectCounts after = gl_count_live_objects(MAX_NAME);
    assert_int_equal(gl_object_counts_total(&after), gl_object_counts_total(&before));
    for (int i = 0; i < n; i++)
        image_free(&fresh[i]);
    scene_free(&s);
}

static void resize_and_exposure(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, "cornell"));
    RenderSettings rs = settings_for(&s, GI_RSM_INTERLEAVED, W, H);
    Renderer r;
    assert_true(renderer_create(&r, &s, &rs));
    renderer_frame(&r, &s.camera);

    /* Exposure: nothing remade, only the tone-mapped image changes. */
    GlObjectCounts c0 = gl_count_live_objects(MAX_NAME);
    GLuint hdr = r.hdr.texture, rsm = r.lights.rsm[0].texel;
    uint8_t *ldr0 = renderer_read_ldr(&r);
    rs.exposure *= 0.5f;
    assert_true(renderer_apply(&r, &rs));
    renderer_frame(&r, &s.camera);
    GlObjectCounts c1 = gl_count_live_objects(MAX_NAME);
    assert_int_equal(gl_object_counts_total(&c1), gl_object_counts_total(&c0));
    assert_int_equal(r.hdr.texture, hdr);
    assert_int_equal(r.lights.rsm[0].texel, rsm);
    uint8_t *ldr1 = renderer_read_ldr(&r);
    assert_true(memcmp(ldr0, ldr1, 3 * (size_t)W * H) != 0);
    free(ldr0);
    free(ldr1);

    /* Size: the same image as a fresh renderer of the new size. */
    const int w2 = 56, h2 = 24;
    rs.width = w2;
    rs.height = h2;
    assert_true(renderer_apply(&r, &rs));
    renderer_frame(&r, &s.camera);
    ImageF got, want;
    assert_true(renderer_read_hdr(&r, &got));
    assert_int_equal(got.width, w2);
    fresh_image(&s, &rs, &want);
    double e = metric_relmse(&got, &want, NULL, NULL);
    print_message("resized %dx%d -> %dx%d vs fresh: relMSE %.3g\n", W, H, w2, h2, e);
    assert_true(e < 1e-10);
    /* Shadow settings: the same as fresh too. */
    rs.shadow = SHADOW_MODE_PCSS;
    rs.set.shadow.map_size = 128;
    assert_true(renderer_apply(&r, &rs));
    renderer_frame(&r, &s.camera);
    image_free(&got);
    image_free(&want);
    assert_true(renderer_read_hdr(&r, &got));
    fresh_image(&s, &rs, &want);
    e = metric_relmse(&got, &want, NULL, NULL);
    print_message("shadow settings changed vs fresh: relMSE %.3g\n", e);
    assert_true(e < 1e-10);
    image_free(&got);
    image_free(&want);
    renderer_destroy(&r);
    scene_free(&s);
}

/* Issue 11: light products cached across frames. A cached (steady) frame
 * equals a cold frame bit for bit and draws no map; moving the light, a
 * new map size or renderer_invalidate redraws what depends on them, and the
 * result equals a fresh renderer's. */
static void cached_light_products(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, "cornell"));
    RenderSettings rs = settings_for(&s, GI_RSM, W, H);
    rs.cache = true;
    Renderer r;
    assert_true(renderer_create(&r, &s, &rs));
    renderer_frame(&r, &s.camera);
    int cold_draws = r.lights.map_draws;
    ImageF cold, steady, got, want;
    assert_true(renderer_read_hdr(&r, &cold));
    renderer_frame(&r, &s.camera);
    assert_true(renderer_read_hdr(&r, &steady));
    assert_int_equal(r.lights.map_draws, cold_draws); /* nothing redrawn */
    assert_memory_equal(cold.rgb, steady.rgb, sizeof(float) * 3 * W * H);
    /* nor the importance pyramid and sample list derived from the RSM */
    assert_int_equal(renderer_collect_stats(&r)->rsm_importance_builds, 1);

    /* The light moves: its shadow map and RSM are redrawn. */
    s.lights[0].position[0] -= 0.05f;
    renderer_frame(&r, &s.camera);
    assert_int_equal(r.lights.map_draws, 2 * cold_draws);
    assert_int_equal(renderer_collect_stats(&r)->rsm_importance_builds, 2);
    assert_true(renderer_read_hdr(&r, &got));
    RenderSettings fresh = rs;
    fresh.cache = false;
    fresh_image(&s, &fresh, &want);
    assert_memory_equal(got.rgb, want.rgb, sizeof(float) * 3 * W * H);
    image_free(&got);
    image_free(&want);

    /* A new shadow-map size remakes (and so redraws) the maps. */
    rs.set.shadow.map_size = 96;
    assert_true(renderer_apply(&r, &rs));
    renderer_frame(&r, &s.camera);
    assert_true(renderer_read_hdr(&r, &got));
    fresh = rs;
    fresh.cache = false;
    fresh_image(&s, &fresh, &want);
    assert_memory_equal(got.rgb, want.rgb, sizeof(float) * 3 * W * H);

    /* Invalidation forces a cold frame with the same image. */
    int before = r.lights.map_draws;
    renderer_invalidate(&r);
    renderer_frame(&r, &s.camera);
    assert_int_equal(r.lights.map_draws, before + cold_draws);
    image_free(&got);
    assert_true(renderer_read_hdr(&r, &got));
    assert_memory_equal(got.rgb, want.rgb, sizeof(float) * 3 * W * H);
    /* Without caching the RSM is redrawn every frame, and so what derives
     * from it is rebuilt. */
    Renderer u;
    assert_true(renderer_create(&u, &s, &fresh));
    renderer_frame(&u, &s.camera);
    renderer_frame(&u, &s.camera);
    assert_int_equal(renderer_collect_stats(&u)->rsm_importance_builds, 2);
    renderer_destroy(&u);
    print_message("cold frame: %d maps drawn; steady frames: 0; redrawn on a light move, a new map size and "
                  "invalidation, each equal to a fresh renderer\n",
                  cold_draws);
    image_free(&cold);
    image_free(&steady);
    image_free(&got);
    image_free(&want);
    renderer_destroy(&r);
    scene_free(&s);
}

/* Issue 11: LPV injection and propagation, and VCT radiance injection and
 * filtering, are kept while the light products (and the grids, which may
 * follow the camera) stand: a steady frame equals the cold one bit for bit
 * without rebuilding them; a moved light rebuilds them (equal to a fresh
 * renderer); a moved camera rebuilds camera-centred grids only; LPV's
 * G-buffer occlusion rebuilds when the camera moves. */
static void cached_gi_volumes(void **state)
{
    (void)state;
    static const struct {
        GiMode gi;
        int cascades_or_levels, bounces;
        bool gbuffer_occlusion;
        const char *what;
    } cases[] = {
        {GI_LPV, 1, 1, false, "lpv"},
        {GI_LPV, 2, 1, false, "lpv, 2 cascades"},
        {GI_LPV, 1, 1, true, "lpv, G-buffer occlusion"},
        {GI_VCT, 1, 1, false, "vct"},
        {GI_VCT, 2, 2, false, "vct, 2-level clipmap, 2 bounces"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        Scene s;
        assert_true(scene_load(&s, "cornell"));
        RenderSettings rs = settings_for(&s, cases[k].gi, W, H);
        rs.cache = true;
        rs.set.gi.lpv.size = 16;
        rs.set.gi.lpv.cascades = cases[k].gi == GI_LPV ? cases[k].cascades_or_levels : 1;
        rs.set.gi.lpv.gbuffer_occlusion = cases[k].gbuffer_occlusion;
        rs.set.gi.vct.size = 16;
        rs.set.gi.vct.levels = cases[k].gi == GI_VCT ? cases[k].cascades_or_levels : 1;
        rs.set.gi.vct.bounces = cases[k].bounces;
        bool follows_camera = cases[k].cascades_or_levels > 1 || cases[k].gbuffer_occlusion;
        Renderer r;
        assert_true(renderer_create(&r, &s, &rs));
        renderer_frame(&r, &s.camera);
        ImageF cold, steady, want;
        assert_true(renderer_read_hdr(&r, &cold));
        renderer_frame(&r, &s.camera);
        assert_true(renderer_read_hdr(&r, &steady));
        int builds = renderer_collect_stats(&r)->volume_builds;
        assert_int_equal(builds, 1);
        assert_memory_equal(cold.rgb, steady.rgb, sizeof(float) * 3 * W * H);
        /* The light moves: rebuilt, as a fresh renderer draws it. */
        s.lights[0].position[0] -= 0.05f;
        renderer_frame(&r, &s.camera);
        assert_int_equal(renderer_collect_stats(&r)->volume_builds, builds + 1);
        image_free(&steady);
        assert_true(renderer_read_hdr(&r, &steady));
        fresh_image(&s, &rs, &want);
        assert_memory_equal(steady.rgb, want.rgb, sizeof(float) * 3 * W * H);
        /* The camera moves by a grid cell or more: camera-centred grids follow. */
        builds = renderer_collect_stats(&r)->volume_builds;
        s.camera.position[0] += 0.2f;
        renderer_frame(&r, &s.camera);
        assert_int_equal(renderer_collect_stats(&r)->volume_builds, builds + (follows_camera ? 1 : 0));
        print_message("%s: built once over two still frames, again when the light moved%s\n", cases[k].what,
                      follows_camera ? " and when the camera did" : ", not when the camera did");
        image_free(&cold);
        image_free(&steady);
        image_free(&want);
        renderer_destroy(&r);
        scene_free(&s);
    }
}

/* Issue 11: a one-sided quad light's shadow map and RSM skip the cube face
 * behind its emitting plane (5 faces each); a point light needs all 6. The
 * images do not change (scripts/render-matrix.sh, before/after). */
static void quad_light_skips_the_face_behind(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, "cornell"));
    assert_int_equal(s.lights[0].type, LIGHT_QUAD);
    RenderSettings rs = settings_for(&s, GI_RSM, W, H);
    Renderer r;
    assert_true(renderer_create(&r, &s, &rs));
    renderer_frame(&r, &s.camera);
    assert_int_equal(r.lights.faces_drawn, 5 + 5);
    renderer_destroy(&r);
    s.lights[0].type = LIGHT_POINT;
    assert_true(renderer_create(&r, &s, &rs));
    renderer_frame(&r, &s.camera);
    assert_int_equal(r.lights.faces_drawn, 6 + 6);
    renderer_destroy(&r);
    scene_free(&s);
}

/* Fault injection (gl_make_fail_at): each make of a texture, buffer or
 * framebuffer that a renderer and two frames of a technique ask for fails
 * in turn. Every failure is reported (renderer_create false, or the frames
 * not whole) and frees what was made (live objects after destroy as
 * before), and the sweep ends where k passes the last make. */
static void every_make_failure_is_reported_and_freed(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, "cornell"));
    for (int m = 0; m < GI_MODE_COUNT + 1; m++) { /* every technique, then none shaded forward */
        RenderSettings rs = settings_for(&s, m < GI_MODE_COUNT ? (GiMode)m : GI_NONE, 16, 16);
        rs.set.gi.lpv.size = 8;
        rs.set.gi.vct.size = 16;
        rs.set.gi.vct.bounces = 2;
        rs.ssaa = m == GI_RSM ? 2 : 1; /* the resolve's targets */
        rs.aa = m == GI_VCT ? AA_FXAA : AA_NONE;
        rs.shading = m == GI_MODE_COUNT ? SHADING_FORWARD : SHADING_DEFERRED;
        GlObjectCounts before = gl_count_live_objects(MAX_NAME);
        int k = 1;
        for (;; k++) {
            gl_make_fail_at(k);
            Renderer r;
            bool created = renderer_create(&r, &s, &rs), whole = false;
            if (created) {
                renderer_frame(&r, &s.camera);
                renderer_frame(&r, &s.camera);
                whole = renderer_frames_whole(&r);
            }
            renderer_destroy(&r);
            bool fired = gl_make_fail_at(0);
            if (!fired) {
                assert_true(created && whole);
                break;
            }
            if (created && whole)
                fail_msg("%s: make %d failed, and the renderer and its frames went on as whole",
                         gi_techniques[rs.gi]->name, k);
            GlObjectCounts after = gl_count_live_objects(MAX_NAME);
            if (resources(&after) != resources(&before))
                fail_msg("%s: make %d failed: %d live resources after destroy, %d before", gi_techniques[rs.gi]->name,
                         k, resources(&after), resources(&before));
        }
        print_message("%-16s %d makes, each failure reported and freed\n", gi_techniques[rs.gi]->name, k - 1);
    }
    /* The window's path: a switch (renderer_apply) from none to a technique,
     * at another size with supersampling and FXAA, whose k-th make fails;
     * the same settings applied again then work, switching back works, and
     * the renderer frees everything. */
    const GiMode switches[] = {GI_RSM_INTERLEAVED, GI_VPL_SLC, GI_LPV, GI_VCT};
    for (size_t m = 0; m < sizeof switches / sizeof switches[0]; m++) {
        RenderSettings base = settings_for(&s, GI_NONE, 16, 16), to = settings_for(&s, switches[m], 24, 16);
        to.set.gi.lpv.size = 8;
        to.set.gi.vct.size = 16;
        to.ssaa = 2;
        to.aa = AA_FXAA;
        GlObjectCounts before = gl_count_live_objects(MAX_NAME);
        int k = 1;
        for (;; k++) {
            Renderer r;
            assert_true(renderer_create(&r, &s, &base));
            renderer_frame(&r, &s.camera);
            gl_make_fail_at(k);
            bool applied = renderer_apply(&r, &to), whole = false;
            if (applied) {
                renderer_frame(&r, &s.camera);
                whole = renderer_frames_whole(&r);
            }
            bool fired = gl_make_fail_at(0);
            if (fired && applied && whole)
                fail_msg("switch to %s: make %d failed, and the frame went on as whole", gi_techniques[to.gi]->name, k);
            if (fired && !applied) { /* the same settings again make what failed (render --timings does) */
                if (!renderer_apply(&r, &to))
                    fail_msg("switch to %s: make %d failed, and the same settings again failed too",
                             gi_techniques[to.gi]->name, k);
                renderer_frame(&r, &s.camera);
                if (!renderer_frames_whole(&r))
                    fail_msg("switch to %s: make %d failed; the same settings again drew no whole frame",
                             gi_techniques[to.gi]->name, k);
            }
            assert_true(renderer_apply(&r, &base));
            renderer_frame(&r, &s.camera);
            assert_true(renderer_frames_whole(&r));
            renderer_destroy(&r);
            GlObjectCounts after = gl_count_live_objects(MAX_NAME);
            if (resources(&after) != resources(&before))
                fail_msg("switch to %s: make %d failed: %d live resources after destroy, %d before",
                         gi_techniques[to.gi]->name, k, resources(&after), resources(&before));
            if (!fired)
                break;
        }
        print_message("switch to %-16s %d makes, each failure reported and freed\n", gi_techniques[to.gi]->name, k - 1);
    }
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(switching_matches_fresh_and_releases),
        cmocka_unit_test(resize_and_exposure),
        cmocka_unit_test(cached_light_products),
        cmocka_unit_test(cached_gi_volumes),
        cmocka_unit_test(quad_light_skips_the_face_behind),
        cmocka_unit_test(every_make_failure_is_reported_and_freed),
    };
    return cmocka_run_group_tests_name("lifetime", tests, test_gl_setup, test_gl_teardown);
}
