/* vct_voxelize_bench.c — vct's voxelization, raster against compute
 * (--vct-voxelize), on the machine it runs on: one renderer per method on
 * the same scene, alternating within each round (a shared machine's load
 * hits both alike), medians printed. Per round and method: the scene's
 * geometry is marked moved (every vertex re-uploaded: a new version), so
 * the next frame revoxelizes the whole volume: its voxelization's wall
 * time (glFinish both sides) and the frame's; then a steady frame and a
 * light-moving frame (every light product redrawn: renderer_invalidate).
 * A third row, "region": compute with only a moved object's vertices
 * re-uploaded (the scene file's first animated object, moved between two
 * times of its track each round; without one, the first vertex), so that
 * the frame revoxelizes its region alone (issue 46). The first frame of
 * each (shader compilation) is left out.
 *
 * usage: vct_voxelize_bench SCENE WxH [ROUNDS] [VCT_SIZE] [raster|compute|region]
 * (SCENE: cornell, or a scene file; ROUNDS default 5; VCT_SIZE the
 * scene's --vct-size by default, 0 too; a method named: that one alone). Not a test: a measuring tool built
 * beside the tests (scripts/gpu-check.sh and docs/performance.md run it). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/animation.h"
#include "test_util.h"
#include "base/util.h"

enum { METHODS = 3, MAX_ROUNDS = 64 };
static const char *const k_methods[METHODS] = {"raster", "compute", "region"};

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Wall time of one frame (glFinish after it). */
static double frame_ms(Renderer *r, const Camera *cam)
{
    double t0 = util_seconds();
    renderer_frame(r, cam);
    glFinish();
    return 1e3 * (util_seconds() - t0);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: vct_voxelize_bench SCENE WxH [ROUNDS] [VCT_SIZE] [raster|compute|region]\n");
        return 2;
    }
    int w, h, rounds = argc > 3 ? atoi(argv[3]) : 5;
    if (sscanf(argv[2], "%dx%d", &w, &h) != 2 || w <= 0 || h <= 0 || rounds < 1 || rounds > MAX_ROUNDS) {
        fprintf(stderr, "vct_voxelize_bench: bad size '%s' or rounds (1-%d)\n", argv[2], MAX_ROUNDS);
        return 2;
    }
    Scene s;
    if (!scene_load(&s, argv[1]))
        return 1;
    if (test_gl_setup(NULL) != 0) {
        scene_free(&s);
        return 1;
    }
    int first = 0, last = METHODS - 1; /* the methods timed */
    for (int m = 0; m < METHODS && argc > 5; m++)
        if (strcmp(argv[5], k_methods[m]) == 0)
            first = last = m;
    int size = argc > 4 && atoi(argv[4]) > 0 ? atoi(argv[4]) : s.settings.gi.vct.size;
    Renderer r[METHODS];
    bool made[METHODS] = {false};
    bool ok = true;
    for (int m = first; m <= last && ok; m++) {
        RenderSettings rs = test_settings(&s, w, h, SHADOW_MODE_PCSS);
        rs.gi = GI_VCT;
        rs.set.gi = s.settings.gi;
        rs.set.gi.vct.voxelize = m == 0 ? VCT_VOXELIZE_RASTER : VCT_VOXELIZE_COMPUTE;
        rs.set.gi.vct.size = size;
        rs.timings = rs.timing_sync = true; /* vct then times its voxelizations (GiStats.voxelize_ms) */
        ok = made[m] = renderer_create(&r[m], &s, &rs);
        if (ok) {
            renderer_frame(&r[m], &s.camera); /* compiles, voxelizes once */
            renderer_frame(&r[m], &s.camera);
        }
    }
    double vox[METHODS][MAX_ROUNDS], moved[METHODS][MAX_ROUNDS], steady[METHODS][MAX_ROUNDS],
        light[METHODS][MAX_ROUNDS];
    unsigned long long region_voxels = 0;
    /* Round 0 is a warm-up of every path (the first revoxelization and
     * light-moving frame compile nothing new, but llvmpipe's caches fill). */
    SceneChange whole = {.what = SCENE_CHANGED_GEOMETRY, .first_vertex = 0, .vertex_count = s.vertex_count};
    SceneChange object = {.what = SCENE_CHANGED_GEOMETRY, .first_vertex = 0, .vertex_count = 1};
    double t_end = animation_present(&s) ? 0.5 * animation_duration(&s) : 0.0;
    for (int round = 0; ok && round <= rounds; round++) {
        SceneChange moved_now = object;
        if (t_end > 0.0 && animation_apply(&s, round % 2 ? t_end : 0.0, &moved_now))
            moved_now.what = SCENE_CHANGED_GEOMETRY; /* the object alone (the lights and camera stand) */
        for (int m = first; m <= last; m++) {
            SceneChange c = m == 2 ? moved_now : whole;
            ok = renderer_scene_changed(&r[m], &c);
            double t_moved = frame_ms(&r[m], &s.camera);
            const GiStats *st = renderer_collect_stats(&r[m]);
            double t_vox = st->voxelize_ms;
            if (m == 2 && round == rounds)
                region_voxels = st->region_voxelizations ? st->region_voxels : 0;
            double t_steady = frame_ms(&r[m], &s.camera);
            renderer_invalidate(&r[m]);
            double t_light = frame_ms(&r[m], &s.camera);
            if (round > 0) {
                vox[m][round - 1] = t_vox;
                moved[m][round - 1] = t_moved;
                steady[m][round - 1] = t_steady;
                light[m][round - 1] = t_light;
            }
        }
    }
    if (ok) {
        printf("vct_voxelize_bench: %s %dx%d, --vct-size %d, %d rounds alternating, medians (wall ms)\n", argv[1], w,
               h, size, rounds);
        printf("%-8s %12s %14s %12s %14s\n", "method", "voxelize_ms", "moved_frame_ms", "steady_ms", "light_moved_ms");
        double med[METHODS] = {0};
        for (int m = first; m <= last; m++) {
            med[m] = median(vox[m], rounds);
            printf("%-8s %12.2f %14.2f %12.2f %14.2f\n", k_methods[m], med[m], median(moved[m], rounds),
                   median(steady[m], rounds), median(light[m], rounds));
        }
        if (first == 0 && last == METHODS - 1)
            printf("voxelize compute/raster: %.3f, region/compute: %.3f (region: %llu of %d^3 voxels%s)\n",
                   med[1] / med[0], med[2] / med[1], region_voxels, size,
                   region_voxels ? "" : ", none: the whole volume was cheaper");
    }
    for (int m = 0; m < METHODS; m++)
        if (made[m])
            renderer_destroy(&r[m]);
    test_gl_teardown(NULL);
    scene_free(&s);
    return ok ? 0 : 1;
}
