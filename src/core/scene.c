#include "core/scene.h"
#include "core/settings.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/log.h"
#include "base/util.h"

void scene_init(Scene *s)
{
    memset(s, 0, sizeof *s);
    s->exposure = 1.0f;
    Settings defaults; /* the settings table's */
    settings_default(&defaults);
    s->settings.shadow = defaults.shadow;
    s->settings.gi = defaults.gi;
    glm_vec3_copy((vec3){0, 1, 5}, s->camera.position);
    glm_vec3_copy((vec3){0, 0, -1}, s->camera.forward);
    glm_vec3_copy((vec3){0, 1, 0}, s->camera.up);
    s->camera.fov_y = glm_rad(60.0f);
    s->camera.znear = 0.01f;
    s->camera.zfar = 100.0f;
    glm_vec3_fill(s->bounds_min, 0.f);
    glm_vec3_fill(s->bounds_max, 0.f);
}

/* The objects and the animation (animation.c made them). */
static void free_time(Scene *s)
{
    for (int i = 0; i < s->object_count; i++) {
        free(s->objects[i].vertices);
        free(s->objects[i].rest);
    }
    free(s->objects);
    s->objects = NULL;
    s->object_count = 0;
    Animation *a = s->animation;
    for (int i = 0; a && i < a->track_count; i++) {
        free(a->tracks[i].times);
        free(a->tracks[i].values);
    }
    if (a)
        free(a->tracks);
    free(a);
    s->animation = NULL;
}

void scene_free(Scene *s)
{
    for (int i = 0; i < s->texture_count; i++)
        free(s->textures[i].rgba);
    free(s->textures);
    free(s->vertices);
    free(s->indices);
    free(s->submeshes);
    free(s->materials);
    free(s->lights);
    free_time(s);
    memset(s, 0, sizeof *s);
}

int scene_add_material(Scene *s, const char *name, const vec3 albedo)
{
    if (!util_realloc("scene", "materials", (void **)&s->materials, (size_t)s->material_count + 1, sizeof(Material)))
        return -1;
    Material *m = &s->materials[s->material_count];
    memset(m, 0, sizeof *m);
    snprintf(m->name, sizeof m->name, "%s", name);
    glm_vec3_copy((float *)albedo, m->albedo);
    m->albedo_tex = -1;
    m->metallic = 0.f;
    m->roughness = 1.f;
    m->specular = 0.f; /* Lambertian unless a loader or the scene file says otherwise */
    m->mr_tex = -1;
    m->alpha_cutoff = 0.5f;
    m->light_index = -1;
    return s->material_count++;
}

/* Appends indices of one material, extending the last submesh if it matches. */
static bool add_indices(Scene *s, int material, const uint32_t *idx, uint32_t n)
{
    if (!util_realloc("scene", "indices", (void **)&s->indices, (size_t)s->index_count + n, sizeof(uint32_t)))
        return false;
    memcpy(s->indices + s->index_count, idx, sizeof(uint32_t) * n);
    Submesh *last = s->submesh_count ? &s->submeshes[s->submesh_count - 1] : NULL;
    if (last && last->material == material && last->first_index + last->index_count == s->index_count) {
        last->index_count += n;
    } else {
        if (!util_realloc("scene", "submeshes", (void **)&s->submeshes, (size_t)s->submesh_count + 1,
                          sizeof(Submesh)))
            return false;
        s->submeshes[s->submesh_count++] = (Submesh){s->index_count, n, material};
    }
    s->index_count += n;
    return true;
}

bool scene_add_quad(Scene *s, int material, const vec3 p0, const vec3 p1, const vec3 p2, const vec3 p3)
{
    vec3 e1, e2, n;
    glm_vec3_sub((float *)p1, (float *)p0, e1);
    glm_vec3_sub((float *)p3, (float *)p0, e2);
    glm_vec3_cross(e1, e2, n);
    glm_vec3_normalize(n);
    const float *p[4] = {p0, p1, p2, p3};
    const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    uint32_t base = s->vertex_count;
    if (!util_realloc("scene", "vertices", (void **)&s->vertices, (size_t)s->vertex_count + 4, sizeof(Vertex)))
        return false;
    for (int i = 0; i < 4; i++) {
        Vertex *v = &s->vertices[s->vertex_count++];
        memcpy(v->position, p[i], sizeof v->position);
        memcpy(v->normal, n, sizeof v->normal);
        v->uv[0] = uv[i][0];
        v->uv[1] = uv[i][1];
    }
    uint32_t idx[6] = {base, base + 1, base + 2, base, base + 2, base + 3};
    return add_indices(s, material, idx, 6);
}

