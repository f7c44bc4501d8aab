// material.glsl — the scene material as set per draw by gpu_scene_draw().
layout(location = LOC_MATERIAL_ALBEDO) uniform vec3 u_albedo;
layout(location = LOC_MATERIAL_HAS_TEX) uniform int u_has_tex;
layout(location = LOC_MATERIAL_CUTOFF) uniform float u_alpha_cutoff;
layout(location = LOC_MATERIAL_EMISSION) uniform vec3 u_emission;
layout(binding = TEX_ALBEDO) uniform sampler2D u_albedo_tex;

// Linear albedo; discards alpha-masked texels. Programs compiled with
// OPAQUE_DRAW draw only opaque materials (gpu_scene_draw_split) and hold no
// discard, so their depth test can run before shading.
vec3 material_albedo(vec2 uv)
{
    vec4 t = u_has_tex != 0 ? texture(u_albedo_tex, uv) : vec4(1.0);
#ifndef OPAQUE_DRAW
    if (u_alpha_cutoff >= 0.0 && t.a < u_alpha_cutoff)
        discard;
#endif
    return u_albedo * t.rgb;
}
