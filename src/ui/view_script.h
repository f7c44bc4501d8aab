/* view_script.h — `rtgi view --ui-test DIR`: a fixed script, one step per
 * frame, through the panel's own actions (no clicks: Xvfb has no user),
 * printing what it measured as "ui-test: ..." lines on stdout and writing
 * its captures to DIR; tests/test_view.c reads both. The steps: the
 * panel's per-pass timings table of frames 1-2; the camera as scene JSON; exposure ×2 (program links and renderer remakes counted);
 * the window with and without the panel and the image as PNG, PFM and EXR; the
 * G key's path into the next technique (pending when slow) and its
 * confirming click; a shader hot reload (with the shader named by
 * RTGI_UI_TEST_BREAK_SHADER broken first); with --compare, the A/B view's
 * reference, difference (and its RMSE) and split. */
#ifndef RTGI_VIEW_SCRIPT_H
#define RTGI_VIEW_SCRIPT_H

#include <stdbool.h>

#include "ui/view_panel.h"

typedef struct ViewScript {
    const char *dir;    /* where the captures go */
    int links, remakes; /* counters before the step being measured */
} ViewScript;

/* Runs frame `frame`'s step (after the frame is drawn, before the swap);
 * false when the script is over. */
bool view_script_step(ViewScript *t, View *v, int frame, int fw, int fh);

#endif
