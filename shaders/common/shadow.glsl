// shadow.glsl — shadow-map visibility: hard, PCF (Reeves 1987) and PCSS
// (Fernando 2005). Maps store the distance to the light divided by far
// (directional: depth along the light direction from the ortho near plane),
// so biases, blocker depths and penumbrae are in metres.

layout(binding = TEX_SHADOW_2D) uniform sampler2D u_shadow_2d;
layout(binding = TEX_SHADOW_CUBE) uniform samplerCube u_shadow_cube;
layout(binding = TEX_SHADOW_COMPARE_2D) uniform sampler2DShadow u_shadow_cmp_2d;
layout(binding = TEX_SHADOW_COMPARE_CUBE) uniform samplerCubeShadow u_shadow_cmp_cube;

struct ShadowCoord {
    vec3 dir;  // cube: unit direction light → receiver
    vec2 uv;   // 2D: shadow-map coordinates
    float d;   // receiver distance (m)
    vec3 t, b; // cube: tangent frame of dir
};

// A program built for one light (LIGHT_FIXED_TYPE, see common/lights.glsl)
// also knows its map kind, SHADOW_FIXED_CUBE: cube maps for point and quad
// lights, but one 2D map for a point light far outside the scene
// (shadow_frame_is_cube). SHADOW_FIXED_MODE and SHADOW_FIXED_BIAS likewise
// fix u_shadow's mode and filter bias to drop the other filters' code.
bool shadow_is_cube()
{
#ifdef SHADOW_FIXED_CUBE
    return SHADOW_FIXED_CUBE != 0;
#else
    return u_light.shadow_info.w > 0.5;
#endif
}
bool shadow_is_ortho() { return light_type(u_light) == LIGHT_DIRECTIONAL; }
int shadow_filter_bias()
{
#ifdef SHADOW_FIXED_BIAS
    return SHADOW_FIXED_BIAS;
#else
    return u_shadow.filter_bias;
#endif
}
int shadow_pcf_filter()
{
#ifdef SHADOW_FIXED_FILTER
    return SHADOW_FIXED_FILTER;
#else
    return u_shadow.pcf_filter;
#endif
}
int shadow_mode()
{
#ifdef SHADOW_FIXED_MODE
    return SHADOW_FIXED_MODE;
#else
    return u_shadow.mode;
#endif
}

// World size of one shadow-map texel at distance d from the light.
float shadow_texel(float d)
{
    return shadow_is_ortho() ? u_light.shadow_info.y : u_light.shadow_info.y * d;
}

ShadowCoord shadow_coord(vec3 x)
{
    ShadowCoord sc;
    sc.t = vec3(0);
    sc.b = vec3(0);
    sc.dir = vec3(0);
    sc.uv = vec2(0);
    if (shadow_is_ortho()) {
        sc.d = dot(x - u_light.shadow_origin.xyz, u_light.direction_width.xyz);
    } else {
        vec3 v = x - u_light.position_type.xyz;
        sc.d = length(v);
        sc.dir = v / sc.d;
        basis(sc.dir, sc.t, sc.b);
    }
    if (!shadow_is_cube()) {
        vec4 c = u_light.shadow_view_proj * vec4(x, 1.0);
        sc.uv = (shadow_is_ortho() ? c.xy : c.xy / c.w) * 0.5 + 0.5;
    }
    return sc;
}

// Stored occluder distance (m) at an offset of `o` texels from the receiver's texel.
float shadow_fetch(ShadowCoord sc, vec2 o)
{
    float far = u_light.shadow_info.x;
    if (shadow_is_cube()) {
        float k = u_light.shadow_info.y;
        vec3 d = sc.dir + (sc.t * o.x + sc.b * o.y) * k;
        return textureLod(u_shadow_cube, d, 0.0).r * far;
    }
    vec2 uv = sc.uv + o / u_light.shadow_info.z;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))))
        return 1e30; // outside the map: nothing recorded, lit
    return textureLod(u_shadow_2d, uv, 0.0).r * far;
}

