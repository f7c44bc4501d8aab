/* vis_split.c — where the VPL techniques' bounce goes with --gi-visibility
 * on (issue 47): the same VPLs summed three ways on the CPU, at the pixel
 * centres the path tracer sees (every `step`-th pixel):
 *   novis  Σ Φ/π·cosθ_p·cosθ_x/(d² + A/π): the papers' gather (vpl-all off)
 *   ism    the same, each term times its imperfect shadow map's depth test
 *          (the renderer's own maps, read back; ism.glsl's test in C)
 *   exact  each term times a ray cast (Embree: the path tracer's scene)
 * and the renderer's own vpl-all images off and on (the GPU's sums, to
 * check that ism/novis here is what the shader does). Against the path
 * tracer's one-bounce light (REF − DIRECT): exact/ref is the VPL set's
 * own error (sampling, the grid's aliasing), ism/exact the maps' error
 * (false occlusion, light through holes); both per image region, and the
 * maps' errors split by the distance from the VPL and by whether the
 * receiver lies in the 3×3×3 cells whose points the map takes densely.
 *
 * usage: vis_split SCENE REF.pfm DIRECT.pfm [--vpls N] [--step K]
 *        [--ism-size 0|1|2] [--ism-points N] [--gi TECH]
 * The images' size is the view measured. Not a test: a measuring tool built
 * beside the tests, sharing their helpers. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/camera.h"
#include "gi/visibility/ism.h"
#include "gl/gl_resources.h"
#include "reference/pt_scene.h"
#include "reference/sampling.h"
#include "frame/renderer.h"
#include "test_util.h"

typedef struct Vpl {
    float p[3], n[3], flux[3], area;
} Vpl;

typedef struct Job {
    const Scene *s;
    const PtScene *ps;
    const Vpl *vpls;
    uint32_t nv;
    const uint32_t *atlas;
    int atlas_w;
    GpuIsmParams ism;
    int w, h, step;
    int next_row;
    pthread_mutex_t lock;
    /* per pixel: indirect radiance luminance of novis, ism, exact */
    double *lum[3];
    /* the maps' errors: [bucket][0: false occlusion, 1: false visibility, 2: exact total] */
    double dist_err[8][3];
    double near_err[2][3];
    double rel_err[6]; /* false occlusion by stored depth / distance */
    double fv_stored[6]; /* false visibility by stored depth / distance */
    double fv_hit[6];    /* false visibility by the occluder's distance from the receiver / distance */
    double tan_err[5][2]; /* [receiver incidence tan bin][false occlusion, exact total] */
} Job;

static const float k_rel_edges[5] = {0.5f, 0.8f, 0.9f, 0.95f, 1.f};
static const float k_fv_edges[5] = {0.8f, 1.f, 1.2f, 2.f, 1e30f};
static const float k_hit_edges[5] = {0.05f, 0.1f, 0.2f, 0.4f, 0.7f};
static const float k_tan_edges[4] = {0.5f, 1.f, 2.f, 4.f};

static const float k_dist_edges[7] = {0.25f, 0.5f, 1.f, 2.f, 4.f, 8.f, 16.f};

/* The bin of v among n ascending edges: the first edge v does not pass, n
 * past the last. */
static int bin_of(float v, const float *edges, int n)
{
    int b = 0;
    while (b < n && v > edges[b])
        b++;
    return b;
}

static float dot3(const float *a, const float *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* ism.glsl's ism_visibility with ISM_SLOPE 2 (ISM_SLOPE in the environment
 * for trials with a shader built so), ISM_MAX_TAN 4. */
