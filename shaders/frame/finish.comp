// frame/finish.comp — the frame's last steps on radiance (pass_finish.h):
// the supersampling resolve, the box-filtered mean of each pixel's N×N
// block (written to the output-size radiance image when asked), and the
// display transform (common/tonemap.glsl; sRGB-encoded bytes, alpha 0
// where the radiance is NaN or infinite). N = 1: tone mapping alone, after
// a forward frame or a deferred one whose last shading dispatch could not
// tone-map (supersampling).
// Inputs: radiance (TEX_HDR: the supersampled image, or the output one).
// Outputs: resolved radiance (IMG_HDR), display colour (IMG_LDR).
#include "shared/gpu_types.h"
#include "common/tonemap.glsl"

layout(local_size_x = SHADE_GROUP, local_size_y = SHADE_GROUP) in;
layout(binding = TEX_HDR) uniform sampler2D u_radiance;
layout(binding = IMG_HDR, rgba32f) uniform writeonly image2D u_hdr;
layout(binding = IMG_LDR, rgba8) uniform writeonly image2D u_ldr;
layout(location = LOC_FINISH_FACTOR) uniform int u_factor;
layout(location = LOC_FINISH_RADIANCE) uniform int u_write_radiance;

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, imageSize(u_ldr))))
        return;
    vec3 radiance = vec3(0.0);
    ivec2 base = px * u_factor;
    for (int y = 0; y < u_factor; y++)
        for (int x = 0; x < u_factor; x++)
            radiance += texelFetch(u_radiance, base + ivec2(x, y), 0).rgb;
    radiance /= float(u_factor * u_factor);
    if (u_write_radiance != 0)
        imageStore(u_hdr, px, vec4(radiance, 1.0));
    imageStore(u_ldr, px, vec4(srgb_encode(tonemap(radiance, u_frame.exposure).rgb),
                               any(isnan(radiance)) || any(isinf(radiance)) ? 0.0 : 1.0));
}