// shadow_fetch for the filters. With the receiver-plane bias a one-sided
// emitter (quad) also ignores what the map holds behind its emitting plane:
// nothing there can block its light, yet a search disk that reaches past the
// horizon of a light that hugs a ceiling (the Cornell box) would find the
// ceiling a few centimetres away and darken the walls under it.
float shadow_fetch_filter(ShadowCoord sc, vec2 o)
{
    if (shadow_filter_bias() != SHADOW_BIAS_LEGACY && light_type(u_light) == LIGHT_QUAD) {
        vec3 d = sc.dir + (sc.t * o.x + sc.b * o.y) * u_light.shadow_info.y;
        if (dot(d, u_light.direction_width.xyz) <= 0.0)
            return 1e30;
    }
    return shadow_fetch(sc, o);
}

// Constant + slope-scaled bias for a filter footprint of `radius` texels
// (hard shadows: 1; the legacy filter bias scales it with the filter's
// footprint; the receiver-plane bias uses at most the one-texel value, see
// shadow_ref).
float shadow_bias(float d, float cos_theta, float radius)
{
    float tan_theta = min(sqrt(max(1.0 - cos_theta * cos_theta, 0.0)) / max(cos_theta, 1e-3), 100.0);
    return u_shadow.bias_const + u_shadow.bias_slope * shadow_texel(d) * tan_theta * max(radius, 1.0);
}

// A world point in the receiver's filter coordinates: xy in texels (2D
// maps: the map's texel grid; cube maps: the tangent plane of sc0.dir that
// shadow_fetch offsets along), z its stored-depth metric (m).
vec3 shadow_local(ShadowCoord sc0, vec3 p)
{
    if (shadow_is_cube()) {
        vec3 v = p - u_light.position_type.xyz;
        float a = max(dot(sc0.dir, v), 1e-6) * u_light.shadow_info.y;
        return vec3(dot(sc0.t, v) / a, dot(sc0.b, v) / a, length(v));
    }
    vec4 c = u_light.shadow_view_proj * vec4(p, 1.0);
    vec2 texel = (c.xy / c.w * 0.5 + 0.5) * u_light.shadow_info.z;
    float d = shadow_is_ortho() ? dot(p - u_light.shadow_origin.xyz, u_light.direction_width.xyz)
                                : length(p - u_light.position_type.xyz);
    return vec3(texel, d);
}

// Receiver-plane depth gradient (m per texel of filter offset): the depth of
// the plane through x with normal n at an offset o is about sc.d + dot(g, o)
// (exact for orthographic maps). From the map coordinates of two points one
// texel away on the plane: J = ∂offset/∂(plane coords), g = J^-T ∂d/∂(plane
// coords). Capped at a slope of 20 texels of depth per texel (87°).
vec2 shadow_receiver_gradient(ShadowCoord sc, vec3 x, vec3 n)
{
    float h = shadow_texel(sc.d), cap = 20.0 * h;
    if (shadow_is_ortho()) {
        // Orthographic maps: the light-space map is linear with orthogonal
        // rows a_u, a_v (texels per metre) and the light direction D (depth),
        // so on the plane n·s = 0, d = −(n·a_u/|a_u|² o_u + n·a_v/|a_v|² o_v)
        // / n·D, the same gradient as the finite differences below to
        // rounding, with three dot products.
        mat4 m = u_light.shadow_view_proj;
        vec3 au = vec3(m[0][0], m[1][0], m[2][0]), av = vec3(m[0][1], m[1][1], m[2][1]);
        float dn = dot(n, u_light.direction_width.xyz);
        if (abs(dn) < 1e-6)
            return vec2(0.0);
        vec2 g = -vec2(dot(n, au) / dot(au, au), dot(n, av) / dot(av, av)) * (2.0 / u_light.shadow_info.z) / dn;
        float len = length(g);
        return len > cap ? g * (cap / len) : g;
    }
    vec3 t1, t2;
    basis(n, t1, t2);
    vec3 p0 = shadow_local(sc, x);
    vec3 da = (shadow_local(sc, x + t1 * h) - p0) / h;
    vec3 db = (shadow_local(sc, x + t2 * h) - p0) / h;
    float det = da.x * db.y - db.x * da.y;
    if (abs(det) < 1e-12)
        return vec2(0.0);
    // inverse(J)^T · (da.z, db.z) with J = [da.xy db.xy] (columns).
    vec2 g = vec2(db.y * da.z - da.y * db.z, -db.x * da.z + da.x * db.z) / det;
    float len = length(g);
    return len > cap ? g * (cap / len) : g;
}

