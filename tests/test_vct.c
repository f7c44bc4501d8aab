/* test_vct.c — voxel cone tracing (SPEC §6) on llvmpipe at small grids:
 * the voxelization is watertight (every voxel a triangle touches is
 * filled, checked against an exact triangle–box test on the CPU) with the
 * conservative expansion (floors lying on voxel boundaries included) and
 * leaks without it; injected radiance against
 * Lambert's ρ·E·cosθ/π; the Cornell box against the path tracer's
 * one-bounce and full references; a closed box against the reference's
 * indirect light; voxelization once per technique; alpha-masked texels
 * left out of the voxels; ambient occlusion (and `render --out-ao`);
 * `render --timings`: every pass's row and the GPU memory the settings
 * call for; bad settings. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "test_util.h"
#include "core/animation.h"
#include "gi/vct/vct.h"
#include "io/metrics.h"
#include "reference/pathtracer.h"

/* A renderer with `--gi vct` and hard shadows on `s`. */
static void vct_renderer(Renderer *r, const Scene *s, int w, int h, const GiParams *gp)
{
    RenderSettings rs = test_settings(s, w, h, SHADOW_MODE_HARD);
    rs.gi = GI_VCT;
    rs.set.gi = gp ? *gp : s->settings.gi;
    assert_true(renderer_create(r, s, &rs));
}

/* One frame of `s` with `gp` (16×16 pixels) and mip 0 of volume `which`
 * (4 floats a voxel, caller frees), with its grid: N, min corner, voxel
 * size. */
static float *vct_volume_of(const Scene *s, const GiParams *gp, VctVolume which, int *n, float origin[3],
                            float *voxel)
{
    Renderer r;
    vct_renderer(&r, s, 16, 16, gp);
    renderer_frame(&r, &s->camera);
    vct_grid(r.gi_state, n, origin, voxel);
    float *vol = malloc(sizeof(float) * 4 * (size_t)*n * (size_t)*n * (size_t)*n);
    assert_non_null(vol);
    assert_true(vct_read_volume(r.gi_state, which, vol));
    renderer_destroy(&r);
    return vol;
}

/* ---- Voxelization --------------------------------------------------------- */

/* Separating-axis test of triangle (a, b, c) against the box centred on
 * `centre` with half extent h (Akenine-Möller 2001), in voxel units. */
static bool tri_box(const double a[3], const double b[3], const double c[3], const double centre[3], double h)
{
    double v[3][3], e[3][3];
    for (int k = 0; k < 3; k++) {
        v[0][k] = a[k] - centre[k];
        v[1][k] = b[k] - centre[k];
        v[2][k] = c[k] - centre[k];
    }
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            e[i][k] = v[(i + 1) % 3][k] - v[i][k];
    double axes[13][3];
    int n = 0;
    for (int i = 0; i < 3; i++) {
        double u[3] = {i == 0, i == 1, i == 2};
        memcpy(axes[n++], u, sizeof u);
    }
    axes[n][0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
    axes[n][1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
    axes[n][2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
    n++;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double u[3] = {i == 0, i == 1, i == 2};
            axes[n][0] = u[1] * e[j][2] - u[2] * e[j][1];
            axes[n][1] = u[2] * e[j][0] - u[0] * e[j][2];
            axes[n][2] = u[0] * e[j][1] - u[1] * e[j][0];
            n++;
        }
    for (int k = 0; k < n; k++) {
        const double *x = axes[k];
        double r = h * (fabs(x[0]) + fabs(x[1]) + fabs(x[2]));
        double p0 = v[0][0] * x[0] + v[0][1] * x[1] + v[0][2] * x[2];
        double p1 = v[1][0] * x[0] + v[1][1] * x[1] + v[1][2] * x[2];
        double p2 = v[2][0] * x[0] + v[2][1] * x[1] + v[2][2] * x[2];
        if (fmin(p0, fmin(p1, p2)) > r || fmax(p0, fmax(p1, p2)) < -r)
            return false;
    }
    return true;
}

/* Voxelizes `s` at N = n and counts holes (voxels a triangle overlaps by
 * more than 1e-3 voxel that are empty) and extras (filled voxels no
 * triangle comes within 1e-3 voxel of). */
static void count_holes(const Scene *s, int n, bool conservative, int *holes, int *extras, int *filled)
{
    GiParams gp = s->settings.gi;
    gp.vct.size = n;
    gp.vct.conservative = conservative;
    gp.vct.aniso = false;
    int size;
    float origin[3], voxel;
    float *vol = vct_volume_of(s, &gp, VCT_VOLUME_ALBEDO, &size, origin, &voxel);
    assert_int_equal(size, n);
    size_t n3 = (size_t)n * n * n;
    unsigned char *may = calloc(n3, 1), *must = calloc(n3, 1);
    assert_true(may && must);
    *holes = *extras = *filled = 0;
    for (uint32_t t = 0; t + 2 < s->index_count; t += 3) {
        double p[3][3], lo[3], hi[3];
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++)
                p[k][a] = (s->vertices[s->indices[t + k]].position[a] - origin[a]) / voxel;
        for (int a = 0; a < 3; a++) {
            lo[a] = fmax(floor(fmin(p[0][a], fmin(p[1][a], p[2][a]))) - 1, 0);
            hi[a] = fmin(floor(fmax(p[0][a], fmax(p[1][a], p[2][a]))) + 1, n - 1);
        }
        for (int z = (int)lo[2]; z <= (int)hi[2]; z++)
            for (int y = (int)lo[1]; y <= (int)hi[1]; y++)
                for (int x = (int)lo[0]; x <= (int)hi[0]; x++) {
                    double c[3] = {x + 0.5, y + 0.5, z + 0.5};
                    size_t i = ((size_t)z * n + y) * n + x;
                    may[i] |= tri_box(p[0], p[1], p[2], c, 0.5 + 1e-3);
                    must[i] |= tri_box(p[0], p[1], p[2], c, 0.5 - 1e-3);
                }
    }
    for (size_t i = 0; i < n3; i++) {
        bool full = vol[4 * i + 3] > 0.f;
        *filled += full;
        *extras += full && !may[i];
        *holes += !full && must[i];
    }
    free(vol);
    free(may);
    free(must);
}

/* A thin plane tilted 4° off the floor (grazing the voxel rows) and a wall
 * 0.6 voxel thick turned 30° about y, both in a 32³ volume; a faint sun. */
static void thin_scene(Scene *s)
{
    scene_init(s);
    int white = scene_add_material(s, "white", (vec3){0.8f, 0.8f, 0.8f});
    float t = tanf(glm_rad(4.f));
    /* The plane: x in [-1, 1], y = 0.2 + t·x. */
    scene_add_quad(s, white, (vec3){-1.f, 0.2f - t, -1.f}, (vec3){-1.f, 0.2f - t, 1.f}, (vec3){1.f, 0.2f + t, 1.f},
                   (vec3){1.f, 0.2f + t, -1.f});
    /* The wall: a box 1.2 × 1 × (0.6 voxel of 2/30 m) turned 30°, standing on y = 0.4. */
    float th = 0.6f * 2.f / 30.f, c = cosf(glm_rad(30.f)), sn = sinf(glm_rad(30.f));
    vec3 corner[8];
    for (int i = 0; i < 8; i++) {
        float lx = (i & 1) ? 0.6f : -0.6f, lz = (i & 2) ? 0.5f * th : -0.5f * th, y = (i & 4) ? 1.f : 0.4f;
        corner[i][0] = c * lx - sn * lz;
        corner[i][1] = y;
        corner[i][2] = sn * lx + c * lz;
    }
    static const int faces[6][4] = {{0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (int f = 0; f < 6; f++)
        scene_add_quad(s, white, corner[faces[f][0]], corner[faces[f][1]], corner[faces[f][2]], corner[faces[f][3]]);
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0.3f, -1.f, 0.2f}, .color = {1.f, 1.f, 1.f}};
    scene_add_light(s, &sun);
    glm_vec3_copy((vec3){0.f, 3.f, 3.f}, s->camera.position);
    glm_vec3_normalize_to((vec3){0.f, -1.f, -1.f}, s->camera.forward);
    glm_vec3_normalize_to((vec3){0.f, 1.f, -1.f}, s->camera.up);
    scene_finalize(s);
}

static void voxelization_is_watertight(void **state)
{
    (void)state;
    Scene s;
    thin_scene(&s);
    int holes[2], extras[2], filled[2];
    count_holes(&s, 32, true, &holes[1], &extras[1], &filled[1]);
    count_holes(&s, 32, false, &holes[0], &extras[0], &filled[0]);
    print_message("voxelization 32^3, thin plane at 4 deg + 0.6-voxel wall at 30 deg: conservative %d filled, "
                  "%d holes, %d extra; fragment centres only %d filled, %d holes, %d extra\n",
                  filled[1], holes[1], extras[1], filled[0], holes[0], extras[0]);
    assert_int_equal(holes[1], 0);
    assert_int_equal(extras[1], 0);
    assert_true(holes[0] > 50); /* without the expansion the rows it grazes and the thin wall leak */
    assert_true(filled[1] > filled[0]);
    scene_free(&s);
}

/* Flat floors lying exactly on voxel boundaries: 64 convex quads at odd
 * integer heights in a grid of 1 m voxels (bounds [-15, 15]³ at N = 32:
 * origin -16, voxel 1, so a floor at y = Y lies on the boundary z = Y + 16
 * between two voxel layers). Their corners are irregular, so each
 * triangle's plane normal is some rounded product, and the plane's depth
 * over a pixel, d / n.z with d = n.z·z, comes out as z or one ulp under it
 * depending on the triangle. One ulp under had emptied the conservative
 * fragment's candidate range (floor(z − ulp) < z) and left the floor out
 * of the voxels: found on NVIDIA, whose division is inexact; here
 * llvmpipe's rounding of n.z·z does it for a few triangles (without the
 * clamp in voxelize.frag, 25 of the 1621 columns below came out empty).
 * Every voxel column wholly under a floor must hold it in the layer above
 * or below the boundary, with and without the conservative expansion. */
#define FLOORS 64
static void boundary_floors(Scene *s, float height[FLOORS], float box[FLOORS][4])
{
    scene_init(s);
    int white = scene_add_material(s, "white", (vec3){0.8f, 0.8f, 0.8f});
    uint32_t seed = 12345u;
#define NEXT() ((seed = seed * 1664525u + 1013904223u), (float)(seed >> 8) / 16777216.f)
    for (int q = 0; q < FLOORS; q++) {
        float y = (float)(2 * (q % 14) - 13); /* -13, -11, ..., 13 */
        float wx = 3.f + 6.f * NEXT(), wz = 3.f + 6.f * NEXT();
        float x0 = -14.f + (28.f - wx) * NEXT(), z0 = -14.f + (28.f - wz) * NEXT();
        /* Each corner pushed out by up to 0.9 m: a convex quad whose
         * inscribed box is [x0, x0 + wx] × [z0, z0 + wz]. */
        vec3 p[4] = {{x0 - 0.9f * NEXT(), y, z0 - 0.9f * NEXT()},
                     {x0 - 0.9f * NEXT(), y, z0 + wz + 0.9f * NEXT()},
                     {x0 + wx + 0.9f * NEXT(), y, z0 + wz + 0.9f * NEXT()},
                     {x0 + wx + 0.9f * NEXT(), y, z0 - 0.9f * NEXT()}};
        assert_true(scene_add_quad(s, white, p[0], p[1], p[2], p[3]));
        height[q] = y;
        box[q][0] = x0;
        box[q][1] = z0;
        box[q][2] = x0 + wx;
        box[q][3] = z0 + wz;
    }
#undef NEXT
    /* Two specks pin the bounds to [-15, 15]³. */
    for (int c = 0; c < 2; c++) {
        float e = c ? 15.f : -15.f, d = c ? -0.01f : 0.01f;
        assert_true(scene_add_quad(s, white, (vec3){e, e, e}, (vec3){e + d, e, e}, (vec3){e + d, e + d, e},
                                   (vec3){e, e + d, e}));
    }
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0.2f, -1.f, 0.1f}, .color = {1.f, 1.f, 1.f}};
    scene_add_light(s, &sun);
    glm_vec3_copy((vec3){0.f, 40.f, 40.f}, s->camera.position);
    glm_vec3_normalize_to((vec3){0.f, -1.f, -1.f}, s->camera.forward);
    glm_vec3_normalize_to((vec3){0.f, 1.f, -1.f}, s->camera.up);
    scene_finalize(s);
}

