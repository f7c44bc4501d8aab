/* test_lpv.c — light propagation volumes (SPEC §5) on llvmpipe at small
 * grids: flux conservation of the injection, one VPL in empty space
 * against Φ/(π d²), occlusion by a wall of cells, the Cornell box against
 * the path tracer's one-bounce references, the leak scene, bad settings. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"
#include "gi/lpv/lpv.h"
#include "metrics.h"
#include "reference/pathtracer.h"

#define LPV_CORNELL_BOUND 0.031 /* relMSE; see cornell_against_reference */
#define SH_NORM 3.5449077018 /* ∫ Y00 dω / Y00² = 2√π: flux of an SH intensity = c00 · 2√π */

/* A renderer with `--gi lpv` and hard shadows on `s`. */
static void lpv_renderer(Renderer *r, const Scene *s, int w, int h, const GiParams *gp)
{
    RenderSettings rs = test_settings(s, w, h, SHADOW_MODE_HARD);
    rs.gi = GI_LPV;
    rs.gi_params = gp ? *gp : s->gi;
    assert_true(renderer_create(r, s, &rs));
}

/* The technique's irradiance image (RGBA32F), row 0 = bottom. Caller frees. */
static float *read_irradiance(const Renderer *r)
{
    int w = r->settings.width, h = r->settings.height;
    float *e = malloc(sizeof(float) * 4 * (size_t)w * (size_t)h);
    assert_non_null(e);
    glGetTextureImage(r->irradiance, 0, GL_RGBA, GL_FLOAT, (GLsizei)(sizeof(float) * 4 * (size_t)w * (size_t)h), e);
    return e;
}

/* Irradiance (channel c) at the pixel of world point p in the scene camera's view. */
static double irradiance_at(const Renderer *r, const float *e, const vec3 p, int c)
{
    int x, y, w = r->settings.width, h = r->settings.height;
    test_project(r->scene, w, h, p, &x, &y);
    return e[4 * ((size_t)(h - 1 - y) * (size_t)w + (size_t)x) + (size_t)c];
}

/* ---- Injection conserves flux ------------------------------------------ */

/* Both injections (compute with fixed-point atomics, points with
 * blending): the grid's flux, Σ c00 · 2√π over the cells, is the VPLs'.
 * `out_volume` gets the accumulated volume after one step. */
static void check_injected_flux(LpvInject method, float *out_volume)
{
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    GiParams gp = s.gi;
    gp.rsm_size = 32;
    gp.lpv_size = 16;
    gp.lpv_iterations = 1;
    gp.lpv_inject = method;
    Renderer r;
    lpv_renderer(&r, &s, 32, 32, &gp);
    renderer_frame(&r, &s.camera);
    /* The RSM's flux: the VPL buffer (every lit texel). */
    uint32_t count = light_stage_vpl_count(&r.lights);
    GpuVpl *v = malloc(sizeof *v * count);
    glGetNamedBufferSubData(r.lights.vpls.vpls, 0, (GLsizeiptr)(sizeof *v * count), v);
    double rsm[3] = {0, 0, 0}, grid[3] = {0, 0, 0};
    for (uint32_t i = 0; i < count; i++)
        for (int c = 0; c < 3; c++)
            rsm[c] += v[i].flux[c];
    int n = lpv_grid_size(r.gi_state);
    size_t n3 = (size_t)n * n * n;
    float *vol = malloc(sizeof(float) * 12 * n3);
    assert_true(lpv_read_volume(r.gi_state, 0, LPV_VOLUME_INJECTED, vol));
    for (int c = 0; c < 3; c++)
        for (size_t i = 0; i < n3; i++)
            grid[c] += vol[(c * n3 + i) * 4] * SH_NORM;
    print_message("flux (%s injection): RSM %.6g %.6g %.6g W (%u VPLs), grid %.6g %.6g %.6g W\n",
                  method == LPV_INJECT_COMPUTE ? "compute" : "points", rsm[0], rsm[1], rsm[2], count, grid[0], grid[1],
                  grid[2]);
    for (int c = 0; c < 3; c++) {
        assert_true(rsm[c] > 0);
        assert_true(fabs(grid[c] - rsm[c]) < 0.01 * rsm[c]);
    }
    /* After a step through the geometry volume, for the comparison. */
    assert_true(lpv_read_volume(r.gi_state, 0, LPV_VOLUME_ACCUMULATED, out_volume));
    free(vol);
    free(v);
    renderer_destroy(&r);
    scene_free(&s);
}

