/* test_lpv.c — light propagation volumes (SPEC §5) on llvmpipe at small
 * grids, stage by stage against closed forms (issue 44):
 *   injection    one VPL of flux Φ holds the 2-band SH of Φ/π·max(0, n·ω)
 *                in the cell half a cell along its normal, in its light
 *                group; the RSM's flux in the grid is the VPLs'
 *   propagation  one step equals a CPU step written from the description
 *                (directional and the paper's faces); in free space the
 *                flux is conserved and the flux outside a sphere around a
 *                source never exceeds it; in a closed box what was injected
 *                is what is stored plus what the walls took, to 1%
 *   lookup       a large uniform emitting plane gives the closed-form
 *                irradiance one cell away, within 10%, at the cell sizes of
 *                three cascades, and wherever the receiver sits in its cell
 *   cascades     each VPL is counted once over nested grids
 * and then one VPL against Φ/(π d²), occlusion by a wall, the Cornell box
 * against the path tracer, the leak scene, bad settings, memory. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"
#include "gi/lpv/lpv.h"
#include "io/metrics.h"
#include "reference/pathtracer.h"

#define LPV_CORNELL_BOUND 0.012 /* relMSE; see cornell_against_reference */
#define SH_NORM 3.5449077018    /* ∫ Y00 dω / Y00² = 2√π: flux of an SH intensity = c00 · 2√π */
#define SH_MOMENT 2.0466534158  /* √(4π/3): first moment ∫ I ω dω = c1 · √(4π/3) */
#define SPEED 0.5773502692      /* --lpv-propagation directional: cells a step (κ = 1/√3) */

/* A renderer with `--gi lpv` and hard shadows on `s`. */
static void lpv_renderer(Renderer *r, const Scene *s, int w, int h, const GiParams *gp)
{
    RenderSettings rs = test_settings(s, w, h, SHADOW_MODE_HARD);
    rs.gi = GI_LPV;
    rs.set.gi = gp ? *gp : s->settings.gi;
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

/* Floats in cascade 0's volume as lpv_read_volume writes them. */
static size_t volume_floats(const Renderer *r)
{
    size_t n = (size_t)lpv_grid_size(r->gi_state);
    return 12 * n * n * n * (size_t)lpv_groups(r->gi_state);
}

/* Cascade k's volume `which` (lpv_read_volume's layout). Caller frees. */
static float *read_volume(const Renderer *r, int k, LpvVolume which)
{
    float *v = malloc(sizeof(float) * volume_floats(r));
    assert_non_null(v);
    assert_true(lpv_read_volume(r->gi_state, k, which, v));
    return v;
}

/* Flux of channel c of a volume (every group): Σ c00 · 2√π. */
static double volume_flux(const Renderer *r, const float *v, int c)
{
    size_t cells = volume_floats(r) / 12;
    double sum = 0;
    for (size_t i = 0; i < cells; i++)
        sum += v[(c * cells + i) * 4] * SH_NORM;
    return sum;
}

/* Octahedral 16-bit code of unit n and the normal it decodes to, as
 * shaders/common/packing.glsl (pack_oct16, unpack_oct16). */
static uint32_t oct16(const vec3 n, vec3 decoded)
{
    float l1 = fabsf(n[0]) + fabsf(n[1]) + fabsf(n[2]), p[2] = {n[0] / l1, n[1] / l1};
    if (n[2] < 0.f) {
        float px = p[0], py = p[1];
        p[0] = (1.f - fabsf(py)) * (px >= 0.f ? 1.f : -1.f);
        p[1] = (1.f - fabsf(px)) * (py >= 0.f ? 1.f : -1.f);
    }
    uint32_t o[2];
    float e[2];
    for (int i = 0; i < 2; i++) {
        o[i] = (uint32_t)lroundf(fminf(fmaxf(p[i] * 0.5f + 0.5f, 0.f), 1.f) * 65535.f);
        e[i] = (float)o[i] * (2.f / 65535.f) - 1.f;
    }
    vec3 d = {e[0], e[1], 1.f - fabsf(e[0]) - fabsf(e[1])};
    float t = fmaxf(-d[2], 0.f);
    d[0] -= d[0] >= 0.f ? t : -t;
    d[1] -= d[1] >= 0.f ? t : -t;
    glm_vec3_normalize_to(d, decoded);
    return o[0] | (o[1] << 16);
}

/* A VPL at p with unit normal n (decoded into `n_used`, may be NULL) and flux. */
static GpuVpl make_vpl(const vec3 p, const vec3 n, const vec3 flux, vec3 n_used)
{
    vec3 d;
    GpuVpl v = {.flux = {flux[0], flux[1], flux[2], 0.f}};
    v.surface[3] = oct16(n, d);
    gpu_vpl_set_position(&v, p);
    glm_vec3_copy(d, v.normal_xi);
    v.normal_xi[3] = 0.5f;
    if (n_used)
        glm_vec3_copy(d, n_used);
    return v;
}

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
    s->settings.gi.rsm.size = 64;
    s->settings.gi.lpv.size = 16;
}

/* Renders one frame with these VPLs instead of the light stage's; returns
 * the irradiance image (caller frees). */
static float *render_vpls(Renderer *r, const Scene *s, const GiParams *gp, int w, const GpuVpl *v, int count)
{
    lpv_renderer(r, s, w, w, gp);
    lpv_set_vpls(r->gi_state, v, count);
    renderer_frame(r, &s->camera);
    return read_irradiance(r);
}

/* One VPL (normal down, flux Φ = 1 W) at p; one frame. */
static float *render_one_vpl(Renderer *r, const Scene *s, const GiParams *gp, int w, const vec3 p)
{
    GpuVpl v = make_vpl(p, (vec3){0.f, -1.f, 0.f}, (vec3){1.f, 1.f, 1.f}, NULL);
    return render_vpls(r, s, gp, w, &v, 1);
}

/* ---- Injection ----------------------------------------------------------- */

/* Two VPLs of flux Φ (per channel), one facing up and sideways (light
 * group 0: n·(1,1,1) ≥ 0), one facing down (group 1). Each lands in the
 * cell that holds p + ½ cell · n and there alone, in its group's layers,
 * as the SH of its clamped-cosine intensity lobe I(ω) = Φ/π · max(0, n·ω):
 * c00 = Φ/π · √π/2 and c1 = Φ/π · √(π/3) · n, so that the cell's flux
 * c00 · 2√π is Φ (W, as the light stage's VPLs carry it: SPEC §3) and its
 * first moment c1 · √(4π/3) is 2Φ/3 · n, the lobe's. Both injections. */
