/* ab_view.c — see ab_view.h. */
#include "ui/ab_view.h"

#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "metrics.h"
#include "shader.h"
#include "shared/gpu_types.h"
#include "targets.h"
#include "util.h"

static GLuint build_program(void)
{
    return shader_program_make("ui.ab_view", "frame/fullscreen.vert", "ui/ab_view.frag", NULL);
}

bool ab_view_create(AbView *v, const char *path)
{
    memset(v, 0, sizeof *v);
    v->mode = AB_SPLIT;
    v->split = 0.5f;
    v->diff_scale = 0.1f;
    if (!image_read(path, &v->reference)) /* logs "<path>: <problem>" */
        return false;
    int bx, by;
    size_t bad = image_count_nonfinite(&v->reference, &bx, &by);
    if (bad) { /* they would show as black or white, and poison the RMSE */
        log_error("view", "--compare %s: %zu of %zu pixels are NaN or infinite (first at x=%d y=%d)", path, bad,
                  (size_t)v->reference.width * v->reference.height, bx, by);
        image_free(&v->reference);
        return false;
    }
    v->display = !util_ends_with(path, ".pfm") && !util_ends_with(path, ".exr");
    int w = v->reference.width, h = v->reference.height;
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (w > max_size || h > max_size) { /* it had been drawn black */
        log_error("view", "--compare %s: %dx%d is larger than this driver's largest texture, %d per side", path, w,
                  h, max_size);
        ab_view_destroy(v);
        return false;
    }
    float *rows = malloc(sizeof(float) * 3 * (size_t)w * h);
    if (!rows) {
        log_error("view", "--compare %s: out of memory for a %dx%d image", path, w, h);
        ab_view_destroy(v);
        return false;
    }
    for (int y = 0; y < h; y++) /* GL rows are bottom-up */
        memcpy(rows + 3 * (size_t)(h - 1 - y) * w, image_px(&v->reference, 0, y), sizeof(float) * 3 * (size_t)w);
    v->texture = gl_texture_make(GL_TEXTURE_2D, GL_RGB32F, w, h, "ui.reference"); /* logs a failure */
    if (v->texture) {
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTextureSubImage2D(v->texture, 0, 0, 0, w, h, GL_RGB, GL_FLOAT, rows);
    }
    free(rows);
    if (!v->texture) {
        ab_view_destroy(v);
        return false;
    }
    glCreateVertexArrays(1, &v->vao);
    v->program = build_program();
    if (!v->program) {
        ab_view_destroy(v);
        return false;
    }
    log_info("view", "--compare %s: %dx%d reference, %s", path, w, h,
             v->display ? "display-referred (shown as is)" : "radiance (shown at the window's exposure)");
    return true;
}

void ab_view_destroy(AbView *v)
{
    image_free(&v->reference);
    glDeleteTextures(1, &v->texture);
    glDeleteProgram(v->program);
    glDeleteVertexArrays(1, &v->vao);
    memset(v, 0, sizeof *v);
}

bool ab_view_reload(AbView *v)
{
    GLuint p = build_program();
    if (!p)
        return false;
    glDeleteProgram(v->program);
    v->program = p;
    return true;
}

void ab_view_draw(const AbView *v, const Renderer *r, int fw, int fh)
{
    glProgramUniform1i(v->program, LOC_AB_MODE, (int)v->mode);
    glProgramUniform1f(v->program, LOC_AB_SPLIT, v->split);
    glProgramUniform1f(v->program, LOC_AB_EXPOSURE, r->settings.exposure);
    glProgramUniform1f(v->program, LOC_AB_DIFF_SCALE, v->diff_scale > 0 ? v->diff_scale : 1e-6f);
    glProgramUniform1i(v->program, LOC_AB_REF_DISPLAY, v->display ? 1 : 0);
    glBindTextureUnit(TEX_HDR, r->hdr.texture);
    glBindTextureUnit(TEX_LDR, r->ldr.texture);
    glBindTextureUnit(TEX_REFERENCE, v->texture);
    fullscreen_draw(v->program, v->vao, 0, fw, fh, false);
}

double ab_view_rmse(const AbView *v, Renderer *r)
{
    if (v->display || v->reference.width != r->settings.width || v->reference.height != r->settings.height)
        return -1;
    ImageF frame;
    if (!renderer_read_hdr(r, &frame))
        return -1;
    double e = metric_rmse(&frame, &v->reference, NULL, NULL);
    image_free(&frame);
    return e;
}
