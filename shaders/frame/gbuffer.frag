// frame/gbuffer.frag — G-buffer pass: the surface (world position and the
// shading normal turned toward the camera: two-sided) and the material
// (base colour, metallic, roughness, specular weight, emitted radiance
// toward the front), packed as common/gbuffer.glsl describes.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/material.glsl"
#define GBUFFER_WRITER
#include "common/gbuffer.glsl"

layout(location = LOC_EYE) uniform vec3 u_eye;

#ifdef OPAQUE_DRAW
layout(early_fragment_tests) in;
#endif

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

layout(location = 0) out uvec4 o_surface;
layout(location = 1) out uvec4 o_material;

void main()
{
    vec3 base = material_albedo(v_uv);
    vec2 mr = material_metal_rough(v_uv);
    vec3 n = normalize(v_normal);
    bool front = dot(n, u_eye - v_world) >= 0.0;
    o_surface = surfel_pack(v_world, front ? n : -n);
    o_material = gb_material_pack(base, mr.x, mr.y, u_pbr.z, front ? u_emission : vec3(0.0));
}
