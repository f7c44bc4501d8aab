#include "test_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/brdf.h"
#include "core/camera.h"
#include "base/util.h"

static GlContext *g_test_gl;

int test_gl_setup(void **state)
{
    (void)state;
    g_test_gl = gl_context_create(false);
    return g_test_gl ? 0 : -1;
}

/* The first error GL recorded since the last call (GL_NO_ERROR: none); the
 * others are cleared, so that one failure is reported once. */
static GLenum take_gl_error(void)
{
    GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        while (glGetError() != GL_NO_ERROR) {
        }
    return e;
}

int test_gl_teardown(void **state)
{
    (void)state;
    /* The whole group's GL calls, including those outside test_render:
     * an error left recorded fails the group. */
    GLenum e = g_test_gl ? take_gl_error() : GL_NO_ERROR;
    if (e != GL_NO_ERROR)
        print_error("GL error 0x%x left recorded by this test program (rtgi render --debug names the call)\n",
                    (unsigned)e);
    gl_context_destroy(g_test_gl);
    g_test_gl = NULL;
    if (e != GL_NO_ERROR) /* cmocka prints a failed group teardown but does not count it in its exit status */
        exit(EXIT_FAILURE);
    return 0;
}

RenderSettings test_settings(const Scene *s, int w, int h, ShadowMode mode)
{
    RenderSettings rs = {0};
    rs.width = w;
    rs.height = h;
    rs.shadow = mode;
    rs.gi = GI_NONE;
    rs.exposure = s->exposure;
    rs.set.shadow = s->settings.shadow;
    return rs;
}

RenderStats test_render_gi(const Scene *s, int w, int h, GiMode gi, const GiParams *gp, ImageF *out)
{
    RenderSettings rs = test_settings(s, w, h, SHADOW_MODE_HARD);
    rs.gi = gi;
    rs.set.gi = gp ? *gp : s->settings.gi;
    Renderer r;
    assert_true(renderer_create(&r, s, &rs));
    renderer_frame(&r, &s->camera);
    assert_true(renderer_read_hdr(&r, out));
    RenderStats st = *renderer_collect_stats(&r);
    renderer_destroy(&r);
    test_expect_no_gl_error("test_render_gi");
    return st;
}

void test_reference_var(const Scene *s, int w, int h, PtMode mode, int spp, bool jitter, ImageF *out, ImageF *var)
{
    PtSettings set;
    pt_settings_default(&set);
    set.width = w;
    set.height = h;
    set.spp = spp;
    set.mode = mode;
    set.pixel_jitter = jitter;
    set.threads = 2;
    assert_true(pt_render(s, &set, out, var, NULL));
}

void test_reference_ex(const Scene *s, int w, int h, PtMode mode, int spp, bool jitter, ImageF *out)
{
    test_reference_var(s, w, h, mode, spp, jitter, out, NULL);
}

void test_reference(const Scene *s, int w, int h, PtMode mode, int spp, ImageF *out)
{
    test_reference_ex(s, w, h, mode, spp, false, out); /* the rasterizer shades pixel centres */
}

bool test_pixel_plane_point(const Scene *s, int w, int h, int x, int y, vec3 p)
{
    vec3 d;
    camera_ray(&s->camera, w, h, (float)x + 0.5f, (float)y + 0.5f, d);
    float t = -s->camera.position[1] / d[1];
    for (int i = 0; i < 3; i++)
        p[i] = s->camera.position[i] + t * d[i];
    return d[1] < 0 && s->camera.position[1] > 0;
}

float test_plane_radiance(const Scene *s, int w, int h, int x, int y, const Light *l, float albedo, vec3 want)
{
    vec3 p, to_l;
    test_pixel_plane_point(s, w, h, x, y, p);
    glm_vec3_sub((float *)l->position, p, to_l);
    float dist2 = glm_vec3_norm2(to_l), cos_t = to_l[1] / sqrtf(dist2);
    for (int c = 0; c < 3; c++)
        want[c] = albedo * l->color[c] * cos_t / (GLM_PIf * dist2);
    return cos_t * sqrtf(dist2);
}

double test_image_mean(const ImageF *img)
{
    double m = 0;
    for (long i = 0; i < (long)img->width * img->height; i++)
        m += luminance(img->rgb + 3 * i);
    return m / ((double)img->width * img->height);
}

