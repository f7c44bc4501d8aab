/* animation.c — a scene file's "objects" and "animation" (animation.h):
 * parsing with one-line errors that name the key, keyframe interpolation,
 * and the scene's state at a time written into the Scene. */
#include "core/animation.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/json_util.h"
#include "base/log.h"
#include "base/util.h"

/* Limits as the scene file's (scene_load.c). */
#define ANIM_MAX_COORD 1e6f
#define ANIM_MAX_POWER 1e30f

/* ------------------------------------------------------------ parsing */

typedef struct Parse {
    const char *file; /* for messages */
    bool ok;          /* false after the first error (later ones are not logged) */
} Parse;

/* Logs "<file>: <where>: <message>" for the first error only. */
static void fail(Parse *p, const char *where, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void fail(Parse *p, const char *where, const char *fmt, ...)
{
    if (!p->ok)
        return;
    p->ok = false;
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    log_error("scene", "%s: %s: %s", p->file, where, msg);
}

/* A JSON number as a finite float into *out; false after logging. */
static bool number(Parse *p, const cJSON *e, const char *where, float *out)
{
    if (!cJSON_IsNumber(e)) {
        fail(p, where, "is not a number");
        return false;
    }
    double d = e->valuedouble;
    float f = (float)d;
    if (!isfinite(d) || !isfinite(f)) {
        fail(p, where, "%g is not a finite 32-bit float (|x| < 3.4e38)", d);
        return false;
    }
    *out = f;
    return true;
}

/* j is an object whose keys are among `known` (json_check_keys); false
 * after logging. */
static bool object_with_keys(Parse *p, const cJSON *j, const char *where, const char *const *known)
{
    if (!cJSON_IsObject(j)) {
        fail(p, where, "must be an object");
        return false;
    }
    if (p->ok && !json_check_keys(j, known, p->file, where))
        p->ok = false;
    return p->ok;
}

/* `dims` numbers (an array of 3, or one number when dims is 1). */
static bool value(Parse *p, const cJSON *e, const char *where, int dims, float out[3])
{
    if (dims == 1)
        return number(p, e, where, &out[0]);
    if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 3) {
        fail(p, where, "must be an array of 3 numbers");
        return false;
    }
    char w[160];
    for (int i = 0; i < 3; i++) {
        snprintf(w, sizeof w, "%s[%d]", where, i);
        if (!number(p, cJSON_GetArrayItem(e, i), w, &out[i]))
            return false;
    }
    return true;
}

/* ---- objects */

static const char *const k_object_keys[] = {"material", "quads", "node", "translate", "rotate_deg", NULL};

void scene_node_map_free(SceneNodeMap *m)
{
    free(m->entries);
    m->entries = NULL;
    m->count = 0;
}

bool animation_wants_nodes(const cJSON *root)
{
    const cJSON *objs = cJSON_GetObjectItemCaseSensitive(root, "objects"), *o;
    if (!cJSON_IsObject(objs))
        return false;
    cJSON_ArrayForEach(o, objs)
    {
        if (cJSON_GetObjectItemCaseSensitive(o, "node"))
            return true;
    }
    return false;
}

/* Adds the vertices of submesh k's triangles to the marks. */
static void mark_submesh(const Scene *s, int k, uint8_t *mark)
{
    const Submesh *sm = &s->submeshes[k];
    for (uint32_t i = sm->first_index; i < sm->first_index + sm->index_count; i++)
        mark[s->indices[i]] = 1;
}

/* Adds the vertices of every triangle of material `m` to the marks. */
static void mark_material(const Scene *s, int m, uint8_t *mark)
{
    for (int k = 0; k < s->submesh_count; k++)
        if (s->submeshes[k].material == m)
            mark_submesh(s, k, mark);
}

/* Material index of `name` (not an emitter), or -1. */
static int material_named(const Scene *s, const char *name)
{
    for (int i = 0; i < s->material_count; i++)
        if (s->materials[i].light_index < 0 && !strcmp(s->materials[i].name, name))
            return i;
    return -1;
}

/* The meshes under mesh node `name` into mark[]; false after logging. */
static bool select_node(Parse *p, const Scene *s, const cJSON *node, const char *where, const SceneNodeMap *nodes,
                        uint8_t *mark)
{
    char w[256];
    snprintf(w, sizeof w, "%s.node", where);
    if (!cJSON_IsString(node)) {
        fail(p, w, "must be the name of a node of the scene's mesh file");
        return false;
    }
    int found = 0;
    for (int i = 0; nodes && i < nodes->count; i++)
        if (!strcmp(nodes->entries[i].name, node->valuestring)) {
            mark_submesh(s, nodes->entries[i].submesh, mark);
            found++;
        }
    if (found)
        return true;
    char names[256] = "";
    for (int i = 0; nodes && i < nodes->count && strlen(names) < 200; i++)
        if (!strstr(names, nodes->entries[i].name) && nodes->entries[i].name[0])
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", names[0] ? ", " : "",
                     nodes->entries[i].name);
    fail(p, w, "\"%s\": no node of that name holds triangles in the mesh file (%s%s)", node->valuestring,
         nodes && nodes->count ? "it has: " : "it has none, or the scene has no \"mesh\"", names);
    return false;
}

/* The object's selection ("material", "node" or "quads") into mark[];
 * false after logging. */
