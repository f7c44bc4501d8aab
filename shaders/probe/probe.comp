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
layout(r32f, binding = IMG_OUT) uniform writeonly image2DArray o_result; // a layer per dispatch layer
layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };

// One sample's data as read (the fetch half of a step).
struct Fetched {
    vec2 q;
    uvec4 t;         // PACKED: the RSM texel
    vec3 xp, np, flux;
};

Fetched probe_fetch(int k, vec2 uv)
{
    Fetched s;
    float a = float(k) * 2.39996323, r = 0.3 * sqrt((float(k) + 0.5) / float(SAMPLES));
    s.q = uv + r * vec2(cos(a), sin(a));
    vec2 q = s.q;
    s.t = uvec4(0u);
    s.xp = vec3(q, 0.0);
    s.np = vec3(0.0, 0.0, 1.0);
    s.flux = vec3(q, 1.0);
#ifdef CUBE
    vec3 d = vec3(q * 2.0 - 1.0, 1.0);
#define FETCH(t) textureLod(t, d, 0.0)
#else
#define FETCH(t) textureLod(t, q, 0.0)
#endif
#if defined(PACKED)
    s.t = FETCH(t_packed);
#elif defined(SSBO)
    // The VPL loops' access: every lane reads the same VPL (a broadcast).
    s.xp = vpl_position(vpls[k]) + vec3(q * 1e-6, 0.0);
    s.np = vpl_shading_normal(vpls[k]);
    s.flux = vpls[k].flux.rgb;
#else
#if FETCHES >= 1
    s.xp = FETCH(t_position).xyz;
#endif
#if FETCHES >= 2
    s.np = FETCH(t_normal).xyz;
#endif
#if FETCHES >= 3
    s.flux = FETCH(t_flux).rgb;
#endif
#endif
    return s;
}

// The evaluation half: the VPL irradiance arithmetic on a fetched sample.
vec3 probe_eval(Fetched s, vec3 x, vec3 n, RsmTexelFrame f)
{
#if defined(PACKED)
    return rsm_texel_irradiance_at(f, s.t, x, n, 1.0 / PI);
#else
    return vpl_irradiance(x, n, s.xp, s.np, s.flux);
#endif
}

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    int layer = int(gl_GlobalInvocationID.z);
    // Every layer (src/gpu/probe.c grows the dispatch by layers until it lasts
    // long enough to time) reads in layer 0's pattern, shifted across the map.
    vec2 uv = fract((vec2(px) + 0.5) / float(GRID) + float(layer) * vec2(0.6180340, 0.3819660));
    vec3 x = vec3(uv, 0.3), n = vec3(0.0, 0.0, 1.0), e = vec3(0.0);
    // The packed maps' frame (src/gpu/probe.c writes them in the unit box).
    RsmTexelFrame f;
    f.box_min = vec3(0.0);
    f.box_step = vec3(1.0 / RSM_POS_MAX);
    f.flux_unit = 1.0;
    f.light = vec3(0.5, 0.5, 1.0);
    f.axis = vec3(0.0, 0.0, -1.0);
    f.ortho = 0.0;
    f.texel_area = 1e-5;
    f.cube = false;
    // Two samples a step, both fetched before either is evaluated, as the
    // RSM gathers do (gi/rsm/sampling.glsl): the reads of the two overlap.
#if SAMPLES % 2 != 0
#error "probe.comp takes samples in pairs: SAMPLES must be even"
#endif
    for (int k = 0; k < SAMPLES; k += 2) {
        Fetched a = probe_fetch(k, uv), b = probe_fetch(k + 1, uv);
        e += probe_eval(a, x, n, f);
        e += probe_eval(b, x, n, f);
    }
    imageStore(o_result, ivec3(px, layer), vec4(e.x + e.y + e.z));
}
