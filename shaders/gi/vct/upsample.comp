// gi/vct/upsample.comp — the full-resolution images from the cones traced
// at every u_scale-th pixel (trace.comp): each pixel takes the bilinear
// mean of its four surrounding traced pixels, keeping only those on its
// surface (normals within ~45°, the traced point within one voxel of the
// pixel's tangent plane), like rsm-interp's screen-space interpolation
// (Dachsbacher & Stamminger 2005, §4) with a geometry test sized to the
// voxels. A pixel with none on its surface (silhouettes, thin objects)
// traces its own cones. Both images: irradiance (alpha: ambient
// visibility) and specular radiance.
#include "gi/vct/shade.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = TEX_INPUT) uniform sampler2D u_low_irradiance;
layout(binding = TEX_SPECULAR) uniform sampler2D u_low_specular;
layout(binding = IMG_OUT, rgba32f) writeonly uniform image2D u_out;
layout(binding = IMG_OUT2, rgba32f) writeonly uniform image2D u_out_specular;
layout(location = LOC_VCT_SCALE) uniform int u_scale;

// Sponza 640×360 against one-bounce (16 spp): relMSE / FLIP every pixel
// traced 0.00557 / 0.0503; scale 2 with 0.9 or 0.7 the same to 3 digits,
// and 0.7 halves the pixels that trace their own cones (normal maps):
// upsample 66 ms against 112–143 at 320×180.
const float MIN_COS = 0.7;

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(u_frame.width, u_frame.height);
    if (any(greaterThanEqual(px, size)))
        return;
    vec3 x, n;
    if (!gb_surface(px, x, n)) {
        imageStore(u_out, px, vec4(0.0, 0.0, 0.0, 1.0));
        imageStore(u_out_specular, px, vec4(0.0));
        return;
    }
    float voxel = vct_voxel_at(x);
    ivec2 low = (size + u_scale - 1) / u_scale;
    vec2 u = vec2(px - u_scale / 2) / float(u_scale); // traced pixel s sits at full-resolution pixel s·scale + scale/2
    ivec2 i0 = ivec2(floor(u));
    vec2 f = u - vec2(i0);
    vec4 e = vec4(0.0), spec = vec4(0.0);
    float wsum = 0.0;
    for (int j = 0; j < 4; j++) {
        ivec2 o = ivec2(j & 1, j >> 1);
        ivec2 s = clamp(i0 + o, ivec2(0), low - 1);
        ivec2 sp = min(s * u_scale + u_scale / 2, size - 1);
        vec3 q, qn;
        bool same = gb_surface(sp, q, qn) && dot(n, qn) >= MIN_COS && abs(dot(n, q - x)) <= voxel;
        float w = same ? (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y) + 1e-3 : 0.0;
        e += w * texelFetch(u_low_irradiance, s, 0);
        spec += w * texelFetch(u_low_specular, s, 0);
        wsum += w;
    }
    if (wsum > 0.0) {
        e /= wsum;
        spec /= wsum;
    } else {
        vct_shade(px, e, spec);
    }
    imageStore(u_out, px, e);
    imageStore(u_out_specular, px, spec);
}
