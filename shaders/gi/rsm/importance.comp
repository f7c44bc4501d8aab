// gi/rsm/importance.comp — importance sampling of a reflective shadow map by
// flux, for the gather's `importance` weighting:
//   MODE_LEVEL0  pyramid level 0: luminance of each RSM texel's flux (the
//                pyramid is a power-of-two 2D array, texels past the RSM are 0)
//   MODE_REDUCE  level L from level L−1: the sum of each 2×2 block
//   MODE_SAMPLE  the sample list: RSM_LIST_SETS sets of list_set points, each a
//                Hammersley set with its own toroidal shift, warped down the
//                pyramid (face by its total, then column and row of each 2×2
//                block by their sums), which keeps each set stratified in
//                the flux CDF; the chosen texel t becomes a VPL with flux
//                Φ_t / p_t, p_t = lum(Φ_t) / Σ lum.
// A pixel's gather takes one whole set (chosen by a hash of the pixel), so
// its samples are stratified and neighbours' are independent.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/rsm_texel.glsl"
#include "common/vpl_record.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(location = LOC_IMPORTANCE_LEVEL) uniform int u_level; // level written (REDUCE), top level (SAMPLE)

#if defined(MODE_LEVEL0)
layout(binding = TEX_RSM) uniform usampler2DArray r_texel;
layout(r32f, binding = IMG_OUT) uniform writeonly image2DArray o_level;
void main()
{
    ivec3 id = ivec3(gl_GlobalInvocationID);
    ivec3 size = imageSize(o_level);
    if (id.x >= size.x || id.y >= size.y || id.z >= size.z)
        return;
    ivec3 rsm = textureSize(r_texel, 0);
    float lum = 0.0;
    if (id.x < rsm.x && id.y < rsm.y) {
        vec3 f = rsm_texel_flux(rsm_texel_frame(), texelFetch(r_texel, id, 0));
        lum = dot(f, vec3(0.2126, 0.7152, 0.0722));
    }
    imageStore(o_level, id, vec4(lum));
}
#elif defined(MODE_REDUCE)
layout(binding = TEX_INPUT) uniform sampler2DArray u_pyramid;
layout(r32f, binding = IMG_OUT) uniform writeonly image2DArray o_level;
void main()
{
    ivec3 id = ivec3(gl_GlobalInvocationID);
    ivec3 size = imageSize(o_level);
    if (id.x >= size.x || id.y >= size.y || id.z >= size.z)
        return;
    ivec2 c = id.xy * 2;
    int l = u_level - 1;
    float s = texelFetch(u_pyramid, ivec3(c, id.z), l).r + texelFetch(u_pyramid, ivec3(c + ivec2(1, 0), id.z), l).r +
              texelFetch(u_pyramid, ivec3(c + ivec2(0, 1), id.z), l).r + texelFetch(u_pyramid, ivec3(c + 1, id.z), l).r;
    imageStore(o_level, id, vec4(s));
}
#elif defined(MODE_SAMPLE)
layout(binding = TEX_INPUT) uniform sampler2DArray u_pyramid;
layout(binding = TEX_RSM) uniform usampler2DArray r_texel;
layout(std430, binding = SSBO_SAMPLES) writeonly buffer SampleBlock { GpuVpl samples[]; };

float radical_inverse2(uint i)
{
    return float(bitfieldReverse(i)) * 2.3283064365386963e-10;
}

// Picks between a (weight wa) and b (weight wb) with u, rescaling u into [0,1).
bool pick_second(float wa, float wb, inout float u)
{
    float t = wa + wb;
    float pa = t > 0.0 ? wa / t : 0.5;
    if (u < pa) {
        u = u / max(pa, 1e-30);
        return false;
    }
    u = (u - pa) / max(1.0 - pa, 1e-30);
    return true;
}

void main()
{
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    uint n = uint(u_gi.list_size);
    if (i >= n)
        return;
    uint set_size = uint(u_gi.list_set), set = i / set_size, j = i % set_size;
    vec2 shift = vec2(hash_u32(set * 2u + 0x68bc21ebu), hash_u32(set * 2u + 0x02e5be93u)) * 2.3283064365386963e-10;
    vec2 u = fract(vec2((float(j) + 0.5) / float(set_size), radical_inverse2(j)) + shift);
    u = clamp(u, vec2(0.0), vec2(0.99999994));
    int top = u_level;
    int layers = textureSize(u_pyramid, 0).z;
    // The face, by its total.
    float total = 0.0;
    for (int f = 0; f < layers; f++)
        total += texelFetch(u_pyramid, ivec3(0, 0, f), top).r;
    float acc = 0.0, pick = u.x * total;
    int face = layers - 1;
    for (int f = 0; f < layers; f++) {
        float w = texelFetch(u_pyramid, ivec3(0, 0, f), top).r;
        if (pick < acc + w || f == layers - 1) {
            face = f;
            u.x = w > 0.0 ? clamp((pick - acc) / w, 0.0, 0.99999994) : 0.5;
            break;
        }
        acc += w;
    }
    // Down the pyramid: column by the sums of the two columns, row by the two
    // texels of the chosen column.
    ivec2 p = ivec2(0);
    for (int l = top - 1; l >= 0; l--) {
        p *= 2;
        float w00 = texelFetch(u_pyramid, ivec3(p, face), l).r;
        float w10 = texelFetch(u_pyramid, ivec3(p + ivec2(1, 0), face), l).r;
        float w01 = texelFetch(u_pyramid, ivec3(p + ivec2(0, 1), face), l).r;
        float w11 = texelFetch(u_pyramid, ivec3(p + ivec2(1, 1), face), l).r;
        bool right = pick_second(w00 + w01, w10 + w11, u.x);
        if (right)
            p.x += 1;
        bool up = right ? pick_second(w10, w11, u.y) : pick_second(w00, w01, u.y);
        if (up)
            p.y += 1;
    }
    ivec3 t = ivec3(p, face);
    float lum = texelFetch(u_pyramid, t, 0).r;
    vec3 xp, np, flux;
    float area;
    uvec4 texel = texelFetch(r_texel, t, 0);
    bool valid = rsm_texel_unpack(rsm_texel_frame(), texel, xp, np, flux, area);
    // Φ_t / p_t with p_t = lum_t / total; empty texels (p = 0) are never
    // chosen unless the whole map is dark, and then carry nothing.
    vec3 w = lum > 0.0 && valid ? flux * (total / lum) : vec3(0.0);
    samples[i] = vpl_make(xp, 0.0, texel.z, w, area);
}
#endif
