/* ab_view.h — the window's A/B view (`rtgi view --compare FILE`): the
 * renderer's frame and a reference image side by side with a movable split,
 * one of them alone, or their difference as a heat map (black → red →
 * yellow → white as max-channel |frame − reference| × exposure goes 0 →
 * scale, the scale automatic or chosen). Draws the window's image area
 * from the render thread's presentation textures, with or without a
 * reference. Owns the reference texture and its program
 * (shaders/ui/ab_view.frag). */
#ifndef RTGI_AB_VIEW_H
#define RTGI_AB_VIEW_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "io/image.h"
#include "frame/renderer.h"

typedef enum AbMode { AB_FRAME = 0, AB_REFERENCE = 1, AB_SPLIT = 2, AB_DIFFERENCE = 3, AB_MODE_COUNT } AbMode;

typedef struct AbView {
    ImageF reference;   /* the reference radiance, row 0 = top (for the RMSE readout); empty: none */
    bool display;       /* read from PNG/JPEG: already exposed and clamped (shown as is, no RMSE) */
    GLuint texture;     /* RGB32F, the reference bottom-up as GL samples it (0: no reference) */
    GLuint program;     /* owned */
    GLuint vao;         /* owned, empty (the window's context) */
    AbMode mode;
    float split;        /* [0, 1] of the width: frame left, reference right */
    bool diff_auto;     /* the heat map's scale follows the difference (AB_AUTO_QUANTILE) ... */
    float diff_scale;   /* ... else |difference| shown as full heat */
} AbView;

/* The automatic heat-map scale is this quantile of the frame's difference:
 * one pixel in a hundred saturates, whatever the difference's size (the
 * fixed 0.1 had left most of a dim scene black, a bright one all white). */
#define AB_AUTO_QUANTILE 0.99

/* The program and its VAO (the window's context current): the frame alone
 * until a reference is loaded. false after logging. */
bool ab_view_create(AbView *v);
/* Reads `path` (any format image_read takes) as the reference and uploads
 * it; the view starts split. false after logging (the file and its
 * problem). The render thread keeps its own copy of the reference (RMSE,
 * the heat map's scale: view_render_set_reference), so the window may
 * replace v->reference while it runs (the live reference's updates). */
bool ab_view_load_reference(AbView *v, const char *path);
/* Takes `img` (moved: the caller's copy is emptied) as the reference;
 * `display`: already exposed and clamped. `what` names it in errors.
 * The texture is reused when the size is the same. false after logging. */
bool ab_view_set_reference(AbView *v, ImageF *img, bool display, const char *what);
/* No reference (the view draws the frame alone until one is set): a live
 * reference restarted and has no image of the new state yet. */
void ab_view_clear_reference(AbView *v);
void ab_view_destroy(AbView *v);
/* The view's program built from the shader files (0 after logging), and
 * taking one over (the old one deleted): a hot reload builds it on the
 * render thread, the window's thread sets it. */
GLuint ab_view_build_program(void);
void ab_view_set_program(AbView *v, GLuint program);
/* Draws the frame (its final image `ldr` and, with a reference, its
 * radiance `hdr` at `exposure`) in the view's mode into the rectangle
 * (x, y, w, h) of the default framebuffer (GL's bottom-up pixels);
 * `diff_scale` is the heat map's full scale. */
void ab_view_draw(const AbView *v, GLuint ldr, GLuint hdr, float exposure, float diff_scale, int x, int y, int w,
                  int h);
/* The heat map's full scale for a frame of radiance `frame` at `exposure`:
 * the q-quantile of max-channel |frame − reference| × exposure (clamped
 * first for a `display`-referred reference) over the frame's pixels, the
 * reference sampled as the view samples it (nearest texel, stretched to
 * the frame); the largest difference where that quantile is 0; 0 where
 * the two agree everywhere or memory runs out. */
float ab_view_diff_quantile(const ImageF *reference, bool display, const ImageF *frame, float exposure, double q);
/* RMSE of `r`'s last frame against `reference` (radiance, the same size
 * only; -1 if the sizes differ, the reference is display-referred or
 * missing, or memory runs out). */
double ab_view_rmse(const ImageF *reference, bool display, Renderer *r);

#endif
