// gi/lpv/geometry_fixed.comp — geometry-volume injection by compute (the
// default `--lpv-inject compute`): a surfel per texel (surfel.glsl), runs
// of them per invocation (below), its normal tensor A/s² · n nᵀ added with
// integer atomics in fixed point (LOC_LPV_FIXED_SCALE units per 1) to
// SSBO_LPV_FIXED[6·cell + j], j = xx, yy, zz, xy, xz, yz;
// geometry_resolve.comp writes the two textures.
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"
#include "gi/lpv/surfel.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = SSBO_LPV_FIXED) buffer FixedBlock { int sums[]; };
layout(location = LOC_LPV_CASCADE) uniform int u_cascade;
layout(location = LOC_LPV_SURFEL_AREA) uniform float u_max_area;
layout(location = LOC_LPV_FIXED_SCALE) uniform float u_scale;

// Adds one cell's summed units (xx yy zz, xy xz yz) to its 6 sums (cell
// index `base`; < 0: none), skipping zeros.
void flush(int base, ivec3 d, ivec3 o)
{
    if (base < 0)
        return;
    for (int j = 0; j < 3; j++) {
        if (d[j] != 0)
            atomicAdd(sums[base + j], d[j]);
        if (o[j] != 0)
            atomicAdd(sums[base + 3 + j], o[j]);
    }
}

// One invocation per LPV_GEOMETRY_RUN texels of a row. Each texel is loaded
// once for the run (a texel's right neighbour is the next one's own), and
// the units of texels in one cell are summed in registers and added with
// one set of atomics (each texel's still rounded alone: the same sums bit
// for bit). One invocation per texel with 5 loads and 6 atomics each had
// cost 40 ms for a 512² cube (Cornell, one llvmpipe thread).
void main()
{
    ivec3 size = surfel_size();
    ivec3 q = ivec3(int(gl_GlobalInvocationID.x) * LPV_GEOMETRY_RUN, gl_GlobalInvocationID.yz);
    if (any(greaterThanEqual(q, size)))
        return;
    const ivec3 X = ivec3(1, 0, 0), Y = ivec3(0, 1, 0);
    SurfelFrame f = surfel_frame();
    vec4 cascade = u_lpv.cascade[u_cascade];
    float max_area = u_max_area, scale = u_scale;
    int size_gv = u_lpv.size + 1, end = min(q.x + LPV_GEOMETRY_RUN, size.x), base = -1;
    uvec4 here = surfel_load(q, size);
    vec4 left = surfel_position_of(f, surfel_load(q - X, size)), pos = surfel_position_of(f, here);
    ivec3 d = ivec3(0), o = ivec3(0);
    for (; q.x < end; q.x++) {
        uvec4 next = surfel_load(q + X, size);
        vec4 right = surfel_position_of(f, next);
        vec3 p, n;
        float area, w;
        bool ok = lpv_surfel_of(here, pos, left, right, surfel_position_of(f, surfel_load(q - Y, size)),
                                surfel_position_of(f, surfel_load(q + Y, size)), max_area, p, n, area);
        ivec3 c = lpv_surfel_cell_in(cascade, p, area, w);
        int at = ok && lpv_inside(c, size_gv) ? 6 * (c.x + size_gv * (c.y + size_gv * c.z)) : -1;
        if (at != base) {
            flush(base, d, o);
            base = at;
            d = o = ivec3(0);
        }
        d += ivec3(round(w * vec3(n.x * n.x, n.y * n.y, n.z * n.z) * scale));
        o += ivec3(round(w * vec3(n.x * n.y, n.x * n.z, n.y * n.z) * scale));
        left = pos;
        pos = right;
        here = next;
    }
    flush(base, d, o);
}
