// frame/vbuffer_classify.comp — the visibility buffer's per-pixel passes
// (pass_vbuffer.c), over the whole image:
//   default: pixels of no surface get the G-buffer's clear value, those of
//     materials without textures are resolved here (their constants are
//     the table's), the others counted in their material's bin;
//   SCATTER: after frame/vbuffer_bins.comp, each counted pixel appends
//     itself to its material's list (SSBO_VBUFFER_PIXELS).
// Material classification: a compute pass binds no textures per pixel, so
// each textured material's pixels are resolved by one indirect dispatch
// with its textures bound (frame/vbuffer_resolve.comp).
#include "shared/gpu_types.h"
#define MATERIAL_ROW
#define MATERIAL_GRADIENTS
#define UNTEXTURED
#include "frame/vbuffer.glsl"

layout(local_size_x = SHADE_GROUP, local_size_y = SHADE_GROUP) in;

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy), size = imageSize(u_id);
    if (any(greaterThanEqual(px, size)))
        return;
    uint id = imageLoad(u_id, px).x;
#ifdef SCATTER
    if (id == 0u)
        return;
    uint m = vbuffer_material(id);
    if (!material_plain(m))
        pixels[atomicAdd(bins[bin_cursor(m)], 1u)] = uint(px.x) | uint(px.y) << 16;
#else
    if (id == 0u) {
        imageStore(u_surface, px, uvec4(0u)); // no surface, no material
        imageStore(u_material, px, uvec4(0u));
        return;
    }
    uint m = vbuffer_material(id);
    if (material_plain(m))
        vbuffer_resolve(px, id, m, size);
    else
        atomicAdd(bins[bin_count(m)], 1u);
#endif
}
