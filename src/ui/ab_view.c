/* ab_view.c — see ab_view.h. */
#include "ui/ab_view.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "base/log.h"
#include "io/metrics.h"
#include "gl/shader.h"
#include "shared/gpu_types.h"
#include "gpu/targets.h"
#include "base/util.h"

GLuint ab_view_build_program(void)
{
    return shader_program_make("ui.ab_view", "frame/fullscreen.vert", "ui/ab_view.frag", NULL);
}

bool ab_view_create(AbView *v)
{
    memset(v, 0, sizeof *v);
    v->mode = AB_FRAME;
    v->split = 0.5f;
    v->diff_auto = true;
    v->diff_scale = 0.1f;
    glCreateVertexArrays(1, &v->vao);
    v->program = ab_view_build_program();
    if (!v->program) {
        ab_view_destroy(v);
        return false;
    }
    return true;
}

bool ab_view_set_reference(AbView *v, ImageF *img, bool display, const char *what)
{
    int bx, by;
    size_t bad = image_count_nonfinite(img, &bx, &by);
    if (bad) { /* they would show as black or white, and poison the RMSE */
        log_error("view", "--compare %s: %zu of %zu pixels are NaN or infinite (first at x=%d y=%d)", what, bad,
                  (size_t)img->width * img->height, bx, by);
        return false;
    }
    int w = img->width, h = img->height;
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (w > max_size || h > max_size) { /* it had been drawn black */
        log_error("view", "--compare %s: %dx%d is larger than this driver's largest texture, %d per side", what, w,
                  h, max_size);
        return false;
    }
    float *rows = malloc(sizeof(float) * 3 * (size_t)w * h);
    if (!rows) {
        log_error("view", "--compare %s: out of memory for a %dx%d image", what, w, h);
        return false;
    }
    for (int y = 0; y < h; y++) /* GL rows are bottom-up */
        memcpy(rows + 3 * (size_t)(h - 1 - y) * w, image_px(img, 0, y), sizeof(float) * 3 * (size_t)w);
    bool same = v->texture && v->reference.width == w && v->reference.height == h;
    GLuint texture = same ? v->texture : gl_texture_make(GL_TEXTURE_2D, GL_RGB32F, w, h, "ui.reference"); /* logs a failure */
    if (texture) {
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTextureSubImage2D(texture, 0, 0, 0, w, h, GL_RGB, GL_FLOAT, rows);
    }
    free(rows);
    if (!texture)
        return false;
    if (!same)
        glDeleteTextures(1, &v->texture);
    v->texture = texture;
    image_free(&v->reference);
    v->reference = *img;
    memset(img, 0, sizeof *img);
    v->display = display;
    return true;
}

bool ab_view_load_reference(AbView *v, const char *path)
{
    ImageF img;
    if (!image_read(path, &img)) /* logs "<path>: <problem>" */
        return false;
    bool display = !util_ends_with(path, ".pfm") && !util_ends_with(path, ".exr");
    if (!ab_view_set_reference(v, &img, display, path)) {
        image_free(&img);
        return false;
    }
    v->mode = AB_SPLIT;
    log_info("view", "--compare %s: %dx%d reference, %s", path, v->reference.width, v->reference.height,
             display ? "display-referred (shown as is)" : "radiance (shown at the window's exposure)");
    return true;
}

void ab_view_clear_reference(AbView *v)
{
    image_free(&v->reference);
    glDeleteTextures(1, &v->texture);
    v->texture = 0;
    v->display = false;
}

void ab_view_destroy(AbView *v)
{
    image_free(&v->reference);
    glDeleteTextures(1, &v->texture);
    glDeleteProgram(v->program);
    glDeleteVertexArrays(1, &v->vao);
    memset(v, 0, sizeof *v);
}

void ab_view_set_program(AbView *v, GLuint program)
{
    glDeleteProgram(v->program);
    v->program = program;
}

void ab_view_draw(const AbView *v, GLuint ldr, GLuint hdr, float exposure, float diff_scale, int x, int y, int w,
                  int h)
{
    AbMode mode = v->texture && hdr ? v->mode : AB_FRAME;
    glProgramUniform1i(v->program, LOC_AB_MODE, (int)mode);
    glProgramUniform1f(v->program, LOC_AB_SPLIT, v->split);
    glProgramUniform1f(v->program, LOC_AB_EXPOSURE, exposure);
    glProgramUniform1f(v->program, LOC_AB_DIFF_SCALE, diff_scale > 0 ? diff_scale : 1e-6f);
    glProgramUniform1i(v->program, LOC_AB_REF_DISPLAY, v->display ? 1 : 0);
    glBindTextureUnit(TEX_LDR, ldr);
    glBindTextureUnit(TEX_HDR, mode == AB_FRAME ? 0 : hdr);
    glBindTextureUnit(TEX_REFERENCE, mode == AB_FRAME ? 0 : v->texture);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(x, y, w, h);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glUseProgram(v->program);
    glBindVertexArray(v->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
}

/* ---- The heat map's scale ----------------------------------------------------- */

/* The k-th smallest of a[0..n) (a is reordered): Wirth's selection, which
 * splits runs of equal values evenly (a difference is mostly zeros). */
static float select_kth(float *a, ptrdiff_t n, ptrdiff_t k)
{
    ptrdiff_t lo = 0, hi = n - 1;
    while (lo < hi) {
        float x = a[k];
        ptrdiff_t i = lo, j = hi;
        do {
            while (a[i] < x)
                i++;
            while (x < a[j])
                j--;
            if (i <= j) {
                float t = a[i];
                a[i++] = a[j];
                a[j--] = t;
            }
        } while (i <= j);
        if (j < k)
            lo = i;
        if (k < i)
            hi = j;
    }
    return a[k];
}

float ab_view_diff_quantile(const ImageF *reference, bool display, const ImageF *frame, float exposure, double q)
{
    int w = frame->width, h = frame->height, rw = reference->width, rh = reference->height;
    size_t n = (size_t)w * h;
    if (n == 0 || rw <= 0 || rh <= 0)
        return 0;
    float *d = malloc(sizeof(float) * n), hi = 0;
    if (!d)
        return 0;
    float ref_scale = display ? 1.f : exposure;
    for (int y = 0; y < h; y++) {
        int ry = (int)(((double)y + 0.5) * rh / h); /* the texel the view's nearest sampler reads */
        for (int x = 0; x < w; x++) {
            int rx = (int)(((double)x + 0.5) * rw / w);
            const float *f = image_px(frame, x, y), *r = image_px(reference, rx, ry);
            float m = 0;
            for (int c = 0; c < 3; c++) {
                float a = f[c] * exposure;
                if (display)
                    a = fminf(fmaxf(a, 0.f), 1.f);
                m = fmaxf(m, fabsf(a - r[c] * ref_scale));
            }
            d[(size_t)y * w + x] = m;
            hi = fmaxf(hi, m);
        }
    }
    ptrdiff_t k = (ptrdiff_t)(fmin(fmax(q, 0.0), 1.0) * (double)(n - 1));
    float s = select_kth(d, (ptrdiff_t)n, k);
    free(d);
    return s > 0 ? s : hi;
}

double ab_view_rmse(const ImageF *reference, bool display, Renderer *r)
{
    if (display || !reference->rgb || reference->width != r->settings.width || reference->height != r->settings.height)
        return -1;
    ImageF frame;
    if (!renderer_read_hdr(r, &frame))
        return -1;
    double e = metric_rmse(&frame, reference, NULL, NULL);
    image_free(&frame);
    return e;
}