int scene_add_light(Scene *s, const Light *l)
{
    if (!util_realloc("scene", "lights", (void **)&s->lights, (size_t)s->light_count + 1, sizeof(Light)))
        return -1;
    s->lights[s->light_count] = *l;
    glm_vec3_normalize(s->lights[s->light_count].direction);
    return s->light_count++;
}

static bool add_emitters(Scene *s);

bool scene_rescale_lights(Scene *s, float scale)
{
    /* Emitter materials, submeshes and vertices are the last ones added. */
    int first_mat = s->material_count;
    while (first_mat > 0 && s->materials[first_mat - 1].light_index >= 0)
        first_mat--;
    int first_sub = s->submesh_count;
    while (first_sub > 0 && s->submeshes[first_sub - 1].material >= first_mat)
        first_sub--;
    if (first_sub < s->submesh_count) {
        uint32_t first_index = s->submeshes[first_sub].first_index;
        uint32_t first_vertex = s->vertex_count;
        for (uint32_t i = first_index; i < s->index_count; i++)
            if (s->indices[i] < first_vertex)
                first_vertex = s->indices[i];
        s->index_count = first_index;
        s->vertex_count = first_vertex;
    }
    s->submesh_count = first_sub;
    s->material_count = first_mat;
    for (int i = 0; i < s->light_count; i++)
        s->lights[i].size *= scale;
    return add_emitters(s);
}

void scene_compute_bounds(Scene *s)
{
    glm_vec3_fill(s->bounds_min, INFINITY);
    glm_vec3_fill(s->bounds_max, -INFINITY);
    for (int k = 0; k < s->submesh_count; k++) {
        const Submesh *sm = &s->submeshes[k];
        if (s->materials[sm->material].light_index >= 0)
            continue;
        for (uint32_t i = sm->first_index; i < sm->first_index + sm->index_count; i++) {
            const float *p = s->vertices[s->indices[i]].position;
            glm_vec3_minv(s->bounds_min, (float *)p, s->bounds_min);
            glm_vec3_maxv(s->bounds_max, (float *)p, s->bounds_max);
        }
    }
    if (s->bounds_min[0] > s->bounds_max[0]) {
        glm_vec3_zero(s->bounds_min);
        glm_vec3_zero(s->bounds_max);
    }
}

bool scene_has_glossy(const Scene *s)
{
    for (int i = 0; i < s->material_count; i++)
        if (s->materials[i].metallic != 0.f || s->materials[i].specular != 0.f)
            return true;
    return false;
}

bool scene_finalize(Scene *s)
{
    if (!add_emitters(s))
        return false;
    scene_compute_bounds(s);
    return true;
}

static bool add_emitters(Scene *s)
{
    /* Emitter geometry for quad lights, so that the camera and the path
     * tracer's BSDF rays see the light's surface. Same power at any size:
     * L' = L / size². */
    for (int i = 0; i < s->light_count; i++) {
        Light *l = &s->lights[i];
        if (l->type != LIGHT_QUAD || l->size <= 0.f)
            continue;
        char name[64];
        snprintf(name, sizeof name, "emitter%d", i);
        int m = scene_add_material(s, name, (vec3){0, 0, 0});
        if (m < 0)
            return false; /* logged */
        scene_emitter_radiance(l, s->materials[m].emission);
        s->materials[m].light_index = i;
        vec3 p[4];
        scene_emitter_corners(l, p);
        if (!scene_add_quad(s, m, p[0], p[1], p[2], p[3]))
            return false; /* logged */
    }
    return true;
}

void scene_emitter_radiance(const Light *l, vec3 out)
{
    glm_vec3_scale((float *)l->color, 1.f / (l->size * l->size), out);
}

