/* view_input.h — the window's keys, drag and camera movement (GLFW key
 * codes), on the window's thread: each changes the View at once (the
 * panel shows it), and the render thread's next frame is drawn from it. */
#ifndef RTGI_VIEW_INPUT_H
#define RTGI_VIEW_INPUT_H

#include <stdbool.h>

#include "ui/view.h"

typedef struct GLFWwindow GLFWwindow;

/* A key pressed (GLFW_KEY_*, GLFW_MOD_* bits), as `rtgi view --help` lists
 * them. */
void view_key(View *v, int key, int mods);
/* Moves the camera by the movement keys held (WASD, Q/E, Shift faster)
 * for dt seconds (clamped to VIEW_MOVE_MAX_DT); true while any is held. */
bool view_move(View *v, GLFWwindow *w, float dt);

#endif
