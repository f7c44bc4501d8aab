// gi/vct/volume.glsl — where the clipmap's voxels are: level k = v.z / N of
// the stacked volume (one level: the volume over the scene bounds).

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
    for (int k = 0; k < u_vct.clip_levels; k++) {
        vec3 lo = u_vct.level[k].xyz + margin;
        vec3 hi = u_vct.level[k].xyz + u_vct.level[k].w * float(u_vct.size) - margin;
        if (all(greaterThanEqual(p, lo)) && all(lessThanEqual(p, hi)))
            return k;
    }
    return -1;
}
