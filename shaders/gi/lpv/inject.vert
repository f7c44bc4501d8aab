// gi/lpv/inject.vert — light injection (Kaplanyan & Dachsbacher 2010): one
// point per VPL. The VPL moves u_lpv.offset cells along its normal
// and lands in the cell that contains it, as the 2-band SH of its
// clamped-cosine intensity lobe I(ω) = Φ/π · max(0, n·ω), one vec4 per
// colour channel. Its flux is preserved: ∫ I dω = c00·2√π = Φ.
// Inputs: SSBO_VPL (the light stage's VPL buffer, or a test's), cascade
// LOC_LPV_CASCADE, and LOC_LPV_EXCLUDE: a finer cascade whose VPLs this
// volume leaves out (see lpv.c on cascades). Output: a point on layer z at
// cell (x, y), layer z of the VPL's light group (lpv_group_layer).
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"
#include "common/vpl_record.glsl"

layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };
layout(location = LOC_LPV_CASCADE) uniform int u_cascade;
layout(location = LOC_LPV_EXCLUDE) uniform int u_exclude; // a finer cascade whose VPLs are left out, or -1
layout(location = LOC_LPV_GROUP) uniform int u_group;     // the light group drawn (sh.glsl), or -1

flat out int v_layer;
flat out vec4 v_a;
flat out vec4 v_b;
flat out vec4 v_c;

void main()
{
    GpuVpl v = vpls[gl_VertexID];
    vec3 n = vpl_normal(v);
    int k = u_cascade, size = u_lpv.size;
    vec3 p = vpl_position(v) + n * (u_lpv.offset * u_lpv.cascade[k].w);
    ivec3 c = lpv_cell(k, p);
    v_layer = lpv_inside(c, size) && lpv_in_group(n, u_group) ? c.z + lpv_group_layer(u_group, size) : -1;
    if (u_exclude >= 0 &&
        lpv_inside(lpv_cell(u_exclude, vpl_position(v) + n * (u_lpv.offset * u_lpv.cascade[u_exclude].w)), size))
        v_layer = -1;
    gl_Position = vec4((vec2(c.xy) + 0.5) / float(size) * 2.0 - 1.0, 0.0, 1.0);
    gl_PointSize = 1.0;
    vec4 lobe = sh_clamped_cos(n) / LPV_PI;
    v_a = v.flux.r * lobe;
    v_b = v.flux.g * lobe;
    v_c = v.flux.b * lobe;
}
