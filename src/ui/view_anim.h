/* view_anim.h — time and lights in `rtgi view` (issue 50, item 4): the
 * scene's animation played, paused and scrubbed from the panel (Space
 * plays and pauses), and the lights moved with keys (arrows, Page Up /
 * Page Down) and their power edited in the panel.
 *
 * The window's thread holds the wanted state (ViewAnim, in the View): the
 * time (View.time) and each light's edit (ViewLightEdits). Both go to the
 * render thread in the request's scene (ViewScene.time, .lights), which
 * writes them into the Scene before the frame (view_anim_apply):
 * animation_apply at the time, the edits over the lights it leaves, then
 * renderer_scene_changed. Nothing else writes the Scene while the window
 * runs, so the window's own reads of it stay to what never changes (the
 * animation's tracks, the light count): the panel's light values come
 * from animation_lights_at over the lights as loaded (ViewAnim.base).
 *
 * Temporal accumulation (gi.temporal) is on while the animation plays and
 * off otherwise, unless --temporal (or the panel's checkbox) chose it:
 * moving frames gain from the history, while a paused window shows the
 * time's frame as `render --time T` draws it (a pause draws that one
 * frame, then nothing). */
#ifndef RTGI_VIEW_ANIM_H
#define RTGI_VIEW_ANIM_H

#include <stdbool.h>

#include "frame/renderer.h"
#include "core/scene.h"
#include "ui/view.h"

/* The render thread's side: what the Scene holds now. */
typedef struct ViewAnimApplied {
    bool made;
    Light base[VIEW_MAX_LIGHTS]; /* the lights as loaded */
    double time;
    ViewLightEdits edits;
    unsigned changes;       /* scene changes applied (renderer_scene_changed calls) */
} ViewAnimApplied;

/* A light's edit applied to it (both threads). */
void view_light_edit_apply(const ViewLightEdits *e, int i, Light *l);

/* ---- The window's thread ---- */

typedef struct GLFWwindow GLFWwindow;

/* The state from the scene (its lights and animation as loaded) and
 * whether --temporal chose temporal accumulation; after the View's camera
 * and settings are set, before the render thread starts. View.scene is
 * then ViewAnim.shown. */
void view_anim_init(View *v, const Scene *s, bool temporal_given);
/* Space (play/pause) and L / Shift-L (the next / previous light); true
 * when the key was one of them. */
bool view_anim_key(View *v, int key, int mods);
/* Plays (from the start when paused at the end of a non-looping
 * animation) or pauses, at wall time `now` (glfwGetTime). */
void view_anim_play(View *v, bool play, double now);
/* The time slider: the animation at t (clamped to it); playback goes on
 * from there. */
void view_anim_scrub(View *v, double t, double now);
/* Light i's power × 2^stops over its loaded or animated value. */
void view_anim_set_stops(View *v, int i, float stops);
/* One step of a light key held for dt seconds (fast: Shift), the selected
 * light moved across the view (arrows: left/right, away/towards along
 * the ground), raised or lowered (Page Up / Page Down), a directional
 * light turned (arrows) instead. Kept within the scene's bounds widened
 * by half their diagonal. */
void view_anim_light_step(View *v, int key, bool fast, float dt);
/* The light keys held since the last pass (each step at most
 * VIEW_MOVE_MAX_DT); true while any is. */
bool view_anim_move_light(View *v, GLFWwindow *w, float dt);
/* Once a pass, before the request: playback's time, the camera when it
 * follows the animation, temporal accumulation's setting. true when any
 * changed (the panel shows it). */
bool view_anim_advance(View *v, double now);
/* Light i as the next frame draws it (animated, edited). */
void view_anim_light(const View *v, int i, Light *out);
/* The panel's Animation and Lights sections. */
void view_anim_panel(View *v);

/* ---- The render thread ---- */

/* Render thread, before renderer_frame: the scene at `time` with the
 * edits (nothing when both are what it holds). false after logging when
 * the renderer failed to follow the change (renderer_scene_changed). */
bool view_anim_apply(ViewAnimApplied *ap, Scene *s, Renderer *r, double time, const ViewLightEdits *e);

#endif
