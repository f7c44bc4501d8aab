// gi/rsm/importance.comp — importance sampling of a reflective shadow map by
// flux, for the gather's `importance` weighting. The pyramid of flux
// luminance sums is a power-of-two 2D array (texels past the RSM are 0)
// whose level L ≥ 1 is stored at mip L − 1; level 0, the luminance of each
// RSM texel's flux, is not stored but read from the RSM where it is needed:
//   MODE_BLOCKS  levels 1 and 2 from the RSM, one invocation per 4×4 texels
//                (a pass writing level 0, 1.5M invocations for a 512² cube,
//                and a reduce reading it had cost 10 of the build's 21 ms
//                on llvmpipe, mostly per-invocation overhead)
//   MODE_REDUCE  level L ≥ 3 from level L−1: the sum of each 2×2 block
//   MODE_SAMPLE  the sample list: RSM_LIST_SETS sets of list_set points, each a
//                Hammersley set with its own toroidal shift, warped down the
//                pyramid (face by its total, then column and row of each 2×2
//                block by their sums), which keeps each set stratified in
//                the flux CDF; the chosen texel t becomes a VPL with flux
//                Φ_t / p_t, p_t = lum(Φ_t) / Σ lum.
// Every sum adds a 2×2 block's texels in the order (0,0), (1,0), (0,1),
// (1,1), whichever pass makes it.
// A pixel's gather takes one whole set (chosen by a hash of the pixel), so
// its samples are stratified and neighbours' are independent.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/rsm_texel.glsl"
#include "common/vpl_record.glsl"
#include "common/rsm_layers.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(location = LOC_IMPORTANCE_LEVEL) uniform int u_level; // level written (REDUCE), top level (SAMPLE)

// Level 0 at texel t of a map of rsm texels a side: the luminance of the
// texel's flux, 0 past the map (the fetch is clamped and its value dropped:
// llvmpipe runs both arms of a branch).
float level0(RsmTexelFrame f, ivec3 t, int rsm)
{
    bool inside = t.x < rsm && t.y < rsm;
    vec3 flux = rsm_texel_flux(f, rsm_layer_texel(ivec3(min(t.xy, ivec2(rsm - 1)), t.z)));
    return inside ? luminance(flux) : 0.0;
}

// A 2×2 block's sum, in the one order every level uses.
float block_sum(float w00, float w10, float w01, float w11) { return w00 + w10 + w01 + w11; }

#if defined(MODE_BLOCKS)
layout(r32f, binding = IMG_OUT) uniform writeonly image2DArray o_level1;
layout(r32f, binding = IMG_OUT2) uniform writeonly image2DArray o_level2;
void main()
{
    ivec3 id = ivec3(gl_GlobalInvocationID);
    ivec3 size = imageSize(o_level2);
    if (id.x >= size.x || id.y >= size.y || id.z >= size.z)
        return;
    RsmTexelFrame f = rsm_texel_frame();
    int rsm = rsm_layers_size().x;
    ivec2 o = id.xy * 4;
    float s[4];
    for (int b = 0; b < 4; b++) { // the 2×2 blocks (0,0), (1,0), (0,1), (1,1) of level 1
        ivec2 c = o + 2 * ivec2(b & 1, b >> 1);
        s[b] = block_sum(level0(f, ivec3(c, id.z), rsm), level0(f, ivec3(c + ivec2(1, 0), id.z), rsm),
                         level0(f, ivec3(c + ivec2(0, 1), id.z), rsm), level0(f, ivec3(c + 1, id.z), rsm));
        imageStore(o_level1, ivec3(id.xy * 2 + ivec2(b & 1, b >> 1), id.z), vec4(s[b]));
    }
    imageStore(o_level2, id, vec4(block_sum(s[0], s[1], s[2], s[3])));
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
    int m = u_level - 2; // level u_level − 1 is mip u_level − 2
    float s = block_sum(texelFetch(u_pyramid, ivec3(c, id.z), m).r, texelFetch(u_pyramid, ivec3(c + ivec2(1, 0), id.z), m).r,
                        texelFetch(u_pyramid, ivec3(c + ivec2(0, 1), id.z), m).r, texelFetch(u_pyramid, ivec3(c + 1, id.z), m).r);
    imageStore(o_level, id, vec4(s));
}
#elif defined(MODE_SAMPLE)
layout(binding = TEX_INPUT) uniform sampler2DArray u_pyramid;
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

// One step down: into the right column of the block (w00 w10 / w01 w11)
// or the left by their sums, then the upper or lower texel of it.
void descend(float w00, float w10, float w01, float w11, inout ivec2 p, inout vec2 u)
{
    bool right = pick_second(w00 + w01, w10 + w11, u.x);
    if (right)
        p.x += 1;
    bool up = right ? pick_second(w10, w11, u.y) : pick_second(w00, w01, u.y);
    if (up)
        p.y += 1;
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
        total += texelFetch(u_pyramid, ivec3(0, 0, f), top - 1).r;
    float acc = 0.0, pick = u.x * total;
    int face = layers - 1;
    for (int f = 0; f < layers; f++) {
        float w = texelFetch(u_pyramid, ivec3(0, 0, f), top - 1).r;
        if (pick < acc + w || f == layers - 1) {
            face = f;
            u.x = w > 0.0 ? clamp((pick - acc) / w, 0.0, 0.99999994) : 0.5;
            break;
        }
        acc += w;
    }
    // Down the pyramid: column by the sums of the two columns, row by the two
    // texels of the chosen column; level l ≥ 1 is mip l − 1, level 0 the RSM.
    ivec2 p = ivec2(0);
    for (int l = top - 1; l >= 1; l--) {
        p *= 2;
        int m = l - 1;
        descend(texelFetch(u_pyramid, ivec3(p, face), m).r, texelFetch(u_pyramid, ivec3(p + ivec2(1, 0), face), m).r,
                texelFetch(u_pyramid, ivec3(p + ivec2(0, 1), face), m).r, texelFetch(u_pyramid, ivec3(p + 1, face), m).r,
                p, u);
    }
    p *= 2;
    RsmTexelFrame tf = rsm_texel_frame();
    int rsm = rsm_layers_size().x;
    descend(level0(tf, ivec3(p, face), rsm), level0(tf, ivec3(p + ivec2(1, 0), face), rsm),
            level0(tf, ivec3(p + ivec2(0, 1), face), rsm), level0(tf, ivec3(p + 1, face), rsm), p, u);
    ivec3 t = ivec3(min(p, ivec2(rsm - 1)), face); // past the map only in a dark face: every texel's lum is 0
    float lum = level0(tf, t, rsm);
    vec3 xp, np, flux;
    float area;
    uvec4 texel = rsm_layer_texel(t);
    bool valid = rsm_texel_unpack(tf, texel, xp, np, flux, area);
    // Φ_t / p_t with p_t = lum_t / total; empty texels (p = 0) are never
    // chosen unless the whole map is dark, and then carry nothing.
    vec3 w = lum > 0.0 && valid ? flux * (total / lum) : vec3(0.0);
    samples[i] = vpl_make(xp, 0.0, texel.z, w, area);
}
#endif
