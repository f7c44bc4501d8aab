// gi/lpv/geometry.vert — geometry-volume injection (Kaplanyan & Dachsbacher
// 2010, §4): one point per surfel, a texel of an RSM (2D array: one layer,
// or six for a cube) or, with GBUFFER defined, a pixel of the camera's
// G-buffer. A surfel of area A and normal n blocks light crossing it in
// direction ω by A/s² · f(n·ω) (s the cell size). The paper's lobe is
// |n·ω|, whose 2-band SH projection has no band 1 (it is even): the
// 2-band volume would block every direction alike. This volume keeps the
// even part instead: the area-weighted normal tensor Σ A/s² · n nᵀ (six
// numbers, the exact projection onto SH bands 0 and 2 of (n·ω)²), so that
// B(ω) = ωᵀ M ω, clamped to 1 where it is read. The surfel's area comes
// from the positions of its neighbouring texels (the nearer of the two on
// each axis, so depth discontinuities do not count), capped at
// LOC_LPV_SURFEL_AREA. The geometry grid is offset by half a cell: its
// cell (i,j,k) is centred on LPV corner (i,j,k) and it has N+1 per side.
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"

#ifdef GBUFFER
layout(binding = TEX_GB_POSITION) uniform sampler2D s_position;
layout(binding = TEX_GB_NORMAL) uniform sampler2D s_normal;
#define FETCH(tex, q) texelFetch(tex, (q).xy, 0)
#else
layout(binding = TEX_RSM_POSITION) uniform sampler2DArray s_position;
layout(binding = TEX_RSM_NORMAL) uniform sampler2DArray s_normal;
#define FETCH(tex, q) texelFetch(tex, q, 0)
#endif
layout(location = LOC_LPV_CASCADE) uniform int u_cascade;
layout(location = LOC_LPV_SURFEL_AREA) uniform float u_max_area;

flat out int v_layer;
flat out vec4 v_a;
flat out vec4 v_b;
flat out vec4 v_c;

// The shorter valid difference to the neighbours along `axis`; zero if none.
vec3 tangent(ivec3 q, ivec3 axis, ivec2 size, vec3 p)
{
    vec3 best = vec3(0.0);
    float best_len = 1e30;
    for (int s = -1; s <= 1; s += 2) {
        ivec3 r = q + s * axis;
        if (any(lessThan(r.xy, ivec2(0))) || any(greaterThanEqual(r.xy, size)))
            continue;
        vec4 o = FETCH(s_position, r);
        if (o.w == 0.0)
            continue;
        vec3 d = o.xyz - p;
        float l = dot(d, d);
        if (l < best_len) {
            best_len = l;
            best = d;
        }
    }
    return best;
}

void main()
{
    v_layer = -1;
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    gl_PointSize = 1.0;
    v_a = v_b = v_c = vec4(0.0);
#ifdef GBUFFER
    ivec2 size = textureSize(s_position, 0);
    ivec3 q = ivec3(gl_VertexID % size.x, gl_VertexID / size.x, 0);
#else
    ivec2 size = textureSize(s_position, 0).xy;
    int per_layer = size.x * size.y;
    int t = gl_VertexID % per_layer;
    ivec3 q = ivec3(t % size.x, t / size.x, gl_VertexID / per_layer);
#endif
    vec4 p = FETCH(s_position, q);
    if (p.w == 0.0)
        return;
    vec3 du = tangent(q, ivec3(1, 0, 0), size, p.xyz), dv = tangent(q, ivec3(0, 1, 0), size, p.xyz);
    if (du == vec3(0.0))
        du = vec3(0.0, 0.0, length(dv)); // no neighbour on one axis: a square of the other's side
    if (dv == vec3(0.0))
        dv = vec3(length(du), 0.0, 0.0);
    vec3 n = normalize(FETCH(s_normal, q).xyz);
    float area = min(abs(dot(cross(du, dv), n)), u_max_area);
    int k = u_cascade, size_gv = u_lpv.size + 1;
    float s = u_lpv.cascade[k].w;
    ivec3 c = ivec3(floor((p.xyz - u_lpv.cascade[k].xyz) / s + 0.5));
    if (!lpv_inside(c, size_gv) || area <= 0.0)
        return;
    float w = area / (s * s);
    v_layer = c.z;
    gl_Position = vec4((vec2(c.xy) + 0.5) / float(size_gv) * 2.0 - 1.0, 0.0, 1.0);
    v_a = w * vec4(n * n, 0.0);
    v_b = w * vec4(n.x * n.y, n.x * n.z, n.y * n.z, 0.0);
}
