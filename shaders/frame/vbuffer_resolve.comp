// frame/vbuffer_resolve.comp — the visibility buffer's resolve of one
// textured material's pixels (pass_vbuffer.c): one indirect dispatch per
// material, its textures bound at TEX_ALBEDO and TEX_MATERIAL_MR, over
// the list frame/vbuffer_classify.comp's SCATTER pass made.
#include "shared/gpu_types.h"
#define MATERIAL_ROW
#define MATERIAL_GRADIENTS
#define OPAQUE_DRAW
#include "frame/vbuffer.glsl"

layout(local_size_x = VBUFFER_GROUP) in;
layout(location = LOC_VBUFFER_MATERIAL) uniform uint u_material_index;

void main()
{
    uint count = bins[bin_count(u_material_index)], start = bins[bin_start(u_material_index)];
    ivec2 size = imageSize(u_id);
    for (uint i = gl_GlobalInvocationID.x; i < count; i += gl_NumWorkGroups.x * uint(VBUFFER_GROUP)) {
        uint p = pixels[start + i];
        ivec2 px = ivec2(p & 0xffffu, p >> 16);
        vbuffer_resolve(px, imageLoad(u_id, px).x, u_material_index, size);
    }
}
