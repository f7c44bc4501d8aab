// light/shadow_depth.frag — shadow-map pass: stores the receiver-comparable
// distance to the light / far (see common/shadow.glsl). Variants:
//   DEPTH_FROM_RASTER  directional lights: the orthographic projection
//                      (near 0, far = far) already rasterizes d / far as
//                      depth, so nothing is written and early depth works
//                      (without it: the distance through gl_FragDepth)
//   ALPHA_MASK         alpha-masked materials fetch their texture and
//                      discard holes; opaque ones fetch nothing
#include "shared/gpu_types.h"
#include "common/material.glsl"

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

#if defined(DEPTH_FROM_RASTER) && !defined(ALPHA_MASK)
layout(early_fragment_tests) in;
#endif

void main()
{
#ifdef ALPHA_MASK
    material_albedo(v_uv); // discards holes
#endif
#ifndef DEPTH_FROM_RASTER
    float d = length(v_world - u_light.position_type.xyz);
    gl_FragDepth = clamp(d / u_light.shadow_info.x, 0.0, 1.0);
#endif
}