static void floors_on_voxel_boundaries(void **state)
{
    (void)state;
    Scene s;
    float height[FLOORS], box[FLOORS][4];
    boundary_floors(&s, height, box);
    for (int conservative = 0; conservative < 2; conservative++) {
        GiParams gp = s.settings.gi;
        gp.vct.size = 32;
        gp.vct.conservative = conservative;
        gp.vct.aniso = false;
        int n;
        float origin[3], voxel;
        float *vol = vct_volume_of(&s, &gp, VCT_VOLUME_ALBEDO, &n, origin, &voxel);
        assert_int_equal(n, 32);
        assert_true(origin[0] == -16.f && origin[1] == -16.f && origin[2] == -16.f && voxel == 1.f);
        int columns = 0, missing = 0;
        for (int q = 0; q < FLOORS; q++) {
            int layer = (int)height[q] + 16; /* the boundary: layers layer - 1 and layer touch it */
            for (int z = (int)ceilf(box[q][1] + 16.f); z + 1 <= (int)floorf(box[q][3] + 16.f); z++)
                for (int x = (int)ceilf(box[q][0] + 16.f); x + 1 <= (int)floorf(box[q][2] + 16.f); x++) {
                    size_t lo = ((size_t)z * n + (size_t)(layer - 1)) * n + (size_t)x;
                    size_t hi = lo + (size_t)n;
                    columns++;
                    missing += vol[4 * lo + 3] == 0.f && vol[4 * hi + 3] == 0.f;
                }
        }
        print_message("floors on voxel boundaries (%s): %d of %d columns under them empty\n",
                      conservative ? "conservative" : "fragment centres", missing, columns);
        assert_true(columns > 500);
        assert_int_equal(missing, 0);
        free(vol);
    }
    scene_free(&s);
}

/* ---- Injection ------------------------------------------------------------ */

/* A white floor (ρ = 0.8) under a sun of irradiance E = (2, 3, 4) W/m² at
 * 35° from the zenith: every opaque voxel holds ρ·E·cosθ/π (premultiplied
 * by opacity 1), to 2%. */
static void injection_matches_lambert(void **state)
{
    (void)state;
    Scene s;
    scene_init(&s);
    int white = scene_add_material(&s, "white", (vec3){0.8f, 0.8f, 0.8f});
    test_add_square(&s, white, (vec3){0.f, 0.f, 0.f}, 2.f);
    float th = glm_rad(35.f);
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {sinf(th), -cosf(th), 0.f}, .color = {2.f, 3.f, 4.f}};
    scene_add_light(&s, &sun);
    test_camera_down(&s.camera, (vec3){0.f, 3.f, 0.01f});
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = 32;
    int n;
    float origin[3], voxel;
    float *vol = vct_volume_of(&s, &gp, VCT_VOLUME_RADIANCE, &n, origin, &voxel);
    size_t n3 = (size_t)n * n * n;
    int count = 0;
    double worst = 0;
    for (size_t i = 0; i < n3; i++) {
        if (vol[4 * i + 3] == 0.f)
            continue;
        count++;
        assert_true(fabsf(vol[4 * i + 3] - 1.f) < 1e-3f);
        for (int c = 0; c < 3; c++) {
            double want = 0.8 * sun.color[c] * cos(th) / GLM_PI;
            worst = fmax(worst, fabs(vol[4 * i + c] / want - 1));
        }
    }
    print_message("injection: %d floor voxels, radiance within %.3f%% of rho E cos/pi\n", count, 100 * worst);
    assert_true(count >= 30 * 30);
    assert_true(worst < 0.02);
    free(vol);
    scene_free(&s);
}

/* A 0.5 m floor and a wall on it under a sun, with a two-level clipmap of
 * 16³: the frame after the clipmap moved (a revoxelization), with
 * `bounces` bounces; its radiance and albedo levels (4·16³·2 floats each,
 * caller frees), and whether the opaque voxels were listed. */
static void moved_clipmap_volumes(int bounces, float **albedo, float **radiance, bool *listed, unsigned *opaque)
{
    Scene s;
    scene_init(&s);
    int white = scene_add_material(&s, "white", (vec3){0.8f, 0.8f, 0.8f});
    test_add_square(&s, white, (vec3){0.f, 0.f, 0.f}, 0.5f);
    scene_add_quad(&s, white, (vec3){0.1f, 0.f, -0.2f}, (vec3){0.1f, 0.3f, -0.2f}, (vec3){0.1f, 0.3f, 0.2f},
                   (vec3){0.1f, 0.f, 0.2f});
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0.5f, -1.f, 0.1f}, .color = {2.f, 3.f, 4.f}};
    scene_add_light(&s, &sun);
    test_camera_down(&s.camera, (vec3){0.f, 0.3f, 0.01f});
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = 16;
    gp.vct.levels = 2;
    gp.vct.bounces = bounces;
    Renderer r;
    vct_renderer(&r, &s, 16, 16, &gp);
    Camera cam = s.camera;
    renderer_frame(&r, &cam);
    float o[3], vox;
    vct_level(r.gi_state, 0, o, &vox);
    cam.position[0] += 3.f * vox;
    renderer_frame(&r, &cam);
    assert_int_equal(renderer_collect_stats(&r)->voxelizations, 2);
    *opaque = vct_opaque_voxels(r.gi_state, listed);
    size_t n3 = 16u * 16u * 16u * 2u;
    *albedo = malloc(sizeof(float) * 4 * n3);
    *radiance = malloc(sizeof(float) * 4 * n3);
    assert_non_null(*albedo);
    assert_non_null(*radiance);
    assert_true(vct_read_volume(r.gi_state, VCT_VOLUME_ALBEDO, *albedo));
    assert_true(vct_read_volume(r.gi_state, VCT_VOLUME_RADIANCE, *radiance));
    renderer_destroy(&r);
    scene_free(&s);
}

/* The injection and the second bounce run over the list of opaque voxels
 * (resolve.comp) when it is short enough; the empty voxels hold the
 * clear's 0 (injection) or the copied direct radiance (bounce). After the
 * clipmap moves, every voxel's radiance opacity equals its albedo
 * opacity, where stale radiance would remain in voxels the scene no longer
 * fills; the bounce adds light to the opaque voxels (the wall and the
 * floor light each other) and nothing to the empty ones. */
static void injection_covers_the_opaque_voxels(void **state)
{
    (void)state;
    size_t n3 = 16u * 16u * 16u * 2u;
    float *albedo, *direct, *albedo2, *bounced;
    bool listed, listed2;
    unsigned opaque, opaque2;
    moved_clipmap_volumes(1, &albedo, &direct, &listed, &opaque);
    moved_clipmap_volumes(2, &albedo2, &bounced, &listed2, &opaque2);
    unsigned filled = 0, mismatched = 0, mismatched2 = 0, brighter = 0, changed_empty = 0;
    for (size_t i = 0; i < n3; i++) {
        bool full = albedo[4 * i + 3] > 0.f;
        filled += full;
        mismatched += fabsf(direct[4 * i + 3] - albedo[4 * i + 3]) > 1e-3f;
        mismatched2 += fabsf(bounced[4 * i + 3] - albedo2[4 * i + 3]) > 1e-3f;
        double d = bounced[4 * i] + bounced[4 * i + 1] + bounced[4 * i + 2] -
                   (direct[4 * i] + direct[4 * i + 1] + direct[4 * i + 2]);
        brighter += full && d > 1e-4;
        changed_empty += !full && d != 0.0;
    }
    print_message("after the clipmap moved: %u opaque voxels (%s), %u filled; radiance opacity differs in %u "
                  "(direct) and %u (2 bounces); the bounce brightens %u opaque voxels and changes %u empty ones\n",
                  opaque, listed && listed2 ? "listed" : "not all listed", filled, mismatched, mismatched2, brighter,
                  changed_empty);
    assert_true(listed && listed2);
    assert_int_equal(opaque, filled);
    assert_int_equal(opaque2, filled);
    assert_true(filled > 20);
    assert_int_equal(mismatched, 0);
    assert_int_equal(mismatched2, 0);
    assert_true(brighter > filled / 4);
    assert_int_equal(changed_empty, 0);
    free(albedo);
    free(direct);
    free(albedo2);
    free(bounced);
}

/* ---- Voxelized once ---------------------------------------------------- */

static void voxelizes_once(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = 16;
    Renderer r;
    vct_renderer(&r, &s, 16, 16, &gp);
    renderer_frame(&r, &s.camera);
    Camera cam = s.camera;
    cam.position[0] += 0.05f;
    renderer_frame(&r, &cam);
    const RenderStats *st = renderer_collect_stats(&r);
    assert_int_equal(st->voxelizations, 1);
    assert_true(st->gpu_bytes >= 3ull * 16 * 16 * 16 * 8);
    renderer_destroy(&r);
    scene_free(&s);
}

/* ---- Alpha masks ------------------------------------------------------------ */

/* A 2 m quad on y = 0 whose texture is opaque on its x < 0 half and
 * transparent on the other (an OBJ whose map_d is the mask, as Sponza's
 * leaves; the same quad without map_d beside it), voxelized at 32³:
 * returns the filled voxels and those whose centre lies more than a voxel
 * past x = 0, on the transparent side. */
static void masked_quad_scene(Scene *s, bool masked)
{
    test_mask_textures("vct_mask_albedo.png", "vct_mask_alpha.png");
    const char *name = masked ? "vct_masked" : "vct_unmasked";
    char mtl[256], obj[1024], file[64];
    snprintf(mtl, sizeof mtl, "newmtl leaf\nKd 0.8 0.8 0.8\nmap_Kd vct_mask_albedo.png\n%s",
             masked ? "map_d vct_mask_alpha.png\n" : "");
    snprintf(file, sizeof file, "%s.mtl", name);
    test_tmp_file(file, mtl);
    /* u from the centre of texel column 0 (x = -1) to that of column 7
     * (x = 1): the bilinear alpha crosses 0.5 at x = 0. */
    snprintf(obj, sizeof obj,
             "mtllib %s.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
             "vt 0.0625 0.0625\nvt 0.9375 0.0625\nvt 0.9375 0.9375\nvt 0.0625 0.9375\nvn 0 1 0\n"
             "usemtl leaf\nf 1/1/1 4/4/1 3/3/1 2/2/1\n",
             name);
    snprintf(file, sizeof file, "%s.obj", name);
    assert_true(scene_load(s, test_tmp_file(file, obj)));
    assert_int_equal(s->materials[s->submeshes[0].material].alpha_mask, masked);
}

