// gi/vpl/params.comp — per-VPL culling parameters (SSBO_VPL_RANGE: α, r).
// Stochastic light culling (Tokuyoshi & Harada 2016): α_i = 2π·e_max /
// (E·max I_i), with max I_i = max(Φ)/π for a diffuse VPL, and the culling
// range r_i = 1/√(α_i·ξ_i) for the VPL's fixed random ξ_i. MODE_CLAMPED: the
// fixed range R for every VPL and α = 0.
#include "shared/gpu_types.h"
#include "common/math.glsl"

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
    vec3 phi = vpls[i].flux.rgb;
    float i_max = max(phi.r, max(phi.g, phi.b)) / PI;
    float alpha = TWO_PI * u_vpl.slc_emax / (u_vpl.slc_exposure * max(i_max, 1e-30));
    ranges[i] = vec2(alpha, inversesqrt(alpha * vpls[i].position_xi.w));
#else
    ranges[i] = vec2(0.0, u_vpl.clamp_range);
#endif
}