static void injection_one_vpl_closed_form(void **state)
{
    (void)state;
    Scene s;
    open_scene(&s, false, 3.f);
    const vec3 pos[2] = {{0.23f, 0.31f, -0.17f}, {-0.4f, 0.62f, 0.35f}};
    const vec3 nrm[2] = {{0.48f, 0.8f, -0.36f}, {0.f, -1.f, 0.f}};
    const vec3 flux[2] = {{1.f, 0.5f, 0.25f}, {0.2f, 0.4f, 0.8f}};
    for (int method = 0; method < 2; method++) {
        GiParams gp = s.settings.gi;
        gp.lpv.inject = method == 0 ? LPV_INJECT_COMPUTE : LPV_INJECT_POINTS;
        gp.lpv.iterations = 1;
        GpuVpl v[2];
        vec3 n[2];
        for (int i = 0; i < 2; i++)
            v[i] = make_vpl(pos[i], nrm[i], flux[i], n[i]);
        Renderer r;
        free(render_vpls(&r, &s, &gp, 32, v, 2));
        assert_int_equal(lpv_groups(r.gi_state), 2);
        int N = lpv_grid_size(r.gi_state);
        size_t n3 = (size_t)N * N * N, cells = 2 * n3;
        float o[3], cell;
        lpv_grid(r.gi_state, 0, o, &cell);
        float *vol = read_volume(&r, 0, LPV_VOLUME_INJECTED);
        size_t at[2];
        double worst = 0, peak = 0, elsewhere = 0;
        for (int i = 0; i < 2; i++) {
            int c[3];
            for (int a = 0; a < 3; a++)
                c[a] = (int)floorf((pos[i][a] + 0.5f * cell * n[i][a] - o[a]) / cell);
            at[i] = ((size_t)(i * N + c[2]) * N + c[1]) * N + c[0]; /* group i's layers */
            for (int ch = 0; ch < 3; ch++) {
                const float *sh = vol + (ch * cells + at[i]) * 4;
                double want[4] = {flux[i][ch] / GLM_PI * sqrt(GLM_PI) / 2, 0, 0, 0};
                for (int a = 0; a < 3; a++)
                    want[1 + a] = flux[i][ch] / GLM_PI * sqrt(GLM_PI / 3) * n[i][a];
                for (int j = 0; j < 4; j++) {
                    worst = fmax(worst, fabs(sh[j] - want[j]));
                    peak = fmax(peak, fabs(want[j]));
                }
                double f = sh[0] * SH_NORM, m = sh[1 + 1] * SH_MOMENT;
                assert_true(fabs(f - flux[i][ch]) < 1e-4 * flux[i][ch]);
                assert_true(fabs(m - 2.0 / 3.0 * flux[i][ch] * n[i][1]) < 1e-4 * flux[i][ch]);
            }
        }
        for (int ch = 0; ch < 3; ch++)
            for (size_t i = 0; i < cells; i++)
                if (i != at[0] && i != at[1])
                    for (int j = 0; j < 4; j++)
                        elsewhere += fabs(vol[(ch * cells + i) * 4 + j]);
        print_message("one VPL per group (%s injection): largest |SH - closed form| %.3g of %.4g; elsewhere %.3g\n",
                      method == 0 ? "compute" : "points", worst, peak, elsewhere);
        assert_true(worst < 1e-5 * peak);
        assert_true(elsewhere < 1e-6 * peak);
        free(vol);
        renderer_destroy(&r);
    }
    scene_free(&s);
}

/* Both injections (compute with fixed-point atomics, points with
 * blending): the grid's flux, Σ c00 · 2√π over the cells of both light
 * groups, is the RSM's. `out_volume` gets the accumulated volume after one
 * step. */