static float ism_vis(const Job *j, uint32_t m, const Vpl *v, const float x[3], const float nx[3], float *rel)
{
    *rel = 2.f;
    float d[3] = {x[0] - v->p[0], x[1] - v->p[1], x[2] - v->p[2]};
    float len = fmaxf(sqrtf(dot3(d, d)), 1e-12f), t[3], b[3];
    onb(v->n, t, b); /* common/math.glsl's basis */
    float l[3] = {dot3(d, t) / len, dot3(d, b) / len, dot3(d, v->n) / len};
    if (l[2] < 0.f)
        return 1.f;
    float uv[2] = {l[0] / (1.f + l[2]) * 0.5f + 0.5f, l[1] / (1.f + l[2]) * 0.5f + 0.5f};
    int size = j->ism.size, shift = 0;
    while ((1 << shift) < j->ism.per_row)
        shift++;
    int tx = (int)(m & (uint32_t)(j->ism.per_row - 1)) * size, ty = (int)(m >> shift) * size;
    int px = (int)(uv[0] * size), py = (int)(uv[1] * size);
    px = px < 0 ? 0 : px > size - 1 ? size - 1 : px;
    py = py < 0 ? 0 : py > size - 1 ? size - 1 : py;
    uint32_t bits = j->atlas[(size_t)(ty + py) * j->atlas_w + tx + px];
    float stored;
    memcpy(&stored, &bits, 4);
    float c[2] = {uv[0] * 2 - 1, uv[1] * 2 - 1};
    float cone = 4.f / ((float)size * (1.f + c[0] * c[0] + c[1] * c[1]));
    float cos_r = fabsf(dot3(nx, d)) / len, tan_r = fminf(sqrtf(fmaxf(1 - cos_r * cos_r, 0)) / fmaxf(cos_r, 1e-6f), 4.f);
    static float slope = -1;
    if (slope < 0)
        slope = getenv("ISM_SLOPE") ? (float)atof(getenv("ISM_SLOPE")) : 2.f;
    float bias = len * (slope * cone * tan_r + j->ism.bias_rel) + j->ism.bias_abs;
    *rel = stored / len;
    return len <= stored + bias ? 1.f : 0.f;
}