// Sample i of the disk turned by the angle whose (cos, sin) is cs (taken
// once per pixel, outside the filters' loops).
vec2 shadow_poisson(int i, vec2 cs)
{
    vec2 p = u_shadow.poisson[i].xy;
    return vec2(cs.x * p.x - cs.y * p.y, cs.y * p.x + cs.x * p.y);
}

// Per-sample depth test reference: the receiver minus the bias (legacy), or
// the receiver's tangent plane under the sample minus a bias that does not
// grow with the filter. On 2D maps the plane is taken at the centre of the
// texel the sample reads (where the map's depth was rasterized), so a
// planar receiver needs only the constant bias (and a quarter of the slope
// bias, below); cube maps keep the one-texel slope bias for that
// quantisation.
struct ShadowRef {
    float d;     // reference depth at offset 0 (m)
    vec2 g;      // its gradient (m per texel); zero for the legacy bias
    vec2 frac;   // 2D receiver-plane: the receiver's position within its texel; else -1
};

// The offset at which the reference is taken for a sample at offset o.
vec2 shadow_ref_offset(ShadowRef r, vec2 o)
{
    return r.frac.x < 0.0 ? o : floor(r.frac + o) + 0.5 - r.frac;
}

// The plane only lowers the reference, where it comes nearer the light than
// the receiver: there it would shadow itself. Where it goes away, whatever
// lies between the receiver's depth and the plane (the other wall of a
// concave corner) cannot be between the light and the receiver, so the
// receiver's own depth stays the reference.
float shadow_ref_at(ShadowRef r, vec2 o) { return r.d + min(dot(r.g, o), 0.0); }

ShadowRef shadow_ref(ShadowCoord sc, vec2 g, float cos_theta, float radius)
{
    ShadowRef r;
    r.frac = vec2(-1.0);
    if (shadow_filter_bias() == SHADOW_BIAS_LEGACY) {
        r.d = sc.d - shadow_bias(sc.d, cos_theta, radius);
        r.g = vec2(0.0);
    } else if (shadow_is_cube()) {
        r.d = sc.d - shadow_bias(sc.d, cos_theta, 1.0);
        r.g = g;
    } else {
        // A quarter of the one-texel slope bias is left for shading normals
        // that are not the rasterized plane (interpolated vertex normals,
        // half-float G-buffer). Measured on Sponza (320×180, 4×4 SSAA, vs
        // the direct reference): mean 0.992 with none (acne), 1.001 with a
        // quarter, 1.007 with the whole one (light past contacts).
        r.d = sc.d - u_shadow.bias_const - 0.25 * (shadow_bias(sc.d, cos_theta, 1.0) - u_shadow.bias_const);
        r.g = g;
        r.frac = fract(sc.uv * u_light.shadow_info.z);
    }
    return r;
}

float shadow_pcf(ShadowCoord sc, vec2 g, float radius, float cos_theta, float angle)
{
    int n = u_shadow.pcf_samples;
    ShadowRef r = shadow_ref(sc, g, cos_theta, radius);
    vec2 cs = vec2(cos(angle), sin(angle));
    float lit = 0.0;
    for (int i = 0; i < n; i++) {
        vec2 o = shadow_ref_offset(r, shadow_poisson(i, cs) * radius);
        lit += shadow_fetch_filter(sc, o) >= shadow_ref_at(r, o) ? 1.0 : 0.0;
    }
    return lit / float(n);
}

