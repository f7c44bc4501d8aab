/* render_sequence.h — time in `rtgi render`: --time T (one instant of the
 * scene file's animation) and --animate --frames N [--fps F] [--video
 * FILE.mp4] (a sequence into --out's frame pattern). */
#ifndef RTGI_RENDER_SEQUENCE_H
#define RTGI_RENDER_SEQUENCE_H

#include <stdbool.h>

#include "app/render_options.h"
#include "frame/renderer.h"
#include "core/scene.h"

/* With --time: puts the scene at T s; with --animate: checks every frame's
 * time and view (animation_check_frames). false after logging one line (no
 * animation, a time past its end, a camera that sees nothing then). */
bool render_time_apply(const RenderOptions *o, Scene *scene);
/* Renders --animate's frames with settings rs (light products cached:
 * what a change invalidates is redrawn) into --out's pattern, all of them
 * or none, and the video; prints "frames:", "time_s:" and "frame_ms:"
 * lines. Needs a current GL context. Returns the exit status. */
int render_sequence(const RenderOptions *o, Scene *scene, const RenderSettings *rs, const char *gl_renderer);

#endif