static void *work(void *arg)
{
    Job *j = arg;
    CameraRayBasis cam;
    camera_ray_basis(&j->s->camera, j->w, j->h, &cam);
    double dist_err[8][3] = {{0}}, near_err[2][3] = {{0}}, rel_err[6] = {0}, tan_err[5][2] = {{0}}, fv_stored[6] = {0}, fv_hit[6] = {0};
    float cell = j->ism.grid[3];
    for (;;) {
        pthread_mutex_lock(&j->lock);
        int y = j->next_row;
        j->next_row += j->step;
        pthread_mutex_unlock(&j->lock);
        if (y >= j->h)
            break;
        for (int x = 0; x < j->w; x += j->step) {
            vec3 dir;
            camera_ray_dir(&cam, (float)x + 0.5f, (float)y + 0.5f, dir);
            PtHit hit;
            if (!pt_intersect(j->ps, j->s->camera.position, dir, INFINITY, &hit))
                continue;
            vec3 albedo;
            pt_albedo(j->ps, &hit, albedo);
            double e[3][3] = {{0}};
            int xc[3];
            for (int k = 0; k < 3; k++)
                xc[k] = (int)floorf((hit.p[k] - j->ism.grid[k]) / cell);
            for (uint32_t i = 0; i < j->nv; i++) {
                const Vpl *v = &j->vpls[i];
                float d[3] = {hit.p[0] - v->p[0], hit.p[1] - v->p[1], hit.p[2] - v->p[2]};
                float d2 = fmaxf(dot3(d, d), 1e-12f), inv = 1.f / sqrtf(d2);
                float c = fmaxf(0.f, dot3(v->n, d) * inv) * fmaxf(0.f, -dot3(hit.ns, d) * inv);
                if (c <= 0.f)
                    continue;
                float f = c / GLM_PIf / (d2 + v->area / GLM_PIf);
                float rel;
                float vi = ism_vis(j, i, v, hit.p, hit.ns, &rel);
                /* the exact test: from the receiver (off its surface, on
                 * the VPL's side) to just short of the VPL */
                vec3 o, to = {-d[0] * inv, -d[1] * inv, -d[2] * inv}, ng;
                glm_vec3_copy(hit.ng, ng);
                if (glm_vec3_dot(ng, to) < 0.f)
                    glm_vec3_negate(ng);
                pt_offset(hit.p, ng, o);
                float len = sqrtf(d2), tmax = len - fmaxf(0.01f * len, 0.002f);
                float ve = tmax <= 0.f || !pt_occluded(j->ps, o, to, tmax) ? 1.f : 0.f;
                for (int ch = 0; ch < 3; ch++) {
                    double t = (double)v->flux[ch] * f;
                    e[0][ch] += t;
                    e[1][ch] += t * vi;
                    e[2][ch] += t * ve;
                }
                double lum = (0.2126 * v->flux[0] + 0.7152 * v->flux[1] + 0.0722 * v->flux[2]) * f *
                             (0.2126 * albedo[0] + 0.7152 * albedo[1] + 0.0722 * albedo[2]) / GLM_PI;
                int bin = bin_of(len, k_dist_edges, 7);
                int near = 1;
                for (int k = 0; k < 3; k++)
                    near &= abs(xc[k] - (int)floorf((v->p[k] - j->ism.grid[k]) / cell)) <= 1;
                double *de = dist_err[bin], *ne = near_err[near];
                float cr = fabsf(dot3(hit.ns, d)) * inv, tr = sqrtf(fmaxf(1.f - cr * cr, 0.f)) / fmaxf(cr, 1e-6f);
                int tb = bin_of(tr, k_tan_edges, 4);
                tan_err[tb][1] += lum * ve;
                if (ve > 0 && vi == 0) {
                    de[0] += lum;
                    ne[0] += lum;
                    int rb = bin_of(rel, k_rel_edges, 5);
                    rel_err[rb] += lum;
                    tan_err[tb][0] += lum;
                }
                if (ve == 0 && vi > 0) {
                    de[1] += lum;
                    ne[1] += lum;
                    int rb = bin_of(rel, k_fv_edges, 5);
                    fv_stored[rb] += lum;
                    PtHit oh;
                    float th = pt_intersect(j->ps, o, to, tmax, &oh) ? oh.t / len : 1.f;
                    int hb = bin_of(th, k_hit_edges, 5);
                    fv_hit[hb] += lum;
                }
                de[2] += lum * ve;
                ne[2] += lum * ve;
            }
            size_t at = (size_t)y * j->w + x;
            for (int k = 0; k < 3; k++) {
                float rad[3];
                for (int ch = 0; ch < 3; ch++)
                    rad[ch] = (float)(e[k][ch] * albedo[ch] / GLM_PI);
                j->lum[k][at] = luminance(rad);
            }
        }
    }
    pthread_mutex_lock(&j->lock);
    for (int b = 0; b < 8; b++)
        for (int k = 0; k < 3; k++)
            j->dist_err[b][k] += dist_err[b][k];
    for (int b = 0; b < 2; b++)
        for (int k = 0; k < 3; k++)
            j->near_err[b][k] += near_err[b][k];
    for (int b = 0; b < 6; b++) {
        j->rel_err[b] += rel_err[b];
        j->fv_stored[b] += fv_stored[b];
        j->fv_hit[b] += fv_hit[b];
    }
    for (int b = 0; b < 5; b++)
        for (int k = 0; k < 2; k++)
            j->tan_err[b][k] += tan_err[b][k];
    pthread_mutex_unlock(&j->lock);
    return NULL;
}

/* Renders s with technique gi (vpls, visibility `on`) into out; with `grab`,
 * also reads the VPLs back and builds the maps for them. */
