/* vct_probe.c — where one pixel's vct light goes missing (issue 44): the
 * scene's vct frame at W×H, then at image pixel (X, Y) (row 0 = top) the
 * surface point and normal of the G-buffer, and for each cone of the
 * diffuse set (vct_cone_set) three estimates of the radiance arriving over
 * the cone's cell of the hemisphere:
 *   truth   rays of the cell (cosine-weighted) through the path tracer's
 *           scene, each returning the diffuse radiance the first hit sends
 *           back under the scene's directional and quad lights (shadow
 *           rays, 8×8 points on a quad; glossy reflection and other lights
 *           left out);
 *   narrow  the same rays as cones of tan(half-angle) 0.02 through the
 *           volumes (vct_probe: what the voxels hold along the rays);
 *   cone    the cone itself (what the frame's trace reads).
 * Each cell's weight is ∫cosθ dω over it; the sums are irradiance (W/m²).
 * A cone whose `narrow` matches `truth` but whose `cone` does not loses
 * its light in the wide cone's mips; a `narrow` far from `truth` points at
 * the voxels (voxelization, injection).
 *
 * usage: vct_probe SCENE WxH X Y [RAYS] [--tan T] [--dir DX DY DZ]
 * (2·RAYS rays per cone on average, RAYS 256 unless told; --tan: trace the cones with this
 * tan(half-angle) instead of the set's; --dir: one extra cone along
 * (DX, DY, DZ) in the surface's frame (z = normal), printed with its
 * opacity over tan(half-angle) 0.02-0.7 beside the mean of the ray casts
 * inside each.) Environment: VCT_PROBE_MAP=1 also prints the hemisphere
 * (ray casts | narrow cones) as text; VCT_PROBE_SHADERS=DIR reads the
 * shaders from DIR (render --shader-dir); VCT_PROBE_TMAX=1 with --dir
 * traces that cone to growing distances, which needs a copy of
 * gi/vct/probe.comp in DIR that ends each cone at floor(w / 10) / 100 m
 * (w: the probe's tan field; tan = mod(w, 10)). Example (the arcade
 * soffit of issue 44):
 *   build/tests/vct_probe scenes/sponza_nave.json 320x180 270 30 64
 * Not a test: a measuring tool built beside the tests, sharing their
 * helpers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"
#include "frame/renderer.h"
#include "gi/vct/vct.h"
#include "gl/shader.h"
#include "reference/pt_scene.h"

/* common/math.glsl's basis(). */
static void basis(const vec3 n, vec3 t, vec3 b)
{
    float s = n[2] >= 0.f ? 1.f : -1.f, a = -1.f / (s + n[2]), c = n[0] * n[1] * a;
    t[0] = 1.f + s * n[0] * n[0] * a, t[1] = s * c, t[2] = -s * n[0];
    b[0] = c, b[1] = s + n[1] * n[1] * a, b[2] = -n[1];
}

static void to_world(const vec3 t, const vec3 b, const vec3 n, const float l[3], vec3 out)
{
    for (int k = 0; k < 3; k++)
        out[k] = t[k] * l[0] + b[k] * l[1] + n[k] * l[2];
    glm_vec3_normalize(out);
}

