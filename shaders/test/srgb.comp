// test/srgb.comp — common/tonemap.glsl's srgb_encode on the values of a
// buffer, in place (tests/test_direct.c compares it with the standard's
// formula).
#include "shared/gpu_types.h"
#include "common/tonemap.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = SSBO_SAMPLES) buffer Values { vec4 values[]; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i < uint(values.length()))
        values[i].rgb = srgb_encode(values[i].rgb);
}
