// gi/visibility/ism.glsl — imperfect shadow maps (Ritschel et al. 2008):
// whether a VPL sees a shaded point, from a small paraboloid depth map
// around the VPL's normal (src/gi/visibility/ism.c builds them). Map m is
// an S × S tile of the R32UI atlas at TEX_ISM, at (m mod per_row,
// m / per_row)·S; a texel holds the distance (m, the float's bits) from
// the map's source to the nearest scene point in its direction, ISM_EMPTY
// where none is.
// The paraboloid around normal n (Brabec et al. 2002): a unit direction
// d with local coordinates (x, y, z), z along n, lands at (x, y)/(1 + z)
// in the unit disk; the hemisphere z ≥ 0 fills it.
// Requires shared/gpu_types.h, common/math.glsl (basis) and
// common/packing.glsl (unpack_oct16).
#ifndef ISM_GLSL
#define ISM_GLSL

layout(binding = TEX_ISM) uniform usampler2D ism_atlas;

// What a lookup needs from u_ism, read once per invocation (a uniform
// read inside a loop is a per-lane gather on llvmpipe).
struct IsmFrame {
    int size;
    int row_shift;   // log2(per_row)
    float bias_rel, bias_abs;
    vec2 inv_atlas;  // 1 / the atlas's size in texels
};

IsmFrame ism_frame()
{
    IsmFrame f;
    f.size = u_ism.size;
    f.row_shift = findMSB(u_ism.per_row);
    f.bias_rel = u_ism.bias_rel;
    f.bias_abs = u_ism.bias_abs;
    f.inv_atlas = 1.0 / vec2(textureSize(ism_atlas, 0));
    return f;
}

// Map coordinates in [0, 1)² of direction d (not necessarily unit, length
// len) around unit normal n, and false where d lies behind n's plane.
bool ism_project(vec3 d, float len, vec3 n, out vec2 uv)
{
    vec3 t, b;
    basis(n, t, b);
    vec3 l = vec3(dot(d, t), dot(d, b), dot(d, n)) / len;
    uv = l.xy / (1.0 + max(l.z, 0.0)) * 0.5 + 0.5;
    return l.z >= 0.0;
}

// The texel of map m at map coordinates uv.
ivec2 ism_texel(IsmFrame f, uint m, vec2 uv)
{
    uint per_row_mask = (1u << uint(f.row_shift)) - 1u;
    ivec2 tile = ivec2(int(m & per_row_mask), int(m >> uint(f.row_shift))) * f.size;
    return tile + clamp(ivec2(uv * float(f.size)), ivec2(0), ivec2(f.size - 1));
}

// 1 where map m, made from xs with normal ns, holds nothing nearer than x
// (normal nx) within the bias, else 0. A point behind ns's plane gets
// nothing from the VPL anyway (its cosine is 0): 1. The bias: the nearest
// point in a texel's cone lies up to the cone's width (4 / (S (1 + ρ²))
// radians at radius ρ of the paraboloid) times the tangent of x's
// incidence nearer than x on x's own surface, times ISM_SLOPE for
// pull-push's averages and the splats' planes (splat.comp); then
// bias_rel·d + bias_abs. Measured (rsm, indirect ratio against
// one-bounce; without visibility Cornell 1.125, its floor 1.92, Lambertian
// Sponza 1.51): 1.0: Cornell 0.946, floor 0.90, Sponza 0.81; 2.0: 0.973,
// 1.10, 1.01. With flat splats (at the point's distance) 3.0 had been
// needed on the Cornell box, and let Sponza's upper galleries keep 5-30
// times their bounce (whole 1.16): the term grows with the distance.
const float ISM_SLOPE = 2.0;
const float ISM_MAX_TAN = 4.0;

