// gi/count_surfaces.comp — how many pixels a per-pixel pass shades hold a
// surface: the pixels min(g·f + f/2, size − 1) of the lattice of step
// f = u_step (1: every pixel; rsm-interp's low-res gather and vct's traced
// lattice: their factor), the same rule those passes use. Background
// pixels return before they gather anything, so the gathers' evaluation
// counts (render --timings: gathered_pixels, gather_evaluations, and the
// rates derived from them) count only these (gi_count_surfaces, src/gi/gi.c).
#include "shared/gpu_types.h"
#include "common/gbuffer.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = SSBO_STATS) buffer CountBlock { uint count; };
layout(location = LOC_COUNT_STEP) uniform int u_step;

// One invocation per 8 lattice points of a row, one atomic add each (the
// dispatch: gi_count_surfaces).
void main()
{
    ivec2 size = gb_size(), n = (size + u_step - 1) / u_step;
    ivec2 lo = ivec2(gl_GlobalInvocationID.x * 8u, gl_GlobalInvocationID.y);
    if (any(greaterThanEqual(lo, n)))
        return;
    uint found = 0u;
    for (int i = 0; i < 8; i++) {
        vec3 x;
        ivec2 g = lo + ivec2(i, 0);
        if (g.x < n.x && gb_position(min(g * u_step + u_step / 2, size - 1), x))
            found++;
    }
    if (found > 0u)
        atomicAdd(count, found);
}