static void count_masked_quad(bool masked, int *filled, int *beyond)
{
    Scene s;
    masked_quad_scene(&s, masked);
    GiParams gp = s.settings.gi;
    gp.vct.size = 32;
    int n;
    float origin[3], voxel;
    float *vol = vct_volume_of(&s, &gp, VCT_VOLUME_ALBEDO, &n, origin, &voxel);
    size_t n3 = (size_t)n * n * n;
    *filled = *beyond = 0;
    for (size_t i = 0; i < n3; i++) {
        if (vol[4 * i + 3] == 0.f)
            continue;
        ++*filled;
        *beyond += origin[0] + ((float)(i % (size_t)n) + 0.5f) * voxel > voxel;
    }
    free(vol);
    scene_free(&s);
}

/* Measured (llvmpipe, 32³): see the message; with the mask ignored the
 * masked quad fills as many voxels as the plain one, half of them on the
 * transparent side. */
static void alpha_masked_texels_are_skipped(void **state)
{
    (void)state;
    int filled[2], beyond[2];
    count_masked_quad(false, &filled[0], &beyond[0]);
    count_masked_quad(true, &filled[1], &beyond[1]);
    print_message("alpha mask: a 2 m quad at 32^3 fills %d voxels (%d more than a voxel past x = 0); with its x > 0 "
                  "half masked out %d (%d)\n",
                  filled[0], beyond[0], filled[1], beyond[1]);
    assert_true(filled[0] >= 28 * 28);
    assert_true(beyond[0] > filled[0] / 3);
    assert_int_equal(beyond[1], 0);
    assert_true(filled[1] > 0.4 * filled[0] && filled[1] < 0.6 * filled[0]);
}

/* ---- Compute against raster -------------------------------------------------- */

/* Voxelizes `s` at N = n both ways (--vct-voxelize raster, compute) and
 * compares the volumes voxel by voxel: voxels filled by one alone, and the
 * largest difference of albedo and of normal where both are filled. */
static void compare_voxelizations(const Scene *s, int n, const char *what, double albedo_tol)
{
    float *vol[2][2]; /* [method][albedo, normal] */
    int size;
    float origin[3], voxel;
    for (int m = 0; m < 2; m++) {
        GiParams gp = s->settings.gi;
        gp.vct.size = n;
        gp.vct.aniso = false;
        gp.vct.voxelize = m ? VCT_VOXELIZE_COMPUTE : VCT_VOXELIZE_RASTER;
        vol[m][0] = vct_volume_of(s, &gp, VCT_VOLUME_ALBEDO, &size, origin, &voxel);
        vol[m][1] = vct_volume_of(s, &gp, VCT_VOLUME_NORMAL, &size, origin, &voxel);
    }
    size_t n3 = (size_t)n * n * n;
    int filled = 0, only_raster = 0, only_compute = 0;
    double albedo = 0, normal = 0;
    for (size_t i = 0; i < n3; i++) {
        bool r = vol[0][0][4 * i + 3] > 0.f, c = vol[1][0][4 * i + 3] > 0.f;
        filled += r;
        only_raster += r && !c;
        only_compute += c && !r;
        if (!r || !c)
            continue;
        for (int k = 0; k < 3; k++) {
            albedo = fmax(albedo, fabs(vol[0][0][4 * i + k] - vol[1][0][4 * i + k]));
            normal = fmax(normal, fabs(vol[0][1][4 * i + k] - vol[1][1][4 * i + k]));
        }
    }
    print_message("%s at %d^3: raster fills %d voxels; %d filled by raster alone, %d by compute alone; albedo within "
                  "%.5f, normal within %.5f\n",
                  what, n, filled, only_raster, only_compute, albedo, normal);
    assert_true(filled > 100);
    assert_int_equal(only_raster, 0);
    assert_int_equal(only_compute, 0);
    assert_true(albedo <= albedo_tol);
    assert_true(normal <= 2e-3); /* RGBA16F rounding of unit vectors */
    for (int m = 0; m < 2; m++)
        for (int k = 0; k < 2; k++)
            free(vol[m][k]);
}

/* The compute voxelization writes what the raster one does: the same
 * voxels (conservative coverage) with the same albedo and normal, on the
 * Cornell box, the thin plane and wall (so it is as watertight), and a
 * textured quad whose texture is alpha-masked on half of it (texels read
 * at the explicit gradient: bilinear, mip level within rounding of the
 * fragments' derivatives). The Cornell box also at 64³, where its walls
 * span more columns than a triangle walks itself on llvmpipe (voxelize.comp
 * SMALL_COLUMNS, 1024 there): the tile pass. */
static void compute_equals_raster(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    compare_voxelizations(&s, 32, "cornell", 2e-3);
    compare_voxelizations(&s, 64, "cornell", 2e-3);
    scene_free(&s);
    thin_scene(&s);
    compare_voxelizations(&s, 32, "thin plane and wall", 2e-3);
    scene_free(&s);
    masked_quad_scene(&s, true);
    compare_voxelizations(&s, 32, "alpha-masked textured quad", 1e-2);
    scene_free(&s);
}

/* A 2 m floor (grey) and a red wall 0.6 m tall on it at x = 0.3; the
 * wall's four vertices start at *wall. */
static void wall_scene(Scene *s, uint32_t *wall, int shelves)
{
    scene_init(s);
    int grey = scene_add_material(s, "grey", (vec3){0.5f, 0.5f, 0.5f});
    int red = scene_add_material(s, "red", (vec3){0.8f, 0.1f, 0.1f});
    test_add_square(s, grey, (vec3){0.f, 0.f, 0.f}, 2.f);
    for (int i = 1; i <= shelves; i++) /* more opaque voxels: layers over the floor */
        test_add_square(s, grey, (vec3){0.f, 0.2f * (float)i, 0.f}, 2.f);
    *wall = s->vertex_count;
    assert_true(scene_add_quad(s, red, (vec3){0.3f, 0.f, -0.5f}, (vec3){0.3f, 0.6f, -0.5f}, (vec3){0.3f, 0.6f, 0.5f},
                               (vec3){0.3f, 0.f, 0.5f}));
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0.3f, -1.f, 0.2f}, .color = {1.f, 1.f, 1.f}};
    scene_add_light(s, &sun);
    /* a second light: injection adds to what the first wrote */
    Light sun2 = {.type = LIGHT_DIRECTIONAL, .direction = {-0.4f, -1.f, -0.1f}, .color = {0.5f, 0.5f, 0.5f}};
    scene_add_light(s, &sun2);
    test_camera_down(&s->camera, (vec3){0.f, 3.f, 0.01f});
    scene_finalize(s);
}

/* A moved object revoxelizes to what a cold renderer voxelizes, both
 * ways: no sample of where it stood stays (the sums persist between
 * voxelizations, cleared by the resolve behind itself), whether the
 * opaque voxels fit their list (16³) or overflow it (4³, and 16³ with two
 * shelves over the floor: the passes then run over every voxel, chosen on
 * the GPU, gi/vct/args.comp). Albedo volumes equal exactly (integer sums).
 * The compute voxelization revoxelizes the moved wall's region alone
 * where it is at most a quarter of the volume (issue 46: 16³), and its
 * frame equals the cold renderer's bit for bit (the
 * opaque list made again holds every opaque voxel once: a voxel listed
 * twice would be lit twice by the second light; with the list before
 * overflowed, it is made from every voxel). */
static void moved_object_revoxelizes(void **state)
{
    (void)state;
    static const struct {
        int size, shelves;
    } cases[] = {{4, 0}, {16, 0}, {16, 2}};
    for (int m = 0; m < 2; m++) {
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
            int size = cases[c].size;
            bool fits = size == 16 && cases[c].shelves == 0;
            Scene s;
            uint32_t wall;
            wall_scene(&s, &wall, cases[c].shelves);
            GiParams gp = s.settings.gi;
            gp.vct.size = size;
            gp.vct.aniso = false;
            gp.vct.voxelize = m ? VCT_VOXELIZE_COMPUTE : VCT_VOXELIZE_RASTER;
            Renderer r;
            vct_renderer(&r, &s, 16, 16, &gp);
            renderer_frame(&r, &s.camera);
            bool listed_before;
            vct_opaque_voxels(r.gi_state, &listed_before);
            for (uint32_t i = wall; i < wall + 4; i++)
                s.vertices[i].position[0] -= 0.6f; /* to x = -0.3 */
            assert_true(renderer_scene_changed(&r, &(SceneChange){SCENE_CHANGED_GEOMETRY, wall, 4}));
            renderer_frame(&r, &s.camera);
            bool listed;
            unsigned opaque = vct_opaque_voxels(r.gi_state, &listed);
            const GiStats *st = renderer_collect_stats(&r);
            assert_int_equal(st->voxelizations, 2);
            /* 16³: the region is 640 of 4096 voxels; 4³: all of them (whole, cheaper) */
            assert_int_equal(st->region_voxelizations, m && size == 16);
            size_t n3 = (size_t)size * size * size;
            float *moved = malloc(sizeof(float) * 4 * n3);
            assert_non_null(moved);
            assert_true(vct_read_volume(r.gi_state, VCT_VOLUME_ALBEDO, moved));
            if (m) { /* the region's frame against a cold renderer's */
                print_message("compute, %d^3: the region held %llu of %zu voxels\n", size,
                              (unsigned long long)st->region_voxels, n3);
                assert_true(size == 4 || (st->region_voxels > 0 && 4 * st->region_voxels <= n3));
                ImageF got, want;
                assert_true(renderer_read_hdr(&r, &got));
                Renderer cold;
                vct_renderer(&cold, &s, 16, 16, &gp);
                renderer_frame(&cold, &s.camera);
                assert_true(renderer_read_hdr(&cold, &want));
                renderer_destroy(&cold);
                int px = 0;
                for (int i = 0; i < 3 * got.width * got.height; i++)
                    px += got.rgb[i] != want.rgb[i];
                print_message("compute, %d^3: %d frame values differ from a cold renderer's\n", size, px);
                assert_int_equal(px, 0);
                image_free(&got);
                image_free(&want);
            }
            renderer_destroy(&r);
            int n;
            float origin[3], voxel;
            float *cold = vct_volume_of(&s, &gp, VCT_VOLUME_ALBEDO, &n, origin, &voxel);
            int differ = 0, filled = 0;
            for (size_t i = 0; i < 4 * n3; i++)
                differ += moved[i] != cold[i];
            for (size_t i = 0; i < n3; i++)
                filled += cold[4 * i + 3] > 0.f;
            print_message("%s, %d^3: after the wall moved %u opaque voxels (%s, before the move %s), %d filled cold; "
                          "%d values differ from a cold renderer's\n",
                          m ? "compute" : "raster", size, opaque, listed ? "listed" : "overflowing the list",
                          listed_before ? "listed" : "overflowing", filled, differ);
            assert_true(listed == fits && listed_before == listed);
            assert_int_equal(opaque, filled);
            assert_int_equal(differ, 0);
            free(moved);
            free(cold);
            scene_free(&s);
        }
    }
}

/* ---- Clipmap ------------------------------------------------------------- */

/* --vct-levels 3: levels of whole voxels around the camera, each voxel
 * twice the last; a camera move within a finest voxel revoxelizes
 * nothing, a move of three finest voxels revoxelizes and shifts the finest
 * level by whole voxels. */
