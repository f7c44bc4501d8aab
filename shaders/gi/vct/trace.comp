// gi/vct/trace.comp — the cones of every u_scale-th pixel per axis (the
// centre pixel of each u_scale × u_scale block; u_scale 1: every pixel),
// written at the block's place in the (low-resolution) images; with
// u_scale > 1, upsample.comp fills in the full-resolution images. The
// shading itself: gi/vct/shade.glsl.
#include "gi/vct/shade.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = IMG_OUT, rgba32f) writeonly uniform image2D u_out;
layout(binding = IMG_OUT2, rgba32f) writeonly uniform image2D u_out_specular;
layout(location = LOC_VCT_SCALE) uniform int u_scale;

void main()
{
    ivec2 lo = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(u_frame.width, u_frame.height);
    if (any(greaterThanEqual(lo, (size + u_scale - 1) / u_scale)))
        return;
    ivec2 px = min(lo * u_scale + u_scale / 2, size - 1);
    vec4 e, spec;
    vct_shade(px, e, spec);
    imageStore(u_out, lo, e);
    imageStore(u_out_specular, lo, spec);
}
