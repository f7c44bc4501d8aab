// frame/gbuffer.frag — G-buffer pass: world position, shading normal facing the
// camera (two-sided), diffuse albedo ρ_d = (1 − metallic)·base, emitted
// radiance, and the specular parameters (F0, perceptual roughness).
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/brdf.glsl"
#include "common/material.glsl"

layout(location = LOC_EYE) uniform vec3 u_eye;

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

layout(location = 0) out vec4 o_position; // xyz world, w = 1 where geometry
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_albedo;
layout(location = 3) out vec4 o_emission;
layout(location = 4) out vec4 o_specular; // rgb F0, a perceptual roughness

void main()
{
    vec3 base = material_albedo(v_uv);
    vec2 mr = material_metal_rough(v_uv);
    vec3 diffuse, f0;
    brdf_surface(base, mr.x, u_pbr.z, diffuse, f0);
    vec3 n = normalize(v_normal);
    vec3 v = u_eye - v_world;
    bool front = dot(n, v) >= 0.0;
    o_position = vec4(v_world, 1.0);
    o_normal = vec4(front ? n : -n, 0.0);
    o_albedo = vec4(diffuse, 1.0);
    o_specular = vec4(f0, mr.y);
    o_emission = vec4(front ? u_emission : vec3(0.0), 1.0);
}