static void clipmap_follows_the_camera(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = 16;
    gp.vct.levels = 3;
    Renderer r;
    vct_renderer(&r, &s, 16, 16, &gp);
    Camera cam = s.camera;
    renderer_frame(&r, &cam);
    float o[3][3], vox[3];
    for (int k = 0; k < 3; k++) {
        vct_level(r.gi_state, k, o[k], &vox[k]);
        for (int a = 0; a < 3; a++)
            assert_true(fabs(o[k][a] / vox[k] - round(o[k][a] / vox[k])) < 1e-3);
        if (k > 0)
            assert_true(fabsf(vox[k] - 2.f * vox[k - 1]) < 1e-5f * vox[k]);
        /* The camera sits in the middle of every level. */
        for (int a = 0; a < 3; a++)
            assert_true(cam.position[a] > o[k][a] + 7.f * vox[k] && cam.position[a] < o[k][a] + 9.f * vox[k]);
    }
    assert_int_equal(renderer_collect_stats(&r)->voxelizations, 1);
    /* Within the finest voxel the camera is in (the coarser ones hold it). */
    float f = cam.position[0] / vox[0] - floorf(cam.position[0] / vox[0]);
    cam.position[0] += (f < 0.5f ? 0.3f : -0.3f) * vox[0];
    renderer_frame(&r, &cam);
    assert_int_equal(renderer_collect_stats(&r)->voxelizations, 1);
    cam.position[0] += 3.f * vox[0];
    renderer_frame(&r, &cam);
    assert_int_equal(renderer_collect_stats(&r)->voxelizations, 2);
    float o2[3], v2;
    vct_level(r.gi_state, 0, o2, &v2);
    double shift = (o2[0] - o[0][0]) / vox[0];
    assert_true(fabs(shift - round(shift)) < 1e-3 && round(shift) >= 2 && round(shift) <= 4);
    renderer_destroy(&r);
    scene_free(&s);
}

/* ---- The Cornell box against the path tracer --------------------------- */

/* The Cornell box with its light as a point and hard shadows, 64² pixels,
 * 32³ voxels, 6 cones. Measured (llvmpipe) relMSE against one-bounce: vct
 * 0.0071 at the default --vct-trace-scale 2 (every pixel traced 0.0073),
 * isotropic mips 0.0230, a 2-level clipmap 0.0196 (its levels centre on the
 * camera outside the box: coarser voxels), no GI 0.0359; against full:
 * 1 bounce 0.0226, 2 bounces 0.0117, no GI 0.0745. The bound sits between vct and
 * no GI; the second bounce must lower the error against full. */
#define VCT_CORNELL_BOUND 0.015 /* relMSE against one-bounce */
static void cornell_against_reference(void **state)
{
    (void)state;
    enum { W = 64, H = 64 };
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    scene_rescale_lights(&s, 0.f);
    GiParams gp = s.settings.gi;
    gp.vct.size = 32;
    ImageF one, full_res, iso, two, none, ob, full, clip;
    test_render_gi(&s, W, H, GI_VCT, &gp, &one);
    gp.vct.trace_scale = 1;
    test_render_gi(&s, W, H, GI_VCT, &gp, &full_res);
    gp.vct.trace_scale = s.settings.gi.vct.trace_scale;
    gp.vct.levels = 2;
    test_render_gi(&s, W, H, GI_VCT, &gp, &clip);
    gp.vct.levels = 1;
    gp.vct.aniso = false;
    test_render_gi(&s, W, H, GI_VCT, &gp, &iso);
    gp.vct.aniso = true;
    gp.vct.bounces = 2;
    test_render_gi(&s, W, H, GI_VCT, &gp, &two);
    test_render_gi(&s, W, H, GI_NONE, NULL, &none);
    test_reference(&s, W, H, PT_ONE_BOUNCE, 256, &ob);
    test_reference(&s, W, H, PT_FULL, 256, &full);
    double v_ob = metric_relmse(&one, &ob, NULL, NULL), i_ob = metric_relmse(&iso, &ob, NULL, NULL);
    double n_ob = metric_relmse(&none, &ob, NULL, NULL);
    double v_full = metric_relmse(&one, &full, NULL, NULL), t_full = metric_relmse(&two, &full, NULL, NULL);
    double n_full = metric_relmse(&none, &full, NULL, NULL), c_ob = metric_relmse(&clip, &ob, NULL, NULL);
    print_message("relMSE vs one-bounce: vct %.4f (isotropic %.4f, 2-level clipmap %.4f) none %.4f; vs full: vct 1 "
                  "bounce %.4f, 2 bounces %.4f, none %.4f\n",
                  v_ob, i_ob, c_ob, n_ob, v_full, t_full, n_full);
    double f_ob = metric_relmse(&full_res, &ob, NULL, NULL);
    print_message("--vct-trace-scale %d: relMSE vs one-bounce %.4f, every pixel traced %.4f\n", s.settings.gi.vct.trace_scale,
                  v_ob, f_ob);
    assert_true(v_ob < 1.1 * f_ob); /* the upsampling loses (almost) nothing */
    assert_true(c_ob < n_ob);
    assert_true(v_ob < VCT_CORNELL_BOUND);
    assert_true(n_ob > VCT_CORNELL_BOUND); /* the bound means something */
    assert_true(i_ob < n_ob);
    /* The directional volumes are read (the tracers compile them in with
     * VCT_ANISO; without, both images are the isotropic trace). */
    double a_i = metric_relmse(&one, &iso, NULL, NULL);
    print_message("anisotropic against isotropic: relMSE %.2g\n", a_i);
    assert_true(a_i > 1e-3);
    assert_true(t_full < v_full);           /* the second bounce helps against the full reference */
    assert_true(t_full < 0.6 * n_full);
    image_free(&one);
    image_free(&full_res);
    image_free(&clip);
    image_free(&iso);
    image_free(&two);
    image_free(&none);
    image_free(&ob);
    image_free(&full);
    scene_free(&s);
}

/* ---- The diffuse cone sets -------------------------------------------------- */

/* Each set's weights integrate the cosine lobe: under a uniform sky of
 * radiance L the cones' Σ w_i·L is the closed form πL (Σ w_i / π = 1), and
 * their cones' solid angles 2π(1 − cos α_i) tile the hemisphere (Σ = 2π).
 * Each weight also matches ∫cosθ dω over its cone's Voronoi cell counted
 * here on another grid (uniform in cosθ, not in θ as vct.c's). */
static void cone_weights_integrate_the_cosine_lobe(void **state)
{
    (void)state;
    for (int set = 0; set < 3; set++) {
        float dirs[VCT_MAX_CONES][4], tan_half[VCT_MAX_CONES];
        int k = vct_cone_set(set, dirs, tan_half);
        assert_true(k > 0 && k <= VCT_MAX_CONES);
        double w = 0, omega = 0, cell[VCT_MAX_CONES] = {0}, worst = 0, ring = 0;
        enum { NU = 400, NP = 800 };
        for (int i = 0; i < NU; i++) {
            double u = (i + 0.5) / NU, st = sqrt(1 - u * u); /* u = cosθ; dω = du dφ */
            for (int j = 0; j < NP; j++) {
                double ph = (j + 0.5) * 2 * GLM_PI / NP, d[3] = {st * cos(ph), st * sin(ph), u};
                int best = 0;
                double bd = -2;
                for (int c = 0; c < k; c++) {
                    double dd = d[0] * dirs[c][0] + d[1] * dirs[c][1] + d[2] * dirs[c][2];
                    if (dd > bd)
                        bd = dd, best = c;
                }
                cell[best] += u * (1.0 / NU) * (2 * GLM_PI / NP);
            }
        }
        for (int c = 0; c < k; c++) {
            w += dirs[c][3];
            double cos_a = 1 / sqrt(1 + (double)tan_half[c] * tan_half[c]);
            omega += 2 * GLM_PI * (1 - cos_a);
            worst = fmax(worst, fabs(dirs[c][3] / cell[c] - 1));
            /* The cones of one ring are alike: equal weights. */
            for (int e = 1; e < c; e++)
                if (fabsf(dirs[e][2] - dirs[c][2]) < 1e-5f)
                    ring = fmax(ring, fabs(dirs[c][3] / dirs[e][3] - 1));
        }
        print_message("cone set %d (%d cones): sum of weights / pi %.5f, of solid angles / 2pi %.5f, "
                      "weights against their cells within %.4f, within a ring %.4f\n", set, k, w / GLM_PI,
                      omega / (2 * GLM_PI), worst, ring);
        assert_true(fabs(w / GLM_PI - 1) < 1e-3);
        assert_true(fabs(omega / (2 * GLM_PI) - 1) < 1e-3);
        assert_true(worst < 0.01);
        assert_true(ring < 0.002);
    }
}

/* ---- Single cones through a wall ------------------------------------------- */

/* A 2 m white wall (ρ = 0.8) in the plane z = 0 lit head-on by a sun of
 * E = 2 W/m² (radiance L = ρE/π toward +z), and a small quad far behind
 * the probes that sizes the bounds so that at N = 32 the wall's plane
 * lies at a voxel centre: conservative voxelization makes it exactly one
 * voxel thick. Cones start in front of the wall at distance s and travel
 * towards it at `angle` degrees from its normal, s chosen so that their
 * diameter where they reach the wall is 2^m voxels; each must be stopped
 * (opacity ≥ 0.95: < 5% transmittance) and return L. */
static void thin_wall_stops_cones(void **state)
{
    (void)state;
    Scene s;
    scene_init(&s);
    int white = scene_add_material(&s, "white", (vec3){0.8f, 0.8f, 0.8f});
    scene_add_quad(&s, white, (vec3){-1.f, -1.f, 0.f}, (vec3){1.f, -1.f, 0.f}, (vec3){1.f, 1.f, 0.f},
                   (vec3){-1.f, 1.f, 0.f});
    /* Bounds z in [0, 1.4]: voxel 2/30 m, the wall at local z 5.5 voxels. */
    scene_add_quad(&s, white, (vec3){0.9f, 0.9f, 1.4f}, (vec3){0.9f, 1.f, 1.4f}, (vec3){1.f, 1.f, 1.4f},
                   (vec3){1.f, 0.9f, 1.4f});
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0.f, 0.f, -1.f}, .color = {2.f, 2.f, 2.f}};
    scene_add_light(&s, &sun);
    glm_vec3_copy((vec3){0.f, 0.f, 3.f}, s.camera.position);
    glm_vec3_copy((vec3){0.f, 0.f, -1.f}, s.camera.forward);
    glm_vec3_copy((vec3){0.f, 1.f, 0.f}, s.camera.up);
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = 32;
    Renderer r;
    vct_renderer(&r, &s, 16, 16, &gp);
    renderer_frame(&r, &s.camera);
    int n;
    float origin[3], voxel;
    vct_grid(r.gi_state, &n, origin, &voxel);
    assert_true(fabsf(-origin[2] / voxel - 5.5f) < 1e-3f);
    const double want = 0.8 * 2.0 / GLM_PI;
    const float angles[] = {0.f, 30.f, 50.f};
    const float tan_half = 0.66f; /* the 6-cone set's cones: half-angle 33 degrees */
    enum { MIPS = 4, PROBES = 3 * MIPS };
    VctProbe probe[PROBES];
    for (int a = 0; a < 3; a++)
        for (int m = 0; m < MIPS; m++) {
            VctProbe *p = &probe[a * MIPS + m];
            float th = glm_rad(angles[a]);
            p->d[0] = sinf(th), p->d[1] = 0.f, p->d[2] = -cosf(th);
            glm_vec3_copy(p->d, p->n);
            /* Distance along the cone to the wall: diameter 2^m voxels
             * there, and at least 3 voxels past the apex (2.5 voxels off
             * the surface, cone.glsl's VCT_APEX before issue 44's second
             * round (now 1); the first sample 1 voxel past it). */
            float along = 2.5f * voxel + fmaxf((float)(1 << m) * voxel / (2.f * tan_half), 3.f * voxel);
            p->x[0] = -p->d[0] * along, p->x[1] = 0.f, p->x[2] = -p->d[2] * along;
            p->tan_half = tan_half;
        }
    float out[PROBES][4];
    assert_true(vct_probe(r.gi_state, PROBES, probe, out));
    int bad = 0;
    for (int a = 0; a < 3; a++)
        for (int m = 0; m < MIPS; m++) {
            const float *o = out[a * MIPS + m];
            bool ok = o[3] >= 0.95f && fabs(o[1] / want - 1) < 0.1;
            print_message("cone at %2.0f deg meeting the wall at mip %d: transmittance %.3f, radiance %.3f of L%s\n",
                          angles[a], m, 1 - o[3], o[1] / want, ok ? "" : "  <- wrong");
            bad += !ok;
        }
    assert_int_equal(bad, 0);
    renderer_destroy(&r);
    scene_free(&s);
}

