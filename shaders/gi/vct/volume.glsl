// gi/vct/volume.glsl — where the clipmap's voxels are: level k = v.z / N of
// the stacked volume (one level: the volume over the scene bounds).
// VCT_CLIP_LEVELS, the level count, is compiled into every VCT program
// (src/gi/vct/vct.c): loops over the levels unroll with constant indices,
// and with one level the level lookups fold away (llvmpipe reads a uniform
// indexed by a loop counter lane by lane).
#ifndef VCT_CLIP_LEVELS
#error "gi/vct/volume.glsl needs VCT_CLIP_LEVELS (src/gi/vct/vct.c defines it)"
#endif
// Passes over the voxels run either over every stacked voxel (4×4×4
// groups) or, with OPAQUE_LIST, over the opaque-voxel list the
// voxelization appends (gi/vct/voxelize.glsl; 64 entries a group,
// dispatched indirectly from gi/vct/args.comp): vct_voxel_here.

// A stacked voxel as one list entry, and back (N ≤ 256: x, y in 8 bits,
// z = level·N + z' in 16).
uint vct_voxel_code(ivec3 v) { return uint(v.x) | (uint(v.y) << 8) | (uint(v.z) << 16); }
ivec3 vct_voxel_of(uint code) { return ivec3(code & 0xffu, (code >> 8) & 0xffu, code >> 16); }

#ifdef OPAQUE_LIST
layout(std430, binding = SSBO_VCT_OPAQUE) readonly buffer Opaque { uint opaque_count; uint opaque_pad[3]; uint opaque[]; };
#endif

// The voxel this invocation handles; false past the list or the volume
// (compute shaders; the raster voxelization's fragments define
// VCT_FRAGMENT).
#ifndef VCT_FRAGMENT
bool vct_voxel_here(out ivec3 v)
{
#ifdef OPAQUE_LIST
    uint index = gl_GlobalInvocationID.x;
    v = ivec3(0);
    if (index >= opaque_count)
        return false;
    v = vct_voxel_of(opaque[index]);
    return true;
#else
    v = ivec3(gl_GlobalInvocationID);
    return all(lessThan(v, ivec3(u_vct.size, u_vct.size, u_vct.size * VCT_CLIP_LEVELS)));
#endif
}
#endif

// World centre of stacked voxel v and its level's voxel size.
vec3 vct_voxel_centre(ivec3 v, out float voxel)
{
    int k = v.z / u_vct.size;
    voxel = u_vct.level[k].w;
    return u_vct.level[k].xyz + (vec3(v.x, v.y, v.z - k * u_vct.size) + 0.5) * voxel;
}

// The finest level holding p at least `margin` (m) inside; -1 if none.
int vct_level_at(vec3 p, float margin)
{
    for (int k = 0; k < VCT_CLIP_LEVELS; k++) {
        vec3 lo = u_vct.level[k].xyz + margin;
        vec3 hi = u_vct.level[k].xyz + u_vct.level[k].w * float(u_vct.size) - margin;
        if (all(greaterThanEqual(p, lo)) && all(lessThanEqual(p, hi)))
            return k;
    }
    return -1;
}

// The voxel size (m) of the finest level holding p, or of the coarsest where
// none does.
float vct_voxel_at(vec3 p)
{
    int k = vct_level_at(p, 0.0);
    return u_vct.level[k < 0 ? VCT_CLIP_LEVELS - 1 : k].w;
}