static float lum(const float *c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

/* Diffuse radiance the first hit along o + t·d sends back (luminance). */
static float truth_ray(const PtScene *ps, const Scene *s, const vec3 o, const vec3 d)
{
    PtHit h;
    if (!pt_intersect(ps, o, d, 1e30f, &h))
        return 0.f;
    BrdfSurface surf;
    pt_surface(ps, &h, &surf);
    vec3 p;
    pt_offset(h.p, h.ng, p);
    float l = 0.f;
    for (int i = 0; i < s->light_count; i++) {
        const Light *li = &s->lights[i];
        if (li->type == LIGHT_QUAD) { /* 8×8 stratified points, L cosθ cosθ' A / d² */
            vec3 u, v, nl;
            glm_vec3_scale((float *)li->quad_u, li->size, u);
            glm_vec3_scale((float *)li->quad_v, li->size, v);
            glm_vec3_cross(u, v, nl);
            float area = glm_vec3_norm(nl);
            double e = 0;
            for (int a = 0; a < 8; a++)
                for (int bb = 0; bb < 8; bb++) {
                    vec3 q, to;
                    for (int c = 0; c < 3; c++)
                        q[c] = li->position[c] + ((a + 0.5f) / 8 - 0.5f) * u[c] + ((bb + 0.5f) / 8 - 0.5f) * v[c];
                    glm_vec3_sub(q, p, to);
                    float d2 = glm_vec3_norm2(to), dd = sqrtf(d2);
                    glm_vec3_scale(to, 1.f / dd, to);
                    float c1 = glm_vec3_dot(h.ns, to), c2 = -glm_vec3_dot((float *)li->direction, to);
                    if (c1 <= 0.f || c2 <= 0.f || glm_vec3_dot(h.ng, to) <= 0.f || pt_occluded(ps, p, to, dd * 0.999f))
                        continue;
                    e += c1 * c2 * area / d2 / 64.0;
                }
            l += lum(surf.diffuse) / GLM_PIf * lum(li->color) * (float)e;
            continue;
        }
        if (li->type != LIGHT_DIRECTIONAL)
            continue;
        vec3 to = {-li->direction[0], -li->direction[1], -li->direction[2]};
        float c = glm_vec3_dot(h.ns, to);
        if (c <= 0.f || glm_vec3_dot(h.ng, to) <= 0.f || pt_occluded(ps, p, to, 1e30f))
            continue;
        l += lum(surf.diffuse) / GLM_PIf * lum(li->color) * c;
    }
    return l;
}

int main(int argc, char **argv)
{
    if (argc < 5) {
        fprintf(stderr, "usage: vct_probe SCENE WxH X Y [RAYS] [--tan T] [--dir DX DY DZ]\n");
        return 2;
    }
    int w, h, px = atoi(argv[3]), py = atoi(argv[4]), rays = 256;
    float tan_override = 0.f, dir[3] = {0};
    bool extra = false;
    if (sscanf(argv[2], "%dx%d", &w, &h) != 2)
        return 2;
    for (int i = 5; i < argc; i++) {
        if (strcmp(argv[i], "--tan") == 0 && i + 1 < argc)
            tan_override = (float)atof(argv[++i]);
        else if (strcmp(argv[i], "--dir") == 0 && i + 3 < argc) {
            for (int k = 0; k < 3; k++)
                dir[k] = (float)atof(argv[++i]);
            extra = true;
        } else
            rays = atoi(argv[i]);
    }
    test_gl_setup(NULL);
    if (getenv("VCT_PROBE_SHADERS")) /* edited shaders (a debug copy) */
        shader_set_directory(getenv("VCT_PROBE_SHADERS"));
    Scene s;
    if (!scene_load(&s, argv[1]))
        return 1;
    RenderSettings rs = test_settings(&s, w, h, SHADOW_MODE_HARD);
    rs.gi = GI_VCT;
    rs.set.gi = s.settings.gi;
    Renderer r;
    if (!renderer_create(&r, &s, &rs))
        return 1;
    renderer_frame(&r, &s.camera);
    TestGbPixel g;
    test_gbuffer_pixel(&r.gbuffer, px, h - 1 - py, &g);
    if (!g.valid) {
        fprintf(stderr, "vct_probe: no surface at %d %d\n", px, py);
        return 1;
    }
    int n;
    float origin[3], voxel;
    vct_grid(r.gi_state, &n, origin, &voxel);
    printf("pixel %d %d: x (%.3f %.3f %.3f) n (%.3f %.3f %.3f), voxel %.4f m, N %d\n", px, py, g.position[0],
           g.position[1], g.position[2], g.normal[0], g.normal[1], g.normal[2], voxel, n);
    float dirs[VCT_MAX_CONES][4], tan_half[VCT_MAX_CONES];
    int cones = vct_cone_set(s.settings.gi.vct.cones, dirs, tan_half);
    vec3 t, b;
    basis(g.normal, t, b);
    PtScene ps;
    if (!pt_scene_create(&ps, &s))
        return 1;
    vec3 o;
    pt_offset(g.position, g.normal, o);
    /* Rays: cosine-weighted, stratified, each in the cell of its nearest cone. */
    int total = rays * cones * 2;
    double *sum_truth = calloc(VCT_MAX_CONES, sizeof(double)), *sum_narrow = calloc(VCT_MAX_CONES, sizeof(double));
    int *count = calloc(VCT_MAX_CONES, sizeof(int));
    VctProbe *probe = calloc((size_t)total + VCT_MAX_CONES + 1, sizeof *probe);
    int *cell = calloc((size_t)total, sizeof(int));
    float (*out)[4] = calloc((size_t)total + VCT_MAX_CONES + 1, sizeof *out);
    int side = (int)sqrt((double)total);
    int k = 0;
    for (int i = 0; i < side; i++)
        for (int j = 0; j < side; j++) {
            float u1 = ((float)i + 0.5f) / (float)side, u2 = ((float)j + 0.5f) / (float)side;
            float rr = sqrtf(u1), ph = 2.f * GLM_PIf * u2;
            float l[3] = {rr * cosf(ph), rr * sinf(ph), sqrtf(fmaxf(1.f - u1, 0.f))};
            int best = 0;
            float bd = -2.f;
            for (int c = 0; c < cones; c++) {
                float dd = l[0] * dirs[c][0] + l[1] * dirs[c][1] + l[2] * dirs[c][2];
                if (dd > bd)
                    bd = dd, best = c;
            }
            cell[k] = best;
            VctProbe *p = &probe[k];
            glm_vec3_copy(g.position, p->x);
            glm_vec3_copy(g.normal, p->n);
            to_world(t, b, g.normal, l, p->d);
            p->tan_half = 0.02f;
            sum_truth[best] += truth_ray(&ps, &s, o, p->d);
            count[best]++;
            k++;
        }
    for (int c = 0; c < cones; c++) {
        VctProbe *p = &probe[k + c];
        glm_vec3_copy(g.position, p->x);
        glm_vec3_copy(g.normal, p->n);
        to_world(t, b, g.normal, dirs[c], p->d);
        p->tan_half = tan_override > 0.f ? tan_override : tan_half[c];
    }
    static const float sweep[] = {0.02f, 0.05f, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.7f};
    enum { SWEEP = sizeof sweep / sizeof sweep[0] };
    if (extra) {
        glm_vec3_normalize(dir);
        for (int i = 0; i < SWEEP; i++) {
            VctProbe *p = &probe[k + cones + i];
            glm_vec3_copy(g.position, p->x);
            glm_vec3_copy(g.normal, p->n);
            to_world(t, b, g.normal, dir, p->d);
            p->tan_half = sweep[i];
        }
    }
    enum { TSTEPS = 40 };
    int tsweep = extra && getenv("VCT_PROBE_TMAX") ? TSTEPS : 0;
    for (int i = 0; i < tsweep; i++) {
        VctProbe *p = &probe[k + cones + SWEEP + i];
        *p = probe[k + cones];
        /* A debug copy of probe.comp decodes tmax = floor(w / 10) / 100. */
        p->tan_half = (tan_override > 0.f ? tan_override : 0.2f) + 10.f * (float)(15 * (i + 1));
    }
    if (!vct_probe(r.gi_state, k + cones + (extra ? SWEEP : 0) + tsweep, probe, out))
        return 1;
    double e_truth = 0, e_narrow = 0, e_cone = 0;
    for (int i = 0; i < k; i++)
        sum_narrow[cell[i]] += lum(out[i]);
    printf("cone  theta  phi   weight tan   | truth L   narrow L  cone L   opacity | cone/truth | world dir\n");
    for (int c = 0; c < cones; c++) {
        double lt = count[c] ? sum_truth[c] / count[c] : 0, ln = count[c] ? sum_narrow[c] / count[c] : 0;
        double lc = lum(out[k + c]);
        double th = acos(dirs[c][2]) * 180 / GLM_PI, ph = atan2(dirs[c][1], dirs[c][0]) * 180 / GLM_PI;
        printf("%4d %6.1f %6.1f %6.3f %5.3f | %8.4f %8.4f %8.4f  %6.3f | %6.2f | %6.3f %6.3f %6.3f\n", c, th, ph,
               dirs[c][3], probe[k + c].tan_half, lt, ln, lc, out[k + c][3], lt > 0 ? lc / lt : 0, probe[k + c].d[0],
               probe[k + c].d[1], probe[k + c].d[2]);
        e_truth += dirs[c][3] * lt, e_narrow += dirs[c][3] * ln, e_cone += dirs[c][3] * lc;
    }
    printf("irradiance (luminance): truth %.4f narrow %.4f cones %.4f  (cones/truth %.3f, narrow/truth %.3f)\n",
           e_truth, e_narrow, e_cone, e_cone / e_truth, e_narrow / e_truth);
    if (extra) {
        vec3 wd;
        to_world(t, b, g.normal, dir, wd);
        PtHit hh;
        bool hit = pt_intersect(&ps, o, wd, 1e30f, &hh);
        printf("extra cone (%.2f %.2f %.2f), world (%.3f %.3f %.3f): truth L %.4f, hit at t %.3f (%.2f %.2f %.2f) n (%.2f %.2f %.2f)\n",
               dir[0], dir[1], dir[2], wd[0], wd[1], wd[2], truth_ray(&ps, &s, o, wd), hit ? hh.t : -1.f, hh.p[0],
               hh.p[1], hh.p[2], hh.ng[0], hh.ng[1], hh.ng[2]);
        /* Every surface the axis crosses. */
        PtHit all[16];
        int nh = pt_intersect_all(&ps, o, wd, 1e30f, all, 16);
        for (int i = 0; i < nh; i++)
            printf("    crosses t %.3f at (%.2f %.2f %.2f), material %s\n", all[i].t, all[i].p[0], all[i].p[1],
                   all[i].p[2], s.materials[all[i].material].name);
        vec3 et, eb;
        basis(wd, et, eb);
        for (int i = 0; i < SWEEP; i++) {
            /* The rays of the cone, uniform in solid angle: their mean L. */
            double sum = 0;
            int m = 0;
            float cos_a = 1.f / sqrtf(1.f + sweep[i] * sweep[i]);
            for (int a = 0; a < 24; a++)
                for (int bb = 0; bb < 24; bb++) {
                    float u1 = (a + 0.5f) / 24, u2 = (bb + 0.5f) / 24;
                    float ct = 1 - u1 * (1 - cos_a), st = sqrtf(1 - ct * ct), ph = 2 * GLM_PIf * u2;
                    float l[3] = {st * cosf(ph), st * sinf(ph), ct};
                    vec3 rd;
                    to_world(et, eb, wd, l, rd);
                    if (glm_vec3_dot(rd, g.normal) <= 0)
                        continue;
                    sum += truth_ray(&ps, &s, o, rd);
                    m++;
                }
            printf("  tan %.2f: L %.4f opacity %.3f   (rays of the cone: L %.4f)\n", sweep[i], lum(out[k + cones + i]),
                   out[k + cones + i][3], m ? sum / m : 0);
        }
        for (int i = 0; i < tsweep; i++)
            printf("  to t %.2f: L %.4f opacity %.3f\n", 0.15f * (float)(i + 1),
                   lum(out[k + cones + SWEEP + i]), out[k + cones + SWEEP + i][3]);
    }
    if (getenv("VCT_PROBE_MAP")) {
        /* The hemisphere seen from above (x right = t, y up = b; disk radius =
         * sinθ): truth | narrow, luminance in steps of the brightest cell. */
        enum { M = 41 };
        static float tm[M][M], nm[M][M];
        static VctProbe mp[M * M];
        static float mo[M * M][4];
        int mk = 0;
        for (int yy = 0; yy < M; yy++)
            for (int xx = 0; xx < M; xx++) {
                float l[3] = {(xx + 0.5f) / M * 2 - 1, 1 - (yy + 0.5f) / M * 2, 0};
                float r2 = l[0] * l[0] + l[1] * l[1];
                tm[yy][xx] = -1;
                if (r2 >= 1)
                    continue;
                l[2] = sqrtf(1 - r2);
                VctProbe *p = &mp[mk++];
                glm_vec3_copy(g.position, p->x);
                glm_vec3_copy(g.normal, p->n);
                to_world(t, b, g.normal, l, p->d);
                p->tan_half = 0.02f;
                tm[yy][xx] = truth_ray(&ps, &s, o, p->d);
            }
        vct_probe(r.gi_state, mk, mp, mo);
        float mx = 1e-9f;
        mk = 0;
        for (int yy = 0; yy < M; yy++)
            for (int xx = 0; xx < M; xx++)
                if (tm[yy][xx] >= 0) {
                    nm[yy][xx] = lum(mo[mk]) + 10 * (mo[mk][3] < 0.5f); /* 10+: no hit */
                    mk++;
                    mx = fmaxf(mx, tm[yy][xx]);
                }
        const char *ramp = " .:-=+*#%@";
        for (int yy = 0; yy < M; yy++) {
            for (int xx = 0; xx < M; xx++)
                putchar(tm[yy][xx] < 0 ? ' ' : ramp[(int)fminf(tm[yy][xx] / mx * 9.99f, 9)]);
            printf("   ");
            for (int xx = 0; xx < M; xx++)
                putchar(tm[yy][xx] < 0 ? ' ' : nm[yy][xx] >= 10 ? 'o' : ramp[(int)fminf(nm[yy][xx] / mx * 9.99f, 9)]);
            putchar('\n');
        }
        printf("t = (%.2f %.2f %.2f) right, b = (%.2f %.2f %.2f) up; max L %.4f; o: the narrow cone hit nothing\n", t[0],
               t[1], t[2], b[0], b[1], b[2], mx);
    }
    pt_scene_destroy(&ps);
    renderer_destroy(&r);
    scene_free(&s);
    return 0;
}