/* ---- A surface does not light itself ---------------------------------------- */

/* A lone 2 m white square under a sun, turned `yaw` about y and tilted
 * `tilt` about x (so that its plane crosses the voxel rows at an angle):
 * nothing else in the scene, so every bit of light vct adds to it is light
 * its cones read from its own voxels. Returns Σ(vct − none) / Σ none over
 * the image (the square's direct light). */
static double self_lit_share(float yaw, float tilt, int n, bool conservative)
{
    Scene s;
    scene_init(&s);
    int white = scene_add_material(&s, "white", (vec3){0.8f, 0.8f, 0.8f});
    mat4 rot;
    glm_mat4_identity(rot);
    glm_rotate_y(rot, glm_rad(yaw), rot);
    glm_rotate_x(rot, glm_rad(tilt), rot);
    vec3 q[4] = {{-1.f, 0.f, -1.f}, {-1.f, 0.f, 1.f}, {1.f, 0.f, 1.f}, {1.f, 0.f, -1.f}};
    for (int i = 0; i < 4; i++)
        glm_mat4_mulv3(rot, q[i], 1.f, q[i]);
    scene_add_quad(&s, white, q[0], q[1], q[2], q[3]);
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0.2f, -1.f, 0.3f}, .color = {2.f, 2.f, 2.f}};
    glm_vec3_normalize(sun.direction);
    scene_add_light(&s, &sun);
    test_camera_down(&s.camera, (vec3){0.f, 3.f, 0.01f});
    s.camera.fov_y = glm_rad(50.f);
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = n;
    gp.vct.conservative = conservative;
    ImageF vct, none;
    test_render_gi(&s, 48, 48, GI_VCT, &gp, &vct);
    test_render_gi(&s, 48, 48, GI_NONE, NULL, &none);
    double added = 0, direct = 0;
    for (size_t i = 0; i < 48 * 48; i++) {
        added += luminance(vct.rgb + 3 * i) - luminance(none.rgb + 3 * i);
        direct += luminance(none.rgb + 3 * i);
    }
    image_free(&vct);
    image_free(&none);
    scene_free(&s);
    return added / direct;
}

static void surfaces_do_not_light_themselves(void **state)
{
    (void)state;
    const float orient[][2] = {{0.f, 0.f}, {17.f, 0.f}, {17.f, 25.f}, {40.f, 50.f}};
    double worst = 0;
    /* Both voxelizations: the cones keep clear of c.top (cone.glsl,
     * VCT_SURFACE_TOP), 1 voxel past the plane with conservative coverage
     * (measured: at most 0.8% added), ¾ with fragment centres (1.1%: the
     * clearance traded for light through narrow gaps, Sponza's arcades). */
    double worst_centres = 0;
    for (int conservative = 1; conservative >= 0; conservative--)
        for (size_t i = 0; i < sizeof orient / sizeof orient[0]; i++) {
            double share = self_lit_share(orient[i][0], orient[i][1], 32, conservative);
            print_message("lone square yaw %.0f tilt %.0f deg, %s: light vct adds %.4f of its direct light\n",
                          orient[i][0], orient[i][1], conservative ? "conservative" : "fragment centres", share);
            if (conservative)
                worst = fmax(worst, fabs(share));
            else
                worst_centres = fmax(worst_centres, fabs(share));
        }
    assert_true(worst < 0.01);
    assert_true(worst_centres < 0.015);
}

/* ---- Banding on a turned face ---------------------------------------------- */

/* The Cornell box's short block stands turned about y, so its front face
 * crosses the voxel columns at an angle. Its indirect light (vct − no GI)
 * averaged over each pixel column of the face must follow a smooth curve:
 * the RMS of the column means about their least-squares quadratic, over
 * their mean. The bands' cause: the cones read the face's own voxels
 * (gi/vct/cone.glsl lifted a sample one diameter along n, which left the
 * filter's lower texels on the face), and how much of them a cone read
 * depended on where the face cuts each voxel column. Measured at 64³:
 * 0.21 then, 0.08 now, and 0.08 with the samples kept clear of the
 * face's voxels alone (on the old mips, every voxel sending its light every
 * way): the clearance is what removed the bands. */
static double face_banding(const ImageF *vct, const ImageF *none, const uint8_t *mask, int w, int h)
{
    double sx[5] = {0}, sy[3] = {0}, total = 0;
    int cols = 0;
    double m[256];
    int used[256] = {0};
    for (int x = 0; x < w && x < 256; x++) {
        double sum = 0;
        int n = 0;
        for (int y = 0; y < h; y++)
            if (mask[(size_t)y * w + x]) {
                size_t i = (size_t)y * w + x;
                sum += luminance(vct->rgb + 3 * i) - luminance(none->rgb + 3 * i);
                n++;
            }
        if (n < 4)
            continue;
        m[x] = sum / n;
        used[x] = 1;
        double t = 1;
        for (int k = 0; k < 5; k++, t *= x)
            sx[k] += t;
        t = 1;
        for (int k = 0; k < 3; k++, t *= x)
            sy[k] += t * m[x];
        total += m[x];
        cols++;
    }
    assert_true(cols >= 8);
    /* Normal equations of the quadratic a + b x + c x², by Cramer's rule. */
    double A[3][3] = {{sx[0], sx[1], sx[2]}, {sx[1], sx[2], sx[3]}, {sx[2], sx[3], sx[4]}};
    double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                 A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
    double coef[3];
    for (int k = 0; k < 3; k++) {
        double B[3][3];
        memcpy(B, A, sizeof B);
        for (int r = 0; r < 3; r++)
            B[r][k] = sy[r];
        coef[k] = (B[0][0] * (B[1][1] * B[2][2] - B[1][2] * B[2][1]) - B[0][1] * (B[1][0] * B[2][2] - B[1][2] * B[2][0]) +
                   B[0][2] * (B[1][0] * B[2][1] - B[1][1] * B[2][0])) / det;
    }
    double ss = 0;
    for (int x = 0; x < w && x < 256; x++)
        if (used[x]) {
            double fit = coef[0] + coef[1] * x + coef[2] * x * x;
            ss += (m[x] - fit) * (m[x] - fit);
        }
    return sqrt(ss / cols) / (total / cols);
}

#define VCT_BAND_BOUND 0.12
static void turned_face_has_no_bands(void **state)
{
    (void)state;
    enum { W = 128 };
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = 64;
    gp.vct.trace_scale = 1;
    ImageF vct, none;
    test_render_gi(&s, W, W, GI_VCT, &gp, &vct);
    test_render_gi(&s, W, W, GI_NONE, NULL, &none);
    uint8_t *mask = malloc((size_t)W * W);
    assert_non_null(mask);
    int n = test_surface_mask(&s, W, W, "short_block", PT_FACE_NEG_Z, mask);
    double band = face_banding(&vct, &none, mask, W, W);
    print_message("short block's front face (%d px): column means of vct's indirect light vary by %.4f "
                  "(RMS about a quadratic, over their mean)\n", n, band);
    assert_true(n > 200);
    assert_true(band < VCT_BAND_BOUND);
    free(mask);
    image_free(&vct);
    image_free(&none);
    scene_free(&s);
}

/* ---- Sponza ---------------------------------------------------------------- */

/* The shipped scenes/sponza_nave.json (its volume: 256³, 0.12 m voxels,
 * voxelized by fragment centres, 6 cones) at 320×180 against the path
 * tracer's one bounce (64 spp at pixel centres): the indirect ratio of the
 * whole image within [0.8, 1.25], and every 16×9 block whose reference
 * bounce is above the median within the issue's [⅓, 3]. Measured 1.053,
 * blocks 0.340 .. 2.58 (seeds 2–4: 0.337 .. 0.348; 256 spp with jitter,
 * scripts/gi-regions.sh: 1.050, 0.343 .. 2.52): the lowest block is 3%
 * above the bound, which a 16-spp reference's noise (0.314 .. 0.392 over
 * four seeds) had crossed. The lowest blocks are the soffits of the arcades' arches (y =
 * 3 m, facing down), lit by the sunlit floor through the 0.75 m between
 * the arch and the curtain's rod below it (tests/vct_probe). Before issue
 * 44's fourth round (conservative voxelization: the rod and the curtain
 * a voxel fatter, and the cones' clearance over a surface's own voxels
 * 1 voxel, not ¾) the lowest block read 0.27 (at 160×90 0.23); with
 * fragment centres and the clearance of 1, 0.331; at 160×90 the same
 * code reads 0.31, hence 320×180. Before the cap and the lift asked the
 * same clearance (cone.glsl) the lift put the soffits' cones into the
 * curtain: blocks 0.02 .. 2.23 at 256³. --gi none reads 0. Skipped where
 * the asset is not present (as test_sponza.c). */
static void sponza_against_one_bounce(void **state)
{
    (void)state;
    test_skip_without_sponza();
    const char *file = test_sponza_file();
    enum { W = 320, H = 180 };
    Scene s;
    assert_true(scene_load(&s, file));
    assert_int_equal(s.settings.gi.vct.size, 256);
    double whole, lo, hi;
    assert_false(s.settings.gi.vct.conservative);
    test_one_bounce_regions(&s, GI_VCT, W, H, "Sponza vct", &whole, &lo, &hi);
    assert_true(whole > 0.8 && whole < 1.25);
    assert_true(lo > 1.0 / 3.0 && hi < 3.0);
    scene_free(&s);
}

/* ---- A closed box --------------------------------------------------------- */

/* Inside a closed white box (2 m, ρ = 0.5) with a point light off centre,
 * seen from inside: the indirect light vct adds to the direct image against
 * the one the path tracer's one-bounce adds to its direct light (the two
 * agree on direct light with a point light). Measured at 32³: mean
 * indirect ratio 0.849 (cones that started 2.5 voxels off the surface
 * missed the light of what is nearer), relMSE 0.0050 (no GI 0.0735). Bounds: the
 * ratio within 25%, relMSE under a fifth of no GI's. */
