// gbuffer.glsl — the G-buffer's layout, in one place: frame/gbuffer.frag
// packs it, every pass that reads it reads it through these functions
// (targets.c makes the two RGBA32UI targets). Per pixel:
//   surface  (TEX_GB_SURFACE) a surfel (common/surfel.glsl): the world
//            position (float bits, exact) and the shading normal turned
//            toward the camera (octahedral, 15 bits per coordinate); not
//            valid where no surface was drawn (the clear value, 0).
//   material (TEX_GB_MATERIAL) the glTF parameters (scene.h Material):
//            x: base colour r, g; y: base colour b, perceptual roughness;
//            w: metallic, dielectric specular weight (all unorm16); z: the
//            emitted radiance as RGB9E5 (a shared exponent and 9-bit
//            mantissas, EXT_texture_shared_exponent's encoding: within
//            0.2% of the largest channel, saturating at 65408 where half
//            floats overflowed to infinity at 65504). ρ_d and F0 follow
//            from them by brdf_surface, the same function every renderer
//            uses (src/core/brdf.c).
// 32 bytes per pixel, two render targets: five targets of 48 bytes
// (RGBA32F position, four RGBA16F) cost Sponza's G-buffer pass a quarter
// of its time on llvmpipe and every pass that read them a fetch per target.
// Passes that shade the de-interleaved copies (gi/interleave.comp) bind
// those at TEX_GB_SURFACE instead. Needs shared/gpu_types.h; the material
// functions need common/brdf.glsl (define GBUFFER_MATERIAL before the
// include to get them).
#ifndef GBUFFER_GLSL
#define GBUFFER_GLSL

#include "common/math.glsl"
#include "common/surfel.glsl"

uvec4 gb_material_pack(vec3 base, float metallic, float roughness, float specular, vec3 emission)
{
    return uvec4(packUnorm2x16(base.rg), packUnorm2x16(vec2(base.b, roughness)), pack_rgb9e5(emission),
                 packUnorm2x16(vec2(metallic, specular)));
}

#ifndef GBUFFER_WRITER
layout(binding = TEX_GB_SURFACE) uniform usampler2D g_surface;

// World position and unit normal of pixel px; false where no surface was
// drawn (position and normal are then meaningless).
bool gb_surface(ivec2 px, out vec3 position, out vec3 normal)
{
    uvec4 s = FETCH_NEAREST(g_surface, px);
    position = surfel_unpack_position(s);
    normal = surfel_unpack_normal(s);
    return surfel_valid(s);
}

// The same without the normal's decoding, for passes that test positions.
bool gb_position(ivec2 px, out vec3 position)
{
    uvec4 s = FETCH_NEAREST(g_surface, px);
    position = surfel_unpack_position(s);
    return surfel_valid(s);
}

ivec2 gb_size() { return textureSize(g_surface, 0); }

#ifdef GBUFFER_MATERIAL
layout(binding = TEX_GB_MATERIAL) uniform usampler2D g_material;

struct GbMaterial {
    vec3 diffuse;    // ρ_d = (1 − metallic)·base
    vec3 f0;         // Schlick's F0
    float roughness; // perceptual (α = roughness², brdf_alpha)
    vec3 emission;   // emitted radiance, W/(m²·sr)
};

GbMaterial gb_material(ivec2 px)
{
    uvec4 m = FETCH_NEAREST(g_material, px);
    vec2 rg = unpackUnorm2x16(m.x), b_rough = unpackUnorm2x16(m.y);
    vec2 metal_spec = unpackUnorm2x16(m.w);
    GbMaterial g;
    brdf_surface(vec3(rg, b_rough.x), metal_spec.x, metal_spec.y, g.diffuse, g.f0);
    g.roughness = b_rough.y;
    g.emission = unpack_rgb9e5(m.z);
    return g;
}
#endif
#endif

#endif
