// gi/vct/voxelize.frag — the raster voxelization's fragment: the voxels of
// its column that its triangle touches (gi/vct/voxelize.glsl, vct_column).
// Alpha-masked texels are skipped (material_albedo discards them).
#include "shared/gpu_types.h"
#define VCT_FRAGMENT
#include "common/material.glsl"
#include "gi/vct/voxelize.glsl"

layout(location = LOC_VCT_LEVEL) uniform int u_level; // clipmap level drawn: its slab of the stack

in vec2 g_uv;
in vec3 g_normal;
flat in vec3 g_t0;
flat in vec3 g_t1;
flat in vec3 g_t2;
flat in vec4 g_bounds;
flat in int g_axis;

void main()
{
    vec2 f = gl_FragCoord.xy;
    if (u_vct.conservative != 0 && (f.x < g_bounds.x || f.y < g_bounds.y || f.x > g_bounds.z || f.y > g_bounds.w))
        return;
    VctTri t = VctTri(g_t0, g_t1, g_t2, g_axis);
    VctSat sat = vct_sat_setup(t);
    ivec2 px = ivec2(floor(f));
    if (u_vct.conservative != 0 && !vct_column_touched(sat, px))
        return; // the enlarged triangle's corners, or a column it only nears (VCT_COVER_MARGIN)
    vec3 albedo = clamp(material_diffuse(g_uv), 0.0, 1.0); // ρ_d: voxels reflect diffusely
    vct_column(t, sat, px, u_level, albedo, vct_canonical_normal(g_normal));
}