static void check_injected_flux(LpvInject method, float *out_volume)
{
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.rsm.size = 32;
    gp.lpv.size = 16;
    gp.lpv.iterations = 1;
    gp.lpv.inject = method;
    Renderer r;
    lpv_renderer(&r, &s, 32, 32, &gp);
    renderer_frame(&r, &s.camera);
    /* The RSM's flux: the VPL buffer (every lit texel). */
    uint32_t count = light_stage_vpl_count(&r.lights);
    GpuVpl *v = malloc(sizeof *v * count);
    glGetNamedBufferSubData(r.lights.vpls.vpls, 0, (GLsizeiptr)(sizeof *v * count), v);
    double rsm[3] = {0, 0, 0}, grid[3];
    for (uint32_t i = 0; i < count; i++)
        for (int c = 0; c < 3; c++)
            rsm[c] += v[i].flux[c];
    float *vol = read_volume(&r, 0, LPV_VOLUME_INJECTED);
    for (int c = 0; c < 3; c++)
        grid[c] = volume_flux(&r, vol, c);
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
    enum { N3 = 2 * 16 * 16 * 16 }; /* two light groups */
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

/* ---- Propagation ----------------------------------------------------------- */

/* 1/π ∫ max(0, d·ω) max(0, e·ω) dω for unit d, e with d·e = mu. */
static double g0(double mu)
{
    mu = fmax(-1.0, fmin(1.0, mu));
    return 2.0 / (3.0 * GLM_PI) * ((GLM_PI - acos(mu)) * mu + sqrt(1.0 - mu * mu));
}

/* The part of light `sh` (2-band SH) that crosses face e (a unit axis) in a
 * directional step, as SH, written in doubles from the description in
 * shaders/gi/lpv/propagate.comp: the moments P = c00·2√π, F = c1·√(4π/3)
 * read as a clamped-cosine lobe of share a = min(1, 1.5|F|/P) around d =
 * F/|F| plus isotropic light; per unit flux the lobe sends κ·g0(d·e) with
 * moment κ·(1 + d·e)/8·(d + e), the isotropic part κ/4 with moment κ/6·e. */
static void cpu_send(const double sh[4], const double e[3], double out[4])
{
    double p = fmax(sh[0] * SH_NORM, 0.0), f[3], fl = 0.0, d[3], mu = 0.0;
    for (int a = 0; a < 3; a++) {
        f[a] = sh[1 + a] * SH_MOMENT;
        fl += f[a] * f[a];
    }
    fl = sqrt(fl);
    double lobe = p > 0.0 ? fmin(1.5 * fl / p, 1.0) : 0.0;
    for (int a = 0; a < 3; a++) {
        d[a] = fl > 0.0 ? f[a] / fl : 0.0;
        mu += d[a] * e[a];
    }
    mu = fmax(-1.0, fmin(1.0, mu));
    out[0] = SPEED * p * (lobe * g0(mu) + 0.25 * (1.0 - lobe)) / SH_NORM;
    for (int a = 0; a < 3; a++)
        out[1 + a] = SPEED * p * (lobe * (1.0 + mu) * 0.125 * (d[a] + e[a]) + (1.0 - lobe) / 6.0 * e[a]) / SH_MOMENT;
}

/* The share of the face between cell c and its neighbour c − e (e = ±axis
 * `ax`) that the geometry volume leaves open: 1 − min(1, M_aa), M averaged
 * over the face's 4 corner texels (gv: the geometry readback); 1 without
 * occlusion. */
static double open_share(int n, const int c[3], int ax, int sgn, const float *gv, bool occlusion)
{
    if (!occlusion)
        return 1.0;
    size_t g = (size_t)n + 1;
    double m = 0.0;
    for (int k = 0; k < 4; k++) {
        int q[3] = {c[0], c[1], c[2]};
        q[ax] = sgn > 0 ? c[ax] : c[ax] + 1;
        q[(ax + 1) % 3] += k & 1;
        q[(ax + 2) % 3] += k >> 1;
        m += 0.25 * gv[(((size_t)q[2] * g + q[1]) * g + q[0]) * 4 + ax];
    }
    return 1.0 - fmin(fmax(m, 0.0), 1.0);
}

/* One directional step of one light group on the CPU: in, out 3·N³ SH (in
 * lpv_read_volume's layout, one group). Each cell keeps its light less what
 * it sends across its 6 faces and gathers what its neighbours send it, times
 * the shared face's open share; then |F| ≤ P. Adds the flux the geometry
 * took to *blocked and what left the grid to *left. */
static void cpu_directional_step(int n, const double *in, const float *gv, bool occlusion, double *out,
                                 double *blocked, double *left)
{
    static const double E[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    size_t n3 = (size_t)n * n * n;
    for (int ch = 0; ch < 3; ch++)
        for (int z = 0; z < n; z++)
            for (int y = 0; y < n; y++)
                for (int x = 0; x < n; x++) {
                    int c[3] = {x, y, z};
                    size_t ci = ((size_t)z * n + y) * n + x;
                    const double *own = in + (ch * n3 + ci) * 4;
                    double r[4] = {own[0], own[1], own[2], own[3]}, s[4];
                    for (int k = 0; k < 6; k++) {
                        int ax = k / 2, sgn = k & 1 ? -1 : 1, to[3] = {x, y, z}, from[3] = {x, y, z};
                        to[ax] += sgn;
                        from[ax] -= sgn;
                        cpu_send(own, E[k], s);
                        for (int j = 0; j < 4; j++)
                            r[j] -= s[j];
                        if (to[ax] < 0 || to[ax] >= n)
                            *left += s[0] * SH_NORM;
                        else
                            *blocked += (1.0 - open_share(n, to, ax, sgn, gv, occlusion)) * s[0] * SH_NORM;
                        if (from[ax] < 0 || from[ax] >= n)
                            continue;
                        cpu_send(in + (ch * n3 + ((size_t)from[2] * n + from[1]) * n + from[0]) * 4, E[k], s);
                        double f = open_share(n, c, ax, sgn, gv, occlusion);
                        for (int j = 0; j < 4; j++)
                            r[j] += f * s[j];
                    }
                    double p = fmax(r[0], 0.0) * SH_NORM, fl = sqrt(r[1] * r[1] + r[2] * r[2] + r[3] * r[3]) * SH_MOMENT;
                    for (int j = 1; fl > p && j < 4; j++)
                        r[j] *= p / fl;
                    memcpy(out + (ch * n3 + ci) * 4, r, sizeof r);
                }
}

/* The Cornell box (12³ cells, one directional step, both light groups):
 * the accumulated volume is the injected one plus one step, which must
 * equal cpu_directional_step on the read-back injected and geometry
 * volumes, with occlusion and without. */
static void directional_step_matches_cpu(void **state)
{
    (void)state;
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    for (int occ = 0; occ < 2; occ++) {
        GiParams gp = s.settings.gi;
        gp.rsm.size = 32;
        gp.lpv.size = 12;
        gp.lpv.iterations = 1;
        gp.lpv.occlusion = occ == 1;
        Renderer r;
        lpv_renderer(&r, &s, 32, 32, &gp);
        renderer_frame(&r, &s.camera);
        int n = lpv_grid_size(r.gi_state), groups = lpv_groups(r.gi_state);
        size_t n3 = (size_t)n * n * n, cells = n3 * (size_t)groups, g3 = (size_t)(n + 1) * (n + 1) * (n + 1);
        float *inj = read_volume(&r, 0, LPV_VOLUME_INJECTED), *acc = read_volume(&r, 0, LPV_VOLUME_ACCUMULATED),
              *gv = malloc(sizeof(float) * 8 * g3);
        double *in = malloc(sizeof(double) * 12 * n3), *step = malloc(sizeof(double) * 12 * n3);
        assert_true(gv && in && step);
        assert_true(lpv_read_geometry(r.gi_state, 0, gv));
        double err = 0.0, scale = 0.0, blocked = 0.0, left = 0.0, moved = 0.0;
        for (int g = 0; g < groups; g++) {
            for (int ch = 0; ch < 3; ch++)
                for (size_t i = 0; i < 4 * n3; i++)
                    in[ch * 4 * n3 + i] = inj[(ch * cells + g * n3) * 4 + i];
            cpu_directional_step(n, in, gv, gp.lpv.occlusion, step, &blocked, &left);
            for (int ch = 0; ch < 3; ch++)
                for (size_t i = 0; i < 4 * n3; i++) {
                    size_t gi = (ch * cells + g * n3) * 4 + i;
                    double got = (double)acc[gi] - (double)inj[gi];
                    err = fmax(err, fabs(got - step[ch * 4 * n3 + i]));
                    scale = fmax(scale, fabs(step[ch * 4 * n3 + i]));
                    moved += fabs(step[ch * 4 * n3 + i]);
                }
        }
        print_message("one directional step, occlusion %s: max |GPU - CPU| = %.3g of the largest value %.4g; the "
                      "geometry took %.4g W, %.4g W left the grid\n",
                      occ ? "on" : "off", err, scale, blocked, left);
        assert_true(scale > 0.0 && moved > 0.0);
        assert_true(err < 2e-5 * scale);
        if (gp.lpv.occlusion)
            assert_true(blocked > 0.0);
        else
            assert_true(blocked == 0.0);
        free(inj);
        free(acc);
        free(gv);
        free(in);
        free(step);
        renderer_destroy(&r);
    }
    scene_free(&s);
}

/* Flux of every channel of the cells of a one-group volume inside (or
 * outside) the ball of radius `radius` cells around cell centre `at`. */
static double flux_in_ball(int n, const float *v, const double at[3], double radius, bool inside)
{
    size_t n3 = (size_t)n * n * n;
    double sum = 0.0;
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++) {
                double d2 = (x - at[0]) * (x - at[0]) + (y - at[1]) * (y - at[1]) + (z - at[2]) * (z - at[2]);
                if ((d2 <= radius * radius) != inside)
                    continue;
                for (int ch = 0; ch < 3; ch++)
                    sum += v[(ch * n3 + ((size_t)z * n + y) * n + x) * 4] * SH_NORM;
            }
    return sum;
}

/* A point source in free space (two VPLs back to back, 1 W each channel, at
 * the centre of a 20³ grid, no occlusion, one light group). Step by step,
 * until light can reach the grid's border (a cell a step at most), the
 * grid's flux is what was injected, and the flux outside a sphere of 3
 * cells (what has crossed it) never exceeds the source's and does not fall
 * back by more than 1% of it (light crosses the sphere outwards). The
 * paper's faces fail this: a step evaluates the 2-band SH, which goes
 * negative, clamped at 0, so every step adds flux (a cosine lobe's SH:
 * +12.5% of the flux it moves). */
static void propagation_free_space(void **state)
{
    (void)state;
    Scene s;
    open_scene(&s, false, 3.f);
    for (int mode = 0; mode < 2; mode++) {
        GiParams gp = s.settings.gi;
        gp.lpv.size = 20;
        gp.lpv.occlusion = false;
        gp.lpv.groups = 1;
        gp.lpv.propagation = mode == 0 ? LPV_PROPAGATION_DIRECTIONAL : LPV_PROPAGATION_FACES;
        gp.lpv.iterations = 1;
        Renderer r;
        lpv_renderer(&r, &s, 16, 16, &gp);
        renderer_frame(&r, &s.camera);
        int n = lpv_grid_size(r.gi_state);
        float o[3], cell;
        lpv_grid(r.gi_state, 0, o, &cell);
        /* The centre cell's centre; the VPLs sit half a cell off it so that
         * both land in it. */
        double at[3] = {n / 2, n / 2, n / 2};
        vec3 p = {o[0] + (n / 2 + 0.5f) * cell, o[1] + (n / 2 + 0.5f) * cell, o[2] + (n / 2 + 0.5f) * cell};
        GpuVpl v[2] = {make_vpl(p, (vec3){0.f, 1.f, 0.f}, (vec3){1.f, 1.f, 1.f}, NULL),
                       make_vpl(p, (vec3){0.f, -1.f, 0.f}, (vec3){1.f, 1.f, 1.f}, NULL)};
        lpv_set_vpls(r.gi_state, v, 2);
        const double phi = 6.0; /* 2 VPLs × 3 channels */
        double worst_total = 0.0, most_outside = 0.0, last_outside = 0.0, fall = 0.0;
        int steps = n / 2 - 1; /* the border is n/2 − 1 cells from the centre cell's neighbours */
        for (int k = 1; k <= steps; k++) {
            lpv_set_iterations(r.gi_state, k);
            renderer_frame(&r, &s.camera);
            float *step = read_volume(&r, 0, LPV_VOLUME_STEP);
            double total = flux_in_ball(n, step, at, 1e9, true), outside = flux_in_ball(n, step, at, 3.0, false);
            worst_total = fmax(worst_total, fabs(total - phi) / phi);
            most_outside = fmax(most_outside, outside / phi);
            fall = fmax(fall, (last_outside - outside) / phi);
            last_outside = outside;
            free(step);
        }
        print_message("free space, %s, %d steps: grid flux off the injected by %.3g at most; outside 3 cells: %.4f "
                      "of it at the end, %.4f at most, falling back by %.4f at most\n",
                      mode == 0 ? "directional" : "faces (paper)", steps, worst_total, last_outside / phi, most_outside,
                      fall);
        if (mode == 0) {
            assert_true(worst_total < 1e-4);
            assert_true(most_outside <= 1.0 + 1e-4);
            assert_true(fall < 0.01);
            assert_true(last_outside > 0.3 * phi);
        } else {
            assert_true(worst_total > 0.05); /* the baseline: the check fails there */
        }
        renderer_destroy(&r);
    }
    scene_free(&s);
}

/* A closed 2 m room (6 walls facing in, lit by a point light at its centre,
 * so the light's cube RSM holds every wall and the geometry volume closes
 * the room), 12³ cells, one VPL inside, one light group. Step by step, what
 * was injected is what the grid stores plus what the geometry took and
 * what left the grid, to 1% (the taken and left flux from the CPU step on
 * each read-back step, which the GPU's next step must equal); the walls
 * hold the light (little is ever outside the room); and no cell's light is
 * more directional than light can be. */
static void propagation_closed_box(void **state)
{
    (void)state;
    Scene s;
    scene_init(&s);
    int white = scene_add_material(&s, "white", (vec3){0.5f, 0.5f, 0.5f});
    const float h = 1.f;
    for (int a = 0; a < 3; a++)
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            /* The wall at coordinate a = sgn·h, its normal −sgn along a. */
            int b = (a + 1) % 3, c = (a + 2) % 3;
            vec3 q[4];
            for (int i = 0; i < 4; i++) {
                q[i][a] = sgn * h;
                q[i][b] = (i == 1 || i == 2) ? h : -h;
                q[i][c] = i >= 2 ? h : -h;
            }
            if (sgn > 0)
                scene_add_quad(&s, white, q[0], q[3], q[2], q[1]);
            else
                scene_add_quad(&s, white, q[0], q[1], q[2], q[3]);
        }
    Light bulb = {.type = LIGHT_POINT, .position = {0.05f, 0.1f, -0.05f}, .color = {1.f, 1.f, 1.f}};
    scene_add_light(&s, &bulb);
    glm_vec3_copy((vec3){0.f, -0.5f, 0.9f}, s.camera.position);
    glm_vec3_copy((vec3){0.f, 0.f, -1.f}, s.camera.forward);
    glm_vec3_copy((vec3){0.f, 1.f, 0.f}, s.camera.up);
    s.camera.fov_y = glm_rad(90.f);
    s.camera.znear = 0.01f;
    scene_finalize(&s);
    GiParams gp = s.settings.gi;
    gp.rsm.size = 64;
    gp.lpv.size = 12;
    gp.lpv.groups = 1;
    gp.lpv.gbuffer_occlusion = false;
    gp.lpv.iterations = 0;
    Renderer r;
    lpv_renderer(&r, &s, 16, 16, &gp);
    const vec3 p = {0.31f, -0.42f, 0.17f};
    GpuVpl v = make_vpl(p, (vec3){0.6f, 0.64f, 0.48f}, (vec3){1.f, 1.f, 1.f}, NULL);
    lpv_set_vpls(r.gi_state, &v, 1);
    lpv_set_iterations(r.gi_state, 0);
    renderer_frame(&r, &s.camera);
    int n = lpv_grid_size(r.gi_state);
    float o[3], cell;
    lpv_grid(r.gi_state, 0, o, &cell);
    size_t n3 = (size_t)n * n * n, g3 = (size_t)(n + 1) * (n + 1) * (n + 1);
    float *gv = malloc(sizeof(float) * 8 * g3);
    double *in = malloc(sizeof(double) * 12 * n3), *next = malloc(sizeof(double) * 12 * n3);
    assert_true(gv && in && next);
    assert_true(lpv_read_geometry(r.gi_state, 0, gv));
    const double phi = 3.0;
    double taken = 0.0, left = 0.0, worst_balance = 0.0, worst_gpu = 0.0, most_outside = 0.0, stored = phi;
    double most_directional = 0.0; /* |F|/P of a cell's light, at most */
    int steps = 3 * n;
    for (int k = 0; k <= steps; k++) {
        lpv_set_iterations(r.gi_state, k);
        renderer_frame(&r, &s.camera);
        float *step = read_volume(&r, 0, LPV_VOLUME_STEP);
        double outside = 0.0, scale = 0.0;
        stored = 0.0;
        for (int z = 0; z < n; z++)
            for (int y = 0; y < n; y++)
                for (int x = 0; x < n; x++) {
                    int c[3] = {x, y, z};
                    bool in_room = true;
                    for (int a = 0; a < 3; a++) {
                        float centre = o[a] + (c[a] + 0.5f) * cell;
                        in_room = in_room && fabsf(centre) < h;
                    }
                    for (int ch = 0; ch < 3; ch++) {
                        size_t i = ch * n3 + ((size_t)z * n + y) * n + x;
                        double f = step[i * 4] * SH_NORM, m = 0.0;
                        stored += f;
                        outside += in_room ? 0.0 : f;
                        for (int j = 0; j < 4; j++)
                            scale = fmax(scale, fabs(step[i * 4 + j]));
                        for (int j = 1; j < 4; j++)
                            m += (double)step[i * 4 + j] * step[i * 4 + j];
                        if (f > 1e-6)
                            most_directional = fmax(most_directional, sqrt(m) * SH_MOMENT / f);
                    }
                }
        if (k > 0) /* this step against the CPU step from the last */
            for (size_t i = 0; i < 12 * n3; i++)
                worst_gpu = fmax(worst_gpu, fabs(step[i] - next[i]) / scale);
        worst_balance = fmax(worst_balance, fabs(stored + taken + left - phi) / phi);
        most_outside = fmax(most_outside, outside / phi);
        for (size_t i = 0; i < 12 * n3; i++)
            in[i] = step[i];
        cpu_directional_step(n, in, gv, true, next, &taken, &left);
        free(step);
    }
    print_message("closed room, %d steps: stored %.4f + taken by the walls %.4f + left the grid %.2g = %.4f of the "
                  "injected (worst step off by %.2g); outside the room %.4f at most; GPU step vs CPU %.2g; |F|/P "
                  "%.4f at most\n",
                  steps, stored / phi, taken / phi, left / phi, (stored + taken + left) / phi, worst_balance,
                  most_outside, worst_gpu, most_directional);
    assert_true(worst_balance < 0.01);
    assert_true(worst_gpu < 1e-4);
    assert_true(most_outside < 0.02);
    assert_true(taken > 0.9 * phi); /* after 3N steps the walls have taken nearly all */
    /* No cell holds light more directional than light can be (|F| ≤ P):
     * without the step's clamp, what stays of light more directional than
     * its lobe reading piled up moment (|F|/P measured up to 3.9). */
    assert_true(most_directional < 1.0 + 1e-3);
    free(gv);
    free(in);
    free(next);
    renderer_destroy(&r);
    scene_free(&s);
}