void scene_emitter_corners(const Light *l, vec3 p[4])
{
    vec3 hu, hv;
    glm_vec3_scale((float *)l->quad_u, 0.5f * l->size, hu);
    glm_vec3_scale((float *)l->quad_v, 0.5f * l->size, hv);
    /* Wind so that the quad's normal (u×v order) is the emission direction. */
    vec3 n;
    glm_vec3_cross(hu, hv, n);
    if (glm_vec3_dot(n, (float *)l->direction) < 0)
        glm_vec3_negate(hv);
    for (int c = 0; c < 4; c++) {
        float su = (c == 0 || c == 3) ? -1.f : 1.f, sv = (c < 2) ? -1.f : 1.f;
        glm_vec3_copy((float *)l->position, p[c]);
        glm_vec3_muladds(hu, su, p[c]);
        glm_vec3_muladds(hv, sv, p[c]);
    }
}

bool scene_add_default_sun(Scene *s)
{
    Light sun = {0};
    sun.type = LIGHT_DIRECTIONAL;
    /* High and a little aslant: it lights the floor of an interior open to
     * the sky (Sponza's atrium), whose bounce then lights the rest. */
    glm_vec3_copy((vec3){-0.15f, -1.0f, -0.2f}, sun.direction);
    glm_vec3_copy((vec3){4.0f, 3.9f, 3.6f}, sun.color);
    sun.size = glm_rad(0.53f); /* the real sun's angular diameter */
    if (scene_add_light(s, &sun) < 0)
        return false; /* logged */
    log_info("scene", "%s has no lights: added a default sun", s->source);
    return true;
}

void scene_default_camera(Scene *s)
{
    vec3 ext, c;
    glm_vec3_sub(s->bounds_max, s->bounds_min, ext);
    glm_vec3_center(s->bounds_min, s->bounds_max, c);
    int axis = ext[0] >= ext[2] ? 0 : 2; /* look along the longer horizontal axis */
    Camera *cam = &s->camera;
    glm_vec3_copy(c, cam->position);
    /* Inside, a quarter of the way from one end, at a person's height
     * relative to the model, looking down the long axis: for an interior
     * such as Sponza this is its nave; for an object it is a view from its
     * side. */
    int other = 2 - axis;
    cam->position[axis] -= 0.28f * ext[axis];
    cam->position[1] = s->bounds_min[1] + 0.2f * ext[1];
    cam->position[other] -= 0.055f * ext[other];
    vec3 target; /* up and across the nave: its arcades and the upper floor */
    glm_vec3_copy(c, target);
    target[axis] += 0.22f * ext[axis];
    target[1] = s->bounds_min[1] + 0.42f * ext[1];
    target[other] += 0.055f * ext[other];
    float wide = fmaxf(ext[0], ext[2]);
    if (ext[1] < 0.25f * wide) {
        /* A flat scene (a terrain, a floor, one quad): from eye height it
         * would be seen edge-on; look down on it from above its top. */
        cam->position[1] = s->bounds_max[1] + 0.3f * wide;
        target[1] = c[1];
    }
    glm_vec3_sub(target, cam->position, cam->forward);
    glm_vec3_normalize(cam->forward);
    vec3 right;
    glm_vec3_cross(cam->forward, (vec3){0, 1, 0}, right);
    glm_vec3_normalize(right);
    glm_vec3_cross(right, cam->forward, cam->up);
    cam->fov_y = glm_rad(65.f);
    float diag = glm_vec3_norm(ext);
    cam->znear = fmaxf(1e-3f, diag * 1e-4f);
    cam->zfar = diag * 2.f + 0.3f * wide;
}

float light_quad_area(const Light *l)
{
    vec3 n;
    glm_vec3_cross((float *)l->quad_u, (float *)l->quad_v, n);
    return glm_vec3_norm(n) * l->size * l->size;
}

float light_spot_falloff(const Light *l, float cos_theta)
{
    float e0 = cosf(l->spot_outer), e1 = cosf(l->spot_inner);
    float t = (cos_theta - e0) / fmaxf(e1 - e0, 1e-6f);
    t = t < 0.f ? 0.f : (t > 1.f ? 1.f : t);
    return t * t * (3.f - 2.f * t);
}

