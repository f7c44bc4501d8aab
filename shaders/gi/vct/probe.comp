// gi/vct/probe.comp — single cones for tests (vct_probe, src/gi/vct/vct.c):
// each entry of SSBO_VCT_VOXELS (re-used; the voxelization's sums are gone
// by then) names a surface point x, its normal n, a direction d and a
// tan(half-angle), and gets back what vct_cone returns for it: the
// radiance gathered (rgb) and the opacity (a), exactly as the trace's
// cones see the volumes.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "gi/vct/cone.glsl"

layout(local_size_x = 64) in;
struct VctProbe {
    vec4 x;   // xyz: surface point (m)
    vec4 n;   // xyz: unit normal
    vec4 d;   // xyz: unit direction; w: tan(half-angle)
    vec4 result; // rgb radiance, a opacity (written)
};
layout(std430, binding = SSBO_VCT_VOXELS) buffer Probes { VctProbe probes[]; };
layout(location = LOC_VCT_SCALE) uniform int u_count;

void main()
{
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_count)
        return;
    VctProbe p = probes[i];
    float occ;
    probes[i].result = vct_cone(p.x.xyz, p.d.xyz, p.n.xyz, p.d.w, vct_voxel_at(p.x.xyz), occ);
}
