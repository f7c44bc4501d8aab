// frame/shade.comp — deferred shading as a compute pass (pass_shade.h):
// one light's direct radiance from the G-buffer (common/direct_light.glsl),
// added to what the frame's earlier lights left in the radiance image or,
// for the first light, with the surfaces' emitted radiance; the last
// dispatch of a frame also adds the GI technique's indirect light
// (common/composite.glsl) and writes the display image (common/tonemap.glsl,
// the bytes sRGB-encoded here: image stores take no sRGB format). A frame
// of one light and no supersampling is one dispatch: no raster pass, no
// blending, and the radiance is read by nobody but the read-back. What a
// dispatch does is LOC_SHADE_STEPS (SHADE_* bits); the light's type and the
// shadow filter are fixed at compile time (pass_direct.c's variants), so
// that llvmpipe does not pay for the other types' code.
// Inputs: G-buffer, the light block and its shadow map, the GI images.
// Outputs: radiance (IMG_HDR), display colour (IMG_LDR, alpha 0 where the
// radiance is NaN or infinite, as the forward draw marks it).
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/brdf.glsl"
#include "common/lights.glsl"
#include "common/shadow.glsl"
#include "common/direct_light.glsl"
#define GBUFFER_MATERIAL
#include "common/gbuffer.glsl"
#include "common/composite.glsl"
#include "common/tonemap.glsl"

layout(local_size_x = SHADE_GROUP, local_size_y = SHADE_GROUP) in;
layout(binding = IMG_HDR, rgba32f) uniform image2D u_hdr;
layout(binding = IMG_LDR, rgba8) uniform writeonly image2D u_ldr;
layout(location = LOC_SHADE_STEPS) uniform int u_steps;

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, imageSize(u_hdr))))
        return;
    vec3 radiance = (u_steps & SHADE_ACCUMULATE) != 0 ? imageLoad(u_hdr, px).rgb : vec3(0.0);
    vec3 x, n;
    bool surface = gb_surface(px, x, n);
    if (surface && (u_steps & (SHADE_LIGHT | SHADE_EMISSION)) != 0) {
        GbMaterial mat = gb_material(px);
        if ((u_steps & SHADE_LIGHT) != 0)
            radiance += direct_light(x, n, normalize(u_frame.camera.xyz - x), mat.diffuse, mat.f0, mat.roughness,
                                     vec2(px) + 0.5);
        if ((u_steps & SHADE_EMISSION) != 0)
            radiance += mat.emission;
    }
    if ((u_steps & SHADE_COMPOSITE) != 0)
        radiance += composite_indirect(px, gb_material(px), surface, x, n);
    imageStore(u_hdr, px, vec4(radiance, 1.0));
    if ((u_steps & SHADE_TONEMAP) != 0)
        imageStore(u_ldr, px, vec4(srgb_encode(tonemap(radiance, u_frame.exposure).rgb),
                                   any(isnan(radiance)) || any(isinf(radiance)) ? 0.0 : 1.0));
}
