// gi/vct/args.comp — the indirect dispatches over the voxels (vct.c,
// dispatch_voxels), from the opaque lists' counts, so that nothing is read
// back to the CPU: a pass runs over the opaque list when it fits its
// capacity and over every voxel when it overflowed, the other dispatch
// having no groups. One invocation writes (SSBO_VCT_ARGS):
//   [0]  over the list:              (list's groups, 1, 1) or (0, 1, 1)
//   [1]  over every voxel instead:   (0, 1, 1) or the volume's 4×4×4 groups
//   [2], [3]  the same for the list before a region's revoxelization
//        (SSBO_VCT_OPAQUE_PREV; gi/vct/list.comp).
#include "shared/gpu_types.h"
#include "gi/vct/volume.glsl"

layout(local_size_x = 1) in;
layout(std430, binding = SSBO_VCT_OPAQUE) readonly buffer Opaque { uint opaque_count; uint opaque_pad[3]; uint opaque[]; };
layout(std430, binding = SSBO_VCT_OPAQUE_PREV) readonly buffer Prev { uint prev_count; uint prev_pad[3]; uint prev[]; };
layout(std430, binding = SSBO_VCT_ARGS) writeonly buffer Args { uvec4 args[4]; };

void write_pair(int i, uint count, uint capacity)
{
    uint n = uint(u_vct.size), side = (n + 3u) / 4u, depth = (n * uint(VCT_CLIP_LEVELS) + 3u) / 4u;
    bool listed = count <= capacity;
    args[2 * i] = uvec4(listed ? (count + 63u) / 64u : 0u, 1u, 1u, 0u);
    args[2 * i + 1] = listed ? uvec4(0u, 1u, 1u, 0u) : uvec4(side, side, depth, 0u);
}

void main()
{
    write_pair(0, opaque_count, uint(opaque.length()));
    write_pair(1, prev_count, uint(prev.length()));
}
