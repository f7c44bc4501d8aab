// test/layout.comp — uses every block of shared/gpu_types.h so that
// tests/test_layout.c can compare the linked program's offsets with C's,
// and writes the GLSL-only constants for comparison with C's enums.
#include "shared/gpu_types.h"

layout(local_size_x = 1) in;
layout(std430, binding = SSBO_VPL) buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) buffer OutBlock { int values[]; };

void main()
{
    float sink = u_light.color.x + u_shadow.poisson[1].x + float(u_frame.width) + u_gi.rsm_r_max +
                 u_vpl.keep + vpls[0].flux.x + u_vct.cone_aperture[1].x + u_ism.bias_abs + u_ism.grid.w;
    values[0] = LIGHT_DIRECTIONAL;
    values[1] = LIGHT_SPOT;
    values[2] = LIGHT_POINT;
    values[3] = LIGHT_QUAD;
    values[4] = SHADOW_NONE;
    values[5] = SHADOW_HARD;
    values[6] = SHADOW_PCF;
    values[7] = SHADOW_PCSS;
    values[8] = int(sink * 0.0);
    values[9] = SHADOW_BIAS_RECEIVER_PLANE;
    values[10] = SHADOW_BIAS_LEGACY;
    values[11] = RSM_WEIGHT_PAPER;
    values[12] = RSM_WEIGHT_UNBIASED;
    values[13] = RSM_WEIGHT_IMPORTANCE;
    values[14] = AREA_LIGHT_EXACT;
    values[15] = AREA_LIGHT_POINT;
    values[16] = SHADOW_FILTER_DISK;
    values[17] = SHADOW_FILTER_GRID;
}