static void injection_conserves_flux(void **state)
{
    (void)state;
    enum { N3 = 16 * 16 * 16 };
    float *a = malloc(sizeof(float) * 12 * N3), *b = malloc(sizeof(float) * 12 * N3);
    check_injected_flux(LPV_INJECT_COMPUTE, a);
    check_injected_flux(LPV_INJECT_POINTS, b);
    /* The two agree cell by cell, to the fixed point's resolution, after a
     * propagation step (which reads the geometry volume both also make). */
    double diff = 0, norm = 0;
    for (int i = 0; i < 12 * N3; i++) {
        diff += fabs(a[i] - b[i]);
        norm += fabs(b[i]);
    }
    print_message("compute vs points: relative L1 difference %.3g\n", diff / norm);
    assert_true(diff < 1e-4 * norm);
    free(a);
    free(b);
}

/* ---- One propagation step against the CPU ------------------------------ */

/* Solid angle of the triangle (a, b, c) seen from the origin (Van
 * Oosterom & Strackee 1983). */
static double triangle_solid_angle(const double a[3], const double b[3], const double c[3])
{
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]),
           lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double bxc[3] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]};
    double num = fabs(a[0] * bxc[0] + a[1] * bxc[1] + a[2] * bxc[2]);
    double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2], ac = a[0] * c[0] + a[1] * c[1] + a[2] * c[2],
           bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
    return 2.0 * atan2(num, la * lb * lc + ab * lc + ac * lb + bc * la);
}

/* A face of the cell next to a neighbour, seen from the neighbour's centre
 * (cells of unit size, the light travelling along +ax): its centre and its
 * solid angle. side = 0: the far face; ±1: the side face towards that sign
 * of axis s_ax. */
static double face_solid_angle(int ax, int s_ax, int side, double centre[3])
{
    int normal = side == 0 ? ax : s_ax;                   /* the axis the face is normal to */
    int a1 = side == 0 ? (ax + 1) % 3 : ax, a2 = 3 - normal - a1; /* its in-plane axes */
    for (int k = 0; k < 3; k++)
        centre[k] = 0.0;
    centre[ax] = side == 0 ? 1.5 : 1.0;
    if (side != 0)
        centre[s_ax] = 0.5 * side;
    double corner[4][3];
    for (int i = 0; i < 4; i++) {
        for (int k = 0; k < 3; k++)
            corner[i][k] = centre[k];
        corner[i][a1] += (i == 0 || i == 3) ? -0.5 : 0.5;
        corner[i][a2] += i < 2 ? -0.5 : 0.5;
    }
    return triangle_solid_angle(corner[0], corner[1], corner[2]) + triangle_solid_angle(corner[0], corner[2], corner[3]);
}

/* One step of §3.3 on the CPU, in doubles, written from the paper: cell c
 * gathers from each face neighbour src = c − e the flux its intensity
 * (2-band SH) sends through the 5 faces of c other than the shared one,
 * Δω_f · max(0, I(ω_f)), attenuated by the geometry volume's blocking
 * B(ω) = ωᵀ T ω (T the normal tensor, averaged over the shared face's 4
 * corner texels, clamped to [0, 1]) and re-emitted as the clamped-cosine
 * lobe of the face's outward normal, over π. inj: 3·N³ SH; gv: the
 * geometry readback; out: 3·N³ SH. */
