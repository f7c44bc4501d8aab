// gi/visibility/pull_push.comp — fills the holes the points left in the
// imperfect shadow maps (Ritschel et al. 2008, after Grossman & Dally's
// pull-push), on the atlas's mip chain: a map's tile at level l is its
// level-l image, S >> l texels per side, so one dispatch per level serves
// every map. Pull (level l from l − 1): the mean of the four children
// that hold a depth, else ISM_EMPTY. Push (level l from l + 1, after the
// pull, coarsest first): a texel without a depth takes its parent's;
// texels the points reached keep theirs. A map no point reached stays
// ISM_EMPTY (visible). (A work group per map with the pyramid in shared
// memory took 643 ms for 4056 maps of 32² on llvmpipe, its barriers
// serialised; these passes took 206 ms for 3163 maps: docs/techniques.md,
// "Visibility of the bounce".)
#include "shared/gpu_types.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(r32ui, binding = IMG_OUT) uniform uimage2D o_level;       // level l: written (push: read too)
layout(r32ui, binding = IMG_OUT2) uniform readonly uimage2D i_other; // pull: level l − 1; push: level l + 1
layout(location = LOC_ISM_PUSH) uniform int u_push;

void main()
{
    ivec2 at = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(at, imageSize(o_level))))
        return;
    if (u_push == 0) {
        float sum = 0.0, n = 0.0;
        for (int k = 0; k < 4; k++) {
            uint v = imageLoad(i_other, at * 2 + ivec2(k & 1, k >> 1)).r;
            sum += v != ISM_EMPTY ? uintBitsToFloat(v) : 0.0;
            n += v != ISM_EMPTY ? 1.0 : 0.0;
        }
        imageStore(o_level, at, uvec4(n > 0.0 ? floatBitsToUint(sum / n) : ISM_EMPTY));
    } else if (imageLoad(o_level, at).r == ISM_EMPTY) {
        imageStore(o_level, at, imageLoad(i_other, at / 2));
    }
}