int test_surface_mask(const Scene *s, int w, int h, const char *material, int face, uint8_t *mask)
{
    int m = -1;
    for (int i = 0; i < s->material_count && m < 0; i++)
        if (strcmp(s->materials[i].name, material) == 0)
            m = i;
    if (m < 0)
        fail_msg("test_surface_mask: the scene has no material '%s'", material);
    int32_t *ids = malloc(sizeof *ids * (size_t)w * (size_t)h);
    assert_non_null(ids);
    assert_true(pt_surface_map(s, w, h, ids));
    int count = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int32_t id = ids[(size_t)y * w + x];
            bool in = id >= 0 && id / 6 == m && (face < 0 || id % 6 == face);
            for (int dy = -1; dy <= 1 && in; dy++)
                for (int dx = -1; dx <= 1 && in; dx++) {
                    int u = x + dx, v = y + dy;
                    in = u >= 0 && v >= 0 && u < w && v < h && ids[(size_t)v * w + u] == id;
                }
            mask[(size_t)y * w + x] = in;
            count += in;
        }
    free(ids);
    return count;
}

double test_indirect_ratio(const ImageF *tech, const ImageF *none, const ImageF *ref, const ImageF *direct,
                           const uint8_t *mask)
{
    double num = 0, den = 0;
    for (size_t i = 0; i < (size_t)tech->width * tech->height; i++) {
        if (mask && !mask[i])
            continue;
        num += luminance(tech->rgb + 3 * i) - luminance(none->rgb + 3 * i);
        den += luminance(ref->rgb + 3 * i) - luminance(direct->rgb + 3 * i);
    }
    return num / den;
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void test_block_ratio_range(const ImageF *tech, const ImageF *none, const ImageF *ref, const ImageF *direct, int bx,
                            int by, double *lo, double *hi)
{
    int w = tech->width, h = tech->height, n = bx * by;
    double *num = calloc((size_t)n, sizeof *num), *den = calloc((size_t)n, sizeof *den),
           *sorted = malloc(sizeof *sorted * (size_t)n);
    assert_true(num && den && sorted);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            int b = (y * by / h) * bx + x * bx / w;
            num[b] += luminance(tech->rgb + 3 * i) - luminance(none->rgb + 3 * i);
            den[b] += luminance(ref->rgb + 3 * i) - luminance(direct->rgb + 3 * i);
        }
    memcpy(sorted, den, sizeof *sorted * (size_t)n);
    qsort(sorted, (size_t)n, sizeof *sorted, compare_double);
    double median = sorted[n / 2];
    *lo = INFINITY;
    *hi = -INFINITY;
    for (int b = 0; b < n; b++)
        if (den[b] > median && den[b] > 0) {
            *lo = fmin(*lo, num[b] / den[b]);
            *hi = fmax(*hi, num[b] / den[b]);
        }
    free(num);
    free(den);
    free(sorted);
}

const char *test_tmp_file(const char *name, const char *content)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", RTGI_TEST_TMP, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(content, f);
    fclose(f);
    return path;
}

void test_load_scene_file(Scene *s, const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/%s", RTGI_SOURCE_DIR, name);
    assert_true(scene_load(s, path));
}

void test_mask_textures(const char *albedo_name, const char *alpha_name)
{
    enum { T = 8 };
    uint8_t white[T * T * 3], half[T * T * 3];
    for (int i = 0; i < T * T; i++)
        for (int c = 0; c < 3; c++) {
            white[3 * i + c] = 255;
            half[3 * i + c] = i % T < T / 2 ? 255 : 0; /* columns 0-3 opaque */
        }
    char path[512];
    snprintf(path, sizeof path, "%s/%s", RTGI_TEST_TMP, albedo_name);
    assert_true(image_write_png8(path, T, T, white));
    snprintf(path, sizeof path, "%s/%s", RTGI_TEST_TMP, alpha_name);
    assert_true(image_write_png8(path, T, T, half));
}

const char *test_masked_leaf_obj(const char *name)
{
    char albedo[128], alpha[128], file[128], mtl[512], obj[1024];
    snprintf(albedo, sizeof albedo, "%s_albedo.png", name);
    snprintf(alpha, sizeof alpha, "%s_alpha.png", name);
    test_mask_textures(albedo, alpha);
    snprintf(mtl, sizeof mtl, "newmtl leaf\nKd 0.3 0.6 0.3\nmap_Kd %s\nmap_d %s\nnewmtl ground\nKd 0.8 0.8 0.8\n",
             albedo, alpha);
    snprintf(file, sizeof file, "%s.mtl", name);
    test_tmp_file(file, mtl);
    snprintf(obj, sizeof obj,
             "mtllib %s.mtl\n"
             "v -1 0.5 -1\nv 1 0.5 -1\nv 1 0.5 1\nv -1 0.5 1\n"
             "v -3 0 -3\nv 3 0 -3\nv 3 0 3\nv -3 0 3\n"
             "vt 0.0625 0.0625\nvt 0.9375 0.0625\nvt 0.9375 0.9375\nvt 0.0625 0.9375\nvn 0 1 0\n"
             "usemtl leaf\nf 1/1/1 4/4/1 3/3/1 2/2/1\n"
             "usemtl ground\nf 5/1/1 8/4/1 7/3/1 6/2/1\n",
             name);
    snprintf(file, sizeof file, "%s.obj", name);
    return test_tmp_file(file, obj);
}

