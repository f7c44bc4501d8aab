/* test_animation.c — time in scene files (issue 50): keyframe tracks read
 * and interpolated at and between keys, bad tracks refused in one line, a
 * frame of `render --animate` equal to a still render of the same scene
 * with the keyed values written out, every technique's cached products
 * after a light or an object moved equal to a cold renderer's, VCT's
 * voxels following a moving block (none left where it was), and culling
 * bounds following an object moved into view. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/animation.h"
#include "gi/vct/vct.h"
#include "base/log.h"
#include "io/metrics.h"
#include "frame/renderer.h"
#include "test_util.h"

#define TMP RTGI_TEST_TMP

/* A small scene: a floor, a panel (quads[1], the object "panel"), a spot
 * light, a camera; tracks of each kind. */
static const char k_tracks_scene[] =
    "{\n"
    " \"quads\": [\n"
    "  {\"albedo\": [0.8, 0.8, 0.8], \"vertices\": [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]]},\n"
    "  {\"albedo\": [0.5, 0.5, 0.5], \"vertices\": [[-0.2, 0.1, 0], [0.2, 0.1, 0], [0.2, 0.5, 0], [-0.2, 0.5, 0]]}\n"
    " ],\n"
    " \"lights\": [{\"type\": \"spot\", \"position\": [0, 1, 0], \"direction\": [0, -1, 0], \"intensity\": [1, 1, 1]}],\n"
    " \"camera\": {\"position\": [0, 0.5, 3], \"target\": [0, 0.2, 0], \"fov_y_deg\": 40},\n"
    " \"objects\": {\"panel\": {\"quads\": [1], \"rotate_deg\": [0, 90, 0]}},\n"
    " \"animation\": {\"duration\": 3, \"tracks\": [\n"
    "  {\"target\": \"lights[0]\", \"key\": \"position\", \"times\": [0, 1, 3],\n"
    "   \"values\": [[0, 1, 0], [0.5, 1, 0], [0.5, 1, 0.8]]},\n"
    "  {\"target\": \"lights[0]\", \"key\": \"intensity\", \"times\": [0, 2], \"values\": [[1, 1, 1], [3, 2, 1]]},\n"
    "  {\"target\": \"camera\", \"key\": \"fov_y_deg\", \"times\": [0, 2], \"values\": [40, 50]},\n"
    "  {\"target\": \"objects.panel\", \"key\": \"translate\", \"interpolation\": \"catmull-rom\",\n"
    "   \"times\": [0, 1, 2], \"values\": [[0, 0, 0], [0.1, 0, 0], [0, 0, 0]]}\n"
    " ]}\n"
    "}\n";

/* The panel's vertex nearest `p` at rest (its first vertex of the quad). */
static uint32_t panel_vertex(const Scene *s)
{
    return s->objects[0].vertices[0];
}

