/* view_input.h — the window's keys, drag and camera movement (GLFW key
 * codes), on the window's thread: each changes the View at once (the
 * panel shows it), and the render thread's next frame is drawn from it. */
#ifndef RTGI_VIEW_INPUT_H
#define RTGI_VIEW_INPUT_H

#include <stdbool.h>

#include "ui/view_panel.h"

typedef struct GLFWwindow GLFWwindow;

/* The camera's angles from its forward vector, and back. */
void view_set_angles(View *v, const Camera *c);
void view_update_camera(View *v);
/* A key pressed (GLFW_KEY_*, GLFW_MOD_* bits), as `rtgi view --help` lists
 * them. */
void view_key(View *v, int key, int mods);
/* The most a movement step may cover: a window that waited (a slow
 * event, a stall) moves the camera no further than this many seconds of
 * a held key (a frame of over ten seconds had thrown it across Sponza). */
#define VIEW_MOVE_MAX_DT 0.1f
/* Moves the camera by the movement keys held (WASD, Q/E, Shift faster)
 * for dt seconds (clamped to VIEW_MOVE_MAX_DT); true while any is held. */
bool view_move(View *v, GLFWwindow *w, float dt);

#endif