void test_render(const Scene *s, const RenderSettings *rs, ImageF *out)
{
    Renderer r;
    assert_true(renderer_create(&r, s, rs));
    renderer_frame(&r, &s->camera);
    assert_true(renderer_read_hdr(&r, out));
    renderer_destroy(&r);
    test_expect_no_gl_error("test_render");
}

void test_expect_no_gl_error(const char *where)
{
    GLenum e = take_gl_error();
    if (e != GL_NO_ERROR)
        fail_msg("%s: GL error 0x%x (GL_INVALID_OPERATION is 0x502; rtgi render --debug names the call)", where,
                 (unsigned)e);
}

/* Progress lines ("frame i of n took … s", the reference's time left)
 * depend on how fast this machine draws: a new machine's cold shader cache
 * or a loaded CPU makes a frame slow enough to print them, and a test that
 * expects one error line then sees two. Every command a test runs (through
 * run_argv, system or popen) inherits this; a test of the progress lines
 * sets RTGI_PROGRESS_S itself and restores it with test_progress_off. */
__attribute__((constructor)) static void progress_off_by_default(void) { test_progress_off(); }

void test_progress_off(void) { setenv("RTGI_PROGRESS_S", "1e9", 1); }

static int run_argv(char **out, char **err, const char *exe, const char *first, va_list ap)
{
    const char *argv[64];
    int n = 0;
    argv[n++] = exe;
    for (const char *a = first; a && n < 63; a = va_arg(ap, const char *))
        argv[n++] = a;
    argv[n] = NULL;
    char errpath[512], outpath[512];
    snprintf(errpath, sizeof errpath, "%s/cli_stderr_%d.txt", RTGI_TEST_TMP, (int)getpid());
    snprintf(outpath, sizeof outpath, "%s/cli_stdout_%d.txt", RTGI_TEST_TMP, (int)getpid());
    pid_t pid = fork();
    if (pid == 0) {
        if (!freopen(errpath, "w", stderr) || !freopen(out ? outpath : "/dev/null", "w", stdout))
            _exit(127);
        execvp(exe, (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (err)
        *err = util_read_file(errpath, NULL);
    remove(errpath);
    if (out) {
        *out = util_read_file(outpath, NULL);
        remove(outpath);
    }
    if (WIFSIGNALED(status))
        return 128 + WTERMSIG(status); /* a crash: tests treat it as failure */
    return WEXITSTATUS(status);
}

int test_run_cli(char **err, const char *arg0, ...)
{
    va_list ap;
    va_start(ap, arg0);
    int rc = test_run_cli_va(err, arg0, ap);
    va_end(ap);
    return rc;
}

int test_run_cli_out(char **out, char **err, const char *arg0, ...)
{
    va_list ap;
    va_start(ap, arg0);
    int rc = run_argv(out, err, RTGI_BINARY, arg0, ap);
    va_end(ap);
    return rc;
}

int test_run_cli_va(char **err, const char *arg0, va_list ap) { return run_argv(NULL, err, RTGI_BINARY, arg0, ap); }

int test_run_exe(char **err, const char *exe, const char *arg0, ...)
{
    va_list ap;
    va_start(ap, arg0);
    int rc = run_argv(NULL, err, exe, arg0, ap);
    va_end(ap);
    return rc;
}

static pid_t g_xvfb_pid;

static void stop_xvfb(void)
{
    if (g_xvfb_pid > 0) {
        kill(g_xvfb_pid, SIGTERM);
        waitpid(g_xvfb_pid, NULL, 0);
        g_xvfb_pid = 0;
    }
}

void test_x_display(void)
{
    if (g_xvfb_pid > 0)
        return;
    int fds[2];
    assert_int_equal(pipe(fds), 0);
    fcntl(fds[0], F_SETFD, FD_CLOEXEC);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        char fd[16];
        snprintf(fd, sizeof fd, "%d", fds[1]);
        if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr))
            _exit(127);
        execlp("Xvfb", "Xvfb", "-displayfd", fd, "-nolisten", "tcp", "-screen", "0", "1280x1024x24", (char *)NULL);
        _exit(127);
    }
    close(fds[1]);
    char buf[32] = {0};
    size_t n = 0; /* the display number and a newline, once the server is ready */
    while (n < sizeof buf - 1 && !strchr(buf, '\n')) {
        ssize_t k = read(fds[0], buf + n, sizeof buf - 1 - n);
        if (k <= 0)
            break;
        n += (size_t)k;
    }
    close(fds[0]);
    int display = -1;
    if (!strchr(buf, '\n') || sscanf(buf, "%d", &display) != 1) {
        kill(pid, SIGTERM);
        waitpid(pid, NULL, 0);
        fail_msg("Xvfb did not start (is the xvfb package installed? scripts/install-deps.sh installs it)");
    }
    g_xvfb_pid = pid;
    atexit(stop_xvfb);
    char name[32];
    snprintf(name, sizeof name, ":%d", display);
    setenv("DISPLAY", name, 1);
}