static void tracks_interpolate_at_and_between_keys(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, test_tmp_file("anim_tracks.json", k_tracks_scene)));
    assert_true(animation_present(&s));
    assert_float_equal(animation_duration(&s), 3.f, 0.f);
    assert_int_equal(s.object_count, 1);
    assert_int_equal(s.objects[0].vertex_count, 4);
    /* At the keys: the keys' values exactly. */
    const float k1[3] = {0.5f, 1.f, 0.f}, k2[3] = {0.5f, 1.f, 0.8f};
    animation_apply(&s, 1.0, NULL);
    assert_memory_equal(s.lights[0].position, k1, sizeof k1);
    animation_apply(&s, 3.0, NULL);
    assert_memory_equal(s.lights[0].position, k2, sizeof k2);
    /* Between them, linear: halfway from (0.5, 1, 0) to (0.5, 1, 0.8). */
    animation_apply(&s, 2.0, NULL);
    assert_float_equal(s.lights[0].position[2], 0.4f, 1e-6f);
    assert_float_equal(s.lights[0].color[0], 3.f, 0.f); /* the intensity's last key */
    animation_apply(&s, 1.0, NULL);
    assert_float_equal(s.lights[0].color[1], 1.5f, 1e-6f);
    assert_float_equal(glm_deg(s.camera.fov_y), 45.f, 1e-4f);
    /* Past the end: the last key's value. */
    animation_apply(&s, 7.0, NULL);
    assert_memory_equal(s.lights[0].position, k2, sizeof k2);

    /* Catmull-Rom through (0, 0), (1, 0.1), (2, 0): tangents 0.1 at the
     * first key (one-sided) and 0 at the second, so at t = 0.5 the cubic
     * Hermite gives 0.125·0.1 + 0.5·0.1 = 0.0625. The panel also stands
     * turned 90° about y (its file transform), so its x offset shows in x. */
    uint32_t v = panel_vertex(&s);
    animation_apply(&s, 0.0, NULL);
    vec3 rest;
    glm_vec3_copy(s.vertices[v].position, rest);
    SceneChange c;
    assert_true(animation_apply(&s, 0.5, &c));
    assert_true(c.what & SCENE_CHANGED_GEOMETRY);
    assert_true(c.what & SCENE_CHANGED_LIGHTS);
    assert_true(c.what & SCENE_CHANGED_CAMERA);
    assert_true(v >= c.first_vertex && v < c.first_vertex + c.vertex_count);
    assert_float_equal(s.vertices[v].position[0] - rest[0], 0.0625f, 1e-6f);
    assert_float_equal(s.vertices[v].position[2], rest[2], 1e-6f);
    /* The same time again changes nothing. */
    assert_false(animation_apply(&s, 0.5, &c));
    assert_int_equal(c.what, 0);
    /* Turned 90° about y: the panel's normal (0, 0, 1) at rest is (1, 0, 0). */
    assert_float_equal(s.vertices[v].normal[0], 1.f, 1e-6f);
    assert_float_equal(s.vertices[v].normal[2], 0.f, 1e-6f);
    /* A key's value through the track, exactly. */
    const AnimTrack *k = &s.animation->tracks[3];
    float out[3];
    animation_track_value(k, 1.0, out);
    assert_float_equal(out[0], 0.1f, 0.f);
    print_message("keys exact; catmull-rom at 0.5: %.7f (0.0625)\n", (double)(s.vertices[v].position[0] - rest[0]));
    scene_free(&s);
}

/* A scene file of the tracks scene with `animation` replacing its
 * animation (and `objects` its objects); the file's path. */
static const char *scene_with(const char *name, const char *objects, const char *animation)
{
    char text[4096];
    snprintf(text, sizeof text,
             "{\"builtin\": \"cornell\",\n"
             " \"lights\": [{\"type\": \"spot\", \"position\": [0.278, 0.5, 0.28], \"direction\": [0, -1, 0],"
             " \"intensity\": [1, 1, 1]},\n"
             "   {\"type\": \"directional\", \"direction\": [0, -1, 0.2], \"irradiance\": [1, 1, 1]}],\n"
             " \"objects\": %s,\n \"animation\": %s}\n",
             objects, animation);
    return test_tmp_file(name, text);
}

/* Error lines logged while a hook is set, and the last one. */
static int g_errors;
static char g_message[512];

static void capture(LogLevel level, const char *tag, const char *message, void *user)
{
    (void)tag, (void)user;
    if (level != LOG_ERROR)
        return;
    g_errors++;
    snprintf(g_message, sizeof g_message, "%s", message);
}