static bool select_geometry(Parse *p, const Scene *s, const cJSON *j, const char *where, const SceneNodeMap *nodes,
                            uint8_t *mark)
{
    const cJSON *mat = cJSON_GetObjectItemCaseSensitive(j, "material"),
                *quads = cJSON_GetObjectItemCaseSensitive(j, "quads"),
                *node = cJSON_GetObjectItemCaseSensitive(j, "node");
    char w[256];
    if ((mat != NULL) + (quads != NULL) + (node != NULL) != 1) {
        fail(p, where, "give one of \"material\" (every triangle of a material), \"node\" (a mesh file's node) "
                       "or \"quads\" (indices into \"quads\")");
        return false;
    }
    if (node)
        return select_node(p, s, node, where, nodes, mark);
    if (mat) {
        snprintf(w, sizeof w, "%s.material", where);
        if (!cJSON_IsString(mat)) {
            fail(p, w, "must be a material name");
            return false;
        }
        int m = material_named(s, mat->valuestring);
        if (m < 0) {
            char names[256] = "";
            for (int i = 0; i < s->material_count && strlen(names) < 200; i++)
                if (s->materials[i].light_index < 0)
                    snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", names[0] ? ", " : "",
                             s->materials[i].name);
            fail(p, w, "\"%s\": no material of that name in the scene (it has: %s)", mat->valuestring, names);
            return false;
        }
        mark_material(s, m, mark);
        return true;
    }
    snprintf(w, sizeof w, "%s.quads", where);
    if (!cJSON_IsArray(quads) || cJSON_GetArraySize(quads) == 0) {
        fail(p, w, "must be a non-empty array of quad indices");
        return false;
    }
    int i = 0;
    const cJSON *q;
    cJSON_ArrayForEach(q, quads)
    {
        snprintf(w, sizeof w, "%s.quads[%d]", where, i++);
        char name[32];
        if (!cJSON_IsNumber(q) || q->valuedouble != (double)(int)q->valuedouble || q->valueint < 0) {
            fail(p, w, "must be an index into the file's \"quads\"");
            return false;
        }
        snprintf(name, sizeof name, "quad%d", q->valueint);
        int m = material_named(s, name);
        if (m < 0) {
            fail(p, w, "%d: the file has no quads[%d]", q->valueint, q->valueint);
            return false;
        }
        mark_material(s, m, mark);
    }
    return true;
}

/* One entry of "objects": its vertices (those `mark` holds), their rest
 * state, its pivot and transform. `owner` holds, per vertex, 1 + the index
 * of the object that took it (0: none). false after logging. */
static bool make_object(Parse *p, Scene *s, const cJSON *j, int index, const SceneNodeMap *nodes, uint8_t *mark,
                        int *owner)
{
    SceneObject *o = &s->objects[index];
    char where[160], w[200];
    snprintf(where, sizeof where, "objects.%.60s", j->string);
    snprintf(o->name, sizeof o->name, "%s", j->string);
    if (!object_with_keys(p, j, where, k_object_keys))
        return false;
    memset(mark, 0, s->vertex_count);
    if (!select_geometry(p, s, j, where, nodes, mark))
        return false;
    /* Its vertices must be its own: a vertex of another triangle would be
     * dragged along (or torn off). */
    for (int k = 0; k < s->submesh_count; k++) {
        const Submesh *sm = &s->submeshes[k];
        bool mine = true;
        for (uint32_t i = sm->first_index; i < sm->first_index + sm->index_count && mine; i++)
            mine = mark[s->indices[i]] != 0;
        for (uint32_t i = sm->first_index; i < sm->first_index + sm->index_count && !mine; i++)
            if (mark[s->indices[i]]) {
                fail(p, where, "shares vertices with material \"%s\", which it does not hold",
                     s->materials[sm->material].name);
                return false;
            }
    }
    uint32_t n = 0;
    for (uint32_t v = 0; v < s->vertex_count; v++)
        if (mark[v]) {
            if (owner[v]) {
                fail(p, where, "holds geometry of objects.%s too", s->objects[owner[v] - 1].name);
                return false;
            }
            owner[v] = index + 1;
            n++;
        }
    o->vertices = util_malloc("scene", "object vertices", n + 1, sizeof(uint32_t));
    o->rest = util_malloc("scene", "object vertices", n + 1, sizeof *o->rest);
    if (!o->vertices || !o->rest) {
        p->ok = false;
        return false;
    }
    vec3 lo = {INFINITY, INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < s->vertex_count; v++)
        if (mark[v]) {
            const Vertex *vx = &s->vertices[v];
            o->vertices[o->vertex_count] = v;
            memcpy(o->rest[o->vertex_count], vx->position, sizeof vx->position);
            memcpy(o->rest[o->vertex_count] + 3, vx->normal, sizeof vx->normal);
            o->vertex_count++;
            glm_vec3_minv(lo, (float *)vx->position, lo);
            glm_vec3_maxv(hi, (float *)vx->position, hi);
        }
    glm_vec3_center(lo, hi, o->pivot);
    const char *keys[2] = {"translate", "rotate_deg"};
    float *dst[2] = {o->translate, o->rotate_deg};
    for (int k = 0; k < 2; k++) {
        const cJSON *e = cJSON_GetObjectItemCaseSensitive(j, keys[k]);
        snprintf(w, sizeof w, "%s.%s", where, keys[k]);
        if (e && !value(p, e, w, 3, dst[k]))
            return false;
        for (int c = 0; e && c < 3; c++)
            if (!(fabsf(dst[k][c]) <= ANIM_MAX_COORD)) {
                fail(p, w, "%g is beyond the limit of %g", (double)dst[k][c], (double)ANIM_MAX_COORD);
                return false;
            }
    }
    return true;
}