void light_intensity(const Light *l, const vec3 dir, vec3 out)
{
    float c = glm_vec3_dot((float *)dir, (float *)l->direction);
    switch (l->type) {
    case LIGHT_POINT:
        glm_vec3_copy((float *)l->color, out);
        break;
    case LIGHT_SPOT:
        glm_vec3_scale((float *)l->color, light_spot_falloff(l, c), out);
        break;
    case LIGHT_QUAD: {
        /* L·A·cosθ with A at size 1: power is independent of size. */
        vec3 n;
        glm_vec3_cross((float *)l->quad_u, (float *)l->quad_v, n);
        glm_vec3_scale((float *)l->color, glm_vec3_norm(n) * fmaxf(c, 0.f), out);
        break;
    }
    default:
        glm_vec3_zero(out);
    }
}

float light_width(const Light *l)
{
    if (l->type == LIGHT_QUAD)
        return 0.5f * (glm_vec3_norm((float *)l->quad_u) + glm_vec3_norm((float *)l->quad_v)) * l->size;
    return l->size;
}

/* Squared distance from p to triangle abc (Ericson, Real-Time Collision
 * Detection §5.1.5: the closest point by Voronoi region). */
static float dist2_point_triangle(const vec3 p, const float *a, const float *b, const float *c)
{
    vec3 ab, ac, ap, q;
    glm_vec3_sub((float *)b, (float *)a, ab);
    glm_vec3_sub((float *)c, (float *)a, ac);
    glm_vec3_sub((float *)p, (float *)a, ap);
    float d1 = glm_vec3_dot(ab, ap), d2 = glm_vec3_dot(ac, ap);
    if (d1 <= 0.f && d2 <= 0.f)
        return glm_vec3_norm2(ap);
    vec3 bp, cp;
    glm_vec3_sub((float *)p, (float *)b, bp);
    float d3 = glm_vec3_dot(ab, bp), d4 = glm_vec3_dot(ac, bp);
    if (d3 >= 0.f && d4 <= d3)
        return glm_vec3_norm2(bp);
    glm_vec3_sub((float *)p, (float *)c, cp);
    float d5 = glm_vec3_dot(ab, cp), d6 = glm_vec3_dot(ac, cp);
    if (d6 >= 0.f && d5 <= d6)
        return glm_vec3_norm2(cp);
    float vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
    if (vc <= 0.f && d1 >= 0.f && d3 <= 0.f) { /* edge ab */
        glm_vec3_scale(ab, d1 / (d1 - d3), q);
        return glm_vec3_distance2(ap, q);
    }
    if (vb <= 0.f && d2 >= 0.f && d6 <= 0.f) { /* edge ac */
        glm_vec3_scale(ac, d2 / (d2 - d6), q);
        return glm_vec3_distance2(ap, q);
    }
    if (va <= 0.f && d4 - d3 >= 0.f && d5 - d6 >= 0.f) { /* edge bc */
        vec3 bc;
        glm_vec3_sub((float *)c, (float *)b, bc);
        glm_vec3_scale(bc, (d4 - d3) / ((d4 - d3) + (d5 - d6)), q);
        return glm_vec3_distance2(bp, q);
    }
    float den = va + vb + vc;
    if (!(den > 0.f)) /* degenerate: the nearest vertex will do */
        return fminf(glm_vec3_norm2(ap), fminf(glm_vec3_norm2(bp), glm_vec3_norm2(cp)));
    glm_vec3_scale(ab, vb / den, q);
    glm_vec3_muladds(ac, vc / den, q);
    return glm_vec3_distance2(ap, q);
}

float scene_box_dist2(const vec3 p, const vec3 lo, const vec3 hi)
{
    float d2 = 0.f;
    for (int k = 0; k < 3; k++) {
        float d = fmaxf(fmaxf(lo[k] - p[k], p[k] - hi[k]), 0.f);
        d2 += d * d;
    }
    return d2;
}

/* The smallest quad light side, as a fraction of the scene's extent,
 * that both renderers draw and sample in float: the emitter's corners are
 * its centre ± half its sides (they collapse on the centre below about
 * 1e-7 of its distance from the origin, and the path tracer then sees no
 * emitter), and its radiance is its power over its area (it overflowed
 * below 1e-19). A light that small is a point light to every pixel: size 0. */