static void cpu_step(int n, const float *inj, const float *gv, bool occlusion, double *out)
{
    const double C0 = 0.282094792, C1 = 0.488602512, COS0 = 0.886226925, COS1 = 1.023326708;
    size_t n3 = (size_t)n * n * n, g = (size_t)n + 1, g3 = g * g * g;
    for (size_t i = 0; i < 12 * n3; i++)
        out[i] = 0.0;
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++) {
                int c[3] = {x, y, z};
                size_t ci = ((size_t)z * n + y) * n + x;
                for (int ax = 0; ax < 3; ax++)
                    for (int sgn = -1; sgn <= 1; sgn += 2) {
                        int src[3] = {x, y, z};
                        src[ax] -= sgn;
                        if (src[ax] < 0 || src[ax] >= n)
                            continue;
                        size_t si = ((size_t)src[2] * n + src[1]) * n + src[0];
                        /* The shared face's tensor: the corner plane between src and c. */
                        double t6[6] = {0, 0, 0, 0, 0, 0};
                        for (int k = 0; k < 4; k++) {
                            int q[3] = {c[0], c[1], c[2]};
                            q[ax] = sgn > 0 ? c[ax] : c[ax] + 1;
                            q[(ax + 1) % 3] += k & 1;
                            q[(ax + 2) % 3] += k >> 1;
                            size_t gi = ((size_t)q[2] * g + q[1]) * g + q[0];
                            for (int j = 0; j < 3; j++) {
                                t6[j] += 0.25 * gv[gi * 4 + j];
                                t6[3 + j] += 0.25 * gv[(g3 + gi) * 4 + j];
                            }
                        }
                        for (int f = 0; f < 5; f++) {
                            int s_ax = f == 0 ? ax : (ax + 1 + (f - 1) / 2) % 3, side = f == 0 ? 0 : (f & 1 ? 1 : -1);
                            double centre[3], dw = face_solid_angle(ax, s_ax, side, centre);
                            /* Into world axes: the face was built for travel along +ax. */
                            double w[3] = {centre[0], centre[1], centre[2]}, nf[3] = {0, 0, 0};
                            w[ax] *= sgn;
                            double len = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
                            for (int k = 0; k < 3; k++)
                                w[k] /= len;
                            if (f == 0)
                                nf[ax] = sgn;
                            else
                                nf[s_ax] = side;
                            double block = w[0] * w[0] * t6[0] + w[1] * w[1] * t6[1] + w[2] * w[2] * t6[2] +
                                           2.0 * (w[0] * w[1] * t6[3] + w[0] * w[2] * t6[4] + w[1] * w[2] * t6[5]);
                            block = occlusion ? fmin(fmax(block, 0.0), 1.0) : 0.0;
                            double k_face = dw * (1.0 - block) / GLM_PI;
                            for (int ch = 0; ch < 3; ch++) {
                                const float *sh = inj + (ch * n3 + si) * 4;
                                double in = sh[0] * C0 + C1 * (sh[1] * w[0] + sh[2] * w[1] + sh[3] * w[2]);
                                double flux = fmax(0.0, in) * k_face;
                                double *o = out + (ch * n3 + ci) * 4;
                                o[0] += flux * COS0;
                                for (int k = 0; k < 3; k++)
                                    o[1 + k] += flux * COS1 * nf[k];
                            }
                        }
                    }
            }
}

/* The Cornell box (12³ cells, one step): the accumulated volume is the
 * injected one plus one step, which must equal cpu_step on the read-back
 * injected and geometry volumes, with occlusion and without. The faces'
 * solid angles come from the exact formula here, the GPU's are constants;
 * they sum to 4π/6 per neighbour. */
static void propagation_step_matches_cpu(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    double c0[3], sum = 0.0;
    sum += face_solid_angle(0, 0, 0, c0);
    for (int f = 1; f < 5; f++)
        sum += face_solid_angle(0, 1 + (f - 1) / 2, f & 1 ? 1 : -1, c0);
    assert_true(fabs(sum - 4.0 * GLM_PI / 6.0) < 1e-9);
    for (int occ = 0; occ < 2; occ++) {
        GiParams gp = s.gi;
        gp.rsm_size = 32;
        gp.lpv_size = 12;
        gp.lpv_iterations = 1;
        gp.lpv_occlusion = occ == 1;
        Renderer r;
        lpv_renderer(&r, &s, 32, 32, &gp);
        renderer_frame(&r, &s.camera);
        int n = lpv_grid_size(r.gi_state);
        size_t n3 = (size_t)n * n * n, g3 = (size_t)(n + 1) * (n + 1) * (n + 1);
        float *inj = malloc(sizeof(float) * 12 * n3), *acc = malloc(sizeof(float) * 12 * n3),
              *gv = malloc(sizeof(float) * 8 * g3);
        double *step = malloc(sizeof(double) * 12 * n3);
        assert_true(inj && acc && gv && step);
        assert_true(lpv_read_volume(r.gi_state, 0, LPV_VOLUME_INJECTED, inj));
        assert_true(lpv_read_volume(r.gi_state, 0, LPV_VOLUME_ACCUMULATED, acc));
        assert_true(lpv_read_geometry(r.gi_state, 0, gv));
        cpu_step(n, inj, gv, gp.lpv_occlusion, step);
        double scale = 0.0, err = 0.0, moved = 0.0, blocked = 0.0;
        for (size_t i = 0; i < 12 * n3; i++) {
            scale = fmax(scale, fmax(fabs(step[i]), fabs(acc[i])));
            moved += fabs(step[i]);
        }
        for (size_t i = 0; i < 12 * n3; i++)
            err = fmax(err, fabs((double)acc[i] - (double)inj[i] - step[i]));
        /* How much the geometry holds back: the step without it, less. */
        if (gp.lpv_occlusion) {
            cpu_step(n, inj, gv, false, step);
            double open = 0.0;
            for (size_t i = 0; i < 12 * n3; i++)
                open += fabs(step[i]);
            blocked = 1.0 - moved / open;
        }
        print_message("one step, occlusion %s: max |GPU - CPU| = %.3g of the largest value %.4g; geometry holds back "
                      "%.1f%%\n",
                      occ ? "on" : "off", err, scale, 100.0 * blocked);
        assert_true(scale > 0.0);
        assert_true(err < 1e-6 * scale);
        if (gp.lpv_occlusion)
            assert_true(blocked > 0.02); /* the walls are in the volume (measured 3.5%): the comparison sees them */
        free(inj);
        free(acc);
        free(gv);
        free(step);
        renderer_destroy(&r);
    }
    scene_free(&s);
}

