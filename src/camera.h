/* camera.h — pinhole camera matrices and projection of world points. */
#ifndef RTGI_CAMERA_H
#define RTGI_CAMERA_H

#include <stdbool.h>

#include "scene.h"

void camera_view_proj(const Camera *c, float aspect, mat4 out);
/* Pixel (x right, y down, top-left origin) of a world point in a w×h image;
 * false if behind the camera. */
bool camera_project(const Camera *c, int w, int h, const vec3 world, float *px, float *py);
/* Unit ray direction through pixel position (px, py) (same convention). */
void camera_ray(const Camera *c, int w, int h, float px, float py, vec3 dir);

#endif
