// rsm_texel.glsl — one reflective-shadow-map texel in one RGBA32UI texel
// (16 bytes: one fetch per gather sample, issue 11), the light's frame it is
// read in, and the surface area a texel stands for.
//   x, y  position: 21 bits per axis, fixed point in the light's box
//         (GpuLight.rsm_box_min/step: the scene bounds; a quantum is 1/2²¹
//         of the box, < 1e-6 of the scene), y's bit 31 marks a surface
//   z     lit side's normal: octahedral map (Cigolle et al. 2014), 16 bits
//         per coordinate (error < 5e-5 rad)
//   w     reflected flux Φ / rsm_box_min.w as RGB9E5 (common/packing.glsl):
//         every channel within 2⁻⁹ of the largest
// The area is not stored: it follows from the position, the normal and the
// light, as light/rsm.frag would compute it — A_texel = a·h³/max(n·(−d),
// 0.05·|d|) with d the light-to-surface vector, h its length along the face
// axis (the cube face's major axis, the spot's axis) and a the texel area on
// the projection plane at distance 1; a directional light takes d = its unit
// direction, so A_texel = A/max(n·l, 0.05).
// Define RSM_CUBE (point, quad) or RSM_2D (spot, directional) where the
// program only reads one kind; otherwise rsm_texel_frame's `cube` decides.
#ifndef RSM_TEXEL_GLSL
#define RSM_TEXEL_GLSL

#include "common/math.glsl"
#include "common/packing.glsl"
#include "common/vpl.glsl"

const float RSM_POS_MAX = 2097151.0; // 2²¹ − 1

// What unpacking needs from the light (read once, outside sample loops).
struct RsmTexelFrame {
    vec3 box_min, box_step; // position quantum per axis (m)
    float flux_unit;        // W per packed unit
    vec3 light;             // the light's position (spot, cube); 0 for directional
    vec3 axis;              // unit direction of the light (spot axis, sun's direction)
    float ortho;            // 1 for a directional light, else 0
    float texel_area;       // a: texel area on the projection plane (ortho: A, m²)
    bool cube;
};

RsmTexelFrame rsm_texel_frame()
{
    RsmTexelFrame f;
    f.box_min = u_light.rsm_box_min.xyz;
    f.box_step = u_light.rsm_box_step.xyz;
    f.flux_unit = u_light.rsm_box_min.w;
    f.ortho = int(u_light.position_type.w) == LIGHT_DIRECTIONAL ? 1.0 : 0.0;
    f.light = u_light.position_type.xyz * (1.0 - f.ortho);
    f.axis = u_light.direction_width.xyz;
    f.texel_area = u_light.shadow_info.y * u_light.shadow_info.y;
    f.cube = u_light.shadow_info.w > 0.5;
    return f;
}

// ---- The texel -------------------------------------------------------------

uvec4 rsm_texel_pack(RsmTexelFrame f, vec3 position, vec3 normal, vec3 flux)
{
    uvec3 q = uvec3(clamp(round((position - f.box_min) / f.box_step), vec3(0.0), vec3(RSM_POS_MAX)));
    return uvec4(q.x | (q.y << 21), (q.y >> 11) | (q.z << 10) | 0x80000000u, pack_oct16(normal),
                 pack_rgb9e5(flux / f.flux_unit));
}

bool rsm_texel_valid(uvec4 t) { return (t.y & 0x80000000u) != 0u; }

vec3 rsm_texel_position(RsmTexelFrame f, uvec4 t)
{
    uvec3 q = uvec3(t.x, (t.x >> 21) | (t.y << 11), t.y >> 10) & 0x1fffffu;
    return f.box_min + vec3(q) * f.box_step;
}

vec3 rsm_texel_normal(uvec4 t) { return unpack_oct16(t.z); }

vec3 rsm_texel_flux(RsmTexelFrame f, uvec4 t) { return unpack_rgb9e5(t.w) * f.flux_unit; }

// The surface area texel (p, n) stands for (see the top), as a fraction:
// a·h³ over its denominator, so that rsm_texel_irradiance_at (below) can
// fold the denominator into its own division rather than pay for two.
vec2 rsm_texel_area_fraction(RsmTexelFrame f, vec3 p, vec3 n)
{
    vec3 d = mix(p - f.light, f.axis, f.ortho), a = abs(d);
#if defined(RSM_CUBE)
    float h = max(a.x, max(a.y, a.z));
#elif defined(RSM_2D)
    float h = abs(dot(d, f.axis));
#else
    float h = f.cube ? max(a.x, max(a.y, a.z)) : abs(dot(d, f.axis));
#endif
    return vec2(f.texel_area * h * h * h, max(max(-dot(n, d), 0.05 * length(d)), 1e-30));
}

float rsm_texel_area(RsmTexelFrame f, vec3 p, vec3 n)
{
    vec2 a = rsm_texel_area_fraction(f, p, n);
    return a.x / a.y;
}

// Irradiance at x (normal n) from texel t: vpl_irradiance_disk with the
// disk's r² = area·r2_per_area, the area's denominator folded into the
// irradiance's own division (vpl_irradiance_disk_fraction). rsm 256², one
// thread, medians of 5 alternated runs: gather 242 -> 229 ms against two
// divisions; images equal to rounding (relMSE 5e-17). An empty texel
// unpacks to flux 0 and a finite area: it adds 0.
vec3 rsm_texel_irradiance_at(RsmTexelFrame f, uvec4 t, vec3 x, vec3 n, float r2_per_area)
{
    vec3 xp = rsm_texel_position(f, t), np = rsm_texel_normal(t);
    vec2 area = rsm_texel_area_fraction(f, xp, np);
    return vpl_irradiance_disk_fraction(x, n, xp, np, rsm_texel_flux(f, t), area.x * r2_per_area, area.y);
}

// Everything at once; false where the texel holds no surface (then flux and
// area are 0).
bool rsm_texel_unpack(RsmTexelFrame f, uvec4 t, out vec3 p, out vec3 n, out vec3 flux, out float area)
{
    p = rsm_texel_position(f, t);
    n = rsm_texel_normal(t);
    flux = rsm_texel_flux(f, t);
    bool valid = rsm_texel_valid(t);
    area = valid ? rsm_texel_area(f, p, n) : 0.0;
    return valid;
}

#endif
