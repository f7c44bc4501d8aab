#include "gpu/shadow_frame.h"

#include <math.h>
#include <string.h>

/* An up vector not parallel to d. */
static void pick_up(const vec3 d, vec3 up)
{
    if (fabsf(d[1]) > 0.99f)
        glm_vec3_copy((vec3){0, 0, 1}, up);
    else
        glm_vec3_copy((vec3){0, 1, 0}, up);
}

/* Distance from p to the farthest corner of the bounds. */
static float farthest_corner(const vec3 p, const vec3 bmin, const vec3 bmax)
{
    float m = 0.f;
    for (int c = 0; c < 8; c++) {
        vec3 q = {(c & 1) ? bmax[0] : bmin[0], (c & 2) ? bmax[1] : bmin[1], (c & 4) ? bmax[2] : bmin[2]};
        m = fmaxf(m, glm_vec3_distance((float *)p, q));
    }
    return m;
}

/* The bounds' bounding sphere: its centre in c, its radius returned. */
static float bounding_sphere(const vec3 bmin, const vec3 bmax, vec3 c)
{
    glm_vec3_center((float *)bmin, (float *)bmax, c);
    return 0.5f * glm_vec3_distance((float *)bmin, (float *)bmax);
}

bool shadow_frame_point_fitted(const Light *l, const vec3 bmin, const vec3 bmax)
{
    if (l->type != LIGHT_POINT)
        return false;
    vec3 c;
    float r = bounding_sphere(bmin, bmax, c);
    return r > 0.f && glm_vec3_distance((float *)l->position, c) >= 2.f * r;
}

bool shadow_frame_is_cube(const Light *l, const vec3 bmin, const vec3 bmax)
{
    return l->type == LIGHT_QUAD || (l->type == LIGHT_POINT && !shadow_frame_point_fitted(l, bmin, bmax));
}

/* A point light's one perspective map around the scene's bounding sphere
 * (centre c, radius r, at distance d ≥ 2r from the light): the sphere's
 * half-angle plus 5%, and at least margin_texels texels inside the map. */
static void fitted_point_frame(const Light *l, const vec3 bmin, const vec3 bmax, int res, int margin_texels,
                               ShadowFrame *f)
{
    vec3 c, axis, up, target;
    float r = bounding_sphere(bmin, bmax, c);
    glm_vec3_sub(c, (float *)l->position, axis);
    float d = glm_vec3_norm(axis);
    glm_vec3_scale(axis, 1.f / d, axis);
    float half = asinf(fminf(r / d, 1.f));
    float keep = 1.f - 2.f * (float)margin_texels / (float)res;
    float t = fmaxf(tanf(1.05f * half), keep > 0.f ? tanf(half) / keep : 0.f);
    glm_vec3_copy((float *)l->position, f->origin);
    f->far = farthest_corner(l->position, bmin, bmax) * 1.01f + 1e-3f;
    glm_vec3_add(f->origin, axis, target);
    pick_up(axis, up);
    glm_lookat(f->origin, target, up, f->view[0]);
    glm_perspective(2.f * atanf(t), 1.f, fmaxf(0.99f * (d - r), f->far * 1e-4f), f->far, f->proj[0]);
    f->texel_k = 2.f * t / (float)res;
    f->face_count = 1;
}

