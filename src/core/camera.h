/* camera.h — pinhole camera matrices and projection of world points. */
#ifndef RTGI_CAMERA_H
#define RTGI_CAMERA_H

#include <stdbool.h>

#include "core/scene.h"

void camera_view_proj(const Camera *c, float aspect, mat4 out);
/* Pixel (x right, y down, top-left origin) of a world point in a w×h image;
 * false if behind the camera. */
bool camera_project(const Camera *c, int w, int h, const vec3 world, float *px, float *py);
/* Unit ray direction through pixel position (px, py) (same convention). */
void camera_ray(const Camera *c, int w, int h, float px, float py, vec3 dir);
/* camera_ray in two steps for many rays of one image: what depends on the
 * camera and size only, once (a tangent and a cross product), then each
 * direction, the same bits as camera_ray's. */
typedef struct CameraRayBasis {
    vec3 forward, up, right; /* unit */
    float tan_half;          /* tan(fov_y / 2) */
    float width, height;     /* the image's size in pixels */
} CameraRayBasis;
void camera_ray_basis(const Camera *c, int w, int h, CameraRayBasis *b);
void camera_ray_dir(const CameraRayBasis *b, float px, float py, vec3 dir);

#endif
