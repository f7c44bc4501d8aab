/* test_progressive.c — the reference path tracer converging in the
 * background (src/reference/pt_progressive.h): its image after n samples
 * is pt_render's for n samples, a restart takes the scene's state at the
 * call (and only that), a target relMSE stops it, pause and destroy stop
 * its threads. No GL, no timing assertions: every wait polls the status
 * until a state is reached (ctest's timeout catches a hang). */
#define _GNU_SOURCE /* SCHED_IDLE */
#include <dirent.h>
#include <math.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "test_util.h"
#include "reference/pathtracer.h"
#include "reference/pt_progressive.h"
#include "core/animation.h"
#include "ui/live_reference.h"

static void nap(void)
{
    nanosleep(&(struct timespec){0, 20 * 1000 * 1000}, NULL);
}

/* Polls until the renderer is done, collecting the sample counts published
 * on the way (at most `max` of them; seen may be NULL). */
static int wait_done(PtProgressive *p, PtProgressiveStatus *st, int *seen, int max)
{
    int n = 0, last = -1;
    for (;;) {
        pt_progressive_status(p, st);
        if (seen && st->spp != last && st->spp > 0 && n < max)
            seen[n++] = st->spp;
        last = st->spp;
        if (st->done)
            return n;
        nap();
    }
}

/* The Cornell box rendered at size² on 2 threads up to `spp` (target:
 * the target relMSE, 0 for none), started. */
static PtProgressive *start(Scene *s, PtSettings *set, int size, int spp, double target)
{
    scene_build_cornell(s);
    scene_finalize(s);
    pt_settings_default(set);
    set->width = set->height = size;
    set->spp = spp;
    set->threads = 2;
    set->target_relmse = target;
    /* At the lowest priority (the window's) a machine busy with other tests
     * leaves the threads almost nothing: this file took 94 s instead of a
     * few under a load of 12 on 2 cores. What is tested does not depend on it. */
    set->ordinary_priority = true;
    PtProgressive *p = pt_progressive_create(s, set);
    assert_non_null(p);
    return p;
}

/* Passes of 1, 2, 4, ... spp up to a whole one (64² has 64 spp a pass),
 * then whole passes, published one by one (the polling may miss the
 * quick first ones), and the final image is pt_render's for 192 spp to
 * the bit. */
static void matches_pt_render(void **state)
{
    (void)state;
    Scene s;
    PtSettings set;
    PtProgressive *p = start(&s, &set, 64, 192, 0.0);
    PtProgressiveStatus st;
    int seen[16];
    int n = wait_done(p, &st, seen, 16);
    for (int i = 0; i < n; i++)
        print_message("published %d spp\n", seen[i]);
    assert_int_equal(st.spp, 192);
    for (int i = 0; i < n; i++)
        assert_true((seen[i] & (seen[i] - 1)) == 0 || seen[i] % 64 == 0); /* 1, 2, 4, ..., then whole passes */
    assert_true(st.relmse_estimate > 0);
    ImageF live, ref;
    assert_true(image_alloc(&live, 64, 64));
    assert_true(pt_progressive_read(p, &live, &st));
    assert_int_equal(st.spp, 192);
    assert_true(pt_render(&s, &set, &ref, NULL, NULL));
    assert_memory_equal(live.rgb, ref.rgb, sizeof(float) * 3 * 64 * 64);
    /* A wrong size is refused, not overrun. */
    ImageF small;
    assert_true(image_alloc(&small, 32, 32));
    assert_false(pt_progressive_read(p, &small, NULL));
    image_free(&small);
    pt_progressive_destroy(p);
    image_free(&live);
    image_free(&ref);
    scene_free(&s);
}

/* A restart renders the camera, lights and materials of the call: after
 * the caller moves its camera, doubles its light, darkens its first
 * material and restarts, then changes its own scene again (the light off,
 * the material back), the image is pt_render's of the state at the
 * restart (the path tracer's per-pass material table, MatShade, included). */
static void restart_takes_the_state_of_the_call(void **state)
{
    (void)state;
    Scene s;
    PtSettings set;
    PtProgressive *p = start(&s, &set, 32, 64, 0.0);
    PtProgressiveStatus st;
    wait_done(p, &st, NULL, 0);
    assert_int_equal(st.restarts, 0);
    ImageF before, after, ref;
    assert_true(image_alloc(&before, 32, 32));
    assert_true(image_alloc(&after, 32, 32));
    assert_true(pt_progressive_read(p, &before, NULL));

    s.camera.position[0] += 0.05f;
    glm_vec3_scale(s.lights[0].color, 2.f, s.lights[0].color);
    vec3 albedo0;
    glm_vec3_copy(s.materials[0].albedo, albedo0);
    glm_vec3_scale(s.materials[0].albedo, 0.5f, s.materials[0].albedo);
    assert_true(pt_progressive_restart(p, &s));
    assert_true(pt_render(&s, &set, &ref, NULL, NULL)); /* the state of the restart */
    glm_vec3_zero(s.lights[0].color);                    /* not seen by the renderer */
    glm_vec3_copy(albedo0, s.materials[0].albedo);
    pt_progressive_status(p, &st);
    assert_int_equal(st.restarts, 1);
    wait_done(p, &st, NULL, 0);
    assert_true(pt_progressive_read(p, &after, &st));
    assert_int_equal(st.spp, 64);
    assert_memory_equal(after.rgb, ref.rgb, sizeof(float) * 3 * 32 * 32);
    assert_memory_not_equal(after.rgb, before.rgb, sizeof(float) * 3 * 32 * 32);
    pt_progressive_destroy(p);
    image_free(&before);
    image_free(&after);
    image_free(&ref);
    scene_free(&s);
}

