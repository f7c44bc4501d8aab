// gi/vpl/cull.comp — tiled light culling: one work group per 16×16 screen tile
// bounds the tile's G-buffer points (a world-space box: the depth bounds and
// the tile's extent together), then tests every VPL's sphere (centre x_i,
// radius r_i from vpl_params.comp) against it, and drops VPLs whose plane
// has the whole box behind it. Survivors go to the tile's list in
// SSBO_TILES: counts[tiles], then lists of `capacity` indices per tile from
// VPL_TILE_LIST_BASE, each padded with index 0 to a multiple of 4 entries
// (shade.comp reads them four at a time); counts[tiles] (one past the last
// tile) accumulates overflow.
#include "shared/gpu_types.h"
#include "common/gbuffer.glsl"
#include "common/vpl_record.glsl"

layout(local_size_x = VPL_TILE, local_size_y = VPL_TILE) in;

layout(std430, binding = SSBO_VPL) readonly buffer VplBlock { GpuVpl vpls[]; };
layout(std430, binding = SSBO_COUNTERS) readonly buffer CounterBlock { uint counters[]; };
layout(std430, binding = SSBO_VPL_RANGE) readonly buffer RangeBlock { vec2 ranges[]; };
layout(std430, binding = SSBO_TILES) buffer TileBlock { uint tiles[]; };

shared vec3 s_min[VPL_TILE * VPL_TILE];
shared vec3 s_max[VPL_TILE * VPL_TILE];
shared uint s_count;

void main()
{
    uint lid = gl_LocalInvocationIndex;
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    vec3 p;
    bool valid = all(lessThan(px, gb_size())) && gb_position(px, p);
    s_min[lid] = valid ? p : vec3(1e30);
    s_max[lid] = valid ? p : vec3(-1e30);
    if (lid == 0u)
        s_count = 0u;
    barrier();
    for (uint stride = uint(VPL_TILE * VPL_TILE) / 2u; stride > 0u; stride /= 2u) {
        if (lid < stride) {
            s_min[lid] = min(s_min[lid], s_min[lid + stride]);
            s_max[lid] = max(s_max[lid], s_max[lid + stride]);
        }
        barrier();
    }
    vec3 bmin = s_min[0], bmax = s_max[0];
    uint tile = gl_WorkGroupID.y * uint(u_vpl.tiles_x) + gl_WorkGroupID.x;
    uint ntiles = uint(u_vpl.tiles_x * u_vpl.tiles_y);
    uint cap = u_vpl.tile_capacity;
    uint list = VPL_TILE_LIST_BASE(ntiles) + tile * cap;
    if (bmin.x <= bmax.x) { // the tile holds geometry
        uint n = counters[0];
        for (uint i = lid; i < n; i += uint(VPL_TILE * VPL_TILE)) {
            vec3 c = vpl_position(vpls[i]);
            float r = ranges[i].y;
            vec3 q = clamp(c, bmin, bmax);
            if (dot(q - c, q - c) > r * r)
                continue;
            vec3 nv = vpl_normal(vpls[i]);
            vec3 far_corner = mix(bmin, bmax, step(vec3(0.0), nv));
            if (dot(nv, far_corner - c) <= 0.0)
                continue; // the whole tile lies behind the VPL
            uint k = atomicAdd(s_count, 1u);
            if (k < cap)
                tiles[list + k] = i;
        }
    }
    barrier();
    uint c = min(s_count, cap);
    if (lid < ((c + 3u) & ~3u) - c)
        tiles[list + c + lid] = 0u;
    if (lid == 0u) {
        tiles[tile] = c;
        if (s_count > cap)
            atomicAdd(tiles[ntiles], s_count - cap);
    }
}