static bool render(const Scene *s, int w, int h, GiMode gi, const GiParams *gp, bool on, ImageF *out, Job *grab)
{
    RenderSettings rs = test_settings(s, w, h, SHADOW_MODE_PCSS);
    rs.gi = gi;
    rs.set.gi = *gp;
    rs.set.gi.visibility.on = on;
    Renderer r;
    if (!renderer_create(&r, s, &rs))
        return false;
    renderer_frame(&r, &s->camera);
    bool ok = renderer_read_hdr(&r, out);
    if (ok && grab) {
        uint32_t count = 0;
        glGetNamedBufferSubData(r.lights.vpls.counters, 0, 4, &count);
        float *raw = malloc((size_t)count * 48 + 48);
        Vpl *v = calloc((size_t)count + 1, sizeof *v);
        glGetNamedBufferSubData(r.lights.vpls.vpls, 0, (GLsizeiptr)count * 48, raw);
        for (uint32_t i = 0; i < count; i++) {
            const float *q = raw + 12 * i;
            memcpy(v[i].p, q, 12);
            memcpy(v[i].flux, q + 4, 12);
            v[i].area = q[7];
            memcpy(v[i].n, q + 8, 12);
        }
        free(raw);
        grab->vpls = v;
        grab->nv = count;
        GiCreateInfo ci = {.scene = s, .params = &rs.set.gi, .lights = &r.lights, .programs = &r.programs,
                           .width = w, .height = h, .geometry_version = r.gpu_scene.version};
        Ism m;
        ok = ism_create(&m, ISM_FROM_VPLS, &ci);
        if (ok) {
            GiFrame f = {.scene = s, .gpu_scene = &r.gpu_scene, .camera = &s->camera, .params = &rs.set.gi,
                         .lights = &r.lights, .timer = &r.timer};
            ism_update(&m, &f);
            int sz[3];
            gl_texture_level_size(m.atlas, 0, sz);
            uint32_t *atlas = malloc(sizeof(uint32_t) * (size_t)sz[0] * sz[1]);
            glGetTextureImage(m.atlas, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, (GLsizei)(4 * (size_t)sz[0] * sz[1]),
                              atlas);
            grab->atlas = atlas;
            grab->atlas_w = sz[0];
            grab->ism = m.gpu;
            ism_destroy(&m);
        }
    }
    renderer_destroy(&r);
    return ok;
}

static double sum_lum(const ImageF *a, const ImageF *b, int step, int x0, int x1, int y0, int y1)
{
    double s = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++)
            if (x % step == 0 && y % step == 0) {
                size_t i = (size_t)y * a->width + x;
                s += luminance(a->rgb + 3 * i) - (b ? luminance(b->rgb + 3 * i) : 0.f);
            }
    return s;
}