static bool parse_objects(Parse *p, Scene *s, const cJSON *objs, const SceneNodeMap *nodes)
{
    if (!cJSON_IsObject(objs)) {
        fail(p, "objects", "must be an object of name -> {\"material\": ...} or {\"quads\": [...]}");
        return false;
    }
    int n = cJSON_GetArraySize(objs);
    if (n > ANIMATION_MAX_OBJECTS) {
        fail(p, "objects", "%d objects is more than the limit of %d", n, ANIMATION_MAX_OBJECTS);
        return false;
    }
    for (const cJSON *a = objs->child; a; a = a->next)
        for (const cJSON *b = objs->child; b != a; b = b->next)
            if (!strcmp(a->string, b->string)) {
                fail(p, "objects", "duplicate key \"%s\"", a->string);
                return false;
            }
    s->objects = util_calloc("scene", "objects", (size_t)n + 1, sizeof(SceneObject));
    uint8_t *mark = util_malloc("scene", "object marks", (size_t)s->vertex_count + 1, 1);
    int *owner = util_calloc("scene", "object marks", (size_t)s->vertex_count + 1, sizeof(int));
    bool ok = s->objects && mark && owner;
    if (!ok)
        p->ok = false;
    int i = 0;
    for (const cJSON *j = objs->child; ok && j; j = j->next, i++) {
        if (strlen(j->string) == 0 || strlen(j->string) >= sizeof s->objects[0].name) {
            fail(p, "objects", "an object's name must be 1 to %d bytes", (int)sizeof s->objects[0].name - 1);
            ok = false;
            break;
        }
        s->object_count = i + 1; /* counted before it is made: scene_free frees a half-made one */
        ok = make_object(p, s, j, i, nodes, mark, owner);
    }
    free(mark);
    free(owner);
    return ok;
}

/* ---- tracks */

static const char *const k_animation_keys[] = {"duration", "tracks", NULL};
static const char *const k_track_keys[] = {"target", "key", "interpolation", "times", "values", NULL};
static const char *const k_interp_names[] = {"linear", "catmull-rom", NULL};

/* The keys a target may animate, as a list for messages. */
static const char *target_keys(const Scene *s, AnimTarget target, int index)
{
    if (target == ANIM_TARGET_CAMERA)
        return "position, target, fov_y_deg";
    if (target == ANIM_TARGET_OBJECT)
        return "translate, rotate_deg";
    switch (s->lights[index].type) {
    case LIGHT_DIRECTIONAL: return "direction, irradiance";
    case LIGHT_SPOT: return "position, direction, intensity";
    case LIGHT_POINT: return "position, intensity";
    default: return "position, radiance (a quad light's direction cannot move: its u and v would not follow)";
    }
}

static const char *light_type_name(LightType t)
{
    return t == LIGHT_DIRECTIONAL ? "directional" : t == LIGHT_SPOT ? "spot" : t == LIGHT_POINT ? "point" : "quad";
}

/* The channel `key` names for the target, or -1. */
static int channel_of(const Scene *s, AnimTarget target, int index, const char *key)
{
    if (target == ANIM_TARGET_CAMERA)
        return !strcmp(key, "position") ? ANIM_POSITION : !strcmp(key, "target") ? ANIM_TARGET
                                                       : !strcmp(key, "fov_y_deg") ? ANIM_FOV
                                                                                   : -1;
    if (target == ANIM_TARGET_OBJECT)
        return !strcmp(key, "translate") ? ANIM_TRANSLATE : !strcmp(key, "rotate_deg") ? ANIM_ROTATE : -1;
    LightType t = s->lights[index].type;
    if (!strcmp(key, "position") && t != LIGHT_DIRECTIONAL)
        return ANIM_POSITION;
    if (!strcmp(key, "direction") && (t == LIGHT_DIRECTIONAL || t == LIGHT_SPOT))
        return ANIM_DIRECTION;
    const char *power = t == LIGHT_DIRECTIONAL ? "irradiance" : t == LIGHT_QUAD ? "radiance" : "intensity";
    if (!strcmp(key, power))
        return ANIM_POWER;
    return -1;
}

/* "camera", "lights[N]" or "objects.NAME" into *target and *index. */
static bool parse_target(Parse *p, const Scene *s, const cJSON *j, const char *where, AnimTarget *target, int *index)
{
    char w[200];
    snprintf(w, sizeof w, "%s.target", where);
    if (!cJSON_IsString(j)) {
        fail(p, w, "missing or not a string (\"camera\", \"lights[N]\" or \"objects.NAME\")");
        return false;
    }
    const char *v = j->valuestring;
    *index = 0;
    if (!strcmp(v, "camera")) {
        *target = ANIM_TARGET_CAMERA;
        return true;
    }
    int n = 0, end = 0;
    if (sscanf(v, "lights[%d]%n", &n, &end) == 1 && v[end] == 0) {
        if (n < 0 || n >= s->light_count) {
            fail(p, w, "\"%s\": no such light (the scene has %d: lights[0] to lights[%d])", v, s->light_count,
                 s->light_count - 1);
            return false;
        }
        *target = ANIM_TARGET_LIGHT;
        *index = n;
        return true;
    }
    if (!strncmp(v, "objects.", 8)) {
        for (int i = 0; i < s->object_count; i++)
            if (!strcmp(s->objects[i].name, v + 8)) {
                *target = ANIM_TARGET_OBJECT;
                *index = i;
                return true;
            }
        fail(p, w, "\"%s\": no such object (name it under \"objects\")", v);
        return false;
    }
    fail(p, w, "\"%s\" is not \"camera\", \"lights[N]\" or \"objects.NAME\"", v);
    return false;
}

