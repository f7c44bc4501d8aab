// test/brdf.comp — evaluates common/brdf.glsl and common/lights.glsl's
// polygon_irradiance on inputs from tests/test_brdf.c, which compares them
// with src/core/brdf.c and with analytic irradiance.
// Case i reads 6 vec4 from `cases` and writes one vec4 to `results`:
//   mode 0 (BRDF): n, v, l, (ρ_d rgb, roughness), (F0 rgb, –), – → (f rgb, –)
//   mode 1 (polygon): x, n, p0, p1, p2, p3 → (E/L, –, –, –)
//   mode 2 (diffuse irradiance weight): (F0 rgb, n·v) → (w rgb, –)
//   mode 3 (specular albedo): (F0 rgb, n·v), (roughness, –, –, –) → (albedo rgb, –)
#include "shared/gpu_types.h"
#include "common/math.glsl"
#include "common/brdf.glsl"
#include "common/lights.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = SSBO_PATTERN) readonly buffer Cases { vec4 cases[]; };
layout(std430, binding = SSBO_SAMPLES) writeonly buffer Results { vec4 results[]; };
layout(location = 10) uniform int u_mode;
layout(location = 11) uniform int u_count;

void main()
{
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_count)
        return;
    int b = 6 * i;
    if (u_mode == 0) {
        vec4 d = cases[b + 3], f = cases[b + 4];
        results[i] = vec4(brdf_eval(d.rgb, f.rgb, d.a, cases[b].xyz, cases[b + 1].xyz, cases[b + 2].xyz), 0.0);
    } else if (u_mode == 3) {
        results[i] = vec4(brdf_specular_albedo(cases[b].rgb, cases[b + 1].x, cases[b].a), 0.0);
    } else if (u_mode == 2) {
        results[i] = vec4(brdf_diffuse_irradiance_weight(cases[b].rgb, cases[b].a), 0.0);
    } else {
        vec3 p[4] = vec3[4](cases[b + 2].xyz, cases[b + 3].xyz, cases[b + 4].xyz, cases[b + 5].xyz);
        results[i] = vec4(polygon_irradiance(cases[b].xyz, cases[b + 1].xyz, p), 0.0, 0.0, 0.0);
    }
}