static double sum_cpu(const double *l, int w, int step, int x0, int x1, int y0, int y1)
{
    double s = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++)
            if (x % step == 0 && y % step == 0)
                s += l[(size_t)y * w + x];
    return s;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: vis_split SCENE REF.pfm DIRECT.pfm [--vpls N] [--step K] [--ism-size 0|1|2] "
                        "[--ism-points N] [--gi TECH]\n");
        return 2;
    }
    Scene s;
    if (!scene_load(&s, argv[1]))
        return 1;
    ImageF ref, direct;
    if (!image_read(argv[2], &ref) || !image_read(argv[3], &direct))
        return 1;
    int w = ref.width, h = ref.height, step = 2;
    GiParams gp = s.settings.gi;
    GiMode gi = GI_VPL_ALL;
    for (int i = 4; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--vpls") == 0)
            gp.vpl.count = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--step") == 0)
            step = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--ism-size") == 0)
            gp.visibility.ism_size = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--ism-points") == 0)
            gp.visibility.ism_points = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--gi") == 0)
            gi = (GiMode)gi_technique_find(argv[i + 1]);
        else {
            fprintf(stderr, "vis_split: unknown argument %s\n", argv[i]);
            return 2;
        }
    }
    if (!gl_context_create(false))
        return 1;
    ImageF none, off, on;
    Job j = {.s = &s, .w = w, .h = h, .step = step};
    if (!render(&s, w, h, GI_NONE, &gp, false, &none, NULL) || !render(&s, w, h, gi, &gp, false, &off, NULL) ||
        !render(&s, w, h, gi, &gp, true, &on, &j))
        return 1;
    PtScene ps;
    if (!pt_scene_create(&ps, &s))
        return 1;
    j.ps = &ps;
    for (int k = 0; k < 3; k++)
        j.lum[k] = calloc((size_t)w * h, sizeof(double));
    pthread_mutex_init(&j.lock, NULL);
    pthread_t th[2];
    for (int t = 0; t < 2; t++)
        pthread_create(&th[t], NULL, work, &j);
    for (int t = 0; t < 2; t++)
        pthread_join(th[t], NULL);
    printf("%s %dx%d, %u VPLs, every %d-th pixel; maps %d² with %u + %u points\n", argv[1], w, h, j.nv, step,
           j.ism.size, j.ism.far_points, j.ism.near_points);
    printf("| region | ref bounce | GPU off/ref | GPU on/ref | CPU novis/ref | ism/ref | exact/ref | GPU on/off | "
           "ism/novis | exact/novis | ism/exact |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    int gx = 4, gy = 3;
    for (int r = -1; r < gx * gy; r++) {
        int x0 = r < 0 ? 0 : (r % gx) * w / gx, x1 = r < 0 ? w : (r % gx + 1) * w / gx;
        int y0 = r < 0 ? 0 : (r / gx) * h / gy, y1 = r < 0 ? h : (r / gx + 1) * h / gy;
        double rb = sum_lum(&ref, &direct, step, x0, x1, y0, y1), go = sum_lum(&off, &none, step, x0, x1, y0, y1),
               gn = sum_lum(&on, &none, step, x0, x1, y0, y1), cn = sum_cpu(j.lum[0], w, step, x0, x1, y0, y1),
               ci = sum_cpu(j.lum[1], w, step, x0, x1, y0, y1), ce = sum_cpu(j.lum[2], w, step, x0, x1, y0, y1);
        char name[32];
        if (r < 0)
            snprintf(name, sizeof name, "whole");
        else
            snprintf(name, sizeof name, "col %d row %d", r % gx, r / gx);
        printf("| %s | %.3g | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |\n", name, rb, go / rb,
               gn / rb, cn / rb, ci / rb, ce / rb, gn / go, ci / cn, ce / cn, ci / ce);
    }
    double tot = 0;
    for (int b = 0; b < 8; b++)
        tot += j.dist_err[b][2];
    printf("\nThe maps' errors, as fractions of the exact visible bounce (%.4g):\n\n| VPL distance | exact share | "
           "false occlusion | false visibility |\n|---|---|---|---|\n",
           tot);
    for (int b = 0; b < 8; b++)
        printf("| %s%.2g m | %.3f | %.3f | %.3f |\n", b < 7 ? "< " : "≥ ", k_dist_edges[b < 7 ? b : 6],
               j.dist_err[b][2] / tot, j.dist_err[b][0] / tot, j.dist_err[b][1] / tot);
    for (int b = 0; b < 2; b++)
        printf("| %s | %.3f | %.3f | %.3f |\n", b ? "near cells" : "far cells", j.near_err[b][2] / tot,
               j.near_err[b][0] / tot, j.near_err[b][1] / tot);
    printf("\nFalse occlusion by the map's stored depth over the distance:");
    for (int b = 0; b < 6; b++)
        printf(" %s%.2g: %.3f", b < 5 ? "<" : ">", k_rel_edges[b < 5 ? b : 4], j.rel_err[b] / tot);
    printf("\nFalse visibility by the map's stored depth over the distance:");
    for (int b = 0; b < 6; b++)
        printf(" %s%.2g: %.3f", b < 5 ? "<" : ">", k_fv_edges[b < 5 ? b : 4], j.fv_stored[b] / tot);
    printf("\nFalse visibility by the occluder's distance from the receiver over the distance:");
    for (int b = 0; b < 6; b++)
        printf(" %s%.2g: %.3f", b < 5 ? "<" : ">", k_hit_edges[b < 5 ? b : 4], j.fv_hit[b] / tot);
    printf("\nBy the receiver's incidence tan (exact share, false occlusion):");
    for (int b = 0; b < 5; b++)
        printf(" %s%.2g: %.3f %.3f", b < 4 ? "<" : ">", k_tan_edges[b < 4 ? b : 3], j.tan_err[b][1] / tot,
               j.tan_err[b][0] / tot);
    printf("\n");
    return 0;
}
