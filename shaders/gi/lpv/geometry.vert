// gi/lpv/geometry.vert — geometry-volume injection (Kaplanyan & Dachsbacher
// 2010, §4): one point per surfel, a texel of an RSM (2D array: one layer,
// or six for a cube) or, with GBUFFER defined, a pixel of the camera's
// G-buffer. A surfel of area A and normal n blocks light crossing it in
// direction ω by A/s² · f(n·ω) (s the cell size). The paper's lobe is
// |n·ω|, whose 2-band SH projection has no band 1 (it is even): the
// 2-band volume would block every direction alike. This volume keeps the
// even part instead: the area-weighted normal tensor Σ A/s² · n nᵀ (six
// numbers, the exact projection onto SH bands 0 and 2 of (n·ω)²), so that
// B(ω) = ωᵀ M ω, clamped to 1 where it is read. The surfel (surfel.glsl):
// area from its neighbours, capped at LOC_LPV_SURFEL_AREA. The geometry
// grid is offset by half a cell: its cell (i,j,k) is centred on LPV corner
// (i,j,k) and it has N+1 per side. (--lpv-inject points; the default adds
// the same with atomics: geometry_fixed.comp.)
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"

#include "gi/lpv/surfel.glsl"

layout(location = LOC_LPV_CASCADE) uniform int u_cascade;
layout(location = LOC_LPV_SURFEL_AREA) uniform float u_max_area;

flat out int v_layer;
flat out vec4 v_a;
flat out vec4 v_b;
flat out vec4 v_c;

void main()
{
    v_layer = -1;
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    gl_PointSize = 1.0;
    v_a = v_b = v_c = vec4(0.0);
    ivec3 size = surfel_size();
    int per_layer = size.x * size.y;
    int t = gl_VertexID % per_layer;
    ivec3 q = ivec3(t % size.x, t / size.x, gl_VertexID / per_layer);
    vec3 p, n;
    float area, w;
    if (!lpv_surfel(q, u_max_area, p, n, area))
        return;
    ivec3 c = lpv_surfel_cell(u_cascade, p, area, w);
    int size_gv = u_lpv.size + 1;
    if (!lpv_inside(c, size_gv))
        return;
    v_layer = c.z;
    gl_Position = vec4((vec2(c.xy) + 0.5) / float(size_gv) * 2.0 - 1.0, 0.0, 1.0);
    v_a = w * vec4(n * n, 0.0);
    v_b = w * vec4(n.x * n.y, n.x * n.z, n.y * n.z, 0.0);
}
