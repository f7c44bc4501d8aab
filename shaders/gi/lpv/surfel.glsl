// gi/lpv/surfel.glsl — a texel of an RSM (common/rsm_layers.glsl: one
// layer, or six for a cube) or, with GBUFFER defined, a pixel of the
// camera's G-buffer as a surfel for the geometry volume: position, normal and area, the area from
// the positions of its neighbouring texels (the nearer of the two on each
// axis, so depth discontinuities do not count; a square of the one side
// found when only one axis has a neighbour), capped at `max_area`.
// The geometry volume stores per cell of side s the area-weighted normal
// tensor Σ A/s² · n nᵀ (see geometry.vert); lpv_surfel_cell gives the
// geometry cell (offset by half a cell: N+1 per side) and that weight.
#ifndef LPV_SURFEL_GLSL
#define LPV_SURFEL_GLSL

// surfel_position_of: xyz, w = 1 where the texel holds a surface.
// G-buffer pixels are packed surfels (common/surfel.glsl), RSM texels packed
// RSM texels (common/rsm_texel.glsl, positions in the light's box).
#include "common/surfel.glsl"
#include "common/rsm_texel.glsl" // (the shader loader inlines a file once, wherever it is first named)
// A texel is read once (surfel_load: uvec4(0), no surface, off the map)
// and unpacked by surfel_position_of / surfel_normal_of in a SurfelFrame
// (what unpacking needs from uniforms, read once outside loops).
#ifdef GBUFFER
layout(binding = TEX_GB_SURFACE) uniform usampler2D s_surfel;
ivec3 surfel_size() { return ivec3(textureSize(s_surfel, 0), 1); }
uvec4 surfel_texel(ivec3 q) { return texelFetch(s_surfel, q.xy, 0); }
struct SurfelFrame { int none; };
SurfelFrame surfel_frame() { return SurfelFrame(0); }
vec4 surfel_position_of(SurfelFrame f, uvec4 s) { return vec4(surfel_unpack_position(s), surfel_valid(s) ? 1.0 : 0.0); }
vec3 surfel_normal_of(uvec4 s) { return surfel_unpack_normal(s); }
#else
#include "common/rsm_layers.glsl"
ivec3 surfel_size() { return rsm_layers_size(); }
uvec4 surfel_texel(ivec3 q) { return rsm_layer_texel(q); }
#define SurfelFrame RsmTexelFrame
SurfelFrame surfel_frame() { return rsm_texel_frame(); }
vec4 surfel_position_of(SurfelFrame f, uvec4 t) { return vec4(rsm_texel_position(f, t), rsm_texel_valid(t) ? 1.0 : 0.0); }
vec3 surfel_normal_of(uvec4 t) { return rsm_texel_normal(t); }
#endif

uvec4 surfel_load(ivec3 q, ivec3 size)
{
    bool inside = all(greaterThanEqual(q.xy, ivec2(0))) && all(lessThan(q.xy, size.xy));
    uvec4 t = surfel_texel(clamp(q, ivec3(0), size - 1));
    return inside ? t : uvec4(0u);
}

// The shorter difference from p to its neighbours a (before) and b (after)
// on one axis that hold a surface (w = 1); zero if neither does.
vec3 surfel_tangent_of(vec3 p, vec4 a, vec4 b)
{
    vec4 side[2] = vec4[2](a, b);
    vec3 best = vec3(0.0);
    float best_len = 1e30;
    for (int s = 0; s < 2; s++) {
        vec3 d = side[s].xyz - p;
        float l = dot(d, d);
        if (side[s].w != 0.0 && l < best_len) {
            best_len = l;
            best = d;
        }
    }
    return best;
}

// Surfel of texel t (position pw) with its neighbours' positions along u
// (left, right) and v (up, down); false where the texel holds no surface.
bool lpv_surfel_of(uvec4 t, vec4 pw, vec4 left, vec4 right, vec4 up, vec4 down, float max_area, out vec3 p,
                   out vec3 n, out float area)
{
    p = pw.xyz;
    n = vec3(0.0, 1.0, 0.0);
    area = 0.0;
    if (pw.w == 0.0)
        return false;
    n = normalize(surfel_normal_of(t));
    vec3 du = surfel_tangent_of(p, left, right), dv = surfel_tangent_of(p, up, down);
    bool u = du != vec3(0.0), v = dv != vec3(0.0);
    area = u && v ? abs(dot(cross(du, dv), n)) : u ? dot(du, du) : v ? dot(dv, dv) : 0.0;
    area = min(area, max_area);
    return area > 0.0;
}

// Surfel of texel q (layer q.z); false where the texel holds no surface.
bool lpv_surfel(ivec3 q, float max_area, out vec3 p, out vec3 n, out float area)
{
    ivec3 size = surfel_size(), X = ivec3(1, 0, 0), Y = ivec3(0, 1, 0);
    SurfelFrame f = surfel_frame();
    uvec4 t = surfel_load(q, size);
    return lpv_surfel_of(t, surfel_position_of(f, t), surfel_position_of(f, surfel_load(q - X, size)),
                         surfel_position_of(f, surfel_load(q + X, size)), surfel_position_of(f, surfel_load(q - Y, size)),
                         surfel_position_of(f, surfel_load(q + Y, size)), max_area, p, n, area);
}

// Geometry cell of the cascade (origin xyz, cell size w) holding p, and the
// surfel's weight A/s².
ivec3 lpv_surfel_cell_in(vec4 cascade, vec3 p, float area, out float w)
{
    float s = cascade.w;
    w = area / (s * s);
    return ivec3(floor((p - cascade.xyz) / s + 0.5));
}

// The same in cascade k.
ivec3 lpv_surfel_cell(int k, vec3 p, float area, out float w) { return lpv_surfel_cell_in(u_lpv.cascade[k], p, area, w); }

#endif
