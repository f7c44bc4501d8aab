// lights.glsl — the light model; identical to light_intensity() in
// src/core/scene.c, which the path tracer uses. Change both together.

// FLAT_UNIFORMS (the direct-light programs, pass_direct.c): the light block
// reaches the fragment shader as a flat input that the vertex shader copied
// from u_light (frame/scene.vert), and u_light names
// it here; the forward draw's material constants, eye and exposure likewise
// (common/material.glsl, frame/forward.frag). The same values, bit for bit;
// but llvmpipe 22.3 reads a uniform in a fragment shader lane by lane (its
// one-load path needs lane 0 active, which a fragment shader never
// promises): about 34 instructions per scalar per 8 pixels, where a flat
// input costs one load per triangle. pcf_sun.json 800×600, one thread:
// 216 -> 177M instructions per frame (cachegrind) with the light block,
// 155M with the rest; 12.7 -> 10.7 -> 9.4 ms.
#ifdef FLAT_UNIFORMS
flat in GpuLight v_light;
#define u_light v_light
#endif

// The light's LIGHT_* type. A program built for one type (frame/shade.comp's
// variants, see pass_direct.c) defines LIGHT_FIXED_TYPE so that the compiler
// drops the other types' code: llvmpipe pays for code behind branches that
// no pixel takes (the direct pass of a sun: 119 -> 56 ms without the quad
// light's polygon code, 800x600, one thread).
int light_type(GpuLight l)
{
#ifdef LIGHT_FIXED_TYPE
    return LIGHT_FIXED_TYPE;
#else
    return int(l.position_type.w);
#endif
}

// Radiant intensity (W/sr) toward unit direction `dir` (from the light out).
vec3 light_intensity(GpuLight l, vec3 dir)
{
    int type = light_type(l);
    float c = dot(dir, l.direction_width.xyz);
    if (type == LIGHT_SPOT)
        return l.color.rgb * smoothstep(l.spot.x, l.spot.y, c);
    if (type == LIGHT_QUAD)
        return l.color.rgb * max(c, 0.0); // L·A·cosθ
    return l.color.rgb;                  // point
}

// Irradiance at x with normal n (unshadowed) and the unit direction to the light.
vec3 light_irradiance(GpuLight l, vec3 x, vec3 n, out vec3 to_light)
{
    if (light_type(l) == LIGHT_DIRECTIONAL) {
        to_light = -l.direction_width.xyz;
        return l.color.rgb * max(dot(n, to_light), 0.0);
    }
    vec3 d = l.position_type.xyz - x;
    float d2 = max(dot(d, d), 1e-12);
    to_light = d * inversesqrt(d2);
    return light_intensity(l, -to_light) * max(dot(n, to_light), 0.0) / d2;
}

// ---- Quad lights as the real polygon (SPEC §1: exact diffuse irradiance) ----

// The term of one polygon edge a -> b (relative to x) in Lambert's
// formula: the angle it subtends times the unit normal of its plane.
vec3 polygon_edge(vec3 a, vec3 b)
{
    a = normalize(a);
    b = normalize(b);
    vec3 c = cross(a, b);
    float s = length(c);
    return s > 1e-12 ? atan(s, dot(a, b)) / s * c : vec3(0.0);
}

// The part of edge a -> b (relative to x, heights da, db above the tangent
// plane) at or above the horizon; `exits`/`enters` when it crosses down or
// up, at `cut`. Without branches or an indexed array: llvmpipe runs both
// sides of a branch, and a clipped polygon kept in an array indexed by a
// running count lived in memory, lane by lane (the quad light's direct
// pass, Cornell 256², one thread: 13 of its 14 ms).
vec3 polygon_clipped_edge(vec3 a, vec3 b, float da, float db, out bool exits, out bool enters, out vec3 cut)
{
    bool ua = da >= 0.0, ub = db >= 0.0;
    exits = ua && !ub;
    enters = !ua && ub;
    cut = a + (b - a) * (da / (ua != ub ? da - db : 1.0));
    vec3 e = polygon_edge(ua ? a : cut, ub ? b : cut);
    return ua || ub ? e : vec3(0.0);
}

