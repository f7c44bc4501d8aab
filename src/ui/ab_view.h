/* ab_view.h — the window's A/B view (`rtgi view --compare FILE`): the
 * renderer's frame and a reference image side by side with a movable split,
 * one of them alone, or their difference as a heat map (black → red →
 * yellow → white as max-channel |frame − reference| × exposure goes 0 →
 * scale). Draws into the window's default framebuffer in place of the
 * plain blit. Owns the reference texture and its program
 * (shaders/ui/ab_view.frag). */
#ifndef RTGI_AB_VIEW_H
#define RTGI_AB_VIEW_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "image.h"
#include "renderer.h"

typedef enum AbMode { AB_FRAME = 0, AB_REFERENCE = 1, AB_SPLIT = 2, AB_DIFFERENCE = 3, AB_MODE_COUNT } AbMode;

typedef struct AbView {
    ImageF reference;   /* the reference radiance, row 0 = top (for the RMSE readout) */
    bool display;       /* read from PNG/JPEG: already exposed and clamped (shown as is, no RMSE) */
    GLuint texture;     /* RGB32F, the reference bottom-up as GL samples it */
    GLuint program;     /* owned */
    GLuint vao;         /* owned, empty */
    AbMode mode;
    float split;        /* [0, 1] of the width: frame left, reference right */
    float diff_scale;   /* |difference| shown as full heat */
} AbView;

/* Reads `path` (any format image_read takes) and makes the texture and the
 * program. false after logging (the file and its problem). */
bool ab_view_create(AbView *v, const char *path);
void ab_view_destroy(AbView *v);
/* Rebuilds the program from the shader files (hot reload); keeps the old
 * one if the new one fails to build. */
bool ab_view_reload(AbView *v);
/* Draws the view of `r`'s last frame into the default framebuffer (fw × fh). */
void ab_view_draw(const AbView *v, const Renderer *r, int fw, int fh);
/* RMSE of `r`'s last frame against the reference (radiance, the same size
 * only; -1 if the sizes differ, the reference is display-referred or memory
 * runs out). */
double ab_view_rmse(const AbView *v, Renderer *r);

#endif
