// probe/probe.comp — micro-kernel shaped like the GI gathers, for
// `rtgi probe`: every invocation evaluates SAMPLES samples, each fetching
// FETCHES texels (0–3: position, normal, flux) from 512² RGBA32F maps (2D,
// or cubes with CUBE) at scattered coordinates around its own, and the
// VPL irradiance arithmetic of shaders/common/vpl.glsl on them. With
// PACKED each sample instead reads one RSM texel (RGBA32UI,
// common/rsm_texel.glsl) and unpacks position, normal, flux and area as the
// RSM gathers do, with their disk falloff. One evaluation = one sample of
// one invocation. With SSBO the samples read
// GpuVpl entries of a storage buffer instead, the same one in every lane,
// as the VPL shading loops do (its surface and flux: two loads,
// common/vpl_record.glsl).
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/vpl.glsl"

#ifdef CUBE
#define RSM_CUBE
#else
#define RSM_2D
#endif
#include "common/rsm_texel.glsl"
#include "common/vpl_record.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
#ifdef CUBE
layout(binding = TEX_PROBE_MAP + 3) uniform usamplerCube t_packed;
layout(binding = TEX_PROBE_MAP) uniform samplerCube t_position;
layout(binding = TEX_PROBE_MAP + 1) uniform samplerCube t_normal;
layout(binding = TEX_PROBE_MAP + 2) uniform samplerCube t_flux;
#else
layout(binding = TEX_PROBE_MAP + 3) uniform usampler2D t_packed;
layout(binding = TEX_PROBE_MAP) uniform sampler2D t_position;
layout(binding = TEX_PROBE_MAP + 1) uniform sampler2D t_normal;
layout(binding = TEX_PROBE_MAP + 2) uniform sampler2D t_flux;
#endif
layout(rgba32f, binding = IMG_OUT) uniform writeonly image2D o_result;
layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    vec2 uv = (vec2(px) + 0.5) / vec2(imageSize(o_result));
    vec3 x = vec3(uv, 0.3), n = vec3(0.0, 0.0, 1.0), e = vec3(0.0);
    // The packed maps' frame (src/probe.c writes them in the unit box).
    RsmTexelFrame f;
    f.box_min = vec3(0.0);
    f.box_step = vec3(1.0 / RSM_POS_MAX);
    f.flux_unit = 1.0;
    f.light = vec3(0.5, 0.5, 1.0);
    f.axis = vec3(0.0, 0.0, -1.0);
    f.ortho = 0.0;
    f.texel_area = 1e-5;
    f.cube = false;
    for (int k = 0; k < SAMPLES; k++) {
        float a = float(k) * 2.39996323, r = 0.3 * sqrt((float(k) + 0.5) / float(SAMPLES));
        vec2 q = uv + r * vec2(cos(a), sin(a));
#ifdef CUBE
        vec3 d = vec3(q * 2.0 - 1.0, 1.0);
#define FETCH(t) textureLod(t, d, 0.0)
#else
#define FETCH(t) textureLod(t, q, 0.0)
#endif
#if defined(PACKED)
        uvec4 t = FETCH(t_packed);
        vec3 xp = rsm_texel_position(f, t), np = rsm_texel_normal(t);
        e += vpl_irradiance_disk(x, n, xp, np, rsm_texel_flux(f, t), rsm_texel_area(f, xp, np) * (1.0 / PI));
#else
#if defined(SSBO)
        // The VPL loops' access: every lane reads the same VPL (a broadcast).
        GpuVpl v = vpls[k];
        vec3 xp = vpl_position(v) + vec3(q * 1e-6, 0.0), np = vpl_shading_normal(v), flux = v.flux.rgb;
#else
#if FETCHES >= 1
        vec3 xp = FETCH(t_position).xyz;
#else
        vec3 xp = vec3(q, 0.0);
#endif
#if FETCHES >= 2
        vec3 np = FETCH(t_normal).xyz;
#else
        vec3 np = vec3(0.0, 0.0, 1.0);
#endif
#if FETCHES >= 3
        vec3 flux = FETCH(t_flux).rgb;
#else
        vec3 flux = vec3(q, 1.0);
#endif
#endif
        e += vpl_irradiance(x, n, xp, np, flux);
#endif
    }
    imageStore(o_result, px, vec4(e, 1.0));
}