/* ---- The paper's faces --------------------------------------------------------- */

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

/* --lpv-propagation faces (the paper's), one light group: on the Cornell
 * box (12³ cells, one step) the accumulated volume is the injected one plus
 * one step, which must equal cpu_step on the read-back injected and
 * geometry volumes, with occlusion and without. The faces' solid angles
 * come from the exact formula here, the GPU's are constants; they sum to
 * 4π/6 per neighbour. */
static void faces_step_matches_cpu(void **state)
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
        GiParams gp = s.settings.gi;
        gp.rsm.size = 32;
        gp.lpv.size = 12;
        gp.lpv.iterations = 1;
        gp.lpv.occlusion = occ == 1;
        gp.lpv.propagation = LPV_PROPAGATION_FACES;
        gp.lpv.groups = 1;
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
        cpu_step(n, inj, gv, gp.lpv.occlusion, step);
        double scale = 0.0, err = 0.0, moved = 0.0, blocked = 0.0;
        for (size_t i = 0; i < 12 * n3; i++) {
            scale = fmax(scale, fmax(fabs(step[i]), fabs(acc[i])));
            moved += fabs(step[i]);
        }
        for (size_t i = 0; i < 12 * n3; i++)
            err = fmax(err, fabs((double)acc[i] - (double)inj[i] - step[i]));
        /* How much the geometry holds back: the step without it, less. */
        if (gp.lpv.occlusion) {
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
        if (gp.lpv.occlusion)
            assert_true(blocked > 0.02); /* the walls are in the volume (measured 3.5%): the comparison sees them */
        free(inj);
        free(acc);
        free(gv);
        free(step);
        renderer_destroy(&r);
    }
    scene_free(&s);
}

