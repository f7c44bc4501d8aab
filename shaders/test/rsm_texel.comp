// test/rsm_texel.comp — packs each GpuVpl's position, normal and flux into
// an RSM texel in the frame of the bound light (common/rsm_texel.glsl) and
// unpacks it again in place (tests/test_layout.c): normal.w = 1 where the
// texel reads as valid, flux.w = the texel's area. An entry with
// position_xi.w < 0 is read as an empty (cleared) texel instead.
#include "shared/gpu_types.h"
#include "common/rsm_texel.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = SSBO_VPL) buffer VplBlock { GpuVpl vpls[]; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(vpls.length()))
        return;
    RsmTexelFrame f = rsm_texel_frame();
    uvec4 t = vpls[i].position_xi.w < 0.0 ? uvec4(0u)
                                          : rsm_texel_pack(f, vpls[i].position_xi.xyz, vpls[i].normal.xyz,
                                                           vpls[i].flux.rgb);
    vec3 p, n, flux;
    float area;
    bool valid = rsm_texel_unpack(f, t, p, n, flux, area);
    vpls[i].position_xi.xyz = p;
    vpls[i].normal = vec4(n, valid ? 1.0 : 0.0);
    vpls[i].flux = vec4(flux, area);
}