void test_expect_cli_error(int rc, char *err, int want, const char *n1, const char *n2)
{
    if (rc != want || !err || (n1 && !strstr(err, n1)) || (n2 && !strstr(err, n2)))
        fail_msg("exit %d (want %d), stderr: %s (want '%s' and '%s')", rc, want, err ? err : "(none)",
                 n1 ? n1 : "", n2 ? n2 : "");
    assert_true(strstr(err, "\n") == strrchr(err, '\n')); /* one line */
    free(err);
}

/* The octahedral normal of common/surfel.glsl (15 bits per coordinate). */
static void oct_decode(uint32_t w, vec3 n)
{
    float ex = (float)(w & 0x7fffu) / 32767.f * 2.f - 1.f, ey = (float)((w >> 15) & 0x7fffu) / 32767.f * 2.f - 1.f;
    n[0] = ex, n[1] = ey, n[2] = 1.f - fabsf(ex) - fabsf(ey);
    float t = fmaxf(-n[2], 0.f);
    n[0] -= n[0] >= 0.f ? t : -t;
    n[1] -= n[1] >= 0.f ? t : -t;
    glm_vec3_normalize(n);
}

void test_gbuffer_pixel(const GBuffer *g, int x, int y, TestGbPixel *out)
{
    uint32_t s[4], m[4];
    glGetTextureSubImage(g->surface, 0, x, y, 0, 1, 1, 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT, sizeof s, s);
    glGetTextureSubImage(g->material, 0, x, y, 0, 1, 1, 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT, sizeof m, m);
    memset(out, 0, sizeof *out);
    out->valid = (s[3] & 0x80000000u) != 0;
    memcpy(out->position, s, sizeof(vec3));
    oct_decode(s[3], out->normal);
    out->base[0] = (float)(m[0] & 0xffffu) / 65535.f;
    out->base[1] = (float)(m[0] >> 16) / 65535.f;
    out->base[2] = (float)(m[1] & 0xffffu) / 65535.f;
    out->roughness = (float)(m[1] >> 16) / 65535.f;
    for (int c = 0; c < 3; c++) /* RGB9E5 */
        out->emission[c] = ldexpf((float)((m[2] >> (9 * c)) & 0x1ffu), (int)(m[2] >> 27) - 24);
    out->metallic = (float)(m[3] & 0xffffu) / 65535.f;
    out->specular = (float)(m[3] >> 16) / 65535.f;
    BrdfSurface b;
    brdf_surface(out->base, out->metallic, out->roughness, out->specular, &b);
    glm_vec3_copy(b.diffuse, out->diffuse);
    glm_vec3_copy(b.f0, out->f0);
}

void test_emitter_mask(const Scene *s, int w, int h, const int32_t *ids, uint8_t *mask)
{
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            bool keep = true;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int u = x + dx, v = y + dy;
                    if (u < 0 || v < 0 || u >= w || v >= h)
                        continue;
                    int32_t id = ids[(size_t)v * w + u];
                    const float *e = id >= 0 ? s->materials[id / 6].emission : NULL;
                    if (e && (e[0] > 0 || e[1] > 0 || e[2] > 0))
                        keep = false;
                }
            mask[(size_t)y * w + x] = keep;
        }
}

static bool dark(const ImageF *img, int x, int y)
{
    return luminance(image_px(img, x, y)) < 1e-6f;
}

