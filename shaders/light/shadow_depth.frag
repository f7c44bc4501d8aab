// light/shadow_depth.frag — shadow-map pass: stores the receiver-comparable
// distance to the light / far (see common/shadow.glsl).
#include "shared/gpu_types.h"
#include "common/material.glsl"

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

void main()
{
    material_albedo(v_uv); // alpha mask
    float d;
    if (int(u_light.position_type.w) == LIGHT_DIRECTIONAL)
        d = dot(v_world - u_light.shadow_origin.xyz, u_light.direction_width.xyz);
    else
        d = length(v_world - u_light.position_type.xyz);
    gl_FragDepth = clamp(d / u_light.shadow_info.x, 0.0, 1.0);
}
