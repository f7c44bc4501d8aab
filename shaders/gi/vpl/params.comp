// gi/vpl/params.comp — per-VPL culling parameters (SSBO_VPL_RANGE: α, r).
// Stochastic light culling (Tokuyoshi & Harada 2016): α_i = 2π·e_max /
// (E·max I_i), with max I_i = max(Φ)/π for a diffuse VPL, and the culling
// range r_i = 1/√(α_i·ξ_i) for the VPL's fixed random ξ_i (disk VPLs:
// √(1/(α_i·ξ_i) − r_i²), see falloff.glsl). MODE_CLAMPED: the
// fixed range R for every VPL and α = 0.
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "gi/vpl/falloff.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) readonly buffer CounterBlock { uint counters[]; };
layout(std430, binding = SSBO_VPL_RANGE) writeonly buffer RangeBlock { vec2 ranges[]; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= counters[0])
        return;
#ifdef MODE_SLC
    float alpha = vpl_slc_alpha(vpl_slc_num(), vpls[i]);
    // A disk VPL is kept while its falloff 1/(d² + r²) exceeds α·ξ, i.e.
    // within √(1/(α ξ) − r²): then E[kept · max(α, falloff)] = falloff.
    float r2 = vpl_r2(vpl_falloff_params(), vpls[i]), xi = vpl_xi(vpls[i]);
    ranges[i] = vec2(alpha, r2 > 0.0 ? sqrt(max(1.0 / (alpha * xi) - r2, 0.0)) : inversesqrt(alpha * xi));
#else
    ranges[i] = vec2(0.0, u_vpl.range);
#endif
}