/* ---- One VPL in empty space -------------------------------------------- */

/* A 2 m floor (y = 0, the receiver), a tiny square at y = 1 that sets the
 * bounds' height, a faint sun (the light stage needs a light; its VPLs are
 * replaced), a camera looking down. Grid N = 16: cells of 2/14 m. An
 * optional horizontal wall at y = 0.52 across the whole floor. */
static void open_scene(Scene *s, bool wall, float camera_height)
{
    scene_init(s);
    int white = scene_add_material(s, "white", (vec3){0.5f, 0.5f, 0.5f});
    test_add_square(s, white, (vec3){0.f, 0.f, 0.f}, 2.f);
    test_add_square(s, white, (vec3){0.95f, 1.f, 0.95f}, 0.05f);
    if (wall)
        test_add_square(s, white, (vec3){0.f, 0.52f, 0.f}, 2.f);
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0.f, -1.f, 0.f}, .color = {0.01f, 0.01f, 0.01f}};
    scene_add_light(s, &sun);
    glm_vec3_copy((vec3){0.001f, camera_height, 0.002f}, s->camera.position);
    glm_vec3_copy((vec3){0, -1, 0}, s->camera.forward);
    glm_vec3_copy((vec3){0, 0, -1}, s->camera.up);
    s->camera.fov_y = glm_rad(camera_height < 1.f ? 90.f : 45.f);
    s->camera.znear = 0.01f;
    scene_finalize(s);
    s->gi.rsm_size = 64;
    s->gi.lpv_size = 16;
}

/* One VPL (normal down, flux Φ = 1 W) at height h above the floor of
 * open_scene, injected through the test hook; one frame. */
static float *render_one_vpl(Renderer *r, const Scene *s, const GiParams *gp, int w, const vec3 p)
{
    lpv_renderer(r, s, w, w, gp);
    GpuVpl v = {.surface = {0u, 0u, 0u, 32768u}, /* octahedral (0, -1, 0) */
                .flux = {1.f, 1.f, 1.f, 0.f},
                .normal_xi = {0.f, -1.f, 0.f, 0.5f}};
    gpu_vpl_set_position(&v, p);
    lpv_set_vpls(r->gi_state, &v, 1);
    renderer_frame(r, &s->camera);
    return read_irradiance(r);
}

/* The exact irradiance from a VPL of flux 1 W with normal −y at p on the
 * floor point x: Φ/π · cosθ_vpl · cosθ_floor / d² = h² / (π d⁴). */
static double exact_e(const vec3 p, const vec3 x)
{
    double h = p[1] - x[1], d2 = glm_vec3_distance2((float *)p, (float *)x);
    return h * h / (GLM_PI * d2 * d2);
}

/* LPV smears. The paper's reprojection sends the flux that enters a cell
 * through its 4 side faces out again as sideways lobes, and the 2-band
 * lobe of a VPL or a face already sends a quarter of its peak intensity at
 * 90° (the true cosine sends none): a beam widens at every step, so the
 * irradiance right below the VPL falls faster than 1/d². Measured on a 16³
 * grid (cells of 2/14 m), E / (Φ/(πd²)) straight below at 3, 4, 5, 6, 8
 * cells: 1.24, 0.82, 0.50, 0.27, 0.056. Bounds: within a factor 1.6 up to
 * 4 cells, and a ratio that falls with distance. */
