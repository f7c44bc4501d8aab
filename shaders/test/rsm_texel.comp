// test/rsm_texel.comp — packs each GpuVpl's position, normal (normal_xi.xyz)
// and flux into an RSM texel in the frame of the bound light
// (common/rsm_texel.glsl) and unpacks it again in place, as light/vpl_extract.comp
// makes a VPL of it (tests/test_layout.c): normal_xi.w = 1 where the texel
// reads as valid, flux.w = the texel's area. An entry with normal_xi.w < 0
// is read as an empty (cleared) texel instead.
#include "shared/gpu_types.h"
#include "common/rsm_texel.glsl"
#include "common/vpl_record.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = SSBO_VPL) buffer VplBlock { GpuVpl vpls[]; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(vpls.length()))
        return;
    RsmTexelFrame f = rsm_texel_frame();
    uvec4 t = vpl_xi(vpls[i]) < 0.0 ? uvec4(0u)
                                    : rsm_texel_pack(f, vpl_position(vpls[i]), vpl_normal(vpls[i]), vpls[i].flux.rgb);
    vec3 p, n, flux;
    float area;
    bool valid = rsm_texel_unpack(f, t, p, n, flux, area);
    GpuVpl v = vpl_make(p, valid ? 1.0 : 0.0, t.z, flux, area);
    // The record's two normals must agree (the shading loops read the packed one).
    if (vpl_shading_normal(v) != n || vpl_normal(v) != n)
        v.normal_xi.w = 2.0;
    vpls[i] = v;
}