/* ---- Lookup ------------------------------------------------------------------ */

/* A 2 m receiver square facing down at height y_r, lit from above by a faint
 * sun (so the RSM and the geometry volume hold it), the camera `below` m
 * under it looking up at it; with `pin`, tiny squares at y = −0.5 and 1.5 m
 * fix the bounds (else the receiver alone sets them: the grid is centred on
 * it and it lies on a corner plane). */
static void receiver_scene(Scene *s, float y_r, bool pin, float below)
{
    scene_init(s);
    int white = scene_add_material(s, "white", (vec3){0.5f, 0.5f, 0.5f});
    float h = 1.f;
    scene_add_quad(s, white, (vec3){-h, y_r, -h}, (vec3){h, y_r, -h}, (vec3){h, y_r, h}, (vec3){-h, y_r, h});
    if (pin) {
        test_add_square(s, white, (vec3){0.9f, 1.5f, 0.9f}, 0.05f);
        test_add_square(s, white, (vec3){0.9f, -0.5f, 0.9f}, 0.05f);
    }
    Light sun = {.type = LIGHT_DIRECTIONAL, .direction = {0.f, -1.f, 0.f}, .color = {0.01f, 0.01f, 0.01f}};
    scene_add_light(s, &sun);
    glm_vec3_copy((vec3){0.001f, y_r - below, 0.002f}, s->camera.position);
    glm_vec3_copy((vec3){0, 1, 0}, s->camera.forward);
    glm_vec3_copy((vec3){0, 0, 1}, s->camera.up);
    s->camera.fov_y = glm_rad(60.f);
    s->camera.znear = 0.01f;
    scene_finalize(s);
    s->settings.gi.rsm.size = 64;
}

/* Irradiance at x (facing down, y above the plane) from a uniform
 * Lambertian square emitter of exitance M = 1 at height y_e facing up,
 * centred (cx, cz) with side `side`: ∫ cos θ_e cos θ_r / (π r²) dA. */
static double plane_irradiance_q(const vec3 x, float y_e, float cx, float cz, float side, int Q)
{
    double h = x[1] - y_e, da = (double)side * side / (Q * Q), e = 0.0;
    for (int i = 0; i < Q; i++)
        for (int j = 0; j < Q; j++) {
            double dx = cx - 0.5 * side + (i + 0.5) * side / Q - x[0], dz = cz - 0.5 * side + (j + 0.5) * side / Q - x[2];
            double r2 = dx * dx + dz * dz + h * h;
            e += h * h / (GLM_PI * r2 * r2) * da;
        }
    return e;
}

static double plane_irradiance(const vec3 x, float y_e, float cx, float cz, float side)
{
    return plane_irradiance_q(x, y_e, cx, cz, side, 400);
}

/* The VPLs of a uniform emitter of exitance M = 1 W/m² facing up at y_e:
 * the square [x0, x0 + side] × [z0, z0 + side] in steps of `a` (a VPL
 * carries M·a²). */
static GpuVpl *plane_vpls(float x0, float z0, float side, float a, float y_e, int *count)
{
    int per = (int)lroundf(side / a);
    GpuVpl *v = malloc(sizeof *v * (size_t)per * per);
    assert_non_null(v);
    for (int i = 0; i < per; i++)
        for (int j = 0; j < per; j++)
            v[i * per + j] = make_vpl((vec3){x0 + (i + 0.5f) * a, y_e, z0 + (j + 0.5f) * a}, (vec3){0.f, 1.f, 0.f},
                                      (vec3){a * a, a * a, a * a}, NULL);
    *count = per * per;
    return v;
}

/* Mean irradiance (green) over the pixels within `radius` of the image
 * centre: the receiver's middle. */
static double centre_irradiance(const Renderer *r, const float *e, int radius)
{
    int w = r->settings.width, h = r->settings.height;
    double sum = 0.0;
    int count = 0;
    for (int y = h / 2 - radius; y < h / 2 + radius; y++)
        for (int x = w / 2 - radius; x < w / 2 + radius; x++, count++)
            sum += e[4 * ((size_t)y * w + x) + 1];
    return sum / count;
}

/* The receiver's irradiance (the image's middle) from a uniform emitter at
 * y_e over cascade 0's grid of renderer r, injected and drawn, into *got,
 * and the closed form's there (the receiver at height y_r) into *want. */