static void one_vpl_inverse_square(void **state)
{
    (void)state;
    Scene s;
    open_scene(&s, false, 3.f);
    GiParams gp = s.gi;
    gp.lpv_occlusion = false;
    const float cell = 2.f / 14.f;
    const int cells[] = {3, 4, 5, 6, 8};
    enum { W = 96 };
    double last = 1e30, power_ratio[5];
    for (size_t i = 0; i < sizeof cells / sizeof cells[0]; i++) {
        const vec3 p = {0.5f * cell, (float)cells[i] * cell, 0.5f * cell}; /* above a cell centre */
        Renderer r;
        float *e = render_one_vpl(&r, &s, &gp, W, p);
        double got = irradiance_at(&r, e, (vec3){p[0], 0.f, p[2]}, 1);
        double expect = exact_e(p, (vec3){p[0], 0.f, p[2]}), ratio = got / expect;
        /* Power received by the floor seen in the image: Σ E · pixel footprint
         * (the camera looks straight down, so the footprint is constant). */
        double lpv_power = 0, exact_power = 0;
        for (int y = 0; y < W; y++)
            for (int x = 0; x < W; x++) {
                vec3 q;
                test_pixel_plane_point(&s, W, W, x, y, q);
                if (fabsf(q[0]) > 1.f || fabsf(q[2]) > 1.f)
                    continue;
                lpv_power += e[4 * ((size_t)(W - 1 - y) * W + (size_t)x) + 1];
                exact_power += exact_e(p, q);
            }
        print_message("one VPL, d = %d cells (%.3f m): E = %.4g, Phi/(pi d^2) = %.4g, ratio %.3f; "
                      "floor power LPV/exact %.3f\n",
                      cells[i], cells[i] * cell, got, expect, ratio, lpv_power / exact_power);
        if (cells[i] <= 4)
            assert_true(ratio > 1 / 1.6 && ratio < 1.6);
        assert_true(ratio < last);
        last = ratio;
        power_ratio[i] = lpv_power / exact_power;
        free(e);
        renderer_destroy(&r);
    }
    /* The floor's received power falls with height too (measured 0.63, 0.36,
     * 0.19, 0.088, 0.013): the propagated light turns diffuse and spreads
     * in every direction, up included, rather than travelling on. */
    assert_true(power_ratio[0] > 0.5 && power_ratio[0] < 1.2);
    for (int i = 1; i < 5; i++)
        assert_true(power_ratio[i] < power_ratio[i - 1]);
    scene_free(&s);
}

/* ---- Occlusion --------------------------------------------------------- */

/* A horizontal wall (y = 0.52, lit from above so the RSM holds it) between a
 * VPL 6 cells above the floor and the floor below it. */
static void wall_blocks_light(void **state)
{
    (void)state;
    Scene open, walled;
    /* The camera between the wall and the floor, looking down. */
    open_scene(&open, false, 0.4f);
    open_scene(&walled, true, 0.4f);
    const float cell = 2.f / 14.f;
    const vec3 p = {0.5f * cell, 6.f * cell, 0.5f * cell}, below = {p[0], 0.f, p[2]};
    GiParams gp = open.gi;
    gp.lpv_occlusion = false;
    Renderer r;
    float *e = render_one_vpl(&r, &open, &gp, 64, p);
    double free_e = irradiance_at(&r, e, below, 1);
    free(e);
    renderer_destroy(&r);
    e = render_one_vpl(&r, &walled, &gp, 64, p);
    double off = irradiance_at(&r, e, below, 1);
    free(e);
    renderer_destroy(&r);
    gp.lpv_occlusion = true;
    e = render_one_vpl(&r, &walled, &gp, 64, p);
    double on = irradiance_at(&r, e, below, 1);
    free(e);
    renderer_destroy(&r);
    /* The camera's G-buffer adds surfels (here the floor it sees): more
     * blockers can only block more. */
    gp.lpv_gbuffer_occlusion = true;
    e = render_one_vpl(&r, &walled, &gp, 64, p);
    double on_gb = irradiance_at(&r, e, below, 1);
    free(e);
    renderer_destroy(&r);
    print_message("below the wall: E free %.4g, occlusion off %.4g (cut %.1f%%), on %.4g (cut %.1f%%), "
                  "with the G-buffer %.4g\n",
                  free_e, off, 100 * (1 - off / free_e), on, 100 * (1 - on / free_e), on_gb);
    assert_true(on_gb <= on * 1.0001 + 1e-9);
    assert_true(free_e > 0);
    assert_true(on < 0.2 * free_e);
    assert_true(fabs(off - free_e) < 0.2 * free_e); /* without occlusion the wall is not there: the leak */
    scene_free(&open);
    scene_free(&walled);
}

