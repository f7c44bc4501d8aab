// light/vpl_extract.comp — the RSM's lit texels become VPLs in SSBO_VPL (a
// GpuVpl, common/vpl_record.glsl: its ξ ∈ (0,1] a hash of the record and
// the seed light_stage.c leaves in counters[1], where the SLC loop reads it
// too); counters[0] counts them. The RSM is read layer by layer
// (common/rsm_layers.glsl: a 2D RSM is one layer, a cube RSM six).
// u_stride = k: one VPL per k × k block of texels (the RSM drawn k times
// finer than the VPL grid, --vpl-supersample): the block's whole flux, at
// the flux-weighted centroid of the texels on one surface — those within
// 25° of a texel's normal and within a texel's width of its plane. Where a
// block holds one surface (most of them) the VPL is that centroid, the
// same for every seed; where it holds more (edges, corners, a column before
// the floor) one is chosen with probability ∝ its flux (a fixed ξ of the
// block), which keeps the sum unbiased over blocks. A texel-centre grid
// had kept or lost a whole texel's flux wherever a sunlit edge crossed
// it: Sponza's nave read 0.84 of the RSM's bounce at 4096 VPLs, 0.98 at
// 3600 (docs/techniques.md, "Visibility of the bounce"). k = 1: one VPL
// per texel, the papers' grid.
#include "shared/gpu_types.h"
#include "common/rsm_texel.glsl"
#include "common/vpl_record.glsl"
#include "common/rsm_layers.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(location = LOC_VPL_STRIDE) uniform int u_stride; // texels per side of the block one VPL stands for

layout(std430, binding = SSBO_VPL) writeonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) buffer CounterBlock { uint counters[]; };

const int MAX_STRIDE = 4; // light_stage.c's VPL_MAX_SUPERSAMPLE
const float SAME_SURFACE_COS = 0.906; // 25°

float weight(vec3 flux) { return dot(flux, vec3(0.2126, 0.7152, 0.0722)) + 1e-30; }

void main()
{
    ivec3 size = rsm_layers_size();
    int k = clamp(u_stride, 1, MAX_STRIDE);
    ivec3 block = ivec3(gl_GlobalInvocationID);
    ivec3 id = ivec3(block.xy * k, block.z);
    if (id.x >= size.x || id.y >= size.y || id.z >= size.z)
        return;
    RsmTexelFrame frame = rsm_texel_frame();
    uint seed = counters[1];
    if (k == 1) {
        vec3 p, n, flux;
        float area;
        uvec4 t = rsm_layer_texel(id);
        if (!rsm_texel_unpack(frame, t, p, n, flux, area) || max(flux.r, max(flux.g, flux.b)) <= 0.0)
            return;
        uint i = atomicAdd(counters[0], 1u);
        vpls[i] = vpl_make(p, vpl_xi_of(uvec4(floatBitsToUint(p), t.z), seed), t.z, flux, area);
        return;
    }
    // The block's lit texels, and its total flux and area.
    vec3 total = vec3(0.0);
    float total_area = 0.0, total_w = 0.0;
    for (int j = 0; j < k * k; j++) {
        ivec3 at = id + ivec3(j % k, j / k, 0);
        if (at.x >= size.x || at.y >= size.y)
            continue;
        vec3 p, n, flux;
        float area;
        if (!rsm_texel_unpack(frame, rsm_layer_texel(at), p, n, flux, area) || max(flux.r, max(flux.g, flux.b)) <= 0.0)
            continue;
        total += flux;
        total_area += area;
        total_w += weight(flux);
    }
    if (total_w <= 1e-30 * float(k * k + 1))
        return;
    // A texel by ξ ∝ flux: its surface is the VPL's. ξ is the block's own,
    // whatever the seed: the seed draws the VPLs' ξ for culling and
    // subsets (an SLC image averaged over seeds must converge to brute
    // force over one VPL set, test_vpl).
    float xi = float(hash_u32(uint(block.x) ^ hash_u32(uint(block.y) ^ hash_u32(uint(block.z) ^ 0x5bd1e995u)))) /
               4294967296.0 * total_w;
    uvec4 chosen = uvec4(0u);
    vec3 cp = vec3(0.0), cn = vec3(0.0);
    float acc = 0.0, carea = 0.0;
    bool found = false;
    for (int j = 0; j < k * k && !found; j++) {
        ivec3 at = id + ivec3(j % k, j / k, 0);
        if (at.x >= size.x || at.y >= size.y)
            continue;
        uvec4 t = rsm_layer_texel(at);
        vec3 p, n, flux;
        float area;
        if (!rsm_texel_unpack(frame, t, p, n, flux, area) || max(flux.r, max(flux.g, flux.b)) <= 0.0)
            continue;
        acc += weight(flux);
        if (xi < acc || j == k * k - 1) {
            chosen = t;
            cp = p;
            cn = n;
            carea = area;
            found = true;
        }
    }
    if (!found) // rounding left ξ past the last lit texel
        return;
    // The centroid of the texels on the chosen one's surface, by flux.
    float reach = sqrt(max(carea, 0.0)) * 1.5; // a texel's width, and then some: the surface's own relief
    vec3 sum_p = vec3(0.0);
    float sum_w = 0.0;
    for (int j = 0; j < k * k; j++) {
        ivec3 at = id + ivec3(j % k, j / k, 0);
        if (at.x >= size.x || at.y >= size.y)
            continue;
        vec3 p, n, flux;
        float area;
        if (!rsm_texel_unpack(frame, rsm_layer_texel(at), p, n, flux, area) || max(flux.r, max(flux.g, flux.b)) <= 0.0)
            continue;
        if (dot(n, cn) < SAME_SURFACE_COS || abs(dot(p - cp, cn)) > reach)
            continue;
        float w = weight(flux);
        sum_p += w * p;
        sum_w += w;
    }
    vec3 p = sum_p / sum_w;
    uint i = atomicAdd(counters[0], 1u);
    vpls[i] = vpl_make(p, vpl_xi_of(uvec4(floatBitsToUint(p), chosen.z), seed), chosen.z, total, total_area);
}
