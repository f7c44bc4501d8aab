/* animation.h — time in a scene (SPEC §10): named rigid objects and
 * keyframe tracks over a duration, read from a scene file's "objects" and
 * "animation" (docs/guide.md, "Animation"), and the scene's state at any
 * time t written into the Scene itself.
 *
 *   objects   a name for a part of the scene's geometry (every triangle of
 *             a material, e.g. the Cornell box's "short_block" or a mesh's
 *             material, a mesh file's node, or inline quads by index), with an optional rigid
 *             transform: a rotation (degrees about x, then y, then z)
 *             about the centre of its bounds, then a translation.
 *   tracks    keyframes (times in seconds, strictly increasing in
 *             [0, duration]) of one value: a light's position, direction
 *             or power (intensity / irradiance / radiance by its type), the
 *             camera's position, target or fov_y_deg, an object's translate
 *             or rotate_deg. Linear between keys, or Catmull-Rom (a cubic
 *             through every key, tangents from the neighbouring keys) for
 *             positions (position, target, translate); before the first
 *             key and after the last, the key's value.
 *
 * Lifetime: the scene owns its objects and animation (scene_free frees
 * them; their types are in scene.h). The scene's lights, camera and object
 * vertices as loaded are its state at t = 0; animation_apply rewrites them
 * (from the copies kept here, so no error accumulates) for any t.
 *
 * The window's use (and any caller that moves time):
 *     SceneChange c;
 *     if (animation_apply(scene, t, &c))
 *         renderer_scene_changed(renderer, &c);   // before renderer_frame
 *     renderer_frame(renderer, &scene->camera);
 * renderer_scene_changed uploads moved vertices and tells the light stage
 * and the technique what changed; lights and the camera are read from the
 * scene every frame anyway. A caller that edits a light by hand (the
 * window's keys) needs nothing more, the light stage noticing a changed
 * light, but for a quad light's emitter geometry: animation_place_emitter,
 * then renderer_scene_changed (src/ui/view_anim.c, view_anim_apply). */
#ifndef RTGI_ANIMATION_H
#define RTGI_ANIMATION_H

#include <stdbool.h>
#include <stdint.h>

#include <cjson/cJSON.h>

#include "core/scene.h"

/* Limits on a scene file's animation. */
#define ANIMATION_MAX_TRACKS 256
#define ANIMATION_MAX_KEYS 100000  /* keys per track */
#define ANIMATION_MAX_OBJECTS 256
#define ANIMATION_MAX_DURATION 1e6 /* seconds */

/* What a change of time (or an edit) changed: flags and the vertices
 * rewritten (object vertices and quad-light emitters). */
typedef enum SceneChangeFlags {
    SCENE_CHANGED_LIGHTS = 1u << 0,   /* a light's position, direction or power */
    SCENE_CHANGED_CAMERA = 1u << 1,   /* the camera */
    SCENE_CHANGED_GEOMETRY = 1u << 2, /* vertices in [first_vertex, first_vertex + vertex_count) */
    SCENE_CHANGED_BOUNDS = 1u << 3,   /* the scene's bounds (grids fitted to them are remade) */
} SceneChangeFlags;

typedef struct SceneChange {
    unsigned what;          /* SceneChangeFlags */
    uint32_t first_vertex;  /* with SCENE_CHANGED_GEOMETRY: the rewritten range */
    uint32_t vertex_count;
} SceneChange;

/* A mesh file's node names and the submeshes under each (scene_load.c
 * makes it when a scene file's object names a "node"): pairs, a node's
 * own meshes and every descendant's. */
typedef struct SceneNodeMap {
    struct SceneNodeEntry {
        char name[64];
        int submesh;
    } *entries;          /* owned */
    int count;
} SceneNodeMap;
void scene_node_map_free(SceneNodeMap *m);

/* Reads a loaded scene file's "objects" and "animation" (`root` is the
 * file's top-level object; `file` names it in messages) into s, which is
 * finalized (scene_finalize), then puts the objects' transforms in place
 * and applies the animation at t = 0. false after logging one line
 * "<file>: objects.<name>.<key>: ..." or "<file>: animation.tracks[i].<key>:
 * ..."; the caller frees the scene. */
bool animation_parse(Scene *s, const cJSON *root, const char *file, const SceneNodeMap *nodes);
/* Whether a scene file's "objects" name a mesh node (its mesh is then
 * loaded with the nodes' meshes kept apart: scene_load_mesh_nodes). */
bool animation_wants_nodes(const cJSON *root);

/* Whether the scene has an animation, and its duration (s; 0 if none). */
bool animation_present(const Scene *s);
float animation_duration(const Scene *s);

/* The value of track `k` at time t (dims floats into out). Exact at keys. */
void animation_track_value(const AnimTrack *k, double t, float out[3]);

/* Writes the scene's state at time t (clamped to [0, duration]) into its
 * lights, camera and object vertices (and quad-light emitters, scene
 * bounds). *changed (may be NULL) says what differs from the state it held
 * before. Returns whether anything changed. A scene without animation is
 * left as it is. */
bool animation_apply(Scene *s, double t, SceneChange *changed);

/* The animated channels of the lights at time t (clamped to [0,
 * duration]) written into `lights`, an array of the scene's light_count
 * (its other values left as they are): what animation_apply writes into
 * the scene's lights, without touching the scene (the window's panel
 * reads it on its own thread while the render thread applies). */
void animation_lights_at(const Scene *s, double t, Light *lights);
/* The camera at time t from the animation's camera tracks, written over
 * *cam (what no track moves kept); false, *cam left as it was, where the
 * animation has no camera track or its target meets its position. Reads
 * the scene's animation only. */
bool animation_camera_at(const Scene *s, double t, Camera *cam);
/* Whether the scene's geometry can move: it has objects, or a quad light
 * with a size (its emitter is geometry that follows the light). */
bool animation_geometry_moves(const Scene *s);
/* The scene's vertices at time t (clamped to [0, duration]), its quad
 * lights' emitters placed at `lights` (an array of the scene's
 * light_count: the lights as animated and edited), written into `out` (the
 * scene's vertex_count): what animation_apply and animation_place_emitter
 * would leave in s->vertices, without writing s or reading the vertices
 * they write (the window's live reference makes its own geometry on its
 * thread while the render thread applies the animation to s). false after
 * logging (out of memory). */
bool animation_vertices_at(const Scene *s, double t, const Light *lights, Vertex *out);
/* After a caller edited light `light` by hand (a quad light moved or its
 * radiance changed in the window): its emitter geometry and emission
 * follow, the vertices rewritten added to *c (nothing for other types). */
void animation_place_emitter(Scene *s, int light, SceneChange *c);

/* The time of frame i of n: with fps > 0, i / fps; else spread over the
 * duration, from 0 to the end (n = 1: 0). */
double animation_frame_time(const Scene *s, int i, int n, double fps);

/* Checks that frames 0..n-1 (animation_frame_time) stay within the
 * duration and that the camera and lights at each are valid
 * (scene_check_view, scene_check_lights), then puts the scene back at
 * t = 0. `what` names the option for messages ("--animate"). false after
 * logging one line naming the frame and its time (or that the scene has
 * no animation). */
bool animation_check_frames(Scene *s, int n, double fps, const char *what);
/* The same for one time t, in [0, duration]; the scene is left at t. */
bool animation_check_time(Scene *s, double t, const char *what);

#endif
