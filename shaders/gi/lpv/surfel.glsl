// gi/lpv/surfel.glsl — a texel of an RSM (common/rsm_layers.glsl: one
// layer, or six for a cube) or, with GBUFFER defined, a pixel of the camera's G-buffer as a
// surfel for the geometry volume: position, normal and area, the area from
// the positions of its neighbouring texels (the nearer of the two on each
// axis, so depth discontinuities do not count; a square of the one side
// found when only one axis has a neighbour), capped at `max_area`.
// The geometry volume stores per cell of side s the area-weighted normal
// tensor Σ A/s² · n nᵀ (see geometry.vert); lpv_surfel_cell gives the
// geometry cell (offset by half a cell: N+1 per side) and that weight.
#ifndef LPV_SURFEL_GLSL
#define LPV_SURFEL_GLSL

// surfel_position: xyz, w = 1 where the texel holds a surface.
// G-buffer pixels are packed surfels (common/surfel.glsl), RSM texels packed
// RSM texels (common/rsm_texel.glsl, positions in the light's box).
#include "common/surfel.glsl"
#include "common/rsm_texel.glsl" // (the shader loader inlines a file once, wherever it is first named)
#ifdef GBUFFER
layout(binding = TEX_GB_SURFACE) uniform usampler2D s_surfel;
ivec3 surfel_size() { return ivec3(textureSize(s_surfel, 0), 1); }
vec4 surfel_position(ivec3 q)
{
    uvec4 s = texelFetch(s_surfel, q.xy, 0);
    return vec4(surfel_unpack_position(s), surfel_valid(s) ? 1.0 : 0.0);
}
vec3 surfel_normal(ivec3 q) { return surfel_unpack_normal(texelFetch(s_surfel, q.xy, 0)); }
#else
#include "common/rsm_layers.glsl"
ivec3 surfel_size() { return rsm_layers_size(); }
vec4 surfel_position(ivec3 q)
{
    uvec4 t = rsm_layer_texel(q);
    return vec4(rsm_texel_position(rsm_texel_frame(), t), rsm_texel_valid(t) ? 1.0 : 0.0);
}
vec3 surfel_normal(ivec3 q) { return rsm_texel_normal(rsm_layer_texel(q)); }
#endif

// The shorter valid difference to the neighbours along `axis`; zero if none.
vec3 surfel_tangent(ivec3 q, ivec3 axis, ivec2 size, vec3 p)
{
    vec3 best = vec3(0.0);
    float best_len = 1e30;
    for (int s = -1; s <= 1; s += 2) {
        ivec3 r = q + s * axis;
        if (any(lessThan(r.xy, ivec2(0))) || any(greaterThanEqual(r.xy, size)))
            continue;
        vec4 o = surfel_position(r);
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

// Surfel of texel q (layer q.z); false where the texel holds no surface.
bool lpv_surfel(ivec3 q, float max_area, out vec3 p, out vec3 n, out float area)
{
    ivec2 size = surfel_size().xy;
    vec4 pw = surfel_position(q);
    p = pw.xyz;
    n = vec3(0.0, 1.0, 0.0);
    area = 0.0;
    if (pw.w == 0.0)
        return false;
    n = normalize(surfel_normal(q));
    vec3 du = surfel_tangent(q, ivec3(1, 0, 0), size, p), dv = surfel_tangent(q, ivec3(0, 1, 0), size, p);
    bool u = du != vec3(0.0), v = dv != vec3(0.0);
    area = u && v ? abs(dot(cross(du, dv), n)) : u ? dot(du, du) : v ? dot(dv, dv) : 0.0;
    area = min(area, max_area);
    return area > 0.0;
}

// Geometry cell of cascade k holding p, and the surfel's weight A/s².
ivec3 lpv_surfel_cell(int k, vec3 p, float area, out float w)
{
    float s = u_lpv.cascade[k].w;
    w = area / (s * s);
    return ivec3(floor((p - u_lpv.cascade[k].xyz) / s + 0.5));
}

#endif