static void bad_tracks_are_refused_in_one_line(void **state)
{
    (void)state;
    static const struct {
        const char *objects, *animation, *want1, *want2;
    } cases[] = {
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"lights[0]\", \"key\": \"position\", \"times\": [0, 1, 0.5],"
               " \"values\": [[0,0.4,0], [0.1,0.4,0], [0.2,0.4,0]]}]}",
         "animation.tracks[0].times[2]", "times must increase"},
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"lights[3]\", \"key\": \"position\", \"times\": [0],"
               " \"values\": [[0,0.4,0]]}]}",
         "animation.tracks[0].target", "no such light"},
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"lights[0]\", \"key\": \"position\", \"times\": [0, 1],"
               " \"values\": [[0,0.4,0], [1e999,0.4,0]]}]}",
         "animation.tracks[0].values[1][0]", "not a finite"},
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"lights[0]\", \"key\": \"irradiance\", \"times\": [0],"
               " \"values\": [[1,1,1]]}]}",
         "animation.tracks[0].key", "a spot light"},
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"lights[1]\", \"key\": \"direction\", \"interpolation\":"
               " \"catmull-rom\", \"times\": [0], \"values\": [[0,-1,0]]}]}",
         "animation.tracks[0].interpolation", "catmull-rom is for positions"},
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"camera\", \"key\": \"fov_y_deg\", \"times\": [0, 1],"
               " \"values\": [40]}]}",
         "animation.tracks[0].values", "one per time"},
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"camera\", \"key\": \"fov_y_deg\", \"times\": [0, 2.5],"
               " \"values\": [40, 50]}]}",
         "animation.tracks[0].times[1]", "outside the animation"},
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"objects.nope\", \"key\": \"translate\", \"times\": [0],"
               " \"values\": [[0,0,0]]}]}",
         "animation.tracks[0].target", "no such object"},
        {"{\"b\": {\"material\": \"shortblock\"}}", "{\"duration\": 2, \"tracks\": [{\"target\": \"camera\", \"key\":"
               " \"fov_y_deg\", \"times\": [0], \"values\": [40]}]}",
         "objects.b.material", "no material of that name"},
        {"{}", "{\"tracks\": [{\"target\": \"camera\", \"key\": \"fov_y_deg\", \"times\": [0], \"values\": [40]}]}",
         "animation.duration", "missing"},
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"camera\", \"key\": \"fov_y_deg\", \"times\": [0], \"values\": [40]},"
               " {\"target\": \"camera\", \"key\": \"fov_y_deg\", \"times\": [1], \"values\": [50]}]}",
         "animation.tracks[1]", "what tracks[0] animates"},
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"camera\", \"key\": \"fov_y_deg\", \"tims\": [0], \"values\": [40]}]}",
         "animation.tracks[0].tims", "did you mean \"times\""},
        {"{}", "{\"duration\": 2, \"tracks\": [{\"target\": \"camera\", \"key\": \"fov_y_deg\", \"times\": [0], \"values\": [200]}]}",
         "animation.tracks[0].values[0]", "(1, 179)"},
    };
    /* Loaded in-process: one error line each (the log hook sees every
     * line), naming the key and the problem. */
    log_set_hook(capture, NULL);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char name[32];
        snprintf(name, sizeof name, "anim_bad%zu.json", i);
        const char *path = scene_with(name, cases[i].objects, cases[i].animation);
        g_errors = 0;
        g_message[0] = 0;
        Scene s;
        bool loaded = scene_load(&s, path);
        if (loaded)
            scene_free(&s);
        print_message("%s\n", g_message);
        if (loaded || g_errors != 1 || !strstr(g_message, cases[i].want1) || !strstr(g_message, cases[i].want2))
            fail_msg("case %zu: loaded %d, %d error lines, last '%s' (want '%s' and '%s')", i, loaded, g_errors,
                     g_message, cases[i].want1, cases[i].want2);
    }
    log_set_hook(NULL, NULL);
    /* Through the command line, once: exit status 1 and one line. */
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--scene", scene_with("anim_bad_cli.json", cases[0].objects,
                          cases[0].animation), "--size", "8x8", "--out", TMP "/anim_bad.png", NULL);
    test_expect_cli_error(rc, err, 1, cases[0].want1, cases[0].want2);
    /* The command line's time options. */
    const char *ok_scene = scene_with("anim_ok.json", "{}",
                                      "{\"duration\": 2, \"tracks\": [{\"target\": \"camera\", \"key\": \"fov_y_deg\","
                                      " \"times\": [0, 2], \"values\": [40, 50]}]}");
    rc = test_run_cli(&err, "render", "--scene", ok_scene, "--size", "8x8", "--time", "2.5", "--out",
                          TMP "/anim_t.png", NULL);
    test_expect_cli_error(rc, err, 1, "--time", "outside the animation's [0, 2]");
    rc = test_run_cli(&err, "render", "--scene", "cornell", "--size", "8x8", "--animate", "--frames", "3", "--out",
                      TMP "/anim_%d.png", NULL);
    test_expect_cli_error(rc, err, 1, "--animate", "no animation");
    rc = test_run_cli(&err, "render", "--scene", ok_scene, "--size", "8x8", "--animate", "--out", TMP "/anim_%d.png",
                      NULL);
    test_expect_cli_error(rc, err, 2, "--animate", "--frames N");
    rc = test_run_cli(&err, "render", "--scene", ok_scene, "--size", "8x8", "--animate", "--frames", "3", "--out",
                      TMP "/anim.png", NULL);
    test_expect_cli_error(rc, err, 2, "--out", "one frame number");
    rc = test_run_cli(&err, "render", "--scene", ok_scene, "--size", "8x8", "--animate", "--frames", "30", "--fps",
                      "10", "--out", TMP "/anim_%d.png", NULL);
    test_expect_cli_error(rc, err, 1, "frame 29 falls at 2.9 s", "after the animation's 2 s");
    rc = test_run_cli(&err, "reference", "--scene", ok_scene, "--size", "8x8", "--frames", "3", "--out",
                      TMP "/anim_%d.pfm", NULL);
    test_expect_cli_error(rc, err, 2, "--frames", "needs --animate");
    /* reference's instant is --at (its --time is the time budget). */
    rc = test_run_cli(&err, "reference", "--scene", ok_scene, "--size", "8x8", "--at", "2.5", "--out",
                      TMP "/anim_t.pfm", NULL);
    test_expect_cli_error(rc, err, 1, "--at", "outside the animation's [0, 2]");
    rc = test_run_cli(&err, "reference", "--scene", ok_scene, "--size", "8x8", "--at", "1", "--animate", "--frames",
                      "2", "--out", TMP "/anim_%d.pfm", NULL);
    test_expect_cli_error(rc, err, 2, "--at and --animate", "give one");
}