static void plane_receives(Renderer *r, const Scene *s, float y_r, float y_e, double *got, double *want)
{
    int n = lpv_grid_size(r->gi_state), count;
    float o[3], cell;
    lpv_grid(r->gi_state, 0, o, &cell);
    GpuVpl *v = plane_vpls(o[0], o[2], n * cell, cell / 2.f, y_e, &count);
    lpv_set_vpls(r->gi_state, v, count);
    renderer_frame(r, &s->camera);
    float *e = read_irradiance(r);
    *got = centre_irradiance(r, e, 2);
    *want = plane_irradiance((vec3){0.f, y_r, 0.f}, y_e, o[0] + 0.5f * n * cell, o[2] + 0.5f * n * cell, n * cell);
    free(e);
    free(v);
}

/* A large uniform emitter (VPLs over the whole grid, M = 1) two cells below
 * the receiver, whose lookups read the cell between: the irradiance there
 * is the closed form's (nearly M: the emitter is 16 cells wide) within 10%,
 * for grids of 8, 16 and 32 cells (the cell sizes of three cascades, each
 * twice the last); and with 6 cells between (32³), still within 10%. The
 * paper's faces pass one cell away but give a fraction far off: the light
 * of a plane diffuses (a step turns 4/5 of it sideways) rather than
 * travelling on. */
static void lookup_uniform_plane(void **state)
{
    (void)state;
    const float y_r = 0.8f;
    Scene s;
    receiver_scene(&s, y_r, false, 0.2f);
    const int sizes[] = {8, 16, 32, 32, 32};
    double faces = 0.0;
    for (size_t k = 0; k < 5; k++) {
        GiParams gp = s.settings.gi;
        gp.lpv.size = sizes[k];
        gp.lpv.propagation = k < 4 ? LPV_PROPAGATION_DIRECTIONAL : LPV_PROPAGATION_FACES;
        float between = k < 3 ? 1.f : 6.f; /* cells between emitter and receiver */
        Renderer r;
        lpv_renderer(&r, &s, 32, 32, &gp);
        renderer_frame(&r, &s.camera);
        int n = lpv_grid_size(r.gi_state);
        float o[3], cell;
        lpv_grid(r.gi_state, 0, o, &cell);
        double got, want;
        plane_receives(&r, &s, y_r, y_r - (between + 1.f) * cell, &got, &want);
        print_message("uniform plane, %s %d³ (cells of %.3f m), %.0f cell(s) between: E = %.4f, closed form %.4f, "
                      "ratio %.3f\n",
                      k < 4 ? "directional" : "faces (paper)", n, cell, between, got, want, got / want);
        if (k < 4)
            assert_true(fabs(got / want - 1.0) < 0.1);
        else
            faces = got / want;
        renderer_destroy(&r);
    }
    assert_true(faces < 0.8); /* the baseline fails the check */
    scene_free(&s);
}

/* The same emitter and a receiver at 0.1 to 0.9 of a cell above the corner
 * plane two cells over the emitter: the irradiance must not depend on where
 * in its cell the receiver lies (the geometry volume blocks at the nearest
 * corner plane, so a surface in the lower half of its cell has that cell
 * behind its blocking plane: read half a cell along the normal, as the
 * paper does, it mixed in that dark cell, 1 − f of the light lost). */
static void lookup_anywhere_in_the_cell(void **state)
{
    (void)state;
    const float fracs[] = {0.1f, 0.3f, 0.45f, 0.6f, 0.9f};
    double lo = 1e30, hi = 0.0;
    for (size_t k = 0; k < sizeof fracs / sizeof fracs[0]; k++) {
        Scene s;
        receiver_scene(&s, 0.f, true, 0.2f); /* to learn the grid: the pins and the receiver's span set it */
        GiParams gp = s.settings.gi;
        gp.lpv.size = 16;
        Renderer r;
        lpv_renderer(&r, &s, 32, 32, &gp);
        renderer_frame(&r, &s.camera);
        float o[3], cell;
        lpv_grid(r.gi_state, 0, o, &cell);
        renderer_destroy(&r);
        scene_free(&s);
        /* The receiver at corner plane 6 + frac: the grid is the same (the
         * pins bound it in y). */
        float y_r = o[1] + (6.f + fracs[k]) * cell, y_e = o[1] + 4.f * cell;
        receiver_scene(&s, y_r, true, 0.2f);
        lpv_renderer(&r, &s, 32, 32, &gp);
        renderer_frame(&r, &s.camera);
        float o2[3], cell2;
        lpv_grid(r.gi_state, 0, o2, &cell2);
        assert_true(fabsf(o2[1] - o[1]) < 1e-5f && fabsf(cell2 - cell) < 1e-6f);
        double got, want;
        plane_receives(&r, &s, y_r, y_e, &got, &want);
        print_message("receiver at %.2f of its cell: E = %.4f, closed form %.4f, ratio %.3f\n", fracs[k], got, want,
                      got / want);
        lo = fmin(lo, got / want);
        hi = fmax(hi, got / want);
        renderer_destroy(&r);
        scene_free(&s);
    }
    assert_true(hi < 1.1 && lo > 0.9);
}

/* ---- Cascades ------------------------------------------------------------------ */

/* Nested grids (3 cascades of 8³ around the camera) count each VPL once:
 * a coarser cascade's "outer" volume holds exactly the VPLs outside the
 * next finer one (its flux plus the finer one's is the coarser one's
 * whole), and a uniform emitter 1.2 m below a receiver gives it, pixel by
 * pixel, the closed form's irradiance within 15%, with one grid and with 3
 * cascades, across an image that spans the finest cascade's border band
 * (where two cascades are blended, light counted twice or lost would
 * show). The emitter is as wide as the coarsest grid (VPLs outside a grid
 * are not in it). */