static void closed_box(void **state)
{
    (void)state;
    enum { W = 48 };
    Scene s;
    scene_init(&s);
    int white = scene_add_material(&s, "white", (vec3){0.5f, 0.5f, 0.5f});
    vec3 c[8];
    for (int i = 0; i < 8; i++) {
        c[i][0] = (i & 1) ? 1.f : -1.f;
        c[i][1] = (i & 2) ? 1.f : -1.f;
        c[i][2] = (i & 4) ? 1.f : -1.f;
    }
    /* Faces wound so that their normals point inwards. */
    static const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; f++)
        scene_add_quad(&s, white, c[faces[f][0]], c[faces[f][1]], c[faces[f][2]], c[faces[f][3]]);
    Light lamp = {.type = LIGHT_POINT, .position = {0.3f, 0.5f, -0.2f}, .color = {1.f, 1.f, 1.f}};
    scene_add_light(&s, &lamp);
    glm_vec3_copy((vec3){0.f, -0.2f, 0.9f}, s.camera.position);
    glm_vec3_copy((vec3){0.f, 0.f, -1.f}, s.camera.forward);
    glm_vec3_copy((vec3){0.f, 1.f, 0.f}, s.camera.up);
    s.camera.fov_y = glm_rad(90.f);
    s.camera.znear = 0.01f;
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = 32;
    ImageF vct, none, ob;
    test_render_gi(&s, W, W, GI_VCT, &gp, &vct);
    test_render_gi(&s, W, W, GI_NONE, NULL, &none);
    test_reference(&s, W, W, PT_ONE_BOUNCE, 256, &ob);
    double vi = test_image_mean(&vct) - test_image_mean(&none), ri = test_image_mean(&ob) - test_image_mean(&none);
    double v_ob = metric_relmse(&vct, &ob, NULL, NULL), n_ob = metric_relmse(&none, &ob, NULL, NULL);
    print_message("closed box: mean indirect vct %.5f, reference %.5f (ratio %.3f); relMSE vct %.4f, none %.4f\n",
                  vi, ri, vi / ri, v_ob, n_ob);
    assert_true(ri > 0);
    assert_true(fabs(vi / ri - 1) < 0.25);
    assert_true(v_ob < 0.2 * n_ob);
    image_free(&vct);
    image_free(&none);
    image_free(&ob);
    scene_free(&s);
}

/* ---- Directional volumes -------------------------------------------------- */

/* What a level-0 voxel (radiance × occupancy rgba, normal volume n with
 * the lit side in w) sends along axis direction dir: its radiance from its
 * lit side or edge-on, none from behind, a ramp between (aniso.comp,
 * seen_along). */
static void seen_along(const float *v, const float *n, const double dir[3], double out[4])
{
    double lum = 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
    double sigma = lum > 0 ? fmin(fmax(n[3] / lum, -1.0), 1.0) : 0.0;
    double f = 1.0 - 2.0 * sigma * (n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2]);
    f = fmin(fmax(f, 0.0), 1.0);
    for (int c = 0; c < 3; c++)
        out[c] = v[c] * f;
    out[3] = v[3];
}

/* (1 − e^(−βk)) / β, its limit k as β → 0. */
static double opacity_per_density(double beta, double t, double k) { return beta > 1e-6 ? (1 - t) / beta : k; }

/* Level 0 of each directional volume is aniso.comp's composite of the
 * isotropic level 0 in transmittance: a voxel of occupancy density β
 * passes t = e^(−β·VCT_OPTICAL_DEPTH), a pair of voxels along the axis
 * t_f·t_b and sends L_f(1 − t_f) + t_f·L_b(1 − t_b), the block the mean of
 * its four pairs, stored back as density β = −ln t̄ / (2·VCT_OPTICAL_DEPTH)
 * and radiance × β. For every voxel, axis and sign the GPU's value equals
 * the same sum on the CPU (within RGBA16F rounding), at a power-of-two N,
 * at one that is not (N = 24: the slabs are padded to 16 voxels deep) and
 * in each level of a clipmap. The two signs differ where a block holds
 * surfaces of two colours along the axis, or a surface lit on one side. */
static void check_directional(int n, int levels)
{
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = n;
    gp.vct.levels = levels;
    gp.vct.aniso = true;
    Renderer r;
    vct_renderer(&r, &s, 16, 16, &gp);
    renderer_frame(&r, &s.camera);
    size_t n3 = (size_t)n * n * n, m = (size_t)n / 2, m3 = m * m * m;
    float *iso = malloc(sizeof(float) * 4 * n3 * (size_t)levels), *dir = malloc(sizeof(float) * 4 * m3);
    float *nrm = malloc(sizeof(float) * 4 * n3 * (size_t)levels);
    assert_non_null(iso);
    assert_non_null(dir);
    assert_non_null(nrm);
    assert_true(vct_read_volume(r.gi_state, VCT_VOLUME_RADIANCE, iso));
    assert_true(vct_read_volume(r.gi_state, VCT_VOLUME_NORMAL, nrm));
    const double K = VCT_OPTICAL_DEPTH;
    int compared = 0, bad = 0, sided = 0;
    double worst = 0;
    for (int k = 0; k < levels; k++)
        for (int axis = 0; axis < 3; axis++) {
            float *plus = malloc(sizeof(float) * 4 * m3);
            assert_non_null(plus);
            for (int neg = 0; neg < 2; neg++) {
                float *out = neg ? dir : plus;
                assert_true(vct_read_directional(r.gi_state, axis, neg, k, out));
                for (int z = 0; z < (int)m; z++)
                    for (int y = 0; y < (int)m; y++)
                        for (int x = 0; x < (int)m; x++) {
                            int o[3] = {x, y, z}, ua = axis == 0 ? 1 : 0, wa = axis == 2 ? 1 : 2;
                            double dv[3] = {0, 0, 0}, t_sum = 0, c_sum[3] = {0, 0, 0}, want[4];
                            dv[axis] = neg ? -1 : 1;
                            for (int i = 0; i < 2; i++)
                                for (int j = 0; j < 2; j++) {
                                    int c0[3] = {2 * o[0], 2 * o[1], 2 * o[2]};
                                    c0[ua] += i;
                                    c0[wa] += j;
                                    int c1[3] = {c0[0], c0[1], c0[2]};
                                    c1[axis] += 1;
                                    const int *fc = neg ? c1 : c0, *bc = neg ? c0 : c1;
                                    size_t fi = 4 * (((size_t)(k * n + fc[2]) * n + fc[1]) * n + fc[0]);
                                    size_t bi = 4 * (((size_t)(k * n + bc[2]) * n + bc[1]) * n + bc[0]);
                                    double f[4], b[4];
                                    seen_along(iso + fi, nrm + fi, dv, f);
                                    seen_along(iso + bi, nrm + bi, dv, b);
                                    double tf = exp(-f[3] * K), tb = exp(-b[3] * K);
                                    for (int c = 0; c < 3; c++)
                                        c_sum[c] += f[c] * opacity_per_density(f[3], tf, K) +
                                                    tf * b[c] * opacity_per_density(b[3], tb, K);
                                    t_sum += tf * tb;
                                }
                            double t = fmax(0.25 * t_sum, 1e-30), beta = -log(t) / (2 * K);
                            for (int c = 0; c < 3; c++)
                                want[c] = t < 1 ? 0.25 * c_sum[c] * beta / (1 - t) : 0;
                            want[3] = beta;
                            const float *got = out + 4 * (((size_t)z * m + y) * m + x);
                            for (int c = 0; c < 4; c++) {
                                double e = fabs(got[c] - want[c]);
                                worst = fmax(worst, e / fmax(fabs(want[c]), 1e-3));
                                bad += e > 2e-3 * fabs(want[c]) + 1e-6;
                            }
                            compared++;
                            if (neg) {
                                const float *p = plus + 4 * (((size_t)z * m + y) * m + x);
                                double d = fabs(p[0] - got[0]) + fabs(p[1] - got[1]) + fabs(p[2] - got[2]);
                                sided += d > 0.1 * (p[0] + p[1] + p[2] + got[0] + got[1] + got[2]) && d > 1e-4;
                            }
                        }
            }
            free(plus);
        }
    print_message("directional level 0, N = %d, %d level(s): %d voxels compared, %d channels off, worst %.2g "
                  "relative; %d voxels whose two sides differ by > 10%%\n",
                  n, levels, compared, bad, worst, sided);
    assert_int_equal(bad, 0);
    assert_true(sided > 10);
    free(iso);
    free(nrm);
    free(dir);
    renderer_destroy(&r);
    scene_free(&s);
}

static void directional_volumes_composite(void **state)
{
    (void)state;
    check_directional(32, 1);
    check_directional(24, 1);
    check_directional(16, 2);
}

/* A cone reads the side of the directional volumes it faces: a wall of
 * two layers in neighbouring voxels, red facing -x, green facing +x, each lit
 * from its side, stands on a white floor. The floor left of it sees red,
 * right of it green; the isotropic mips blend the two layers into one
 * colour, so only the directional volumes give the left floor's (R - G)
 * and the right floor's (G - R) a clear sign. Reading the far side (the
 * signs swapped) turns both negative. */
static void cones_see_the_facing_side(void **state)
{
    (void)state;
    enum { W = 48 };
    Scene s;
    scene_init(&s);
    int white = scene_add_material(&s, "white", (vec3){0.8f, 0.8f, 0.8f});
    int red = scene_add_material(&s, "red", (vec3){0.9f, 0.05f, 0.05f});
    int green = scene_add_material(&s, "green", (vec3){0.05f, 0.9f, 0.05f});
    /* The grid: 32 voxels of 2/30 m from x = -16/15 m (gi_grid_around over
     * the floor's 2 m), so voxels 17 and 18 centre on x = 0.1 and 0.1667:
     * one block of mip 2, two of mip 1. */
    float xr = 0.1f, xg = 0.1f + 2.f / 30.f;
    scene_add_quad(&s, white, (vec3){-1.f, -0.5f, -1.f}, (vec3){-1.f, -0.5f, 1.f}, (vec3){1.f, -0.5f, 1.f},
                   (vec3){1.f, -0.5f, -1.f});
    scene_add_quad(&s, red, (vec3){xr, -0.5f, -0.6f}, (vec3){xr, 0.5f, -0.6f}, (vec3){xr, 0.5f, 0.6f},
                   (vec3){xr, -0.5f, 0.6f});
    scene_add_quad(&s, green, (vec3){xg, -0.5f, 0.6f}, (vec3){xg, 0.5f, 0.6f}, (vec3){xg, 0.5f, -0.6f},
                   (vec3){xg, -0.5f, -0.6f});
    Light left = {.type = LIGHT_POINT, .position = {-0.4f, 0.3f, 0.f}, .color = {1.f, 1.f, 1.f}};
    Light right = {.type = LIGHT_POINT, .position = {0.6f, 0.3f, 0.f}, .color = {1.f, 1.f, 1.f}};
    scene_add_light(&s, &left);
    scene_add_light(&s, &right);
    test_camera_down(&s.camera, (vec3){0.f, 2.f, 0.01f});
    s.camera.fov_y = glm_rad(60.f);
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = 32;
    double side[2][2]; /* [aniso][left/right]: mean (R − G) left, (G − R) right, over the floor's outer thirds */
    for (int a = 0; a < 2; a++) {
        gp.vct.aniso = a == 1;
        ImageF img;
        test_render_gi(&s, W, W, GI_VCT, &gp, &img);
        for (int half = 0; half < 2; half++) {
            double sum = 0;
            int count = 0;
            for (int y = W / 4; y < 3 * W / 4; y++)
                for (int x = half ? 2 * W / 3 : 0; x < (half ? W : W / 3); x++) {
                    const float *p = img.rgb + 3 * ((size_t)y * W + x);
                    sum += half ? p[1] - p[0] : p[0] - p[1];
                    count++;
                }
            side[a][half] = sum / count;
        }
        image_free(&img);
    }
    print_message("floor left of the wall (R - G) isotropic %.5f, directional %.5f; right (G - R) %.5f, %.5f\n",
                  side[0][0], side[1][0], side[0][1], side[1][1]);
    /* Measured: isotropic -0.00001 and 0.00015 (the mips blend the layers
     * to yellow), directional 0.0034 and 0.0199; with the signs swapped
     * -0.0034 and -0.0194. */
    assert_true(side[1][0] > side[0][0] + 0.001);
    assert_true(side[1][1] > side[0][1] + 0.005);
    scene_free(&s);
}