/* Reads a PFM the test wrote. */
static void read_image(const char *path, ImageF *img)
{
    assert_true(image_read(path, img));
}

/* The largest |difference| between two images of one size. */
static double max_abs_diff(const ImageF *a, const ImageF *b)
{
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->height, b->height);
    double m = 0;
    for (size_t i = 0; i < 3 * (size_t)a->width * a->height; i++)
        m = fmax(m, fabs((double)a->rgb[i] - b->rgb[i]));
    return m;
}

/* Frame 1 of `render --animate --frames 4` (t = duration / 3, between keys)
 * against `render` of the still scene whose file holds the values the
 * tracks give at that time: equal pixel for pixel. A spot light orbiting
 * (its position Catmull-Rom, its direction linear) with vpl-slc, and the
 * moving block with vct (revoxelized, its grid fitted to the bounds). */
static void animated_frame_equals_still_render(void **state)
{
    (void)state;
    static const struct {
        const char *scene, *gi;
    } cases[] = {{"cornell_orbit.json", "vpl-slc"}, {"cornell_moving_block.json", "vct"}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char scene_path[512], pattern[256], frame1[256], still[4096];
        snprintf(scene_path, sizeof scene_path, "%s/scenes/%s", RTGI_SOURCE_DIR, cases[k].scene);
        snprintf(pattern, sizeof pattern, TMP "/anim_eq%zu_%%02d.pfm", k);
        snprintf(frame1, sizeof frame1, TMP "/anim_eq%zu_01.pfm", k);
        char *err = NULL;
        int rc = test_run_cli(&err, "render", "--scene", scene_path, "--animate", "--frames", "4", "--size", "32x32",
                              "--gi", cases[k].gi, "--vpls", "1024", "--vct-size", "32", "--out", pattern, NULL);
        if (rc != 0)
            fail_msg("render --animate: %s", err ? err : "");
        free(err);
        /* The values at frame 1's time, written out as a still scene. */
        Scene s;
        assert_true(scene_load(&s, scene_path));
        double t = animation_frame_time(&s, 1, 4, 0);
        animation_apply(&s, t, NULL);
        float v[4][3];
        for (int i = 0; i < s.animation->track_count && i < 4; i++)
            animation_track_value(&s.animation->tracks[i], t, v[i]);
        if (k == 0) { /* tracks: position, direction of the spot */
            snprintf(still, sizeof still,
                     "{\"builtin\": \"cornell\", \"lights\": [{\"type\": \"spot\", \"position\": [%.9g, %.9g, %.9g],"
                     " \"direction\": [%.9g, %.9g, %.9g], \"intensity\": [0.5, 0.45, 0.4], \"inner_deg\": 35,"
                     " \"outer_deg\": 50, \"diameter\": 0.02}]}\n",
                     (double)v[0][0], (double)v[0][1], (double)v[0][2], (double)v[1][0], (double)v[1][1],
                     (double)v[1][2]);
        } else { /* the block's translation */
            snprintf(still, sizeof still,
                     "{\"builtin\": \"cornell\", \"objects\": {\"block\": {\"material\": \"short_block\", \"translate\":"
                     " [%.9g, %.9g, %.9g]}}}\n",
                     (double)v[0][0], (double)v[0][1], (double)v[0][2]);
        }
        scene_free(&s);
        char name[64];
        snprintf(name, sizeof name, "anim_still%zu.json", k);
        /* The still scene rendered in this process by a new renderer, as
         * `render` does (the settings the options above give). */
        Scene still_scene;
        assert_true(scene_load(&still_scene, test_tmp_file(name, still)));
        RenderSettings rs = test_settings(&still_scene, 32, 32, SHADOW_MODE_PCSS);
        rs.gi = (GiMode)gi_technique_find(cases[k].gi);
        rs.set.gi = still_scene.settings.gi;
        rs.set.gi.vpl.count = 1024;
        rs.set.gi.vct.size = 32;
        ImageF a, b, first;
        test_render(&still_scene, &rs, &b);
        scene_free(&still_scene);
        read_image(frame1, &a);
        snprintf(frame1, sizeof frame1, TMP "/anim_eq%zu_00.pfm", k);
        read_image(frame1, &first);
        double diff = max_abs_diff(&a, &b), e = metric_relmse(&a, &b, NULL, NULL);
        double moved = metric_relmse(&first, &b, NULL, NULL);
        print_message("%s with %s at t = %.4f s: max |frame - still| %.3g, relMSE %.3g (frame 0 vs still: %.3g)\n",
                      cases[k].scene, cases[k].gi, t, diff, e, moved);
        assert_true(e < 1e-6);
        assert_true(moved > 1e-4); /* the comparison sees the motion */
        image_free(&a);
        image_free(&b);
        image_free(&first);
    }
}

