// frame/scene.vert — transforms the scene's vertices; world-space outputs.
#include "shared/gpu_types.h"

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;

layout(location = LOC_VIEW_PROJ) uniform mat4 u_view_proj;

invariant gl_Position; // the same depth in every program that draws the scene (GL_EQUAL tests)

out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
#ifdef FLAT_LIGHT
flat out GpuLight v_light; // common/lights.glsl
#endif

void main()
{
    v_world = a_position;
    v_normal = a_normal;
    v_uv = a_uv;
#ifdef FLAT_LIGHT
    v_light = u_light;
#endif
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