/* Checks one key's value for its channel; false after logging. */
static bool check_value(Parse *p, const AnimTrack *k, const float v[3], const char *where)
{
    switch (k->channel) {
    case ANIM_POSITION:
    case ANIM_TARGET:
    case ANIM_TRANSLATE:
    case ANIM_ROTATE:
        for (int c = 0; c < 3; c++)
            if (!(fabsf(v[c]) <= ANIM_MAX_COORD)) {
                fail(p, where, "%g is beyond the limit of %g", (double)v[c], (double)ANIM_MAX_COORD);
                return false;
            }
        return true;
    case ANIM_DIRECTION:
        if (!(glm_vec3_norm((float *)v) > 1e-6f)) {
            fail(p, where, "is zero (a direction must have a length)");
            return false;
        }
        return true;
    case ANIM_POWER:
        for (int c = 0; c < 3; c++)
            if (!(v[c] >= 0.f && v[c] <= ANIM_MAX_POWER)) {
                fail(p, where, "%g is outside [0, %g]", (double)v[c], (double)ANIM_MAX_POWER);
                return false;
            }
        return true;
    case ANIM_FOV:
        if (!(v[0] > 1.f && v[0] < 179.f)) {
            fail(p, where, "%g: must be in (1, 179)", (double)v[0]);
            return false;
        }
        return true;
    }
    return true;
}

static bool parse_track(Parse *p, const Scene *s, const cJSON *j, int ti, float duration, AnimTrack *k)
{
    char where[64], w[200];
    snprintf(where, sizeof where, "animation.tracks[%d]", ti);
    if (!object_with_keys(p, j, where, k_track_keys))
        return false;
    if (!parse_target(p, s, cJSON_GetObjectItemCaseSensitive(j, "target"), where, &k->target, &k->index))
        return false;
    const cJSON *key = cJSON_GetObjectItemCaseSensitive(j, "key");
    snprintf(w, sizeof w, "%s.key", where);
    char what[64];
    if (k->target == ANIM_TARGET_LIGHT)
        snprintf(what, sizeof what, "lights[%d] (a %s light)", k->index, light_type_name(s->lights[k->index].type));
    else
        snprintf(what, sizeof what, "%s", k->target == ANIM_TARGET_CAMERA ? "the camera" : "an object");
    if (!cJSON_IsString(key)) {
        fail(p, w, "missing or not a string (%s animates: %s)", what, target_keys(s, k->target, k->index));
        return false;
    }
    int ch = channel_of(s, k->target, k->index, key->valuestring);
    if (ch < 0) {
        fail(p, w, "\"%s\" is not a key %s animates (it animates: %s)", key->valuestring, what,
             target_keys(s, k->target, k->index));
        return false;
    }
    k->channel = (AnimChannel)ch;
    k->dims = k->channel == ANIM_FOV ? 1 : 3;
    const cJSON *interp = cJSON_GetObjectItemCaseSensitive(j, "interpolation");
    snprintf(w, sizeof w, "%s.interpolation", where);
    if (interp) {
        int m = -1;
        for (int i = 0; cJSON_IsString(interp) && k_interp_names[i]; i++)
            if (!strcmp(interp->valuestring, k_interp_names[i]))
                m = i;
        if (m < 0) {
            fail(p, w, "must be \"linear\" or \"catmull-rom\"");
            return false;
        }
        k->interp = (AnimInterp)m;
        bool positional = k->channel == ANIM_POSITION || k->channel == ANIM_TARGET || k->channel == ANIM_TRANSLATE;
        if (k->interp == ANIM_CATMULL_ROM && !positional) {
            fail(p, w, "catmull-rom is for positions (position, target, translate); %s is linear",
                 key->valuestring);
            return false;
        }
    }
    const cJSON *times = cJSON_GetObjectItemCaseSensitive(j, "times"),
                *values = cJSON_GetObjectItemCaseSensitive(j, "values");
    snprintf(w, sizeof w, "%s.times", where);
    if (!cJSON_IsArray(times) || cJSON_GetArraySize(times) < 1) {
        fail(p, w, "missing or not a non-empty array of times (s)");
        return false;
    }
    int n = cJSON_GetArraySize(times);
    if (n > ANIMATION_MAX_KEYS) {
        fail(p, w, "%d keys is more than the limit of %d", n, ANIMATION_MAX_KEYS);
        return false;
    }
    snprintf(w, sizeof w, "%s.values", where);
    if (!cJSON_IsArray(values) || cJSON_GetArraySize(values) != n) {
        fail(p, w, "must be an array of %d value%s, one per time", n, n == 1 ? "" : "s");
        return false;
    }
    k->times = util_malloc("scene", "animation keys", (size_t)n, sizeof(float));
    k->values = util_malloc("scene", "animation keys", (size_t)n, sizeof *k->values);
    if (!k->times || !k->values) {
        p->ok = false;
        return false;
    }
    k->key_count = n;
    for (int i = 0; i < n; i++) {
        snprintf(w, sizeof w, "%s.times[%d]", where, i);
        if (!number(p, cJSON_GetArrayItem(times, i), w, &k->times[i]))
            return false;
        if (i > 0 && !(k->times[i] > k->times[i - 1])) {
            fail(p, w, "%g is not after times[%d] = %g (times must increase)", (double)k->times[i], i - 1,
                 (double)k->times[i - 1]);
            return false;
        }
        if (!(k->times[i] >= 0.f && k->times[i] <= duration)) {
            fail(p, w, "%g is outside the animation's [0, %g] s", (double)k->times[i], (double)duration);
            return false;
        }
        snprintf(w, sizeof w, "%s.values[%d]", where, i);
        memset(k->values[i], 0, sizeof k->values[i]);
        if (!value(p, cJSON_GetArrayItem(values, i), w, k->dims, k->values[i]) || !check_value(p, k, k->values[i], w))
            return false;
    }
    return true;
}