static void cascades_count_once(void **state)
{
    (void)state;
    const float y_r = 0.8f, y_e = y_r - 1.2f;
    Scene s;
    receiver_scene(&s, y_r, false, 0.45f);
    s.camera.fov_y = glm_rad(120.f);
    enum { W = 32 };
    for (int casc = 1; casc <= 3; casc += 2) {
        GiParams gp = s.settings.gi;
        gp.lpv.size = 8;
        gp.lpv.cascades = casc;
        Renderer r;
        lpv_renderer(&r, &s, W, W, &gp);
        int count;
        /* The emitter over 6 m (more than the coarsest grid), 4 VPLs per
         * finest cell. */
        GpuVpl *v = plane_vpls(-3.f, -3.f, 6.f, 0.0625f, y_e, &count);
        lpv_set_vpls(r.gi_state, v, count);
        renderer_frame(&r, &s.camera);
        for (int k = 1; k < casc; k++) {
            float *all = read_volume(&r, k, LPV_VOLUME_INJECTED), *outer = read_volume(&r, k, LPV_VOLUME_INJECTED_OUTER),
                  *finer = read_volume(&r, k - 1, LPV_VOLUME_INJECTED);
            double fa = volume_flux(&r, all, 1), fo = volume_flux(&r, outer, 1), ff = volume_flux(&r, finer, 1);
            print_message("cascade %d: all %.5f W = outer %.5f + cascade %d's %.5f (off by %.2g)\n", k, fa, fo, k - 1,
                          ff, fabs(fo + ff - fa) / fa);
            assert_true(fa > 0);
            assert_true(fabs(fo + ff - fa) < 1e-4 * fa);
            free(all);
            free(outer);
            free(finer);
        }
        float o[3], cell, fo[3], fcell;
        lpv_grid(r.gi_state, casc - 1, o, &cell);
        lpv_grid(r.gi_state, 0, fo, &fcell);
        float half_view = 0.45f * tanf(glm_rad(60.f));
        if (casc > 1) { /* the finest cascade's border crosses the view */
            print_message("finest cascade x from %.3f to %.3f m; the receiver in view spans about ±%.2f m\n", fo[0],
                          fo[0] + 8 * fcell, half_view);
            assert_true(fo[0] > -half_view);
        }
        float *e = read_irradiance(&r);
        double lo = 1e30, hi = 0.0;
        for (int y = 2; y < W - 2; y++)
            for (int x = 2; x < W - 2; x++) {
                vec3 d, q;
                camera_ray(&s.camera, W, W, x + 0.5f, (float)(W - 1 - y) + 0.5f, d);
                float t = (y_r - s.camera.position[1]) / d[1];
                for (int a = 0; a < 3; a++)
                    q[a] = s.camera.position[a] + t * d[a];
                double want = plane_irradiance_q(q, y_e, o[0] + 4.f * cell, o[2] + 4.f * cell, 8.f * cell, 100);
                double ratio = e[4 * ((size_t)y * W + x) + 1] / want;
                lo = fmin(lo, ratio);
                hi = fmax(hi, ratio);
            }
        print_message("%d cascade(s) of 8³ (coarsest cells of %.3f m): E / closed form over the receiver %.3f .. "
                      "%.3f\n",
                      casc, cell, lo, hi);
        assert_true(lo > 0.85 && hi < 1.15);
        free(e);
        free(v);
        renderer_destroy(&r);
    }
    scene_free(&s);
}

/* ---- One VPL in empty space ------------------------------------------------------- */

/* The exact irradiance from a VPL of flux 1 W with normal −y at p on the
 * floor point x: Φ/π · cosθ_vpl · cosθ_floor / d² = h² / (π d⁴). */
static double exact_e(const vec3 p, const vec3 x)
{
    double h = p[1] - x[1], d2 = glm_vec3_distance2((float *)p, (float *)x);
    return h * h / (GLM_PI * d2 * d2);
}

/* One VPL (normal down, 1 W) in empty space, 16³ (cells of 2/14 m), no
 * occlusion: the irradiance straight below at 3, 4, 5, 6 and 8 cells against
 * Φ/(π d²), and the power the floor in view receives against the exact.
 * Measured (directional): 1.96, 1.79, 1.52, 1.27, 0.92, the floor's power
 * 0.72 to 0.56: near the VPL too bright (its light fills whole cells, and a
 * cell's lobe is never narrower than a cosine, where the true field of a
 * point narrows with distance), within a factor 2.2 everywhere. The
 * paper's faces measured 1.24, 0.82, 0.50, 0.27, 0.056 and a floor power
 * falling from 0.63 to 0.013: its light turned sideways at every step and
 * spread in every direction, up included, rather than travelling on. */
static void one_vpl_inverse_square(void **state)
{
    (void)state;
    Scene s;
    open_scene(&s, false, 3.f);
    GiParams gp = s.settings.gi;
    gp.lpv.occlusion = false;
    const float cell = 2.f / 14.f;
    const int cells[] = {3, 4, 5, 6, 8};
    enum { W = 96 };
    double power_ratio[5];
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
        assert_true(ratio > 1 / 2.2 && ratio < 2.2);
        power_ratio[i] = lpv_power / exact_power;
        free(e);
        renderer_destroy(&r);
    }
    for (int i = 0; i < 5; i++)
        assert_true(power_ratio[i] > 0.5 && power_ratio[i] < 1.2);
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
    GiParams gp = open.settings.gi;
    gp.lpv.occlusion = false;
    Renderer r;
    float *e = render_one_vpl(&r, &open, &gp, 64, p);
    double free_e = irradiance_at(&r, e, below, 1);
    free(e);
    renderer_destroy(&r);
    e = render_one_vpl(&r, &walled, &gp, 64, p);
    double off = irradiance_at(&r, e, below, 1);
    free(e);
    renderer_destroy(&r);
    gp.lpv.occlusion = true;
    e = render_one_vpl(&r, &walled, &gp, 64, p);
    double on = irradiance_at(&r, e, below, 1);
    free(e);
    renderer_destroy(&r);
    /* The camera's G-buffer adds surfels (here the floor it sees): more
     * blockers can only block more. */
    gp.lpv.gbuffer_occlusion = true;
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
 * test_rsm.c), 16³ cells, 64² RSM, the default steps: relMSE against
 * one-bounce (the bounce occluded) and one-bounce-novis, and with 2
 * cascades (whose coarser grid holds the box); no GI for the bound's sake;
 * colour bleeding on the ceiling, its red/green ratio near each side wall
 * within 25% of the path tracer's. Measured: lpv 0.0020 / 0.0025, 2
 * cascades 0.0067, no GI 0.0360 / 0.0402: the bound 0.012 sits between;
 * ceiling R/G 2.62 and 1.63 (one-bounce 2.48, 1.49). The paper's faces
 * (16³, 8 steps) measured 0.0261 / 0.0271, and R/G 18.7 by the red wall,
 * 0.33 by the green one (tinted ceiling corners, the middle black). */
static void cornell_against_reference(void **state)
{
    (void)state;
    enum { W = 80, H = 80 };
    Scene s;
    scene_build_cornell(&s);
    scene_finalize(&s);
    scene_rescale_lights(&s, 0.f);
    s.settings.gi.rsm.size = 64;
    s.settings.gi.lpv.size = 16;
    ImageF lpv, none, ob, novis, casc;
    test_render_gi(&s, W, H, GI_LPV, NULL, &lpv);
    GiParams gp = s.settings.gi;
    gp.lpv.cascades = 2;
    test_render_gi(&s, W, H, GI_LPV, &gp, &casc);
    test_render_gi(&s, W, H, GI_NONE, NULL, &none);
    test_reference(&s, W, H, PT_ONE_BOUNCE, 256, &ob);
    test_reference(&s, W, H, PT_ONE_BOUNCE_NOVIS, 256, &novis);
    double l_ob = metric_relmse(&lpv, &ob, NULL, NULL), n_ob = metric_relmse(&none, &ob, NULL, NULL);
    double l_nv = metric_relmse(&lpv, &novis, NULL, NULL), n_nv = metric_relmse(&none, &novis, NULL, NULL);
    double c_ob = metric_relmse(&casc, &ob, NULL, NULL);
    const vec3 ceil_red = {0.52f, 0.5488f, 0.3f}, ceil_green = {0.04f, 0.5488f, 0.3f};
    double cr = red_over_green(&s, &lpv, ceil_red), cg = red_over_green(&s, &lpv, ceil_green);
    double rr = red_over_green(&s, &ob, ceil_red), rg = red_over_green(&s, &ob, ceil_green);
    print_message("relMSE vs one-bounce: lpv %.4f (2 cascades %.4f) none %.4f; vs one-bounce-novis: lpv %.4f "
                  "none %.4f; ceiling R/G red side %.3f green side %.3f (one-bounce: %.3f, %.3f)\n",
                  l_ob, c_ob, n_ob, l_nv, n_nv, cr, cg, rr, rg);
    assert_true(l_ob < LPV_CORNELL_BOUND && l_nv < LPV_CORNELL_BOUND && c_ob < LPV_CORNELL_BOUND);
    assert_true(n_ob > LPV_CORNELL_BOUND && n_nv > LPV_CORNELL_BOUND); /* the bound means something */
    assert_true(cr > 1.5 * cg);
    assert_true(fabs(cr / rr - 1.0) < 0.25 && fabs(cg / rg - 1.0) < 0.25);
    image_free(&lpv);
    image_free(&none);
    image_free(&ob);
    image_free(&novis);
    image_free(&casc);
    scene_free(&s);
}