/* Settings for the cached-versus-cold comparison: small everything. */
static RenderSettings small_settings(const Scene *s, GiMode gi, bool cache)
{
    RenderSettings rs = test_settings(s, 24, 24, SHADOW_MODE_PCF);
    rs.gi = gi;
    rs.set.gi = s->settings.gi;
    rs.set.gi.rsm.size = 32;
    rs.set.gi.rsm.samples = 32;
    rs.set.gi.vpl.count = 512;
    rs.set.gi.lpv.size = 8;
    rs.set.gi.vct.size = 16;
    rs.set.shadow.map_size = 64;
    rs.cache = cache;
    return rs;
}

/* Every technique: a cached renderer that drew the scene at t0, then moved
 * to t1 (animation_apply + renderer_scene_changed), draws what a renderer
 * without caching draws at t1 (every map redrawn, the technique made anew
 * for it), bit for bit; what the change invalidates was rebuilt (maps drawn
 * again, VPLs extracted again, the metalight grouping, LPV and VCT volumes,
 * the voxels) and, for a camera move alone, no light product was redrawn.
 * With --gi-visibility on too, for the techniques that take it: its maps
 * are redrawn from the moved light and from the moved geometry's points
 * (a renderer made after a move draws its points from the geometry it was
 * made with), and are the same whatever order the VPLs were extracted in.
 * Orbiting spot light and moving block. (Two renderers per scene switched
 * from technique to technique, as the window switches: their programs
 * compile once.) */
