// material.glsl — the scene material as set per draw by gpu_scene_draw():
// glTF metallic-roughness (scene.h Material; the BRDF is common/brdf.glsl).
#ifdef MATERIAL_ROW
// Compute passes over the pixels of many materials (frame/vbuffer_*.comp):
// the constants from the row (GpuMaterial) the caller copies into
// material_row; the textures are still bound per material. Such a program
// declares none of the uniforms: gpu_scene_bind_material must not be used
// on it.
GpuMaterial material_row;
#define u_albedo material_row.albedo.rgb
#define u_has_tex int(material_row.albedo.w)
#define u_alpha_cutoff material_row.emission.w
#define u_emission material_row.emission.rgb
#define u_pbr material_row.pbr
#else
layout(location = LOC_MATERIAL_ALBEDO) uniform vec3 u_albedo;
layout(location = LOC_MATERIAL_HAS_TEX) uniform int u_has_tex;
layout(location = LOC_MATERIAL_CUTOFF) uniform float u_alpha_cutoff;
layout(location = LOC_MATERIAL_EMISSION) uniform vec3 u_emission;
layout(location = LOC_MATERIAL_PBR) uniform vec4 u_pbr; // metallic, roughness, specular weight, has MR texture
#endif
layout(binding = TEX_ALBEDO) uniform sampler2D u_albedo_tex;
layout(binding = TEX_MATERIAL_MR) uniform sampler2D u_mr_tex;
#ifdef FLAT_UNIFORMS
// The constants as flat inputs from frame/scene.vert (common/lights.glsl).
flat in vec3 v_albedo;
flat in vec3 v_emission;
flat in vec4 v_pbr;
#define u_albedo v_albedo
#define u_emission v_emission
#define u_pbr v_pbr
#endif
#ifdef MATERIAL_GRADIENTS
// Compute shaders (no derivatives, no discard: gi/vct/voxelize.comp): the
// caller sets the uv's screen-space gradients, and an alpha-masked texel
// sets material_masked instead of discarding.
vec2 material_dx, material_dy;
bool material_masked;
#define MATERIAL_TEXTURE(t, uv) textureGrad(t, uv, material_dx, material_dy)
#define MATERIAL_DISCARD material_masked = true
#else
#define MATERIAL_TEXTURE(t, uv) texture(t, uv)
#define MATERIAL_DISCARD discard
#endif

// Linear base colour; discards alpha-masked texels. Programs compiled with
// OPAQUE_DRAW draw only opaque materials (gpu_scene_draw_split) and hold no
// discard, so their depth test can run before shading. The mask is read
// from the base level, as the path tracer reads it: the mip chain's mean
// alpha crosses the cutoff where the texels' does not (Sponza's leaves, 38%
// opaque, vanished with distance; their shadows too), which put the direct
// light 1% high (issue 49).
vec3 material_albedo(vec2 uv)
{
#ifdef UNTEXTURED
    vec4 t = vec4(1.0); // programs for materials without textures (gpu_scene.h DrawPrograms)
#else
    vec4 t = u_has_tex != 0 ? MATERIAL_TEXTURE(u_albedo_tex, uv) : vec4(1.0);
#ifndef OPAQUE_DRAW
    if (u_alpha_cutoff >= 0.0 && u_has_tex != 0 && textureLod(u_albedo_tex, uv, 0.0).a < u_alpha_cutoff)
        MATERIAL_DISCARD;
#endif
#endif
    return u_albedo * t.rgb;
}

// Metallic (x) and perceptual roughness (y): factors × the texture's B and G.
vec2 material_metal_rough(vec2 uv)
{
    vec2 mr = u_pbr.xy;
#ifndef UNTEXTURED
    if (u_pbr.w != 0.0) {
        vec4 t = MATERIAL_TEXTURE(u_mr_tex, uv);
        mr *= vec2(t.b, t.g);
    }
#endif
    return mr;
}

// Diffuse albedo ρ_d = (1 − metallic)·base (what RSM/VPL flux reflects).
vec3 material_diffuse(vec2 uv)
{
    vec3 base = material_albedo(uv);
    return (1.0 - material_metal_rough(uv).x) * base;
}