/* ---- The specular cone ---------------------------------------------------- */

/* With --vct-f0 > 0 every surface's cone takes F0 and roughness from the
 * settings. On the Cornell floor the specular image reflects the red wall
 * near it and the green wall near that one; the built-in box's materials
 * have F0 = 0 and leave the image black. */
static void specular_cone(void **state)
{
    (void)state;
    enum { W = 48 };
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = 32;
    gp.vct.f0 = 0.5f;
    gp.vct.roughness = 0.3f;
    Renderer r;
    vct_renderer(&r, &s, W, W, &gp);
    renderer_frame(&r, &s.camera);
    float *e = malloc(sizeof(float) * 4 * W * W);
    glGetTextureImage(r.specular, 0, GL_RGBA, GL_FLOAT, (GLsizei)(sizeof(float) * 4 * W * W), e);
    int x, y;
    test_project(&s, W, W, (vec3){0.45f, 0.f, 0.05f}, &x, &y);
    const float *red_side = &e[4 * ((W - 1 - y) * W + x)];
    test_project(&s, W, W, (vec3){0.10f, 0.f, 0.05f}, &x, &y);
    const float *green_side = &e[4 * ((W - 1 - y) * W + x)];
    double rr = red_side[0] / fmax(red_side[1], 1e-9), rg = green_side[0] / fmax(green_side[1], 1e-9);
    print_message("specular cone on the floor: R/G near the red wall %.3f, near the green wall %.3f\n", rr, rg);
    assert_true(red_side[0] > 0 && green_side[1] > 0);
    assert_true(rr > 1.5 * rg);
    renderer_destroy(&r);
    gp.vct.f0 = 0.f;
    vct_renderer(&r, &s, W, W, &gp);
    renderer_frame(&r, &s.camera);
    glGetTextureImage(r.specular, 0, GL_RGBA, GL_FLOAT, (GLsizei)(sizeof(float) * 4 * W * W), e);
    for (int i = 0; i < W * W; i++)
        assert_true(e[4 * i] == 0.f && e[4 * i + 1] == 0.f && e[4 * i + 2] == 0.f);
    renderer_destroy(&r);
    free(e);
    scene_free(&s);
}

/* ---- Glossy materials ------------------------------------------------------ */

/* R/G of what an image adds to `base` over a 5×5 window around world point p. */
static double added_red_over_green(const Scene *s, const ImageF *img, const ImageF *base, const vec3 p)
{
    int x, y;
    test_project(s, img->width, img->height, p, &x, &y);
    double r = test_mean(img, x, y, 2, 0) - test_mean(base, x, y, 2, 0);
    double g = test_mean(img, x, y, 2, 1) - test_mean(base, x, y, 2, 1);
    return r / fmax(g, 1e-9);
}

/* scenes/cornell_glossy.json (a glossy floor, a copper-like tall block):
 * the floor next to the red wall reflects it; the indirect light vct adds
 * there has the reference's colour ratio (the one-bounce reference's,
 * direct light removed), and vct beats no GI against that reference.
 * Diffuse colour bleeding alone also passes that floor check (the floor's
 * F0 is 0.04), so the test also takes the tall block: a metal, diffuse
 * albedo 0, so every bit of indirect light on it is the specular cone's.
 * On its front face (the camera's side) the light vct adds must be the
 * reference's (one-bounce minus direct) within 2×; no GI and a trace
 * without the specular cone add exactly 0 there.
 * Measured: floor (64², 32³) R/G vct 2.90, reference 3.40; metal face
 * (128², 64³, 35 points) added luminance vct 0.0148, reference 0.0111 (0
 * without the specular cone: checked with the cone zeroed in shade.glsl);
 * relMSE (64²) vct 0.0195, no GI 0.0338. */
static void glossy_cornell(void **state)
{
    (void)state;
    enum { W = 64 };
    Scene s;
    assert_true(scene_load(&s, RTGI_SOURCE_DIR "/scenes/cornell_glossy.json"));
    scene_rescale_lights(&s, 0.f);
    GiParams gp = s.settings.gi;
    gp.vct.size = 32;
    ImageF vct, none, ob;
    test_render_gi(&s, W, W, GI_VCT, &gp, &vct);
    test_render_gi(&s, W, W, GI_NONE, NULL, &none);
    test_reference(&s, W, W, PT_ONE_BOUNCE, 512, &ob);
    const vec3 floor_red = {0.45f, 0.f, 0.1f};
    double v = added_red_over_green(&s, &vct, &none, floor_red), r = added_red_over_green(&s, &ob, &none, floor_red);
    double v_ob = metric_relmse(&vct, &ob, NULL, NULL), n_ob = metric_relmse(&none, &ob, NULL, NULL);
    print_message("cornell_glossy: floor by the red wall, added R/G vct %.3f reference %.3f; relMSE vs one-bounce "
                  "vct %.4f none %.4f\n",
                  v, r, v_ob, n_ob);
    assert_true(r > 1.2 && v > 1.2);
    assert_true(v > r / 1.5 && v < r * 1.5);
    assert_true(v_ob < n_ob);
    /* The metal block's front face, from (265, 296) to (423, 247) mm, outward
     * normal (-0.296, 0, -0.955): the light added at 35 points spread over
     * it (5 across × 7 up, 3 mm off the face), at 128² with 64³ voxels (a
     * metal face's reflection is a few pixels of a 64² image and blurred
     * by 32³ voxels: 0.5-1.9× the reference there). */
    enum { WM = 128 };
    GiParams gm = s.settings.gi;
    gm.vct.size = 64;
    ImageF mv, mn, mob, md;
    test_render_gi(&s, WM, WM, GI_VCT, &gm, &mv);
    test_render_gi(&s, WM, WM, GI_NONE, NULL, &mn);
    test_reference(&s, WM, WM, PT_ONE_BOUNCE, 256, &mob);
    test_reference(&s, WM, WM, PT_DIRECT, 64, &md);
    double metal_v = 0, metal_r = 0;
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 7; j++) {
            float u = 0.15f + 0.175f * (float)i, h = 0.33f * (0.1f + 0.8f * (float)j / 6.f);
            const vec3 p = {0.265f + u * 0.158f - 0.003f * 0.296f, h, 0.296f - u * 0.049f - 0.003f * 0.955f};
            int x, y;
            test_project(&s, WM, WM, p, &x, &y);
            metal_v += test_mean(&mv, x, y, 0, 3) - test_mean(&mn, x, y, 0, 3);
            metal_r += test_mean(&mob, x, y, 0, 3) - test_mean(&md, x, y, 0, 3);
        }
    print_message("cornell_glossy: metal block face, added luminance vct %.4f reference %.4f\n", metal_v / 35,
                  metal_r / 35);
    assert_true(metal_r > 0.002 * 35);
    assert_true(metal_v > metal_r / 2 && metal_v < metal_r * 2);
    image_free(&mv);
    image_free(&mn);
    image_free(&mob);
    image_free(&md);
    image_free(&vct);
    image_free(&none);
    image_free(&ob);
    scene_free(&s);
}

/* ---- Ambient occlusion -------------------------------------------------- */

/* Ambient visibility (the irradiance image's alpha) is in [0, 1], lower in
 * the Cornell box's floor corner than in the middle of its floor; 1 (to
 * 1e-6) with --vct-ao off. */
static void ambient_occlusion(void **state)
{
    (void)state;
    enum { W = 48 };
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.vct.size = 32;
    Renderer r;
    vct_renderer(&r, &s, W, W, &gp);
    renderer_frame(&r, &s.camera);
    float *e = malloc(sizeof(float) * 4 * W * W);
    glGetTextureImage(r.irradiance, 0, GL_RGBA, GL_FLOAT, (GLsizei)(sizeof(float) * 4 * W * W), e);
    int x, y;
    test_project(&s, W, W, (vec3){0.278f, 0.f, 0.05f}, &x, &y);
    double middle = e[4 * ((W - 1 - y) * W + x) + 3];
    test_project(&s, W, W, (vec3){0.545f, 0.003f, 0.55f}, &x, &y);
    double corner = e[4 * ((W - 1 - y) * W + x) + 3];
    double lo = 1, hi = 0;
    for (int i = 0; i < W * W; i++) {
        lo = fmin(lo, e[4 * i + 3]);
        hi = fmax(hi, e[4 * i + 3]);
    }
    print_message("ambient visibility: floor front %.3f, back corner %.3f, range [%.3f, %.3f]\n", middle, corner, lo,
                  hi);
    assert_true(lo >= 0 && hi <= 1);
    assert_true(corner < middle - 0.05);
    renderer_destroy(&r);
    gp.vct.ao = false;
    vct_renderer(&r, &s, W, W, &gp);
    renderer_frame(&r, &s.camera);
    glGetTextureImage(r.irradiance, 0, GL_RGBA, GL_FLOAT, (GLsizei)(sizeof(float) * 4 * W * W), e);
    /* 1 to the division's precision: the upsampling's weighted mean of
     * 1s (Σw·1 / Σw) is 1 exactly on llvmpipe, 1 − 6e-8 on NVIDIA's
     * approximate division. */
    for (int i = 0; i < W * W; i++)
        assert_true(fabsf(e[4 * i + 3] - 1.f) <= 1e-6f);
    renderer_destroy(&r);
    free(e);
    scene_free(&s);
}

/* `render --out-ao FILE.pfm`: the ambient visibility as a grey image in
 * [0, 1], darker than open sky on average (the box's corners and edges);
 * with --vct-ao off, or another technique, there is none to write: exit 2,
 * one line, nothing written. */
static void out_ao_cli(void **state)
{
    (void)state;
    char img[512], ao[512];
    snprintf(img, sizeof img, "%s/vct_ao_render.pfm", RTGI_TEST_TMP);
    snprintf(ao, sizeof ao, "%s/vct_ao.pfm", RTGI_TEST_TMP);
    remove(ao);
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--gi", "vct", "--vct-size", "16", "--size", "32x32", "--out", img,
                          "--out-ao", ao, "--quiet", NULL);
    if (rc != 0)
        fail_msg("render --out-ao: exit %d: %s", rc, err ? err : "");
    free(err);
    ImageF a;
    assert_true(image_read(ao, &a));
    assert_int_equal(a.width, 32);
    assert_int_equal(a.height, 32);
    double lo = 1, hi = 0, mean = 0;
    for (int i = 0; i < 3 * a.width * a.height; i++) {
        lo = fmin(lo, a.rgb[i]);
        hi = fmax(hi, a.rgb[i]);
        mean += a.rgb[i];
    }
    mean /= 3.0 * a.width * a.height;
    print_message("render --out-ao (Cornell, 32x32, 16^3): ambient visibility in [%.3f, %.3f], mean %.3f\n", lo, hi,
                  mean);
    assert_true(lo >= 0 && hi <= 1);
    assert_true(mean < 0.95);
    image_free(&a);
    remove(ao);
    rc = test_run_cli(&err, "render", "--gi", "vct", "--vct-ao", "off", "--size", "8x8", "--out", img, "--out-ao",
                      ao, NULL);
    test_expect_cli_error(rc, err, 2, "--out-ao", "--vct-ao on");
    rc = test_run_cli(&err, "render", "--gi", "rsm", "--size", "8x8", "--out", img, "--out-ao", ao, NULL);
    test_expect_cli_error(rc, err, 2, "--out-ao", "--gi vct");
    assert_int_not_equal(access(ao, F_OK), 0);
}