// Vector irradiance per unit radiance at x from the convex polygon p[0..3]
// (world space) clipped to the horizon of x with normal n (the half-space
// n·(p − x) ≥ 0): Lambert's formula  F = ½ Σ_i θ_i ĝ_i,  θ_i the angle
// edge i subtends, ĝ_i the unit normal of the plane through x and that edge,
// oriented so that E/L = n·F ≥ 0. F's direction is the polygon's mean
// light direction. Clipping keeps each edge's part above the horizon and
// adds the edge along the horizon from where the (convex) polygon goes
// below to where it comes back.
vec3 polygon_vector(vec3 x, vec3 n, vec3 p[4])
{
    vec3 a0 = p[0] - x, a1 = p[1] - x, a2 = p[2] - x, a3 = p[3] - x;
    float d0 = dot(a0, n), d1 = dot(a1, n), d2 = dot(a2, n), d3 = dot(a3, n);
    bool x0, x1, x2, x3, e0, e1, e2, e3;
    vec3 c0, c1, c2, c3;
    vec3 sum = polygon_clipped_edge(a0, a1, d0, d1, x0, e0, c0) + polygon_clipped_edge(a1, a2, d1, d2, x1, e1, c1) +
               polygon_clipped_edge(a2, a3, d2, d3, x2, e2, c2) + polygon_clipped_edge(a3, a0, d3, d0, x3, e3, c3);
    vec3 exit_at = x0 ? c0 : x1 ? c1 : x2 ? c2 : c3, enter_at = e0 ? c0 : e1 ? c1 : e2 ? c2 : c3;
    vec3 closing = polygon_edge(exit_at, enter_at);
    sum += (x0 || x1 || x2 || x3) && (e0 || e1 || e2 || e3) ? closing : vec3(0.0);
    return 0.5 * (dot(sum, n) < 0.0 ? -sum : sum);
}

// Irradiance per unit radiance, E/L, at x with normal n from the polygon.
float polygon_irradiance(vec3 x, vec3 n, vec3 p[4])
{
    return dot(polygon_vector(x, n, p), n);
}

// The four corners of a quad light at its size (counter-clockwise about u × v).
void quad_corners(GpuLight l, out vec3 p[4])
{
    vec3 c = l.position_type.xyz, hu = 0.5 * l.quad_u.xyz, hv = 0.5 * l.quad_v.xyz;
    p[0] = c - hu - hv;
    p[1] = c + hu - hv;
    p[2] = c + hu + hv;
    p[3] = c - hu + hv;
}

// Lambert's F (polygon_vector) of quad light l at x (normal n; `to_light`
// the unit direction to its centre). A quad whose longer side w is under
// QUAD_POINT_LIMIT of its distance d subtends too little for the polygon
// formula in float: its edge terms, each about w/d, cancel to a sum of
// about (w/d)² (the solid angle), and their rounding swamped it (15× too
// bright at w/d = 3e-5, 1e5× at 1e-6). Such a quad takes the point
// formula, F = A·cosθ_l/d² toward its centre. At the limit the two differ
// by at most 1.2e-3 of the exact value (5e-4 where both cosines exceed 0.3;
// a double-precision check of 4000 random rectangles and receivers), and
// the polygon's own float rounding is about 4e-4.
const float QUAD_POINT_LIMIT = 0.03;
vec3 quad_vector(GpuLight l, vec3 x, vec3 n, vec3 to_light)
{
    vec3 d = l.position_type.xyz - x;
    float d2 = dot(d, d), w2 = max(dot(l.quad_u.xyz, l.quad_u.xyz), dot(l.quad_v.xyz, l.quad_v.xyz));
    if (w2 < QUAD_POINT_LIMIT * QUAD_POINT_LIMIT * d2) {
        float cos_l = max(-dot(to_light, l.direction_width.xyz), 0.0);
        return to_light * (l.quad_v.w * cos_l / d2 * step(0.0, dot(n, to_light)));
    }
    vec3 corners[4];
    quad_corners(l, corners);
    return polygon_vector(x, n, corners);
}