static bool parse_animation(Parse *p, Scene *s, const cJSON *j)
{
    if (!object_with_keys(p, j, "animation", k_animation_keys))
        return false;
    Animation *a = s->animation = util_calloc("scene", "the animation", 1, sizeof(Animation));
    if (!a) {
        p->ok = false;
        return false;
    }
    a->time = -1.0; /* nothing applied yet */
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(j, "duration");
    if (!d) {
        fail(p, "animation.duration", "missing (seconds)");
        return false;
    }
    if (!number(p, d, "animation.duration", &a->duration))
        return false;
    if (!(a->duration > 0.f && a->duration <= ANIMATION_MAX_DURATION)) {
        fail(p, "animation.duration", "%g s: must be in (0, %g]", (double)a->duration, ANIMATION_MAX_DURATION);
        return false;
    }
    const cJSON *tracks = cJSON_GetObjectItemCaseSensitive(j, "tracks");
    if (!cJSON_IsArray(tracks) || cJSON_GetArraySize(tracks) == 0) {
        fail(p, "animation.tracks", "missing or not a non-empty array of tracks");
        return false;
    }
    int n = cJSON_GetArraySize(tracks);
    if (n > ANIMATION_MAX_TRACKS) {
        fail(p, "animation.tracks", "%d tracks is more than the limit of %d", n, ANIMATION_MAX_TRACKS);
        return false;
    }
    a->tracks = util_calloc("scene", "animation tracks", (size_t)n, sizeof(AnimTrack));
    if (!a->tracks) {
        p->ok = false;
        return false;
    }
    int i = 0;
    const cJSON *t;
    cJSON_ArrayForEach(t, tracks)
    {
        AnimTrack *k = &a->tracks[i];
        a->track_count = i + 1;
        if (!parse_track(p, s, t, i, a->duration, k))
            return false;
        for (int o = 0; o < i; o++) {
            const AnimTrack *x = &a->tracks[o];
            if (x->target == k->target && x->index == k->index && x->channel == k->channel) {
                char w[64];
                snprintf(w, sizeof w, "animation.tracks[%d]", i);
                fail(p, w, "animates what tracks[%d] animates (one track per target and key)", o);
                return false;
            }
        }
        i++;
    }
    return true;
}

/* The camera's "up" of the file (unit; default +y). */
static void file_camera_up(const cJSON *root, vec3 up)
{
    glm_vec3_copy((vec3){0, 1, 0}, up);
    const cJSON *cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    const cJSON *u = cam ? cJSON_GetObjectItemCaseSensitive(cam, "up") : NULL;
    if (cJSON_IsArray(u) && cJSON_GetArraySize(u) == 3)
        for (int i = 0; i < 3; i++)
            up[i] = (float)cJSON_GetArrayItem(u, i)->valuedouble; /* checked by the camera's parser */
    glm_vec3_normalize(up);
}

bool animation_parse(Scene *s, const cJSON *root, const char *file, const SceneNodeMap *nodes)
{
    Parse p = {file, true};
    const cJSON *objs = cJSON_GetObjectItemCaseSensitive(root, "objects");
    const cJSON *anim = cJSON_GetObjectItemCaseSensitive(root, "animation");
    if (objs && !parse_objects(&p, s, objs, nodes))
        return false;
    if (anim && !parse_animation(&p, s, anim))
        return false;
    if (s->animation)
        file_camera_up(root, s->animation->camera_up);
    if (s->object_count || s->animation)
        animation_apply(s, 0.0, NULL);
    return true;
}

bool animation_present(const Scene *s) { return s->animation != NULL; }

float animation_duration(const Scene *s) { return s->animation ? s->animation->duration : 0.f; }

/* --------------------------------------------------------- interpolation */

/* Track k's tangent at key j (d value / d t): from the neighbouring keys,
 * one-sided at the ends. */
static double tangent(const AnimTrack *k, int j, int c)
{
    int a = j > 0 ? j - 1 : 0, b = j + 1 < k->key_count ? j + 1 : j;
    double dt = (double)k->times[b] - k->times[a];
    return dt > 0 ? ((double)k->values[b][c] - k->values[a][c]) / dt : 0.0;
}

