// test/surfel.comp — packs each GpuVpl's position and normal into a
// G-buffer surfel texel and unpacks it again in place (tests/test_layout.c);
// normal_xi.w = 1 where the texel reads as valid.
#include "shared/gpu_types.h"
#include "common/surfel.glsl"
#include "common/vpl_record.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = SSBO_VPL) buffer VplBlock { GpuVpl vpls[]; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(vpls.length()))
        return;
    uvec4 s = surfel_pack(vpl_position(vpls[i]), vpl_normal(vpls[i]));
    vpls[i].surface.xyz = floatBitsToUint(surfel_unpack_position(s));
    vpls[i].normal_xi = vec4(surfel_unpack_normal(s), surfel_valid(s) ? 1.0 : 0.0);
}