static void cached_products_equal_cold_after_motion(void **state)
{
    (void)state;
    static const char *const scenes[] = {"cornell_orbit.json", "cornell_moving_block.json"};
    for (int sc = 0; sc < 2; sc++) {
        Scene s;
        test_load_scene_file(&s, scenes[sc]);
        Renderer r, cold;
        RenderSettings rs = small_settings(&s, GI_NONE, true), rs_cold = small_settings(&s, GI_NONE, false);
        assert_true(renderer_create(&r, &s, &rs));
        assert_true(renderer_create(&cold, &s, &rs_cold));
        for (int run = 0; run < 2 * GI_MODE_COUNT; run++) {
            /* Each technique, and with --gi-visibility on those that take it
             * (its maps follow the light and the geometry). */
            int gi = run / 2, vis = run % 2;
            if (vis && !(gi_techniques[gi]->flags & GI_VISIBILITY))
                continue;
            SceneChange c;
            animation_apply(&s, 0.0, &c);
            assert_true(renderer_scene_changed(&r, &c) && renderer_scene_changed(&cold, &c));
            rs = small_settings(&s, (GiMode)gi, true);
            rs_cold = small_settings(&s, (GiMode)gi, false);
            rs.set.gi.visibility.on = rs_cold.set.gi.visibility.on = vis;
            assert_true(renderer_apply(&r, &rs) && renderer_apply(&cold, &rs_cold));
            renderer_invalidate(&r);
            renderer_frame(&r, &s.camera);
            renderer_frame(&r, &s.camera); /* steady */
            int draws = r.lights.map_draws, extractions = r.lights.vpl_extractions;
            RenderStats st0 = *renderer_collect_stats(&r);
            /* A camera move alone redraws no light product. */
            Camera keep = s.camera;
            s.camera.position[0] += 0.01f;
            renderer_frame(&r, &s.camera);
            assert_int_equal(r.lights.map_draws, draws);
            s.camera = keep;
            assert_true(animation_apply(&s, 0.7, &c));
            assert_true(renderer_scene_changed(&r, &c) && renderer_scene_changed(&cold, &c));
            renderer_frame(&r, &s.camera);
            renderer_frame(&cold, &s.camera);
            ImageF got, want;
            assert_true(renderer_read_hdr(&r, &got));
            assert_true(renderer_read_hdr(&cold, &want));
            RenderStats st1 = *renderer_collect_stats(&r);
            /* Equal up to the order of floating-point sums (the VPL gathers'
             * work groups: 1e-15); a stale product is off by far more. */
            if (memcmp(got.rgb, want.rgb, sizeof(float) * 3 * 24 * 24) != 0 &&
                !(metric_relmse(&got, &want, NULL, NULL) < 1e-12))
                fail_msg("%s, %s%s: the cached frame after the move differs from a cold one (relMSE %.3g)", scenes[sc],
                         gi_techniques[gi]->name, vis ? " (visibility)" : "", metric_relmse(&got, &want, NULL, NULL));
            /* What depends on the move was rebuilt. */
            assert_true(r.lights.map_draws > draws);
            if (r.lights.desc.needs & LIGHT_NEEDS_VPLS)
                assert_true(r.lights.vpl_extractions > extractions);
            if (gi == GI_VPL_METALIGHTS)
                assert_true(st1.metalight_regroups > st0.metalight_regroups);
            if (gi == GI_LPV || gi == GI_VCT)
                assert_true(st1.volume_builds > st0.volume_builds);
            if (gi == GI_VCT && sc == 1)
                assert_true(st1.voxelizations > st0.voxelizations);
            print_message("%-26s %-16s%s equal to cold; maps drawn %d -> %d, VPL extractions %d -> %d\n", scenes[sc],
                          gi_techniques[gi]->name, vis ? " (visibility)" : "", draws, r.lights.map_draws, extractions,
                          r.lights.vpl_extractions);
            image_free(&got);
            image_free(&want);
        }
        assert_true(renderer_frames_whole(&r) && renderer_frames_whole(&cold));
        renderer_destroy(&r);
        renderer_destroy(&cold);
        scene_free(&s);
    }
}

/* Opaque voxels whose centre lies at height y in (0.03, 0.14) m (above
 * the floor's voxels, below the block's top) inside the short block's
 * footprint (a convex quadrilateral, moved by `dx`, `dz`), grown by `grow`. */
static int block_voxels(const float *vol, int n, const float origin[3], float voxel, float dx, float dz, float grow)
{
    /* The short block's footprint corners (m), counter-clockwise in x-z. */
    const float fx[4] = {0.130f, 0.290f, 0.240f, 0.082f}, fz[4] = {0.065f, 0.114f, 0.272f, 0.225f};
    int count = 0;
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++) {
                if (vol[4 * (((size_t)z * n + y) * n + x) + 3] < 0.5f)
                    continue;
                float px = origin[0] + (x + 0.5f) * voxel - dx, py = origin[1] + (y + 0.5f) * voxel,
                      pz = origin[2] + (z + 0.5f) * voxel - dz;
                if (!(py > 0.03f && py < 0.14f))
                    continue;
                bool inside = true;
                for (int e = 0; e < 4 && inside; e++) {
                    int f = (e + 1) % 4;
                    float ex = fx[f] - fx[e], ez = fz[f] - fz[e], len = sqrtf(ex * ex + ez * ez);
                    float side = (ex * (pz - fz[e]) - ez * (px - fx[e])) / len; /* > 0: left of the edge */
                    inside = side > -grow;
                }
                count += inside;
            }
    return count;
}