/* ---- Sponza ---------------------------------------------------------------- */

/* The shipped scenes/sponza_nave.json (its LPV: 3 cascades of 32³ around
 * the camera, the coarsest on the scene) at 160×90 against the path
 * tracer's one bounce (64 spp at pixel centres): the indirect ratio of the
 * whole image within [0.75, 1.33], and every 16×9 block whose reference
 * bounce is above the median within [0.3, 3]. Measured 1.15, blocks
 * 0.348 .. 2.25 (seeds 2–4: 0.338 .. 0.353; at 16 spp 0.325 .. 0.357) (the CLI with PCSS 0.33 .. 2.42; 320×180, 64 spp: 1.13,
 * 0.36 .. 2.21; scripts/gi-regions.sh). With one grid (1 m cells; the
 * scene file before issue 44's second round) 1.04, blocks 0.20 .. 2.48
 * (320×180: 0.21 .. 2.22):
 * the lowest blocks are the bottom rows, surfaces within a few metres of
 * the camera beside the sunlit floor (the curtains' feet, a column's
 * base), which the 1 m cells under-light; the cascades' finer cells near
 * the camera lift them (2 cascades: 0.31). The paper's faces read the
 * whole image 3.9×, blocks up to 18× (the sunlit floor lighting its shaded
 * surroundings). Skipped where the asset is not present (as
 * test_sponza.c). */
static void sponza_against_one_bounce(void **state)
{
    (void)state;
    test_skip_without_sponza();
    const char *file = test_sponza_file();
    enum { W = 160, H = 90 };
    Scene s;
    assert_true(scene_load(&s, file));
    assert_int_equal(s.settings.gi.lpv.size, 32);
    assert_int_equal(s.settings.gi.lpv.cascades, 3);
    double whole, lo, hi;
    test_one_bounce_regions(&s, GI_LPV, W, H, "Sponza lpv", &whole, &lo, &hi);
    assert_true(whole > 0.75 && whole < 1.33);
    assert_true(lo > 0.3 && hi < 3.0);
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
    s.settings.gi.rsm.size = 32;
    GiParams gp = s.settings.gi;
    ImageF img;
    double dark[4], lit[4];
    const char *what[4] = {"16^3 occlusion off", "16^3", "32^3", "none"};
    for (int i = 0; i < 4; i++) {
        gp.lpv.size = i == 2 ? 32 : 16;
        gp.lpv.occlusion = i != 0;
        test_render_gi(&s, 64, 64, i == 3 ? GI_NONE : GI_LPV, &gp, &img);
        room_means(&s, &img, &dark[i], &lit[i]);
        print_message("leak scene, %s: dark room floor %.5f, lit room floor %.5f (ratio %.4f)\n", what[i], dark[i],
                      lit[i], dark[i] / lit[i]);
        image_free(&img);
    }
    assert_true(dark[3] < 1e-6);          /* the dark room has no direct light */
    assert_true(dark[0] > 0.01 * lit[0]); /* LPV leaks through the 2 cm wall... */
    assert_true(dark[1] < 0.5 * dark[0]); /* ...less with the geometry volume, */
    assert_true(dark[2] < 0.5 * dark[0]); /* at either grid size */
    scene_free(&s);
}

/* ---- Cascades follow the camera ------------------------------------------ */

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
    GiParams gp = s.settings.gi;
    gp.rsm.size = 32;
    gp.lpv.size = 16;
    gp.lpv.iterations = 8;
    gp.lpv.cascades = 3;
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
    rc = test_run_cli(&err, "render", "--gi", "lpv", "--lpv-groups", "3", NULL);
    test_expect_cli_error(rc, err, 2, "--lpv-groups", NULL);
    rc = test_run_cli(&err, "render", "--gi", "lpv", "--lpv-propagation", "sideways", NULL);
    test_expect_cli_error(rc, err, 2, "--lpv-propagation", NULL);
    const char *path = test_tmp_file("badlpv.json", "{ \"builtin\": \"cornell\", \"gi\": { \"lpv_size\": 0 } }\n");
    rc = test_run_cli(&err, "render", "--scene", path, NULL);
    test_expect_cli_error(rc, err, 1, "badlpv.json", "gi.lpv_size");
    /* In range, but about 27 GiB of volumes: refused by the GPU memory
     * budget (4 GiB by default) before anything is made, naming the
     * settings; it had gone on to allocate them. */
    unsetenv("RTGI_GPU_BUDGET_MIB");
    rc = test_run_cli(&err, "render", "--gi", "lpv", "--lpv-size", "256", "--lpv-cascades", "3", "--size", "8x8", NULL);
    test_expect_cli_error(rc, err, 1, "--lpv-size 256 with --lpv-cascades 3", "budget");
}

/* gi_memory_mib of `render --gi lpv --timings` as the settings call for
 * (the figure the budget check adds up before it makes them): per cascade
 * the injected and summed volumes, three RGBA32F N³ per colour set and
 * light group (2 by default; cascades past the first keep a second set
 * without the finer cascade's cells), and the geometry volume's two RGBA32F
 * (N+1)³; the propagation's two RGBA32F 3N·N·N; with occlusion the faces'
 * factors, RGBA32F 2N·N·N (directional, the default); with compute
 * injection the fixed-point sums, 12 words a cell and 6 a geometry corner;
 * the parameter block and the 16-byte indirect command. */
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
        double bytes = 16 * (sets * 2 * 3 * n3 * 2 + runs[k].cascades * 2 * g3 + 2 * 3 * n3);
        if (strcmp(runs[k].occlusion, "on") == 0)
            bytes += 16 * 2 * n3;
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
        cmocka_unit_test(injection_one_vpl_closed_form),
        cmocka_unit_test(injection_conserves_flux),
        cmocka_unit_test(directional_step_matches_cpu),
        cmocka_unit_test(propagation_free_space),
        cmocka_unit_test(propagation_closed_box),
        cmocka_unit_test(faces_step_matches_cpu),
        cmocka_unit_test(lookup_uniform_plane),
        cmocka_unit_test(lookup_anywhere_in_the_cell),
        cmocka_unit_test(cascades_count_once),
        cmocka_unit_test(one_vpl_inverse_square),
        cmocka_unit_test(wall_blocks_light),
        cmocka_unit_test(cornell_against_reference),
        cmocka_unit_test(sponza_against_one_bounce),
        cmocka_unit_test(leak_scene),
        cmocka_unit_test(cascades_snap),
        cmocka_unit_test(bad_lpv_settings),
        cmocka_unit_test(memory_as_the_settings_say),
    };
    return cmocka_run_group_tests_name("lpv", tests, test_gl_setup, test_gl_teardown);
}
