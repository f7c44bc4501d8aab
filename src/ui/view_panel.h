/* view_panel.h — the state of `rtgi view` and its Dear ImGui panel:
 * technique and shadow pickers, every row of the settings table as a
 * widget with its range, exposure (live: renderer_apply remakes nothing for
 * it), per-pass GPU ms with a history plot, the camera with "copy as scene
 * JSON", captures, shader hot reload, the A/B view of --compare, and the
 * animation and lights (view_anim.h).
 *
 * The View is the window's thread's: the render thread (view_render.h)
 * gets its settings and camera as a request, and hands back its
 * measurements (ViewStats) and the status line (ViewStatus, locked).
 *
 * Slow techniques: a technique whose frame is estimated over `slow_ms` at
 * the current size is marked in the picker and needs a confirming click,
 * from the panel and from the G key alike (see view_estimate_ms). */
#ifndef RTGI_VIEW_PANEL_H
#define RTGI_VIEW_PANEL_H

#include <stdbool.h>

#include "ui/view.h"

/* The docked panel's width in screen coordinates: the window is the image
 * plus this, beside it on the right (H hides the panel and shrinks the
 * window by as much; the image keeps its size). */
#define VIEW_PANEL_WIDTH 360

/* F5: every program rebuilt from the shader files (--shader-dir, else the
 * source tree's shaders/) on the render thread; one that fails keeps its
 * previous build and its error shows in the panel's status. */
void view_ask_reload(View *v);
/* Saves the window's back buffer as shown, panel included (call before the
 * swap), as PNG. */
bool view_save_window(View *v, const char *path, int fw, int fh);
/* Draws the panel for this frame (between ui_frame_begin and ui_frame_end),
 * docked at x (screen coordinates), h high. */
void view_panel_draw(View *v, float x, float h);
/* The panel's live-reference line (live_reference_text of v->live). */
void view_live_text(const View *v, char *out, size_t cap);
/* The busy indicator over the image's top-left corner, while there is one. */
void view_busy_draw(const View *v);

#endif