/* VCT with the short block moving: after the move no voxel of the block is
 * left where it stood (counted in the albedo volume), and its voxels stand
 * where it went; before the move the same count found it there (the count
 * can fail). */
static void vct_keeps_no_stale_voxels(void **state)
{
    (void)state;
    Scene s;
    test_load_scene_file(&s, "cornell_moving_block.json");
    RenderSettings rs = small_settings(&s, GI_VCT, true);
    rs.set.gi.vct.size = 64;
    rs.set.gi.vct.aniso = false;
    Renderer r;
    assert_true(renderer_create(&r, &s, &rs));
    renderer_frame(&r, &s.camera);
    int n;
    float origin[3], voxel;
    vct_grid(r.gi_state, &n, origin, &voxel);
    float *vol = malloc(sizeof(float) * 4 * (size_t)n * n * n);
    assert_non_null(vol);
    assert_true(vct_read_volume(r.gi_state, VCT_VOLUME_ALBEDO, vol));
    float end[3];
    animation_track_value(&s.animation->tracks[0], animation_duration(&s), end);
    int old_before = block_voxels(vol, n, origin, voxel, 0, 0, voxel);
    int new_before = block_voxels(vol, n, origin, voxel, end[0], end[2], 0);
    SceneChange c;
    assert_true(animation_apply(&s, animation_duration(&s), &c));
    assert_true(renderer_scene_changed(&r, &c));
    renderer_frame(&r, &s.camera);
    vct_grid(r.gi_state, &n, origin, &voxel);
    assert_true(vct_read_volume(r.gi_state, VCT_VOLUME_ALBEDO, vol));
    int old_after = block_voxels(vol, n, origin, voxel, 0, 0, voxel);
    int new_after = block_voxels(vol, n, origin, voxel, end[0], end[2], 0);
    print_message("block voxels (%d^3): where it stood %d before, %d after; where it went %d before, %d after\n", n,
                  old_before, old_after, new_before, new_after);
    assert_true(old_before > 20);
    assert_int_equal(old_after, 0);
    assert_true(new_after > 20);
    assert_true(new_before < new_after / 4);
    free(vol);
    renderer_destroy(&r);
    scene_free(&s);
}

/* A moved object is drawn where it went, not culled by the bounds of where
 * it was: the short block starts 3 m behind the camera (outside every
 * frustum: its clusters are culled) and moves back into the box; the
 * cached renderer's frame after the move equals a fresh renderer's of the
 * block written out in place, with culling on. (Bounds kept from the
 * start would leave the block out of the G-buffer and the shadow maps.) */
static void culling_follows_a_moved_object(void **state)
{
    (void)state;
    Scene s, still;
    assert_true(scene_load(&s, scene_with("anim_cull.json",
                                          "{\"block\": {\"material\": \"short_block\", \"translate\": [0, 0, -3]}}",
                                          "{\"duration\": 1, \"tracks\": [{\"target\": \"objects.block\", \"key\":"
                                          " \"translate\", \"times\": [0, 1], \"values\": [[0, 0, -3], [0, 0, 0]]}]}")));
    /* The same scene with the block where the track ends (a track that
     * changes nothing). */
    assert_true(scene_load(&still, scene_with("anim_cull_still.json", "{}",
                                              "{\"duration\": 1, \"tracks\": [{\"target\": \"lights[0]\", \"key\":"
                                              " \"intensity\", \"times\": [0], \"values\": [[1, 1, 1]]}]}")));
    RenderSettings rs = test_settings(&s, 32, 32, SHADOW_MODE_PCF);
    Renderer r;
    assert_true(renderer_create(&r, &s, &rs));
    renderer_frame(&r, &s.camera);
    ImageF before, got, want;
    assert_true(renderer_read_hdr(&r, &before));
    int culled = r.pass_gbuffer.culled;
    SceneChange c;
    assert_true(animation_apply(&s, 1.0, &c));
    assert_true(renderer_scene_changed(&r, &c));
    renderer_frame(&r, &s.camera);
    assert_true(renderer_read_hdr(&r, &got));
    assert_true(renderer_frames_whole(&r));
    renderer_destroy(&r);
    test_render(&still, &rs, &want);
    double e = metric_relmse(&got, &want, NULL, NULL), moved = metric_relmse(&before, &want, NULL, NULL);
    print_message("block moved into view: relMSE %.3g against the still scene (before the move %.3g); clusters "
                  "culled before %d\n", e, moved, culled);
    assert_true(e < 1e-6);
    assert_true(moved > 1e-3); /* the block is seen: its absence would be measured */
    image_free(&before);
    image_free(&got);
    image_free(&want);
    scene_free(&s);
    scene_free(&still);
}