/* ---- render --timings ------------------------------------------------------ */

/* The GPU memory (MiB) the volumes and low-resolution images take for
 * these settings: RGBA16F (8 bytes) albedo and normal volumes of N³ per
 * clipmap level, radiance with its mip chain (two with a second bounce),
 * with --vct-aniso six directional volumes of (N/2)³ and their chains (three
 * textures of both signs; N a power of two, as here: no padding), and
 * two RGBA32F images of ⌈w/s⌉ × ⌈h/s⌉ at --vct-trace-scale s > 1, the
 * opaque-voxel list (a count, an indirect dispatch and N³·L/8 entries),
 * the voxelization's sums (8 uints a voxel) and, voxelizing in compute, its
 * work buffer on `s` (4 words per submesh and 1 per triangle, per level). */
static double vct_memory_mib(int n, int levels, bool aniso, int bounces, int w, int h, int scale, const Scene *s)
{
    double chain = 0, half_chain = 0;
    for (int k = n; k >= 1; k /= 2)
        chain += (double)k * k * k;
    for (int k = n / 2; k >= 1; k /= 2)
        half_chain += (double)k * k * k;
    /* With the directional volumes the isotropic radiance is level 0 alone. */
    double radiance = aniso ? (double)n * n * n : chain;
    double voxels = levels * (2.0 * n * n * n + bounces * radiance + (aniso ? 6 * half_chain : 0));
    double low = scale > 1 ? 2.0 * 16 * ((w + scale - 1) / scale) * ((h + scale - 1) / scale) : 0;
    double opaque = 4.0 * (4 + levels * n * n * n / VCT_OPAQUE_SHARE); /* the opaque-voxel list */
    double sums = 32.0 * levels * n * n * n;
    double work = s->settings.gi.vct.voxelize == VCT_VOXELIZE_COMPUTE
                      ? 4.0 * levels * (4.0 * s->submesh_count + (double)(s->index_count / 3))
                      : 0;
    return (8 * voxels + low + opaque + sums + work + sizeof(GpuVctParams)) / (1024.0 * 1024.0); /* and its UBO */
}

/* The row of pass `name` in the --timings table: its GPU and wall ms and
 * whether it is marked once; false if there is none. */
static bool timings_row(const char *out, const char *name, double *gpu, double *wall, bool *once)
{
    char key[64];
    snprintf(key, sizeof key, "\n  %s ", name);
    const char *p = strstr(out, key);
    if (!p)
        return false;
    int end = 0;
    if (sscanf(p + strlen(key), "%lf %lf%n", gpu, wall, &end) != 2)
        return false;
    *once = strncmp(p + strlen(key) + end, "  once\n", 7) == 0;
    return true;
}

/* `render --gi vct --vct-size 16 --size 32x32 --timings` (Cornell box):
 * rows for vct_inject, vct_mips and vct_trace (means of the timed frames),
 * and for vct_voxelize, which ran in the warm-up frame, marked once, its
 * wall ms that of vct_voxelize_wall_ms and not in the total; and
 * gi_memory_mib as the settings call for, with and without --vct-aniso,
 * with two bounces and with a 2-level clipmap. */
static void timings_and_memory_cli(void **state)
{
    (void)state;
    static const struct {
        const char *opt, *val;
        int levels, bounces;
        bool aniso;
    } runs[] = {
        {"--vct-aniso", "on", 1, 1, true},
        {"--vct-aniso", "off", 1, 1, false},
        {"--vct-bounces", "2", 1, 2, true},
        {"--vct-levels", "2", 2, 1, true},
    };
    char img[512];
    snprintf(img, sizeof img, "%s/vct_timings.pfm", RTGI_TEST_TMP);
    Scene cornell; /* what `render` draws: its triangles size the compute voxelization's work buffer */
    scene_build_cornell(&cornell);
    scene_finalize(&cornell);
    for (size_t k = 0; k < sizeof runs / sizeof runs[0]; k++) {
        char *out = NULL, *err = NULL;
        int rc = test_run_cli_out(&out, &err, "render", "--gi", "vct", "--vct-size", "16", "--size", "32x32",
                                  runs[k].opt, runs[k].val, "--timings", "--out", img, "--quiet", NULL);
        if (rc != 0)
            fail_msg("render --timings %s %s: exit %d: %s", runs[k].opt, runs[k].val, rc, err ? err : "");
        free(err);
        assert_non_null(out);
        double mib = -1, want = vct_memory_mib(16, runs[k].levels, runs[k].aniso, runs[k].bounces, 32, 32, 2, &cornell);
        const char *m = strstr(out, "\ngi_memory_mib: ");
        assert_non_null(m);
        assert_int_equal(sscanf(m, "\ngi_memory_mib: %lf", &mib), 1);
        print_message("render --timings %s %s: gi_memory_mib %.3f, computed from the settings %.4f\n", runs[k].opt,
                      runs[k].val, mib, want);
        assert_true(mib > 0 && fabs(mib - want) < 0.0006);
        if (k == 0) {
            static const char *const passes[] = {"vct_inject", "vct_mips", "vct_trace"};
            double gpu, wall, sum = 0, total_gpu, total_wall, vox_gpu, vox_wall, wall_ms = -1;
            bool once;
            for (int i = 0; i < 3; i++) {
                if (!timings_row(out, passes[i], &gpu, &wall, &once))
                    fail_msg("render --timings: no %s row in\n%s", passes[i], out);
                assert_true(gpu > 0 && wall > 0 && !once);
            }
            assert_true(timings_row(out, "total", &total_gpu, &total_wall, &once) && !once);
            if (!timings_row(out, "vct_voxelize", &vox_gpu, &vox_wall, &once) || !once)
                fail_msg("render --timings: no vct_voxelize row marked once in\n%s", out);
            m = strstr(out, "\nvct_voxelize_wall_ms: ");
            assert_non_null(m);
            assert_int_equal(sscanf(m, "\nvct_voxelize_wall_ms: %lf", &wall_ms), 1);
            /* The rows down to the total add up to it without the once row. */
            const char *row = strstr(out, "\n  pass ");
            assert_non_null(row);
            for (row = strchr(row + 1, '\n'); row && strncmp(row, "\n  total ", 9); row = strchr(row + 1, '\n')) {
                char name[64];
                if (sscanf(row, " %63s %lf", name, &gpu) == 2)
                    sum += gpu;
            }
            print_message("render --timings: vct_voxelize once %.3f GPU ms, %.3f wall ms (vct_voxelize_wall_ms %.3f); "
                          "the rows sum to %.3f GPU ms, total %.3f\n",
                          vox_gpu, vox_wall, wall_ms, sum, total_gpu);
            assert_true(vox_gpu > 0 && wall_ms > 0 && vox_wall >= wall_ms);
            assert_true(fabs(sum - total_gpu) < 0.01);
        }
        free(out);
    }
    scene_free(&cornell);
}

/* ---- Bad settings ------------------------------------------------------- */

static void bad_vct_settings(void **state)
{
    (void)state;
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--gi", "vct", "--vct-size", "4", NULL);
    test_expect_cli_error(rc, err, 2, "--vct-size", NULL);
    rc = test_run_cli(&err, "render", "--gi", "vct", "--vct-cones", "7", NULL);
    test_expect_cli_error(rc, err, 2, "--vct-cones", "6, 9, 16");
    rc = test_run_cli(&err, "render", "--gi", "vct", "--vct-bounces", "3", NULL);
    test_expect_cli_error(rc, err, 2, "--vct-bounces", NULL);
    rc = test_run_cli(&err, "render", "--gi", "vct", "--vct-step", "0", NULL);
    test_expect_cli_error(rc, err, 2, "--vct-step", NULL);
    rc = test_run_cli(&err, "render", "--gi", "vct", "--vct-trace-scale", "5", NULL);
    test_expect_cli_error(rc, err, 2, "--vct-trace-scale", NULL);
    rc = test_run_cli(&err, "render", "--gi", "vct", "--vct-levels", "5", NULL);
    test_expect_cli_error(rc, err, 2, "--vct-levels", NULL);
    rc = test_run_cli(&err, "render", "--size", "8x8", "--gi", "vct", "--vct-levels", "2", "--vct-size", "24", NULL);
    test_expect_cli_error(rc, err, 1, "--vct-levels", "power-of-two");
    rc = test_run_cli(&err, "render", "--gi", "vct", "--vct-aniso", "maybe", NULL);
    test_expect_cli_error(rc, err, 2, "--vct-aniso", NULL);
    const char *path = test_tmp_file("badvct.json", "{ \"builtin\": \"cornell\", \"gi\": { \"vct_cones\": 7 } }\n");
    rc = test_run_cli(&err, "render", "--scene", path, NULL);
    test_expect_cli_error(rc, err, 1, "badvct.json", "gi.vct_cones");
    /* A number that names a choice is accepted in the scene file. */
    path = test_tmp_file("goodvct.json", "{ \"builtin\": \"cornell\", \"gi\": { \"vct_cones\": 9 } }\n");
    Scene s;
    assert_true(scene_load(&s, path));
    assert_int_equal(s.settings.gi.vct.cones, VCT_CONES_9);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(voxelization_is_watertight),
        cmocka_unit_test(floors_on_voxel_boundaries),
        cmocka_unit_test(injection_matches_lambert),
        cmocka_unit_test(injection_covers_the_opaque_voxels),
        cmocka_unit_test(voxelizes_once),
        cmocka_unit_test(alpha_masked_texels_are_skipped),
        cmocka_unit_test(compute_equals_raster),
        cmocka_unit_test(moved_object_revoxelizes),
        cmocka_unit_test(clipmap_follows_the_camera),
        cmocka_unit_test(cornell_against_reference),
        cmocka_unit_test(directional_volumes_composite),
        cmocka_unit_test(cones_see_the_facing_side),
        cmocka_unit_test(cone_weights_integrate_the_cosine_lobe),
        cmocka_unit_test(thin_wall_stops_cones),
        cmocka_unit_test(surfaces_do_not_light_themselves),
        cmocka_unit_test(turned_face_has_no_bands),
        cmocka_unit_test(closed_box),
        cmocka_unit_test(sponza_against_one_bounce),
        cmocka_unit_test(specular_cone),
        cmocka_unit_test(glossy_cornell),
        cmocka_unit_test(ambient_occlusion),
        cmocka_unit_test(out_ao_cli),
        cmocka_unit_test(timings_and_memory_cli),
        cmocka_unit_test(bad_vct_settings),
    };
    return cmocka_run_group_tests_name("vct", tests, test_gl_setup, test_gl_teardown);
}