#define QUAD_SIDE_MIN 1e-5f

static bool check_quad_side(const Scene *s, int i, const char *after)
{
    const Light *l = &s->lights[i];
    vec3 ext;
    glm_vec3_sub((float *)s->bounds_max, (float *)s->bounds_min, ext);
    float side = l->size * fminf(glm_vec3_norm((float *)l->quad_u), glm_vec3_norm((float *)l->quad_v));
    float min_side = QUAD_SIDE_MIN * fmaxf(glm_vec3_norm(ext), 1e-3f);
    if (side >= min_side)
        return true;
    log_error("scene", "%s: lights[%d]: the quad light's shorter side is %.3g m (size %g%s), under %g of the "
              "scene's size: at least %.3g m, or size 0 for a point light",
              s->source, i, (double)side, (double)l->size, after ? after : "", (double)QUAD_SIDE_MIN,
              (double)min_side);
    return false;
}

bool scene_check_lights(const Scene *s, const char *after)
{
    for (int i = 0; i < s->light_count; i++) {
        const Light *l = &s->lights[i];
        if (l->type == LIGHT_QUAD && l->size > 0.f && !check_quad_side(s, i, after))
            return false;
        if (l->type != LIGHT_POINT || l->size <= 0.f)
            continue;
        float r = 0.5f * l->size;
        if (scene_box_dist2(l->position, s->bounds_min, s->bounds_max) >= r * r)
            continue;
        float best = INFINITY;
        for (int k = 0; k < s->submesh_count; k++) {
            const Submesh *sm = &s->submeshes[k];
            if (s->materials[sm->material].light_index >= 0)
                continue;
            for (uint32_t t = sm->first_index; t + 2 < sm->first_index + sm->index_count; t += 3)
                best = fminf(best, dist2_point_triangle(l->position, s->vertices[s->indices[t]].position,
                                                        s->vertices[s->indices[t + 1]].position,
                                                        s->vertices[s->indices[t + 2]].position));
        }
        if (best < r * r) {
            /* Both renderers take a sphere light for a light outside every
             * surface: inside it, the path tracer sees none of its light
             * and the rasterizer all of it. */
            log_error("scene", "%s: lights[%d]: the point light's sphere (diameter %g m%s) reaches into the "
                      "scene's surfaces, the nearest %.3g m from its centre: the diameter must be below %.3g m",
                      s->source, i, (double)l->size, after ? after : "", (double)sqrtf(best),
                      (double)(2.f * sqrtf(best)));
            return false;
        }
    }
    return true;
}

bool scene_check_view(const Scene *s)
{
    const Camera *cam = &s->camera;
    if (s->bounds_min[0] > s->bounds_max[0] || s->index_count == 0)
        return true;
    float near2 = scene_box_dist2(cam->position, s->bounds_min, s->bounds_max), far = 0.f, ahead = -INFINITY;
    for (int c = 0; c < 8; c++) {
        vec3 p = {(c & 1) ? s->bounds_max[0] : s->bounds_min[0], (c & 2) ? s->bounds_max[1] : s->bounds_min[1],
                  (c & 4) ? s->bounds_max[2] : s->bounds_min[2]}, d;
        glm_vec3_sub(p, (float *)cam->position, d);
        far = fmaxf(far, glm_vec3_norm(d));
        ahead = fmaxf(ahead, glm_vec3_dot(d, (float *)cam->forward));
    }
    if (near2 > cam->zfar * cam->zfar) {
        log_error("scene", "%s: camera.far %g ends before the scene, whose nearest point is %.3g m from the camera",
                  s->source, (double)cam->zfar, (double)sqrtf(near2));
        return false;
    }
    if (cam->znear >= far) {
        log_error("scene", "%s: camera.near %g starts past the scene, whose farthest point is %.3g m from the camera",
                  s->source, (double)cam->znear, (double)far);
        return false;
    }
    if (ahead <= cam->znear) {
        log_error("scene", "%s: the camera sees none of the scene: all of it lies behind the camera (check "
                  "camera.target or camera.forward)", s->source);
        return false;
    }
    return true;
}