void animation_track_value(const AnimTrack *k, double t, float out[3])
{
    int n = k->key_count;
    memset(out, 0, 3 * sizeof(float));
    int i;
    if (n == 1 || t <= k->times[0]) {
        i = 0;
    } else if (t >= k->times[n - 1]) {
        i = n - 1;
    } else { /* the segment [times[i], times[i+1]) holding t */
        int lo = 0, hi = n - 1;
        while (hi - lo > 1) {
            int mid = (lo + hi) / 2;
            if (k->times[mid] <= t)
                lo = mid;
            else
                hi = mid;
        }
        i = lo;
        if (t > k->times[i]) {
            double t0 = k->times[i], t1 = k->times[i + 1], h = t1 - t0, u = (t - t0) / h;
            for (int c = 0; c < k->dims; c++) {
                double v0 = k->values[i][c], v1 = k->values[i + 1][c], v;
                if (k->interp == ANIM_LINEAR) {
                    v = v0 + (v1 - v0) * u;
                } else { /* cubic Hermite with Catmull-Rom tangents */
                    double u2 = u * u, u3 = u2 * u;
                    v = (2 * u3 - 3 * u2 + 1) * v0 + (u3 - 2 * u2 + u) * h * tangent(k, i, c) +
                        (-2 * u3 + 3 * u2) * v1 + (u3 - u2) * h * tangent(k, i + 1, c);
                }
                out[c] = (float)v;
            }
            return;
        }
    }
    memcpy(out, k->values[i], (size_t)k->dims * sizeof(float)); /* exact at a key */
}

/* ------------------------------------------------------------- applying */

/* The track of (target, index, channel), or NULL. */
static const AnimTrack *find_track(const Animation *a, AnimTarget target, int index, AnimChannel channel)
{
    for (int i = 0; a && i < a->track_count; i++) {
        const AnimTrack *k = &a->tracks[i];
        if (k->target == target && k->index == index && k->channel == channel)
            return k;
    }
    return NULL;
}

/* p' = R (p − pivot) + pivot + translate, n' = R n, with R turning about
 * x, then y, then z by rot (degrees); in double, rounded once. */
/* Object o's vertices at translate and rot, written into `vertices` (the
 * scene's array or a copy of it). */
static void place_object(Vertex *vertices, const SceneObject *o, const vec3 translate, const vec3 rot)
{
    double cx = cos(glm_rad(rot[0])), sx = sin(glm_rad(rot[0])), cy = cos(glm_rad(rot[1])),
           sy = sin(glm_rad(rot[1])), cz = cos(glm_rad(rot[2])), sz = sin(glm_rad(rot[2]));
    /* R = Rz · Ry · Rx (row-major m[row][col]) */
    const double m[3][3] = {
        {cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx},
        {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx},
        {-sy, cy * sx, cy * cx},
    };
    for (uint32_t i = 0; i < o->vertex_count; i++) {
        Vertex *v = &vertices[o->vertices[i]];
        const float *r = o->rest[i];
        double d[3] = {(double)r[0] - o->pivot[0], (double)r[1] - o->pivot[1], (double)r[2] - o->pivot[2]};
        for (int row = 0; row < 3; row++) {
            v->position[row] = (float)(m[row][0] * d[0] + m[row][1] * d[1] + m[row][2] * d[2] + o->pivot[row] +
                                       translate[row]);
            v->normal[row] = (float)(m[row][0] * r[3] + m[row][1] * r[4] + m[row][2] * r[5]);
        }
    }
}

/* Object i (o) at time t: its file's transform, each channel a track
 * moves replaced by the track's value. */
static void object_transform_at(const Animation *a, const SceneObject *o, int i, double t, vec3 translate,
                                vec3 rotate)
{
    const AnimTrack *tr = find_track(a, ANIM_TARGET_OBJECT, i, ANIM_TRANSLATE),
                    *rot = find_track(a, ANIM_TARGET_OBJECT, i, ANIM_ROTATE);
    glm_vec3_copy((float *)o->translate, translate);
    glm_vec3_copy((float *)o->rotate_deg, rotate);
    if (tr)
        animation_track_value(tr, t, translate);
    if (rot)
        animation_track_value(rot, t, rotate);
}

/* Grows the change's vertex range by [first, first + count). */
static void change_vertices(SceneChange *c, uint32_t first, uint32_t count)
{
    if (!count)
        return;
    if (!(c->what & SCENE_CHANGED_GEOMETRY)) {
        c->what |= SCENE_CHANGED_GEOMETRY;
        c->first_vertex = first;
        c->vertex_count = count;
        return;
    }
    uint32_t lo = first < c->first_vertex ? first : c->first_vertex;
    uint32_t hi = first + count > c->first_vertex + c->vertex_count ? first + count : c->first_vertex + c->vertex_count;
    c->first_vertex = lo;
    c->vertex_count = hi - lo;
}

/* The first vertex of submesh k's emitter quad when it is light i's
 * (scene_add_quad's p0 p1 p2 p3 from the first of its six indices), else
 * -1. */
static int64_t emitter_first_vertex(const Scene *s, int k, int i)
{
    const Submesh *sm = &s->submeshes[k];
    if (s->materials[sm->material].light_index != i || sm->index_count < 6)
        return -1;
    return s->indices[sm->first_index];
}

