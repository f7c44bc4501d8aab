// frame/forward.frag — forward direct shading of one light
// (common/direct_light.glsl) while drawing the scene: what frame/gbuffer.frag
// would pack and frame/direct.frag unpack, evaluated in place, for frames
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

layout(location = LOC_EYE) uniform vec3 u_eye;
layout(location = LOC_DIRECT_EMISSION) uniform int u_add_emission;
#ifdef FLAT_UNIFORMS
// The same as flat inputs from frame/scene.vert (common/lights.glsl).
flat in vec4 v_eye_emission; // u_eye, u_add_emission
flat in float v_exposure;    // u_frame.exposure
#define u_eye v_eye_emission.xyz
#define u_add_emission int(v_eye_emission.w)
#define EXPOSURE v_exposure
#else
#define EXPOSURE u_frame.exposure
#endif

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
    vec3 to_eye = u_eye - v_world;
    bool front = dot(n, to_eye) >= 0.0;
    vec3 v = normalize(to_eye);
    n = front ? n : -n;
    vec3 albedo, f0;
    brdf_surface(base, mr.x, u_pbr.z, albedo, f0);
    vec3 radiance = direct_light(v_world, n, v, albedo, f0, mr.y, gl_FragCoord.xy);
    if (u_add_emission != 0 && front)
        radiance += u_emission;
    o_radiance = vec4(radiance, 1.0);
    o_display = vec4(srgb_encode(tonemap(radiance, EXPOSURE).rgb),
                     any(isnan(radiance)) || any(isinf(radiance)) ? 0.0 : 1.0);
}