void shadow_frame_compute(const Light *l, const vec3 bmin, const vec3 bmax, int res, int margin_texels,
                          ShadowFrame *f)
{
    memset(f, 0, sizeof *f);
    vec3 up, target;
    if (l->type == LIGHT_DIRECTIONAL) {
        /* The scene's bounding sphere, 1% and at least margin_texels texels
         * (t = 2r/res each: r − r0 ≥ m·t) inside the map. */
        vec3 c;
        float r0 = bounding_sphere(bmin, bmax, c);
        float keep = 1.f - 2.f * (float)margin_texels / (float)res;
        float r = (keep > 0.f ? fmaxf(r0 * 1.01f, r0 / keep) : r0 * 1.01f) + 1e-3f;
        glm_vec3_copy(c, f->origin);
        glm_vec3_muladds((float *)l->direction, -r, f->origin);
        glm_vec3_add(f->origin, (float *)l->direction, target);
        pick_up(l->direction, up);
        glm_lookat(f->origin, target, up, f->view[0]);
        glm_ortho(-r, r, -r, r, 0.f, 2.f * r, f->proj[0]);
        f->far = 2.f * r;
        f->texel_k = 2.f * r / (float)res;
        f->ortho = true;
        f->face_count = 1;
    } else if (l->type == LIGHT_SPOT) {
        glm_vec3_copy((float *)l->position, f->origin);
        f->far = farthest_corner(l->position, bmin, bmax) * 1.01f + 1e-3f;
        float fov = fminf(2.f * l->spot_outer * 1.05f, glm_rad(170.f));
        glm_vec3_add(f->origin, (float *)l->direction, target);
        pick_up(l->direction, up);
        glm_lookat(f->origin, target, up, f->view[0]);
        glm_perspective(fov, 1.f, f->far * 1e-4f, f->far, f->proj[0]);
        f->texel_k = 2.f * tanf(0.5f * fov) / (float)res;
        f->face_count = 1;
    } else if (shadow_frame_point_fitted(l, bmin, bmax)) {
        fitted_point_frame(l, bmin, bmax, res, margin_texels, f);
    } else {
        /* Cube faces in GL's cube-map orientation (+X, −X, +Y, −Y, +Z, −Z). */
        static const float dirs[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        static const float ups[6][3] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
        glm_vec3_copy((float *)l->position, f->origin);
        f->far = farthest_corner(l->position, bmin, bmax) * 1.01f + 1e-3f;
        for (int i = 0; i < 6; i++) {
            glm_vec3_add(f->origin, (float *)dirs[i], target);
            glm_lookat(f->origin, target, (float *)ups[i], f->view[i]);
            glm_perspective(glm_rad(90.f), 1.f, f->far * 1e-4f, f->far, f->proj[i]);
        }
        f->texel_k = 2.f / (float)res;
        f->cube = true;
        f->face_count = 6;
    }
    for (int i = 0; i < f->face_count; i++)
        glm_mat4_mul(f->proj[i], f->view[i], f->view_proj[i]);
}

void shadow_frame_axis(const ShadowFrame *f, int face, vec3 axis)
{
    const float *v = (const float *)f->view[face];
    axis[0] = -v[2];
    axis[1] = -v[6];
    axis[2] = -v[10];
}

void shadow_frame_project(const ShadowFrame *f, const Light *l, const vec3 world, vec3 out)
{
    vec4 p = {world[0], world[1], world[2], 1.f};
    glm_mat4_mulv((vec4 *)f->view_proj[0], p, p);
    out[0] = 0.5f * p[0] / p[3] + 0.5f;
    out[1] = 0.5f * p[1] / p[3] + 0.5f;
    vec3 v;
    glm_vec3_sub((float *)world, (float *)f->origin, v);
    float d = f->ortho ? glm_vec3_dot(v, (float *)l->direction) : glm_vec3_norm(v);
    out[2] = d / f->far;
}

void shadow_frame_to_gpu(const Light *l, const ShadowFrame *f, int res, GpuLight *g)
{
    memset(g, 0, sizeof *g);
    memcpy(g->position_type, l->position, sizeof(vec3));
    g->position_type[3] = (float)l->type;
    memcpy(g->direction_width, l->direction, sizeof(vec3));
    if (l->type == LIGHT_POINT && !f->cube) /* fitted: the map's axis */
        shadow_frame_axis(f, 0, g->direction_width);
    g->direction_width[3] = l->type == LIGHT_DIRECTIONAL ? tanf(l->size) : light_width(l);
    if (l->type == LIGHT_QUAD) {
        vec3 n;
        glm_vec3_cross((float *)l->quad_u, (float *)l->quad_v, n);
        glm_vec3_scale((float *)l->color, glm_vec3_norm(n), g->color); /* L·A */
        /* The emitter polygon at the light's size (its radiance is then
         * L·A / A_size); size 0 leaves A_size 0: a point. */
        glm_vec3_scale((float *)l->quad_u, l->size, g->quad_u);
        glm_vec3_scale((float *)l->quad_v, l->size, g->quad_v);
        g->quad_v[3] = light_quad_area(l);
    } else {
        memcpy(g->color, l->color, sizeof(vec3));
    }
    g->spot[0] = cosf(l->spot_outer);
    g->spot[1] = cosf(l->spot_inner);
    memcpy(g->shadow_view_proj, f->view_proj[0], sizeof(mat4));
    memcpy(g->shadow_origin, f->origin, sizeof(vec3));
    g->shadow_info[0] = f->far;
    g->shadow_info[1] = f->texel_k;
    g->shadow_info[2] = (float)res;
    g->shadow_info[3] = f->cube ? 1.f : 0.f;
}