float ism_visibility(IsmFrame f, uint m, vec3 xs, vec3 ns, vec3 x, vec3 nx)
{
    vec3 d = x - xs;
    float len = max(length(d), 1e-12);
    vec2 uv;
    if (!ism_project(d, len, ns, uv))
        return 1.0;
    ivec2 at = ism_texel(f, m, uv);
    float stored = uintBitsToFloat(textureLod(ism_atlas, (vec2(at) + 0.5) * f.inv_atlas, 0.0).r);
    vec2 c = uv * 2.0 - 1.0;
    float cone = 4.0 / (float(f.size) * (1.0 + dot(c, c)));
    float cos_r = abs(dot(nx, d)) / len, tan_r = min(sqrt(max(1.0 - cos_r * cos_r, 0.0)) / max(cos_r, 1e-6), ISM_MAX_TAN);
    float bias = len * (ISM_SLOPE * cone * tan_r + f.bias_rel) + f.bias_abs;
    return len <= stored + bias ? 1.0 : 0.0;
}

#ifdef ISM_FROM_RSM
// Maps made for blocks of an RSM's texels (rsm gathers): a sample at xp
// takes the map of its block, made from the block's representative texel.
layout(std430, binding = SSBO_ISM_REPS) readonly buffer IsmRepBlock { uvec4 ism_reps[]; };
layout(location = LOC_ISM_MAP_BASE) uniform uint u_ism_map_base;

// The block of the RSM texel that holds world point xp, as a map index:
// the texel as light/rsm.frag drew it (the light's projection, or the cube
// face and its coordinates by GL's face selection), then its block.
struct IsmRsmFrame {
    IsmFrame f;
    uint base;       // the light's first map
    int blocks;      // per side
    float per_texel; // blocks per unit of map coordinate: rsm_size / block_texels
    mat4 view_proj;  // 2D: the light's projection
    vec3 light;      // cube: the light's position
};

IsmRsmFrame ism_rsm_frame()
{
    IsmRsmFrame r;
    r.f = ism_frame();
    r.base = u_ism_map_base;
    r.blocks = u_ism.blocks;
    r.per_texel = float(u_ism.rsm_size) / float(u_ism.block_texels);
    r.view_proj = u_light.shadow_view_proj;
    r.light = u_light.position_type.xyz;
    return r;
}

uint ism_rsm_map(IsmRsmFrame r, vec3 xp)
{
#ifdef RSM_CUBE
    vec3 d = xp - r.light, a = abs(d);
    uint face;
    vec2 sc;
    float ma;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x >= 0.0 ? 0u : 1u;
        sc = vec2(d.x >= 0.0 ? -d.z : d.z, -d.y);
        ma = a.x;
    } else if (a.y >= a.z) {
        face = d.y >= 0.0 ? 2u : 3u;
        sc = vec2(d.x, d.y >= 0.0 ? d.z : -d.z);
        ma = a.y;
    } else {
        face = d.z >= 0.0 ? 4u : 5u;
        sc = vec2(d.z >= 0.0 ? d.x : -d.x, -d.y);
        ma = a.z;
    }
    vec2 st = sc / max(ma, 1e-30) * 0.5 + 0.5;
#else
    const uint face = 0u;
    vec4 c = r.view_proj * vec4(xp, 1.0);
    vec2 st = c.xy / c.w * 0.5 + 0.5;
#endif
    ivec2 blk = clamp(ivec2(st * r.per_texel), ivec2(0), ivec2(r.blocks - 1));
    return r.base + (face * uint(r.blocks) + uint(blk.y)) * uint(r.blocks) + uint(blk.x);
}

// Visibility of x from the RSM sample at xp (its block's map).
float ism_visibility_rsm(IsmRsmFrame r, vec3 xp, vec3 x, vec3 nx)
{
    uint m = ism_rsm_map(r, xp);
    uvec4 rep = ism_reps[m];
    if (rep.x == 0xffffffffu)
        return 1.0; // a block without a lit texel: its samples carry no flux
    return ism_visibility(r.f, m, uintBitsToFloat(rep.xyz), unpack_oct16(rep.w), x, nx);
}
#endif

#endif