/* ---- Cornell box against the path tracer -------------------------------- */

static double red_over_green(const Scene *s, const ImageF *img, const vec3 p)
{
    int x, y;
    test_project(s, img->width, img->height, p, &x, &y);
    return test_mean(img, x, y, 2, 0) / test_mean(img, x, y, 2, 1);
}

/* The Cornell box with its light as a point and hard shadows (as
 * test_rsm.c), 16³ cells, 8 steps, 64² RSM: relMSE against one-bounce (the
 * bounce occluded) and one-bounce-novis, and with 2 cascades (whose
 * coarser grid holds the box); no GI for the bound's sake; colour bleeding
 * on the ceiling. Measured: lpv 0.0261 / 0.0271, 2 cascades 0.0130, no GI
 * 0.0360 / 0.0403: the bound 0.031 sits between. Finer grids do worse
 * here (32³, 32 steps: 0.042): more steps, more smearing. */
static void cornell_against_reference(void **state)
{
    (void)state;
    enum { W = 80, H = 80 };
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    scene_rescale_lights(&s, 0.f);
    s.gi.rsm_size = 64;
    s.gi.lpv_size = 16;
    s.gi.lpv_iterations = 8;
    ImageF lpv, none, ob, novis, casc;
    test_render_gi(&s, W, H, GI_LPV, NULL, &lpv);
    GiParams gp = s.gi;
    gp.lpv_cascades = 2;
    test_render_gi(&s, W, H, GI_LPV, &gp, &casc);
    test_render_gi(&s, W, H, GI_NONE, NULL, &none);
    test_reference(&s, W, H, PT_ONE_BOUNCE, 256, &ob);
    test_reference(&s, W, H, PT_ONE_BOUNCE_NOVIS, 256, &novis);
    double l_ob = metric_relmse(&lpv, &ob, NULL, NULL), n_ob = metric_relmse(&none, &ob, NULL, NULL);
    double l_nv = metric_relmse(&lpv, &novis, NULL, NULL), n_nv = metric_relmse(&none, &novis, NULL, NULL);
    double c_ob = metric_relmse(&casc, &ob, NULL, NULL);
    const vec3 ceil_red = {0.52f, 0.5488f, 0.3f}, ceil_green = {0.04f, 0.5488f, 0.3f};
    double cr = red_over_green(&s, &lpv, ceil_red), cg = red_over_green(&s, &lpv, ceil_green);
    print_message("relMSE vs one-bounce: lpv %.4f (2 cascades %.4f) none %.4f; vs one-bounce-novis: lpv %.4f "
                  "none %.4f; ceiling R/G red side %.3f green side %.3f\n",
                  l_ob, c_ob, n_ob, l_nv, n_nv, cr, cg);
    assert_true(l_ob < LPV_CORNELL_BOUND && l_nv < LPV_CORNELL_BOUND && c_ob < LPV_CORNELL_BOUND);
    assert_true(n_ob > LPV_CORNELL_BOUND && n_nv > LPV_CORNELL_BOUND); /* the bound means something */
    assert_true(cr > 1.5 * cg);
    image_free(&lpv);
    image_free(&none);
    image_free(&ob);
    image_free(&novis);
    image_free(&casc);
    scene_free(&s);
}

/* ---- The leak scene ----------------------------------------------------- */

/* Mean luminance of the radiance over the floor of the dark room (x in
 * [2.3, 3.7], z in [0.3, 1.7]) and of the lit one (x in [0.3, 1.7]). */
static void room_means(const Scene *s, const ImageF *img, double *dark, double *lit)
{
    double sum[2] = {0, 0};
    int n[2] = {0, 0};
    for (int room = 0; room < 2; room++)
        for (float x = 0.3f; x <= 1.7f; x += 0.2f)
            for (float z = 0.3f; z <= 1.7f; z += 0.2f) {
                int px, py;
                test_project(s, img->width, img->height, (vec3){x + (room ? 0.f : 2.f), 0.f, z}, &px, &py);
                if (px < 0 || py < 0 || px >= img->width || py >= img->height)
                    continue;
                sum[room] += luminance(image_px(img, px, py));
                n[room]++;
            }
    assert_true(n[0] > 10 && n[1] > 10);
    *dark = sum[0] / n[0];
    *lit = sum[1] / n[1];
}