void test_shadow_boundary_mask(const ImageF *a, const ImageF *b, uint8_t *mask, int *excluded)
{
    int w = a->width, h = a->height;
    assert_true(b->width == w && b->height == h);
    *excluded = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            bool edge = false;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && yy >= 0 && xx < w && yy < h && dark(a, xx, yy) != dark(b, xx, yy))
                        edge = true;
                }
            mask[y * w + x] = !edge;
            *excluded += edge;
        }
}

double test_mean(const ImageF *img, int cx, int cy, int r, int c)
{
    double sum = 0;
    int n = 0;
    for (int y = cy - r; y <= cy + r; y++)
        for (int x = cx - r; x <= cx + r; x++) {
            if (x < 0 || y < 0 || x >= img->width || y >= img->height)
                continue;
            const float *p = image_px(img, x, y);
            sum += c == 3 ? luminance(p) : p[c];
            n++;
        }
    return n ? sum / n : 0.0;
}

void test_project(const Scene *s, int w, int h, const vec3 p, int *x, int *y)
{
    float fx, fy;
    assert_true(camera_project(&s->camera, w, h, p, &fx, &fy));
    *x = (int)fx;
    *y = (int)fy;
}

void test_camera_down(Camera *c, const vec3 position)
{
    glm_vec3_copy((float *)position, c->position);
    glm_vec3_copy((vec3){0.f, -1.f, 0.f}, c->forward);
    glm_vec3_copy((vec3){0.f, 0.f, -1.f}, c->up);
}

void test_add_square(Scene *s, int material, const vec3 c, float a)
{
    float h = 0.5f * a;
    vec3 p0 = {c[0] - h, c[1], c[2] - h}, p1 = {c[0] - h, c[1], c[2] + h};
    vec3 p2 = {c[0] + h, c[1], c[2] + h}, p3 = {c[0] + h, c[1], c[2] - h};
    scene_add_quad(s, material, p0, p1, p2, p3);
}

const char *test_sponza_gltf(void)
{
    static char path[1024];
    snprintf(path, sizeof path, "%s/assets/sponza/Sponza.gltf", RTGI_SHARED_DIR);
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fclose(f);
    return path;
}

const char *test_sponza_file(void)
{
    static char path[1024];
    if (!test_sponza_gltf())
        return NULL;
    snprintf(path, sizeof path, "%s/scenes/sponza_nave.json", RTGI_SOURCE_DIR);
    return path;
}

void test_skip_without_sponza(void)
{
    if (!test_sponza_gltf()) {
        print_message("Sponza not found under %s/assets/sponza: skipped\n", RTGI_SHARED_DIR);
        skip();
    }
}

void test_sponza_lambert(Scene *s)
{
    const char *file = test_sponza_file();
    assert_non_null(file);
    assert_true(scene_load(s, file));
    assert_true(scene_rescale_lights(s, 0.f));
    for (int i = 0; i < s->material_count; i++)
        if (s->materials[i].light_index < 0)
            s->materials[i].specular = s->materials[i].metallic = 0.f;
}

void test_one_bounce_regions(const Scene *s, GiMode gi, int w, int h, const char *label, double *whole, double *lo,
                             double *hi)
{
    ImageF tech, none, ob, direct;
    test_render_gi(s, w, h, gi, NULL, &tech);
    test_render_gi(s, w, h, GI_NONE, NULL, &none);
    test_reference(s, w, h, PT_ONE_BOUNCE, 64, &ob);
    test_reference(s, w, h, PT_DIRECT, 64, &direct);
    *whole = test_indirect_ratio(&tech, &none, &ob, &direct, NULL);
    test_block_ratio_range(&tech, &none, &ob, &direct, 16, 9, lo, hi);
    print_message("%s %dx%d: indirect ratio against one-bounce %.3f; 16x9 blocks above the median %.3f .. %.3f\n",
                  label, w, h, *whole, *lo, *hi);
    image_free(&tech);
    image_free(&none);
    image_free(&ob);
    image_free(&direct);
}

int test_run_group_part(const char *name, const struct CMUnitTest *tests, size_t count, int argc, char **argv)
{
    int k = 1, n = 1;
    if (argc > 1 && (sscanf(argv[1], "%d/%d", &k, &n) != 2 || n < 1 || k < 1 || k > n)) {
        fprintf(stderr, "%s: part '%s' is not K/N with 1 <= K <= N\n", name, argv[1]);
        return 2;
    }
    struct CMUnitTest *part = calloc(count, sizeof *part);
    assert_non_null(part);
    size_t m = 0;
    for (size_t i = (size_t)k - 1; i < count; i += (size_t)n)
        part[m++] = tests[i];
    int rc = _cmocka_run_group_tests(name, part, m, NULL, NULL);
    free(part);
    return rc;
}