// Grid PCF: k² bilinear depth-compare taps (the sampler does four depth tests
// and blends them) on a square k = 2⌈r⌉ taps wide, capped at 8, spaced
// 2r/k texels: r = 1 is four taps at (±½, ±½), the 3×3 tent (weights
// 1 2 1 / 2 4 2 / 1 2 1). A tap's four texels share its reference: with
// the receiver-plane bias it is the plane's depth at the lowest of the four
// texel centres (each axis contributes min(−g·f, g·(1−f)) for the tap's
// position f within its texel), with shadow_ref_at's rule that the plane
// only lowers it. Explicit level 0 (the maps have one): no implicit
// derivatives to compute, and none to differ between the programs that
// unroll the loop and those that do not. Programs built for one radius fix
// k (SHADOW_GRID_TAPS, shadow_grid_taps in pass_direct.c): llvmpipe runs a
// loop of a constant count unrolled, twice as fast as the same loop over a
// uniform's count (pcf_sun.json 800×600, one thread: direct pass 32 -> 17
// ms).
int shadow_grid_taps(float radius) { return min(2 * int(ceil(max(radius, 0.5))), 8); }

float shadow_pcf_grid(ShadowCoord sc, vec2 g, float radius, float cos_theta)
{
    ShadowRef r = shadow_ref(sc, g, cos_theta, radius);
    float far = u_light.shadow_info.x;
#ifdef SHADOW_GRID_TAPS
    const int k = SHADOW_GRID_TAPS;
#else
    int k = shadow_grid_taps(radius);
#endif
    float step = 2.0 * max(radius, 0.5) / float(k), first = 0.5 * step * float(1 - k);
    bool plane = shadow_filter_bias() != SHADOW_BIAS_LEGACY;
    float inv_size = 1.0 / u_light.shadow_info.z, inv_far = 1.0 / far;
#ifdef SHADOW_GRID_UNIT_STEP
    // Taps a whole texel apart at half-texel offsets (an integer radius,
    // pass_direct.c): every tap's position within its texel is the
    // receiver's, fract(p − ½) = fract(x), so the plane's lowest texel
    // centre is found once.
    vec2 f1 = fract(sc.uv * u_light.shadow_info.z);
    vec2 lo1 = min(-g * f1, g * (1.0 - f1));
#endif
    // precise: no contraction into FMAs, which the unrolled loop of a
    // constant count got and the general program's did not (1-ulp
    // differences in penumbrae, test_direct).
    precise float lit = 0.0;
    for (int j = 0; j < k; j++)
        for (int i = 0; i < k; i++) {
            precise vec2 o = vec2(first + step * float(i), first + step * float(j));
            precise float ref = r.d;
            if (shadow_is_cube()) {
                if (plane)
                    ref += min(dot(g, o) - 0.5 * (abs(g.x) + abs(g.y)), 0.0);
                vec3 d = sc.dir + (sc.t * o.x + sc.b * o.y) * u_light.shadow_info.y;
                lit += textureGrad(u_shadow_cmp_cube, vec4(d, ref / far), vec3(0.0), vec3(0.0));
            } else {
                vec2 p = sc.uv * u_light.shadow_info.z + o;
                if (plane) {
#ifdef SHADOW_GRID_UNIT_STEP
                    vec2 lo = lo1;
#else
                    vec2 f = fract(p - 0.5);
                    vec2 lo = min(-g * f, g * (1.0 - f));
#endif
                    ref += min(dot(g, o) + lo.x + lo.y, 0.0);
                }
                lit += textureLod(u_shadow_cmp_2d, vec3(p * inv_size, ref * inv_far), 0.0);
            }
        }
    return lit / float(k * k);
}