/* Moves quad light i's emitter geometry and emission to the light. */
static void place_emitter(Scene *s, int i, SceneChange *c)
{
    const Light *l = &s->lights[i];
    for (int k = 0; k < s->submesh_count; k++) {
        int64_t first = emitter_first_vertex(s, k, i);
        if (first < 0)
            continue;
        Material *m = &s->materials[s->submeshes[k].material];
        scene_emitter_radiance(l, m->emission);
        vec3 p[4];
        scene_emitter_corners(l, p);
        for (int v = 0; v < 4; v++)
            memcpy(s->vertices[first + v].position, p[v], sizeof(vec3));
        change_vertices(c, (uint32_t)first, 4);
    }
}

static double clamp_time(const Animation *a, double t);

static bool is_emitter(const Light *l) { return l->type == LIGHT_QUAD && l->size > 0.f; }

bool animation_geometry_moves(const Scene *s)
{
    if (s->object_count > 0)
        return true;
    for (int i = 0; i < s->light_count; i++)
        if (is_emitter(&s->lights[i]))
            return true;
    return false;
}

bool animation_vertices_at(const Scene *s, double t, const Light *lights, Vertex *out)
{
    /* The vertices an animation moves are written, never read: another
     * thread may be rewriting them in s. */
    uint8_t *moved = calloc(s->vertex_count ? s->vertex_count : 1, 1);
    if (!moved) {
        log_error("animation", "cannot allocate a map of %u vertices", s->vertex_count);
        return false;
    }
    const Animation *a = s->animation;
    t = clamp_time(a, t);
    for (int i = 0; i < s->object_count; i++) {
        const SceneObject *o = &s->objects[i];
        vec3 translate, rotate;
        object_transform_at(a, o, i, t, translate, rotate);
        place_object(out, o, translate, rotate);
        for (uint32_t k = 0; k < o->vertex_count; k++)
            moved[o->vertices[k]] = 1;
    }
    for (int i = 0; i < s->light_count; i++) {
        if (!is_emitter(&lights[i]))
            continue;
        vec3 p[4];
        scene_emitter_corners(&lights[i], p);
        for (int k = 0; k < s->submesh_count; k++) {
            int64_t first = emitter_first_vertex(s, k, i);
            for (int v = 0; first >= 0 && v < 4; v++) {
                /* The normal and uv as the scene built them (place_emitter
                 * writes positions only). */
                Vertex *o = &out[first + v];
                const Vertex *in = &s->vertices[first + v];
                memcpy(o->position, p[v], sizeof(vec3));
                memcpy(o->normal, in->normal, sizeof o->normal);
                memcpy(o->uv, in->uv, sizeof o->uv);
                moved[first + v] = 1;
            }
        }
    }
    for (uint32_t v = 0; v < s->vertex_count; v++)
        if (!moved[v])
            out[v] = s->vertices[v];
    free(moved);
    return true;
}

/* The camera at t from its tracks, written over *cam; false (the view
 * kept) where the target meets the position. */
static bool camera_at(const Animation *a, double t, Camera *cam)
{
    const AnimTrack *pos = find_track(a, ANIM_TARGET_CAMERA, 0, ANIM_POSITION),
                    *tgt = find_track(a, ANIM_TARGET_CAMERA, 0, ANIM_TARGET),
                    *fov = find_track(a, ANIM_TARGET_CAMERA, 0, ANIM_FOV);
    float v[3];
    if (pos)
        animation_track_value(pos, t, cam->position);
    if (fov) {
        animation_track_value(fov, t, v);
        cam->fov_y = glm_rad(v[0]);
    }
    if (!tgt && !pos)
        return true;
    vec3 forward, up, right;
    if (tgt) { /* as the scene file's parser makes a camera from position and target */
        animation_track_value(tgt, t, v);
        glm_vec3_sub(v, cam->position, forward);
        if (!(glm_vec3_norm(forward) > 1e-6f))
            return false;
        glm_vec3_normalize(forward);
    } else {
        glm_vec3_copy(cam->forward, forward);
    }
    glm_vec3_copy((float *)a->camera_up, up);
    glm_vec3_cross(forward, up, right);
    if (!(glm_vec3_norm(right) > 1e-4f))
        return false;
    glm_vec3_normalize(right);
    glm_vec3_copy(forward, cam->forward);
    glm_vec3_cross(right, cam->forward, cam->up);
    return true;
}

static double clamp_time(const Animation *a, double t)
{
    float duration = a ? a->duration : 0.f;
    return t < 0 ? 0 : t > duration ? duration : t;
}

bool animation_camera_at(const Scene *s, double t, Camera *cam)
{
    const Animation *a = s->animation;
    if (!a || !(find_track(a, ANIM_TARGET_CAMERA, 0, ANIM_POSITION) || find_track(a, ANIM_TARGET_CAMERA, 0, ANIM_TARGET) ||
                find_track(a, ANIM_TARGET_CAMERA, 0, ANIM_FOV)))
        return false;
    Camera c = *cam;
    if (!camera_at(a, clamp_time(a, t), &c))
        return false;
    *cam = c;
    return true;
}

void animation_lights_at(const Scene *s, double t, Light *lights)
{
    const Animation *a = s->animation;
    t = clamp_time(a, t);
    float v[3];
    for (int i = 0; a && i < a->track_count; i++) {
        const AnimTrack *k = &a->tracks[i];
        if (k->target != ANIM_TARGET_LIGHT)
            continue;
        Light *l = &lights[k->index];
        animation_track_value(k, t, v);
        if (k->channel == ANIM_POSITION)
            glm_vec3_copy(v, l->position);
        else if (k->channel == ANIM_DIRECTION)
            glm_vec3_normalize_to(v, l->direction); /* as scene_add_light */
        else if (k->channel == ANIM_POWER)
            glm_vec3_copy(v, l->color);
    }
}

