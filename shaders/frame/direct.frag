// frame/direct.frag — deferred direct shading of one light
// (common/direct_light.glsl) from the G-buffer; plus emitted radiance when
// u_add_emission is set (the first light of a frame, drawn without
// blending; later lights blend additively).
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/brdf.glsl"
#include "common/lights.glsl"
#include "common/shadow.glsl"
#include "common/direct_light.glsl"
#define GBUFFER_MATERIAL
#include "common/gbuffer.glsl"

layout(location = LOC_DIRECT_EMISSION) uniform int u_add_emission;

out vec4 o_radiance;

void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 x, n;
    if (!gb_surface(px, x, n)) {
        // Background: no surface. The first light's draw is not blended and
        // leaves the target's only value here (see pass_direct.c).
        if (u_add_emission == 0)
            discard;
        o_radiance = vec4(0.0);
        return;
    }
    GbMaterial mat = gb_material(px);
    vec3 v = normalize(u_frame.camera.xyz - x);
    vec3 radiance = direct_light(x, n, v, mat.diffuse, mat.f0, mat.roughness, gl_FragCoord.xy);
    if (u_add_emission != 0)
        radiance += mat.emission;
    o_radiance = vec4(radiance, 1.0);
}
