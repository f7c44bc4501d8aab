// gi/vct/cone.glsl — cone tracing through the voxel volume (Crassin et al.
// 2011, §5): front-to-back accumulation of premultiplied radiance and
// opacity, sampling the mip whose voxel equals the cone's diameter there,
// with the isotropic chain or the six directional volumes (weighted by the
// squared direction components, the three facing the cone) above mip 0.
// A sample's opacity stands for a path of one voxel of its mip; a step of
// `step` diameters corrects it to 1 − (1 − α)^step (and scales the
// radiance with it).
#include "gi/vct/volume.glsl"

layout(binding = TEX_VCT_RADIANCE) uniform sampler3D u_radiance;
// The directional volumes, one texture per axis holding both signs
// (shared/gpu_types.h, GpuVctParams).
layout(binding = TEX_VCT_ANISO + 0) uniform sampler3D u_aniso_x;
layout(binding = TEX_VCT_ANISO + 1) uniform sampler3D u_aniso_y;
layout(binding = TEX_VCT_ANISO + 2) uniform sampler3D u_aniso_z;

// Texture coordinates of `local` (0..1 within level k) in the stack of
// `levels` slabs, z kept half a texel of mip `mip` (of a level of side N)
// inside the slab, so that filtering never reads a neighbouring level.
vec3 vct_stack_uvw(vec3 local, int k, float mip)
{
    if (u_vct.clip_levels == 1)
        return local;
    float h = 0.5 / float(max(u_vct.size >> int(ceil(mip)), 1));
    return vec3(local.xy, (float(k) + clamp(local.z, h, 1.0 - h)) / float(u_vct.clip_levels));
}

// Texture coordinates in an axis's directional volumes of `local` (0..1
// within level k), seen against the axis (neg) or along it: slab 2k + neg,
// whose first N/2 of aniso_slab texels hold the level, z kept half a
// texel of mip `lod` inside them.
vec3 vct_aniso_uvw(vec3 local, int k, bool neg, float lod)
{
    float slab = float(max(u_vct.aniso_slab >> int(ceil(lod)), 1));
    float f = float(u_vct.size / 2) / float(u_vct.aniso_slab), h = 0.5 / slab;
    float z = max(min(local.z * f, f - h), h);
    return vec3(local.xy, (float(2 * k + int(neg)) + z) / float(2 * u_vct.clip_levels));
}

// Level k at mip `mip` (of that level), seen along unit d. Compiled with
// VCT_ANISO (--vct-aniso) or without, not chosen by u_vct.aniso: llvmpipe
// runs the code under a branch whether or not a lane takes it, fetches
// included, so the isotropic trace had also paid for the directional one
// (Cornell 256², one thread: 159 -> 32 ms). For the same reason the
// directional sample reads level 0 of the isotropic chain once, for both
// mip 0 (mip is never below) and the blend up to mip 1, and each axis's
// side in one fetch from the texture holding both (with a texture per
// side, both sides' fetches ran: 147 -> 96 ms).
vec4 vct_sample(int k, vec3 local, float mip, vec3 d)
{
#ifdef VCT_ANISO
    vec3 w = d * d;
    float lod = max(mip - 1.0, 0.0);
    vec4 a = w.x * textureLod(u_aniso_x, vct_aniso_uvw(local, k, d.x < 0.0, lod), lod) +
             w.y * textureLod(u_aniso_y, vct_aniso_uvw(local, k, d.y < 0.0, lod), lod) +
             w.z * textureLod(u_aniso_z, vct_aniso_uvw(local, k, d.z < 0.0, lod), lod);
    vec4 r0 = textureLod(u_radiance, vct_stack_uvw(local, k, 0.0), 0.0);
    return mip < 1.0 ? mix(r0, a, mip) : a;
#else
    return textureLod(u_radiance, vct_stack_uvw(local, k, mip), mip);
#endif
}

// Traces a cone from p along unit d with tan(half-angle) `tan_half`,
// starting at distance t0 (m), from a surface of unit normal n. Returns the
// radiance gathered (rgb) and the opacity (a); `occlusion` gets the opacity
// met within u_vct.ao_range.
// Each sample is lifted along n until it stands one sample diameter off the
// surface's plane: a cone within its half-angle of the horizon (the diffuse
// rings) otherwise reads the surface's own voxels at every mip, so lit
// walls light themselves and unlit ones shadow themselves. On the Cornell
// box (96², point light, against one-bounce) that error grew with the grid:
// relMSE 0.0102, 0.0192, 0.0222 at 32³, 64³, 128³ (back wall 1.4-2.0× the
// reference's indirect light, ceiling 0.47-0.26×); lifted: 0.0092, 0.0113,
// 0.0122. Sponza (320×180): FLIP 0.0465 → 0.0448.
// With a clipmap each sample reads the finest level that holds it (with
// the cone's diameter of margin) and whose voxels are no larger than the
// diameter, unless only a coarser one holds it.
vec4 vct_cone(vec3 p, vec3 d, vec3 n, float tan_half, float t0, out float occlusion)
{
    float v0 = u_vct.level[0].w;
    float max_mip = float(u_vct.levels - 1);
    int last = u_vct.clip_levels - 1;
    vec3 c = vec3(0.0);
    float a = 0.0;
    occlusion = 0.0;
    float t = t0;
    for (int i = 0; i < 4096 && a < 0.99 && t < u_vct.max_distance; i++) {
        float diameter = max(v0, 2.0 * t * tan_half);
        float lift = diameter - t * dot(d, n);
        vec3 q = p + d * t + n * max(lift, 0.0);
        int k = vct_level_at(q, last > 0 ? diameter : 0.0);
        if (k < 0)
            break;
        k = max(k, min(int(floor(log2(diameter / v0))), last));
        float vk = u_vct.level[k].w;
        float size = max(diameter, vk); // what the sample spans
        float mip = log2(size / vk);
        if (mip > max_mip)
            break;
        vec3 local = (q - u_vct.level[k].xyz) / (vk * float(u_vct.size));
        vec4 s = vct_sample(k, local, mip, d);
        float dt = u_vct.step * diameter;
        if (s.a > 0.0) {
            float sa = 1.0 - pow(max(1.0 - s.a, 0.0), dt / size);
            c += (1.0 - a) * s.rgb * (sa / s.a);
            if (t < u_vct.ao_range)
                occlusion += (1.0 - occlusion) * sa;
            a += (1.0 - a) * sa;
        }
        t += dt;
    }
    return vec4(c, a);
}

// Irradiance E (W/m²) at p with unit normal n from the diffuse cone set:
// Σ w_i L_i, w_i = ∫cosθ dω over cone i's cell of the hemisphere (Σ w_i =
// π). `visibility` gets 1 − the cosine-weighted occlusion.
vec3 vct_irradiance(vec3 p, vec3 n, float t0, out float visibility)
{
    vec3 t, b;
    basis(n, t, b);
    vec3 e = vec3(0.0);
    float occluded = 0.0;
    for (int i = 0; i < u_vct.cones; i++) {
        vec3 cd = u_vct.cone[i].xyz;
        vec3 d = normalize(t * cd.x + b * cd.y + n * cd.z);
        float occ;
        vec4 l = vct_cone(p, d, n, u_vct.cone_aperture[i].x, t0, occ);
        e += u_vct.cone[i].w * l.rgb;
        occluded += u_vct.cone[i].w / PI * occ;
    }
    visibility = 1.0 - occluded;
    return e;
}
