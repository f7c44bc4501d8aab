// gi/vct/aniso.comp — one level of one of the six directional volumes
// (Crassin et al. 2011, §4.2 "anisotropic voxels"): each voxel holds what a
// ray travelling along the axis direction sees through the 2×2×2 block
// below it: the two children along the axis composited front to back
// (c = c_front + (1 − α_front)·c_back, likewise α), the four pairs
// averaged. The first level reads the isotropic level 0. Reads outside the
// source are transparent (image loads out of bounds return 0).
#include "shared/gpu_types.h"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = IMG_VCT_SRC, rgba16f) readonly uniform image3D u_src;
layout(binding = IMG_VCT_DST, rgba16f) writeonly uniform image3D u_dst;
layout(location = LOC_VCT_AXIS) uniform int u_axis; // 0..5: +x −x +y −y +z −z

void main()
{
    ivec3 o = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(o, imageSize(u_dst))))
        return;
    int ax = u_axis / 2;
    bool negative = (u_axis & 1) == 1;
    ivec3 step = ivec3(ax == 0, ax == 1, ax == 2);
    ivec3 u = ivec3(ax == 1 || ax == 2, ax == 0, 0); // the two axes across
    ivec3 w = ivec3(0, ax == 2, ax == 0 || ax == 1);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            ivec3 c0 = 2 * o + u * i + w * j, c1 = c0 + step;
            vec4 f = imageLoad(u_src, negative ? c1 : c0), b = imageLoad(u_src, negative ? c0 : c1);
            sum += f + (1.0 - f.a) * b;
        }
    imageStore(u_dst, o, sum * 0.25);
}
