#include "core/camera.h"

#include <math.h>

void camera_view_proj(const Camera *c, float aspect, mat4 out)
{
    mat4 view, proj;
    vec3 target;
    glm_vec3_add((float *)c->position, (float *)c->forward, target);
    glm_lookat((float *)c->position, target, (float *)c->up, view);
    glm_perspective(c->fov_y, aspect, c->znear, c->zfar, proj);
    glm_mat4_mul(proj, view, out);
}

bool camera_project(const Camera *c, int w, int h, const vec3 world, float *px, float *py)
{
    mat4 vp;
    camera_view_proj(c, (float)w / (float)h, vp);
    vec4 p = {world[0], world[1], world[2], 1.f};
    glm_mat4_mulv(vp, p, p);
    if (p[3] <= 0.f)
        return false;
    *px = (0.5f * p[0] / p[3] + 0.5f) * (float)w;
    *py = (0.5f - 0.5f * p[1] / p[3]) * (float)h;
    return true;
}

void camera_ray_basis(const Camera *c, int w, int h, CameraRayBasis *b)
{
    b->tan_half = tanf(0.5f * c->fov_y);
    b->width = (float)w;
    b->height = (float)h;
    glm_vec3_copy((float *)c->forward, b->forward);
    glm_vec3_copy((float *)c->up, b->up);
    glm_vec3_cross((float *)c->forward, (float *)c->up, b->right);
    glm_vec3_normalize(b->right);
}

void camera_ray_dir(const CameraRayBasis *b, float px, float py, vec3 dir)
{
    float t = b->tan_half;
    float sx = (2.f * px / b->width - 1.f) * t * b->width / b->height;
    float sy = (1.f - 2.f * py / b->height) * t;
    for (int i = 0; i < 3; i++)
        dir[i] = b->forward[i] + sx * b->right[i] + sy * b->up[i];
    glm_vec3_normalize(dir);
}

void camera_ray(const Camera *c, int w, int h, float px, float py, vec3 dir)
{
    CameraRayBasis b;
    camera_ray_basis(c, w, h, &b);
    camera_ray_dir(&b, px, py, dir);
}