/* A target relMSE stops the renderer once the estimate reaches it: at
 * 32² (256 spp a pass) 3e-4 takes a few passes (the estimate is about
 * 8e-4 after the first). */
static void target_stops_it(void **state)
{
    (void)state;
    Scene s;
    PtSettings set;
    PtProgressive *p = start(&s, &set, 32, 1 << 20, 3e-4);
    PtProgressiveStatus st;
    int seen[64];
    int n = wait_done(p, &st, seen, 64);
    print_message("target 3e-4: done at %d spp, estimate %.3g, after %d images\n", st.spp, st.relmse_estimate, n);
    assert_true(st.spp > 256 && st.spp < 1 << 20);
    assert_true(st.relmse_estimate <= 3e-4);
    pt_progressive_destroy(p);
    scene_free(&s);
}

/* Paused, it publishes nothing more once idle, and goes on when resumed;
 * destroy stops it in the middle of a pass (no samples cap in sight). */
static void pause_and_destroy(void **state)
{
    (void)state;
    Scene s;
    PtSettings set;
    PtProgressive *p = start(&s, &set, 64, 1 << 20, 0.0);
    PtProgressiveStatus st;
    do {
        pt_progressive_status(p, &st);
        nap();
    } while (st.spp == 0);
    pt_progressive_pause(p, true);
    do {
        pt_progressive_status(p, &st);
        nap();
    } while (!st.idle);
    int held = st.spp;
    for (int i = 0; i < 5; i++)
        nap();
    pt_progressive_status(p, &st);
    assert_true(st.paused && st.idle && !st.done);
    assert_int_equal(st.spp, held);
    pt_progressive_pause(p, false);
    do {
        pt_progressive_status(p, &st);
        nap();
    } while (st.spp == held);
    assert_true(st.spp > held && !st.paused);
    pt_progressive_destroy(p); /* a pass is running: it stops within a tile */
    pt_progressive_destroy(NULL);
    scene_free(&s);
}


/* The threads of this process at SCHED_IDLE, and all of them. */
static int idle_threads(int *all)
{
    int idle = 0;
    *all = 0;
    DIR *d = opendir("/proc/self/task");
    assert_non_null(d);
    for (struct dirent *e; (e = readdir(d));) {
        int tid = atoi(e->d_name);
        if (tid <= 0)
            continue;
        (*all)++;
        idle += sched_getscheduler(tid) == SCHED_IDLE;
    }
    closedir(d);
    return idle;
}

/* Its threads run at the lowest priority (SCHED_IDLE), so that the window
 * using it draws first; with ordinary_priority they do not. (They had all
 * run at the ordinary priority: glibc refuses SCHED_IDLE as a thread
 * attribute, EINVAL, and the fallback took over silently.) */
static void threads_at_the_lowest_priority(void **state)
{
    (void)state;
    for (int ordinary = 0; ordinary < 2; ordinary++) {
        Scene s;
        PtSettings set;
        scene_build_cornell(&s);
        scene_finalize(&s);
        pt_settings_default(&set);
        set.width = set.height = 64;
        set.spp = 1 << 20;
        set.threads = 2;
        set.ordinary_priority = ordinary;
        PtProgressive *p = pt_progressive_create(&s, &set);
        assert_non_null(p);
        int all = 0, idle = 0;
        for (int i = 0; i < 50 && idle < 2; i++) { /* the coordinator and a pass's worker */
            int n = idle_threads(&all);
            idle = n > idle ? n : idle;
            nap();
        }
        print_message("ordinary_priority %d: %d of %d threads at SCHED_IDLE\n", ordinary, idle, all);
        if (ordinary)
            assert_int_equal(idle, 0);
        else
            assert_true(idle >= 1);
        pt_progressive_destroy(p);
        scene_free(&s);
    }
}

/* A quad light's emitter shines with its light's radiance whatever its
 * material holds: with the light doubled, the Cornell box renders the same
 * to the bit before and after the emitter's material follows
 * (animation_place_emitter, which the window's render thread does only at
 * its next frame, after the live reference restarted with the new light).
 * The emitter had shone with the material's old radiance: seen directly
 * and through BSDF hits, against the light samples' new one. */
