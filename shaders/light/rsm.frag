// light/rsm.frag — reflective shadow map (Dachsbacher & Stamminger 2005): per
// texel, in one RGBA32UI (common/rsm_texel.glsl), the world position, the
// normal facing the light, and the reflected flux Φ = ρ_d · (power through the texel): I(ω)·Ω_texel for spot, point and
// quad lights (Ω = a·cos³ of the angle to the face axis, a = texel area on
// the projection plane at distance 1), E·A_texel for directional lights.
#include "shared/gpu_types.h"
#include "common/lights.glsl"
#include "common/material.glsl"
#include "common/rsm_texel.glsl"

layout(location = LOC_RSM_FACE_AXIS) uniform vec3 u_face_axis; // unit axis of this face / spot
layout(location = LOC_RSM_TEXEL_AREA) uniform float u_texel_area; // a (perspective) or A (ortho)

#ifdef OPAQUE_DRAW
layout(early_fragment_tests) in;
#endif

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

layout(location = 0) out uvec4 o_texel; // position, normal, flux (common/rsm_texel.glsl)

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
        vec3 dir = normalize(v_world - u_light.position_type.xyz);
        to_light = -dir;
        float c = abs(dot(dir, u_face_axis));
        power = light_intensity(u_light, dir) * (u_texel_area * c * c * c);
    }
    if (dot(n, to_light) < 0.0)
        n = -n; // two-sided: the lit side reflects
    // The surface area the texel stands for is not stored: readers compute
    // it from the position, the normal and the light (rsm_texel_area).
    o_texel = rsm_texel_pack(rsm_texel_frame(), v_world, n, albedo * power);
}
