// frame/gbuffer.frag — G-buffer pass: world position, shading normal facing the
// camera (two-sided diffuse), linear albedo, emitted radiance.
#include "shared/gpu_types.h"
#include "common/material.glsl"

layout(location = LOC_EYE) uniform vec3 u_eye;

#ifdef OPAQUE_DRAW
layout(early_fragment_tests) in;
#endif

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

layout(location = 0) out vec4 o_position; // xyz world, w = 1 where geometry
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_albedo;
layout(location = 3) out vec4 o_emission;

void main()
{
    vec3 albedo = material_albedo(v_uv);
    vec3 n = normalize(v_normal);
    vec3 v = u_eye - v_world;
    bool front = dot(n, v) >= 0.0;
    o_position = vec4(v_world, 1.0);
    o_normal = vec4(front ? n : -n, 0.0);
    o_albedo = vec4(albedo, 1.0);
    o_emission = vec4(front ? u_emission : vec3(0.0), 1.0);
}
