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
#ifdef FLAT_UNIFORMS
// The forward draw's constants, copied for the fragment shader
// (common/lights.glsl, common/material.glsl, frame/forward.frag).
layout(location = LOC_MATERIAL_ALBEDO) uniform vec3 u_albedo;
layout(location = LOC_MATERIAL_EMISSION) uniform vec3 u_emission;
layout(location = LOC_MATERIAL_PBR) uniform vec4 u_pbr;
layout(location = LOC_EYE) uniform vec3 u_eye;
layout(location = LOC_DIRECT_EMISSION) uniform int u_add_emission;
flat out GpuLight v_light;
flat out vec3 v_albedo;
flat out vec3 v_emission;
flat out vec4 v_pbr;
flat out vec4 v_eye_emission;
flat out float v_exposure;
#endif

void main()
{
    v_world = a_position;
    v_normal = a_normal;
    v_uv = a_uv;
#ifdef FLAT_UNIFORMS
    v_light = u_light;
    v_albedo = u_albedo;
    v_emission = u_emission;
    v_pbr = u_pbr;
    v_eye_emission = vec4(u_eye, float(u_add_emission));
    v_exposure = u_frame.exposure;
#endif
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
