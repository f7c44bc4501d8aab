// light/rsm.frag — reflective shadow map (Dachsbacher & Stamminger 2005): per
// texel the world position, the normal facing the light, and the reflected
// flux Φ = ρ_d · (power through the texel): I(ω)·Ω_texel for spot, point and
// quad lights (Ω = a·cos³ of the angle to the face axis, a = texel area on
// the projection plane at distance 1), E·A_texel for directional lights.
#include "shared/gpu_types.h"
#include "common/lights.glsl"
#include "common/material.glsl"
#include "common/surfel.glsl"

layout(location = LOC_RSM_FACE_AXIS) uniform vec3 u_face_axis; // unit axis of this face / spot
layout(location = LOC_RSM_TEXEL_AREA) uniform float u_texel_area; // a (perspective) or A (ortho)

#ifdef OPAQUE_DRAW
layout(early_fragment_tests) in;
#endif

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

layout(location = 0) out uvec4 o_surfel; // position, normal (common/surfel.glsl)
layout(location = 1) out vec4 o_flux;

void main()
{
    vec3 albedo = material_diffuse(v_uv); // VPLs reflect diffusely (SPEC §1b)
    vec3 n = normalize(v_normal);
    vec3 power;
    vec3 to_light;
    if (int(u_light.position_type.w) == LIGHT_DIRECTIONAL) {
        to_light = -u_light.direction_width.xyz;
        power = u_light.color.rgb * u_texel_area;
    } else {
        vec3 d = v_world - u_light.position_type.xyz;
        vec3 dir = normalize(d);
        to_light = -dir;
        float c = abs(dot(dir, u_face_axis));
        power = light_intensity(u_light, dir) * (u_texel_area * c * c * c);
    }
    if (dot(n, to_light) < 0.0)
        n = -n; // two-sided: the lit side reflects
    // The surface area the texel stands for: its footprint across the ray
    // (A, or Ω·d²) over the cosine to the surface (floored at grazing).
    float cos_s = max(dot(n, to_light), 0.05);
    float area;
    if (int(u_light.position_type.w) == LIGHT_DIRECTIONAL) {
        area = u_texel_area / cos_s;
    } else {
        vec3 d = v_world - u_light.position_type.xyz;
        float c = abs(dot(normalize(d), u_face_axis));
        area = u_texel_area * c * c * c * dot(d, d) / cos_s;
    }
    o_surfel = surfel_pack(v_world, n);
    o_flux = vec4(albedo * power, area);
}
