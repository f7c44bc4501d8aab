// frame/forward.frag — forward direct shading of one light
// (common/direct_light.glsl) while drawing the scene: what frame/gbuffer.frag
// would pack and frame/shade.comp unpack, evaluated in place, for frames
// that need no G-buffer (no GI technique; pass_direct_forward). Built with
// OPAQUE_DRAW for every material: alpha-masked ones too, whose holes the
// depth pre-pass discarded (pass_direct.c). The surface as
// the G-buffer's: the shading normal turned toward the camera (two-sided),
// emission toward the front only, added when u_add_emission is set (the
// first light; later lights blend additively at equal depth).
// o_display is the tone-mapped, sRGB-encoded colour (common/tonemap.glsl):
// a frame of one light with nothing after the shading
// (pass_direct_forward's `display`) binds the final image there and skips
// the tone-mapping pass; other frames bind nothing, and it is dropped.
// A display-only frame (RenderSettings.display_only) binds nothing at
// location 0 either, so no radiance is kept to check for NaN and infinity:
// the final image's alpha is 0 where the radiance is not finite instead
// (renderer_count_nonfinite; everything else writes alpha 1).
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/brdf.glsl"
#include "common/material.glsl"
#include "common/lights.glsl"
#include "common/shadow.glsl"
#include "common/direct_light.glsl"
#include "common/tonemap.glsl"

// Every forward program is built with FLAT_UNIFORMS (pass_direct.c): the
// eye, u_add_emission and the exposure come from frame/scene.vert's flat
// outputs (common/lights.glsl says why).
#ifndef FLAT_UNIFORMS
#error frame/forward.frag reads its constants from frame/scene.vert's flat outputs (FLAT_UNIFORMS)
#endif
flat in vec4 v_eye_emission; // u_eye, u_add_emission
flat in float v_exposure;    // u_frame.exposure

#ifdef OPAQUE_DRAW
layout(early_fragment_tests) in;
#endif

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

layout(location = 0) out vec4 o_radiance;
layout(location = 1) out vec4 o_display;

void main()
{
    vec3 base = material_albedo(v_uv);
    vec2 mr = material_metal_rough(v_uv);
    vec3 n = normalize(v_normal);
    // The side from the unnormalised view vector: the programs of diffuse
    // scenes use v for nothing else, and drop its normalisation.
    vec3 to_eye = v_eye_emission.xyz - v_world;
    bool front = dot(n, to_eye) >= 0.0;
    vec3 v = normalize(to_eye);
    n = front ? n : -n;
    vec3 albedo, f0;
    brdf_surface(base, mr.x, u_pbr.z, albedo, f0);
    vec3 radiance = direct_light(v_world, n, v, albedo, f0, mr.y, gl_FragCoord.xy);
    if (v_eye_emission.w != 0.0 && front)
        radiance += u_emission;
    o_radiance = vec4(radiance, 1.0);
    o_display = vec4(srgb_encode(tonemap(radiance, v_exposure).rgb),
                     any(isnan(radiance)) || any(isinf(radiance)) ? 0.0 : 1.0);
}