static void emitter_shines_with_its_light(void **state)
{
    (void)state;
    Scene s;
    PtSettings set;
    scene_build_cornell(&s);
    scene_finalize(&s);
    pt_settings_default(&set);
    set.width = set.height = 32;
    set.spp = 16;
    set.threads = 2;
    assert_true(s.lights[0].type == LIGHT_QUAD && s.lights[0].size > 0.f);
    ImageF before, edited, placed;
    assert_true(pt_render(&s, &set, &before, NULL, NULL));
    glm_vec3_scale(s.lights[0].color, 2.f, s.lights[0].color);
    assert_true(pt_render(&s, &set, &edited, NULL, NULL));
    SceneChange c = {0};
    animation_place_emitter(&s, 0, &c);
    assert_true(c.what & SCENE_CHANGED_GEOMETRY);
    assert_true(pt_render(&s, &set, &placed, NULL, NULL));
    assert_memory_equal(edited.rgb, placed.rgb, sizeof(float) * 3 * 32 * 32);
    assert_memory_not_equal(edited.rgb, before.rgb, sizeof(float) * 3 * 32 * 32);
    image_free(&before);
    image_free(&edited);
    image_free(&placed);
    scene_free(&s);
}

/* Polls the window's live reference at the state it was last given until
 * it has published its last image (its spp cap). */
static void live_wait(LiveReference *l, const Scene *s, const Camera *cam, double t, int size)
{
    for (;;) {
        assert_int_equal(live_reference_update(l, s, cam, t, size, size), 0);
        live_reference_poll(l);
        if (l->status.done && l->status.spp == l->set.spp)
            return;
        nap();
    }
}

/* Whether the live image is pt_render's of s (as it stands) to the bit. */
static bool live_equals_render(const LiveReference *l, const Scene *s)
{
    ImageF ref;
    assert_true(pt_render(s, &l->set, &ref, NULL, NULL));
    bool same = !memcmp(ref.rgb, l->image.rgb, sizeof(float) * 3 * (size_t)ref.width * ref.height);
    image_free(&ref);
    return same;
}

/* The window's live reference (src/ui/live_reference.h) on a scene whose
 * object moves (scenes/cornell_moving_block.json: the short block slides
 * 0.22 m): each state's image is pt_render's of the scene at that time, to
 * the bit, and stays so while the scene's own vertices are moved on (the
 * window's render thread rewrites them: the renderer must borrow vertices
 * of its own), also when a second move comes while the first one's BVH
 * is being built. It had rendered the first time's BVH over whatever the
 * scene's vertices held. */
static void live_reference_follows_moving_objects(void **state)
{
    (void)state;
    char path[600];
    snprintf(path, sizeof path, "%s/scenes/cornell_moving_block.json", RTGI_SOURCE_DIR);
    Scene s;
    assert_true(scene_load(&s, path));
    Camera cam = s.camera;
    enum { SIZE = 32, SPP = 4 };
    LiveReference l;
    live_reference_init(&l, 2, SPP, true, NULL);
    assert_int_equal(live_reference_update(&l, &s, &cam, 0.0, SIZE, SIZE), 1);
    live_wait(&l, &s, &cam, 0.0, SIZE);
    ImageF at0;
    assert_true(image_alloc(&at0, SIZE, SIZE));
    memcpy(at0.rgb, l.image.rgb, sizeof(float) * 3 * SIZE * SIZE);
    assert_true(live_equals_render(&l, &s));
    /* Moved: the image follows. Then the scene's vertices move on without
     * telling it: its image must not change. */
    assert_true(animation_apply(&s, 3.0, NULL));
    assert_int_equal(live_reference_update(&l, &s, &cam, 3.0, SIZE, SIZE), 1);
    live_wait(&l, &s, &cam, 3.0, SIZE);
    assert_true(live_equals_render(&l, &s));
    assert_true(memcmp(at0.rgb, l.image.rgb, sizeof(float) * 3 * SIZE * SIZE) != 0);
    animation_apply(&s, 1.0, NULL);
    live_reference_poll(&l);
    animation_apply(&s, 3.0, NULL);
    assert_true(live_equals_render(&l, &s));
    /* Two moves in a row (the second, most likely, while the first one's
     * renderer is being made): the last one wins. */
    animation_apply(&s, 1.0, NULL);
    assert_int_equal(live_reference_update(&l, &s, &cam, 1.0, SIZE, SIZE), 1);
    animation_apply(&s, 2.0, NULL);
    assert_int_equal(live_reference_update(&l, &s, &cam, 2.0, SIZE, SIZE), 1);
    live_wait(&l, &s, &cam, 2.0, SIZE);
    assert_true(live_equals_render(&l, &s));
    print_message("live reference: %llu restarts, each state's image pt_render's to the bit\n",
                  (unsigned long long)l.status.restarts);
    live_reference_stop(&l);
    image_free(&at0);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(matches_pt_render),
        cmocka_unit_test(restart_takes_the_state_of_the_call),
        cmocka_unit_test(target_stops_it),
        cmocka_unit_test(pause_and_destroy),
        cmocka_unit_test(threads_at_the_lowest_priority),
        cmocka_unit_test(emitter_shines_with_its_light),
        cmocka_unit_test(live_reference_follows_moving_objects),
    };
    return cmocka_run_group_tests_name("progressive", tests, NULL, NULL);
}
