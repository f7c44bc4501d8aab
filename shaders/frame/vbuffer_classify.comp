// frame/vbuffer_classify.comp — the visibility buffer's per-pixel passes
// (pass_vbuffer.c), over the whole image:
//   default: pixels of no surface get the G-buffer's clear value, those of
//     materials without textures are resolved here (their constants are
//     the table's), the others counted in their material's bin;
//   SCATTER: after frame/vbuffer_bins.comp, each counted pixel appends
//     itself to its material's list (SSBO_VBUFFER_PIXELS).
// Material classification: a compute pass binds no textures per pixel, so
// each textured material's pixels are resolved by one indirect dispatch
// with its textures bound (frame/vbuffer_resolve.comp). A work group's
// pixels of one material take one atomic between them (their count, and
// each its rank among them, from shared memory) where each had taken its
// own: Sponza's nave at 640×360 on llvmpipe, CPU seconds per cold and
// steady frame 0.51-0.56 -> 0.46-0.48 (a tile of 64 pixels holds one or
// two materials).
#include "shared/gpu_types.h"
#define MATERIAL_ROW
#define MATERIAL_GRADIENTS
#define UNTEXTURED
#include "frame/vbuffer.glsl"

layout(local_size_x = SHADE_GROUP, local_size_y = SHADE_GROUP) in;

const uint LANES = uint(SHADE_GROUP * SHADE_GROUP);
shared uint s_key[LANES];  // material + 1 of each lane's pixel where it is binned, else 0
shared uint s_base[LANES]; // SCATTER: a leader's first slot

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy), size = imageSize(u_id);
    bool inside = all(lessThan(px, size));
    uint id = inside ? imageLoad(u_id, px).x : 0u, m = 0u, key = 0u;
    bool textured = false;
    if (id != 0u) {
        m = vbuffer_material(id, textured);
        key = textured ? m + 1u : 0u;
    }
#ifndef SCATTER
    if (inside && id == 0u) {
        imageStore(u_surface, px, uvec4(0u)); // no surface, no material
        imageStore(u_material, px, uvec4(0u));
    } else if (inside && !textured) {
        vbuffer_resolve(px, id, m, size);
    }
#endif
    // This lane's rank among the group's lanes of its material, their
    // count, and the first of them (the leader, which takes the atomic).
    uint lane = gl_LocalInvocationIndex;
    s_key[lane] = key;
    barrier();
    uint rank = 0u, count = 0u, leader = lane;
    if (key != 0u) {
        for (uint j = 0u; j < LANES; j++) {
            bool same = s_key[j] == key;
            count += same ? 1u : 0u;
            rank += same && j < lane ? 1u : 0u;
            leader = same && j < leader ? j : leader;
        }
    }
#ifdef SCATTER
    if (key != 0u && rank == 0u)
        s_base[lane] = atomicAdd(bins[bin_cursor(m)], count);
    barrier();
    if (key != 0u)
        pixels[s_base[leader] + rank] = uint(px.x) | uint(px.y) << 16;
#else
    if (key != 0u && rank == 0u)
        atomicAdd(bins[bin_count(m)], count);
#endif
}