static void leak_scene(void **state)
{
    (void)state;
    Scene s;
    assert_true(scene_load(&s, RTGI_SOURCE_DIR "/scenes/lpv_leak.json"));
    s.gi.rsm_size = 32;
    GiParams gp = s.gi;
    ImageF img;
    double dark[4], lit[4];
    const char *what[4] = {"16^3 occlusion off", "16^3", "32^3", "none"};
    for (int i = 0; i < 4; i++) {
        gp.lpv_size = i == 2 ? 32 : 16;
        gp.lpv_occlusion = i != 0;
        test_render_gi(&s, 64, 64, i == 3 ? GI_NONE : GI_LPV, &gp, &img);
        room_means(&s, &img, &dark[i], &lit[i]);
        print_message("leak scene, %s: dark room floor %.5f, lit room floor %.5f (ratio %.4f)\n", what[i], dark[i],
                      lit[i], dark[i] / lit[i]);
        image_free(&img);
    }
    assert_true(dark[3] < 1e-6);          /* the dark room has no direct light */
    assert_true(dark[0] > 0.01 * lit[0]); /* LPV leaks through the 2 cm wall... */
    assert_true(dark[1] < 0.5 * dark[0]); /* ...less with the geometry volume... */
    assert_true(dark[2] < dark[1]);       /* ...and less with finer cells */
    scene_free(&s);
}

/* ---- Cascades ----------------------------------------------------------- */

/* Nested grids around the camera: origins on whole cells, unchanged by a
 * camera move of a fraction of the finest cell (the image does not swim),
 * shifted by whole cells when it crosses one; each cascade twice the last. */
static void cascades_snap(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    scene_rescale_lights(&s, 0.f);
    GiParams gp = s.gi;
    gp.rsm_size = 32;
    gp.lpv_size = 16;
    gp.lpv_iterations = 8;
    gp.lpv_cascades = 3;
    Renderer r;
    lpv_renderer(&r, &s, 32, 32, &gp);
    Camera cam = s.camera;
    float o[3][3], cell[3], o2[3], c2;
    renderer_frame(&r, &cam);
    for (int k = 0; k < 3; k++) {
        lpv_grid(r.gi_state, k, o[k], &cell[k]);
        for (int a = 0; a < 3; a++)
            assert_true(fabs(o[k][a] / cell[k] - round(o[k][a] / cell[k])) < 1e-3);
        if (k > 0)
            assert_true(fabsf(cell[k] - 2.f * cell[k - 1]) < 1e-5f * cell[k]);
    }
    /* A small move: no cascade moves, unless the camera crossed a cell
     * boundary of it; then by exactly one cell. */
    cam.position[0] += 0.3f * cell[0];
    renderer_frame(&r, &cam);
    for (int k = 0; k < 3; k++) {
        lpv_grid(r.gi_state, k, o2, &c2);
        double shift = (o2[0] - o[k][0]) / cell[k];
        assert_true(fabs(shift) < 1e-3 || fabs(shift - 1) < 1e-3);
        assert_true(fabsf(o2[1] - o[k][1]) < 1e-6f && fabsf(o2[2] - o[k][2]) < 1e-6f);
    }
    renderer_destroy(&r);
    scene_free(&s);
}

/* ---- Bad settings ------------------------------------------------------- */

static void bad_lpv_settings(void **state)
{
    (void)state;
    char *err = NULL;
    int rc = test_run_cli(&err, "render", "--gi", "lpv", "--lpv-size", "0", NULL);
    test_expect_cli_error(rc, err, 2, "--lpv-size", NULL);
    rc = test_run_cli(&err, "render", "--gi", "lpv", "--lpv-cascades", "0", NULL);
    test_expect_cli_error(rc, err, 2, "--lpv-cascades", NULL);
    rc = test_run_cli(&err, "render", "--gi", "lpv", "--lpv-cascades", "9", NULL);
    test_expect_cli_error(rc, err, 2, "--lpv-cascades", NULL);
    rc = test_run_cli(&err, "render", "--gi", "lpv", "--lpv-iterations", "-1", NULL);
    test_expect_cli_error(rc, err, 2, "--lpv-iterations", NULL);
    const char *path = test_tmp_file("badlpv.json", "{ \"builtin\": \"cornell\", \"gi\": { \"lpv_size\": 0 } }\n");
    rc = test_run_cli(&err, "render", "--scene", path, NULL);
    test_expect_cli_error(rc, err, 1, "badlpv.json", "gi.lpv_size");
    /* In range, but about 14 GiB of volumes: refused by the GPU memory
     * budget (4 GiB by default) before anything is made, naming the
     * settings; it had gone on to allocate them. */
    unsetenv("RTGI_GPU_BUDGET_MIB");
    rc = test_run_cli(&err, "render", "--gi", "lpv", "--lpv-size", "256", "--lpv-cascades", "3", "--size", "8x8", NULL);
    test_expect_cli_error(rc, err, 1, "--lpv-size 256 with --lpv-cascades 3", "budget");
}