void animation_place_emitter(Scene *s, int light, SceneChange *c)
{
    if (light >= 0 && light < s->light_count && s->lights[light].type == LIGHT_QUAD && s->lights[light].size > 0.f)
        place_emitter(s, light, c);
}

bool animation_apply(Scene *s, double t, SceneChange *changed)
{
    SceneChange c = {0};
    Animation *a = s->animation;
    if (!a && !s->object_count) {
        if (changed)
            *changed = c;
        return false;
    }
    t = clamp_time(a, t);
    Light old_lights[32];
    int nl = s->light_count < 32 ? s->light_count : 32;
    memcpy(old_lights, s->lights, sizeof(Light) * (size_t)nl);
    Camera old_cam = s->camera;
    animation_lights_at(s, t, s->lights);
    if (a)
        a->camera_degenerate = !camera_at(a, t, &s->camera);
    if (memcmp(old_lights, s->lights, sizeof(Light) * (size_t)nl) != 0)
        c.what |= SCENE_CHANGED_LIGHTS;
    if (memcmp(&old_cam, &s->camera, sizeof old_cam) != 0)
        c.what |= SCENE_CHANGED_CAMERA;
    for (int i = 0; i < nl; i++)
        if (s->lights[i].type == LIGHT_QUAD && s->lights[i].size > 0.f &&
            memcmp(&old_lights[i], &s->lights[i], sizeof(Light)) != 0)
            place_emitter(s, i, &c);
    bool moved = false;
    for (int i = 0; i < s->object_count; i++) {
        SceneObject *o = &s->objects[i];
        vec3 translate, rotate;
        object_transform_at(a, o, i, t, translate, rotate);
        if (o->placed && !memcmp(translate, o->placed_translate, sizeof translate) &&
            !memcmp(rotate, o->placed_rotate_deg, sizeof rotate))
            continue;
        place_object(s->vertices, o, translate, rotate);
        glm_vec3_copy(translate, o->placed_translate);
        glm_vec3_copy(rotate, o->placed_rotate_deg);
        o->placed = true;
        moved = true;
        if (o->vertex_count)
            change_vertices(&c, o->vertices[0], o->vertices[o->vertex_count - 1] - o->vertices[0] + 1);
    }
    if (moved) {
        vec3 lo, hi;
        glm_vec3_copy(s->bounds_min, lo);
        glm_vec3_copy(s->bounds_max, hi);
        scene_compute_bounds(s);
        if (memcmp(lo, s->bounds_min, sizeof lo) || memcmp(hi, s->bounds_max, sizeof hi))
            c.what |= SCENE_CHANGED_BOUNDS;
    }
    if (a)
        a->time = t;
    if (changed)
        *changed = c;
    return c.what != 0;
}

double animation_frame_time(const Scene *s, int i, int n, double fps)
{
    if (fps > 0)
        return i / fps;
    if (n <= 1)
        return 0.0;
    return (double)animation_duration(s) * i / (n - 1);
}

/* The checks of the scene at time t (frame i, or -1), with the time in
 * their one line; the scene is left at t. */
static bool check_at(Scene *s, double t, int i)
{
    char source[sizeof s->source];
    memcpy(source, s->source, sizeof source);
    animation_apply(s, t, NULL);
    if (i >= 0)
        snprintf(s->source, sizeof s->source, "%.400s at %.4g s (frame %d)", source, t, i);
    else
        snprintf(s->source, sizeof s->source, "%.400s at %.4g s", source, t);
    bool ok = true;
    if (s->animation && s->animation->camera_degenerate) {
        log_error("scene", "%s: the camera's target meets its position, or it looks along its up", s->source);
        ok = false;
    }
    ok = ok && scene_check_view(s) && scene_check_lights(s, "");
    memcpy(s->source, source, sizeof source);
    return ok;
}

bool animation_check_time(Scene *s, double t, const char *what)
{
    if (!s->animation) {
        log_error("scene", "%s: %s: the scene has no animation (a scene file's \"animation\")", s->source, what);
        return false;
    }
    if (!(t >= 0 && t <= s->animation->duration)) {
        log_error("scene", "%s: %s: %.4g s is outside the animation's [0, %.4g] s", s->source, what, t,
                  (double)s->animation->duration);
        return false;
    }
    return check_at(s, t, -1);
}

bool animation_check_frames(Scene *s, int n, double fps, const char *what)
{
    if (!s->animation) {
        log_error("scene", "%s: %s: the scene has no animation (a scene file's \"animation\")", s->source, what);
        return false;
    }
    float duration = animation_duration(s);
    double last = animation_frame_time(s, n - 1, n, fps);
    if (last > duration * (1.0 + 1e-9)) {
        log_error("scene", "%s: %s: frame %d falls at %.4g s, after the animation's %.4g s (fewer frames or a "
                  "higher --fps)", s->source, what, n - 1, last, (double)duration);
        return false;
    }
    bool ok = true;
    for (int i = 0; i < n && ok; i++)
        ok = check_at(s, animation_frame_time(s, i, n, fps), i);
    animation_apply(s, 0.0, NULL);
    return ok;
}
