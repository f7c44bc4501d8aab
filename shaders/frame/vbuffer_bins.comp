// frame/vbuffer_bins.comp — the visibility buffer's bins (pass_vbuffer.c):
// from each material's pixel count (frame/vbuffer_classify.comp), where its
// pixels go in SSBO_VBUFFER_PIXELS (an exclusive prefix sum, one
// invocation: a scene has tens of materials) and the indirect dispatch of
// its resolve (frame/vbuffer_resolve.comp: VBUFFER_GROUP pixels a group,
// at most 65535 groups, each then taking several).
#include "shared/gpu_types.h"
#define MATERIAL_ROW
#define MATERIAL_GRADIENTS
#define UNTEXTURED
#include "frame/vbuffer.glsl"

layout(local_size_x = 1) in;

void main()
{
    uint start = 0u;
    for (uint m = 0u; m < material_count(); m++) {
        uint count = bins[bin_count(m)];
        bins[4u * m] = min((count + uint(VBUFFER_GROUP) - 1u) / uint(VBUFFER_GROUP), 65535u);
        bins[4u * m + 1u] = 1u;
        bins[4u * m + 2u] = 1u;
        bins[bin_start(m)] = start;
        bins[bin_cursor(m)] = start;
        start += count;
    }
}
