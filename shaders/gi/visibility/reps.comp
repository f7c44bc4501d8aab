// gi/visibility/reps.comp — the source of each imperfect shadow map made
// for an RSM's blocks (src/gi/visibility/ism.c, ISM_FROM_RSM): block
// (bx, by) of layer z, block_texels² texels, takes its texel of most flux
// (luminance), weighed down by up to half toward the block's corners so
// that a block of one surface keeps a central one: where a block holds two
// surfaces (a column's side before the sunlit floor) the brighter one's
// samples are tested in their own hemisphere; the texel nearest the centre
// had often been the dim one, whose map passes every sample behind its
// plane (Sponza's nave, rsm: 1.09 of the one-bounce light -> 1.04). Its
// position's bits and
// packed normal go to ism_reps[u_ism_map_base + (z·B + by)·B + bx]. A
// block without one keeps the cleared 0xffffffff (no source: its samples
// carry no flux). RSM_CUBE or RSM_2D picks the kind of map.
#include "shared/gpu_types.h"
#include "common/rsm_texel.glsl"
#include "common/rsm_layers.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = SSBO_ISM_REPS) writeonly buffer IsmRepBlock { uvec4 ism_reps[]; };
layout(location = LOC_ISM_MAP_BASE) uniform uint u_ism_map_base;

void main()
{
    int B = u_ism.blocks, bt = u_ism.block_texels;
    ivec3 blk = ivec3(gl_GlobalInvocationID);
    if (blk.x >= B || blk.y >= B)
        return;
    ivec3 size = rsm_layers_size();
    RsmTexelFrame frame = rsm_texel_frame();
    vec2 centre = (vec2(blk.xy) + 0.5) * float(bt);
    float best = -1.0, far2 = 0.5 * float(bt * bt);
    uvec4 pick = uvec4(0xffffffffu);
    for (int j = 0; j < bt; j++)
        for (int i = 0; i < bt; i++) {
            ivec2 at = blk.xy * bt + ivec2(i, j);
            if (at.x >= size.x || at.y >= size.y)
                continue;
            uvec4 t = rsm_layer_texel(ivec3(at, blk.z));
            float d2 = dot(vec2(at) + 0.5 - centre, vec2(at) + 0.5 - centre);
            float flux = rsm_texel_valid(t) ? dot(rsm_texel_flux(frame, t), vec3(0.2126, 0.7152, 0.0722)) : 0.0;
            float score = flux * (1.0 - 0.5 * d2 / far2);
            if (flux > 0.0 && score > best) {
                best = score;
                pick = uvec4(floatBitsToUint(rsm_texel_position(frame, t)), t.z);
            }
        }
    ism_reps[u_ism_map_base + uint((blk.z * B + blk.y) * B + blk.x)] = pick;
}