/* The least x of the box's vertices (above y = 0.1) or the floor's. */
static float least_x(const Scene *s, bool box)
{
    float x = INFINITY;
    for (uint32_t v = 0; v < s->vertex_count; v++)
        if ((s->vertices[v].position[1] > 0.1f) == box)
            x = fminf(x, s->vertices[v].position[0]);
    return x;
}

/* A mesh file's node as an object: an OBJ with two objects ("o floor",
 * "o box") of one material; the box moves, the floor stays (by material
 * the two could not be told apart). An unknown node is one error line. */
static void mesh_node_is_an_object(void **state)
{
    (void)state;
    test_tmp_file("anim_nodes.mtl", "newmtl grey\nKd 0.5 0.5 0.5\n");
    test_tmp_file("anim_nodes.obj", "mtllib anim_nodes.mtl\n"
                                    "o floor\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nusemtl grey\nf 1 3 2\nf 1 4 3\n"
                                    "o box\nv -0.1 0.2 0\nv 0.1 0.2 0\nv 0.1 0.4 0\nv -0.1 0.4 0\nusemtl grey\n"
                                    "f 5 6 7\nf 5 7 8\n");
    const char *path = test_tmp_file(
        "anim_nodes.json", "{\"mesh\": \"anim_nodes.obj\", \"objects\": {\"b\": {\"node\": \"box\"}},\n"
                           " \"camera\": {\"position\": [0, 1, 3], \"target\": [0, 0, 0]},\n"
                           " \"animation\": {\"duration\": 1, \"tracks\": [{\"target\": \"objects.b\", \"key\":"
                           " \"translate\", \"times\": [0, 1], \"values\": [[0, 0, 0], [0.5, 0, 0]]}]}}\n");
    Scene s;
    assert_true(scene_load(&s, path));
    assert_int_equal(s.object_count, 1);
    assert_int_equal(s.objects[0].vertex_count, 4);
    float box_x = least_x(&s, true), floor_x = least_x(&s, false);
    animation_apply(&s, 1.0, NULL);
    assert_float_equal(least_x(&s, true) - box_x, 0.5f, 1e-6f);
    assert_float_equal(least_x(&s, false), floor_x, 0.f);
    scene_free(&s);
    char *err = NULL;
    path = test_tmp_file("anim_nodes_bad.json",
                         "{\"mesh\": \"anim_nodes.obj\", \"objects\": {\"b\": {\"node\": \"bx\"}},\n"
                         " \"lights\": [{\"type\": \"directional\", \"direction\": [0, -1, 0], \"irradiance\": 1}]}\n");
    int rc = test_run_cli(&err, "render", "--scene", path, "--size", "8x8", "--out", TMP "/anim_nodes.png", NULL);
    test_expect_cli_error(rc, err, 1, "objects.b.node", "it has: ");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(tracks_interpolate_at_and_between_keys),
        cmocka_unit_test(bad_tracks_are_refused_in_one_line),
        cmocka_unit_test(animated_frame_equals_still_render),
        cmocka_unit_test(cached_products_equal_cold_after_motion),
        cmocka_unit_test(vct_keeps_no_stale_voxels),
        cmocka_unit_test(culling_follows_a_moved_object),
        cmocka_unit_test(mesh_node_is_an_object),
    };
    return cmocka_run_group_tests_name("animation", tests, test_gl_setup, test_gl_teardown);
}
