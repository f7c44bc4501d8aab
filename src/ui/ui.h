/* ui.h — the C interface to Dear ImGui (Debian libimgui-dev: the library and
 * its GLFW and OpenGL 3 back-ends), the only C++ in rtgi (ui_imgui.cpp).
 * One UI per process, bound to one GLFW window whose GL context is current.
 * Widgets follow ImGui's immediate mode: call them between ui_frame_begin
 * and ui_frame_end every frame; a widget returns true when the user changed
 * its value this frame. Labels are ImGui IDs ("name##id" hides the suffix). */
#ifndef RTGI_UI_H
#define RTGI_UI_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct GLFWwindow GLFWwindow;

/* Installs ImGui's GLFW callbacks (they chain to the window's callbacks
 * installed before this call) and its GL 3 renderer (its own GL loader, next
 * to libepoxy). false after logging. */
bool ui_create(GLFWwindow *window);
void ui_destroy(void);
/* Whether the UI uses the keyboard / mouse this frame (the window's own
 * keys and camera drag must then leave them alone). */
bool ui_wants_keyboard(void);
bool ui_wants_mouse(void);

void ui_frame_begin(void);
/* Draws the frame's widgets into the current framebuffer (the window's). */
void ui_frame_end(void);

/* A panel docked at (x, y) with size w × h (screen coordinates), kept
 * there (no moving, resizing or collapsing: the window is laid out
 * around it); `open` (may be NULL) adds a close button. Always pair with
 * ui_window_end. */
bool ui_panel_begin(const char *title, bool *open, float x, float y, float w, float h);
void ui_window_end(void);
/* A line of text in a small translucent box at (x, y) over everything,
 * taking no input (the busy indicator over the image). */
void ui_overlay_text(const char *id, float x, float y, const char *text);
/* A colour bar the panel's width: `stops` colours (RGB in [0, 1]) evenly
 * spaced and blended linearly between, `labels` evenly spaced under it
 * (the first at its left end, the last at its right). */
void ui_color_bar(const char *id, const float (*stops)[3], int stop_count, const char *const *labels,
                  int label_count, float height);
/* A collapsing header; true while open. */
bool ui_header(const char *label, bool open_by_default);
void ui_text(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void ui_text_colored(float r, float g, float b, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
void ui_text_wrapped(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* A tooltip for the last widget while it is hovered. */
void ui_tooltip(const char *text);
void ui_separator(void);
void ui_same_line(void);
void ui_push_id(int id);
void ui_pop_id(void);
bool ui_button(const char *label);
bool ui_checkbox(const char *label, bool *v);
/* `items` has `count` labels; *index is the selected one. */
bool ui_combo(const char *label, int *index, const char *const *items, int count);
bool ui_slider_float(const char *label, float *v, float lo, float hi, bool logarithmic, const char *format);
bool ui_slider_int(const char *label, int *v, int lo, int hi, bool logarithmic);
bool ui_slider_int2(const char *label, int v[2], int lo, int hi);
bool ui_input_text(const char *label, char *buf, size_t cap);
/* The last widget was released after changing its value (apply costly
 * settings once, not on every drag step). */
bool ui_item_deactivated_after_edit(void);
/* A table of `columns` text columns with a header row. */
bool ui_table_begin(const char *id, int columns, const char *const *headers);
void ui_table_row(const char *const *cells, int columns);
void ui_table_end(void);
/* A line plot of `count` values read from `offset` on (a ring buffer). */
void ui_plot_lines(const char *label, const float *values, int count, int offset, const char *overlay, float lo,
                   float hi, float height);
/* Copies text to the system clipboard. */
void ui_set_clipboard(const char *text);

#ifdef __cplusplus
}
#endif

#endif