// Light width as seen from distance 1: PCSS's w_light/d for perspective
// lights becomes w·(1/d_b); the sun's is tan of its angular diameter.
float shadow_pcss(ShadowCoord sc, vec2 g, float cos_theta, float angle)
{
    float w = u_light.direction_width.w;
    float max_r = u_shadow.pcss_max_radius;
    // (1) Blocker search: the light's footprint through the receiver, taken at
    // a tenth of the receiver distance (blockers nearer the light than that
    // give penumbrae wider than the cap anyway), in texels, capped.
    float d_min = shadow_is_ortho() ? 0.0 : 0.1 * sc.d;
    float search_world = shadow_is_ortho() ? w * sc.d : w * (sc.d - d_min) / sc.d;
    float search = clamp(0.5 * search_world / shadow_texel(max(d_min, 1e-4)), 1.0, max_r);
    int nb = u_shadow.blocker_samples;
    ShadowRef r = shadow_ref(sc, g, cos_theta, search);
    float sum = 0.0;
    int count = 0;
    vec2 cs = vec2(cos(angle), sin(angle));
    for (int i = 0; i < nb; i++) {
        vec2 o = shadow_ref_offset(r, shadow_poisson(i, cs) * search);
        float z = shadow_fetch_filter(sc, o);
        if (z < shadow_ref_at(r, o)) {
            sum += z;
            count++;
        }
    }
    if (count == 0)
        return 1.0;
    float d_b = sum / float(count);
    // (2) Penumbra width at the receiver: w_p = (d_r − d_b)·w_light/d_b.
    float w_p = shadow_is_ortho() ? (sc.d - d_b) * w : (sc.d - d_b) * w / max(d_b, 1e-4);
    // (3) PCF with a radius of half the penumbra, in texels at the receiver.
    float radius = clamp(0.5 * w_p / shadow_texel(sc.d), 1.0, max_r);
    // Receiver-plane mode: the filter's disk is turned by the golden angle
    // against the search's, so the two do not share one pattern's gaps.
    float turn = shadow_filter_bias() == SHADOW_BIAS_LEGACY ? 0.0 : 2.39996323;
    return shadow_pcf(sc, g, radius, cos_theta, angle + turn);
}

// Visibility in [0,1] of the light from x (normal n, unit direction to light l).
float shadow_visibility(vec3 x, vec3 n, vec3 l, vec2 pixel)
{
    int mode = shadow_mode();
    if (mode == SHADOW_NONE)
        return 1.0;
    float cos_theta = max(dot(n, l), 0.0);
    ShadowCoord sc = shadow_coord(x);
    // Normal offset: move the receiver along n by a few texels before
    // lookup (off by default: then xo = x exactly). Without a branch:
    // llvmpipe runs an if's body whether or not a lane takes it, and this
    // one's, never taken by default, cost 3% of the instructions of a
    // pcf_sun frame (800×600); the transform it saved is dead code for
    // orthographic maps.
    vec3 xo = x + n * (u_shadow.normal_offset * shadow_texel(sc.d));
    sc = shadow_coord(xo);
    if (mode == SHADOW_HARD)
        return shadow_fetch(sc, vec2(0.0)) >= sc.d - shadow_bias(sc.d, cos_theta, 1.0) ? 1.0 : 0.0;
    // Per-pixel rotation of the disk by interleaved gradient noise (Jimenez
    // 2014): on the best-candidate disk it leaves fine grain, where on the
    // legacy spiral it drew a hatching (a turned spiral is a shifted one).
    float angle = TWO_PI * ign(pixel);
    vec2 g = shadow_filter_bias() == SHADOW_BIAS_LEGACY ? vec2(0.0) : shadow_receiver_gradient(sc, xo, n);
    if (mode == SHADOW_PCF)
        return shadow_pcf_filter() == SHADOW_FILTER_GRID ? shadow_pcf_grid(sc, g, u_shadow.pcf_radius, cos_theta)
                                                         : shadow_pcf(sc, g, u_shadow.pcf_radius, cos_theta, angle);
    return shadow_pcss(sc, g, cos_theta, angle);
}
