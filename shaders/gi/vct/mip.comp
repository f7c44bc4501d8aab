// gi/vct/mip.comp — one level of the isotropic radiance chain: each voxel
// the mean of the 2×2×2 block below it (premultiplied radiance and
// opacity, as the cones read them), what glGenerateMipmap's box filter
// computes, as a dispatch of our own: on an NVIDIA H100 the driver's 3D
// mip generation took 21.9 ms for a chain this pass builds in a few
// dispatches (issue 46). The clip levels stacked along z halve with the
// volume, so a block never straddles two of them. A source side of 1
// (the last levels of a small volume) is read clamped: its one texel.
// Run by gl_texture3d_build_mips (src/gl/gl_resources.h): level L − 1 on
// image unit 0, level L on unit 1, 4³ invocations a group.

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = 0, rgba16f) readonly uniform image3D u_src;
layout(binding = 1, rgba16f) writeonly uniform image3D u_dst;

void main()
{
    ivec3 o = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(o, imageSize(u_dst))))
        return;
    ivec3 last = imageSize(u_src) - 1;
    vec4 sum = vec4(0.0);
    for (int c = 0; c < 8; c++)
        sum += imageLoad(u_src, min(2 * o + ivec3(c & 1, (c >> 1) & 1, c >> 2), last));
    imageStore(u_dst, o, sum * 0.125);
}