/* gi_memory_mib of `render --gi lpv --timings` as the settings call for
 * (the figure the budget check adds up before it makes them): per cascade
 * the injected and summed volumes, three RGBA32F N³ per colour set (cascades
 * past the first keep a second set without the finer cascade's cells), and
 * the geometry volume's two RGBA32F (N+1)³; the propagation's two RGBA32F
 * 3N·N·N; with occlusion the faces' RGBA32F 8N·N·N; with compute injection
 * the fixed-point sums, 12 words a cell and 6 a geometry corner; the
 * parameter block and the 16-byte indirect command. */
static void memory_as_the_settings_say(void **state)
{
    (void)state;
    static const struct {
        int n, cascades;
        const char *occlusion, *inject;
    } runs[] = {{8, 1, "on", "compute"}, {8, 2, "off", "points"}, {6, 3, "on", "points"}};
    char img[512];
    snprintf(img, sizeof img, "%s/lpv_memory.pfm", RTGI_TEST_TMP);
    for (size_t k = 0; k < sizeof runs / sizeof runs[0]; k++) {
        char nb[16], cb[16];
        snprintf(nb, sizeof nb, "%d", runs[k].n);
        snprintf(cb, sizeof cb, "%d", runs[k].cascades);
        char *out = NULL, *err = NULL;
        int rc = test_run_cli_out(&out, &err, "render", "--gi", "lpv", "--lpv-size", nb, "--lpv-cascades", cb,
                                  "--lpv-occlusion", runs[k].occlusion, "--lpv-inject", runs[k].inject, "--size",
                                  "16x16", "--timings", "--out", img, "--quiet", NULL);
        if (rc != 0)
            fail_msg("render --gi lpv --timings: exit %d: %s", rc, err ? err : "");
        free(err);
        double n = runs[k].n, n3 = n * n * n, g3 = (n + 1) * (n + 1) * (n + 1);
        double sets = 1 + 2 * (runs[k].cascades - 1);
        double bytes = 16 * (sets * 2 * 3 * n3 + runs[k].cascades * 2 * g3 + 2 * 3 * n3);
        if (strcmp(runs[k].occlusion, "on") == 0)
            bytes += 16 * 8 * n3;
        if (strcmp(runs[k].inject, "compute") == 0)
            bytes += 4 * (12 * n3 + 6 * g3);
        double want = (bytes + sizeof(GpuLpvParams) + 16) / (1024.0 * 1024.0), mib = -1;
        const char *m = out ? strstr(out, "\ngi_memory_mib: ") : NULL;
        assert_non_null(m);
        assert_int_equal(sscanf(m, "\ngi_memory_mib: %lf", &mib), 1);
        print_message("lpv N=%d, %d cascades, occlusion %s, %s injection: gi_memory_mib %.4f, from the settings %.4f\n",
                      runs[k].n, runs[k].cascades, runs[k].occlusion, runs[k].inject, mib, want);
        assert_true(fabs(mib - want) < 0.0006);
        free(out);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(injection_conserves_flux),
        cmocka_unit_test(propagation_step_matches_cpu),
        cmocka_unit_test(one_vpl_inverse_square),
        cmocka_unit_test(wall_blocks_light),
        cmocka_unit_test(cornell_against_reference),
        cmocka_unit_test(leak_scene),
        cmocka_unit_test(cascades_snap),
        cmocka_unit_test(bad_lpv_settings),
        cmocka_unit_test(memory_as_the_settings_say),
    };
    return cmocka_run_group_tests_name("lpv", tests, test_gl_setup, test_gl_teardown);
}
