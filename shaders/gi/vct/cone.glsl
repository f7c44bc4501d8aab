// gi/vct/cone.glsl — cone tracing through the voxel volume (Crassin et al.
// 2011, §5): front-to-back accumulation of premultiplied radiance and
// opacity, sampling the mip whose voxel equals the cone's diameter there,
// with the isotropic chain or the six directional volumes (weighted by the
// squared direction components, the three facing the cone) above mip 0.
// The volumes hold occupancy density β and radiance × β (shared/
// gpu_types.h, VCT_OPTICAL_DEPTH): a step of dt through a sample is opaque
// 1 − e^(−β·VCT_OPTICAL_DEPTH·dt/voxel) and sends its radiance rgb/β.
#include "gi/vct/volume.glsl"

layout(binding = TEX_VCT_RADIANCE) uniform sampler3D u_radiance;
// The directional volumes, one texture per axis holding both signs
// (shared/gpu_types.h, GpuVctParams).
layout(binding = TEX_VCT_ANISO + 0) uniform sampler3D u_aniso_x;
layout(binding = TEX_VCT_ANISO + 1) uniform sampler3D u_aniso_y;
layout(binding = TEX_VCT_ANISO + 2) uniform sampler3D u_aniso_z;

// What a cone's steps read of u_vct, read once per cone: in a loop llvmpipe
// reads every uniform lane by lane.
struct VctCone {
    vec3 p, d, n;       // apex, unit direction, the surface's unit normal
    vec3 x;             // the surface point the cone leaves (on its plane)
    vec3 axis;          // the normal's dominant axis (a unit vector)
    float sign_a;       // the sign of the normal's component along it
    float n_a;          // |that component|
    float spread;       // the plane's slope against that axis: (L1(n) − n_a) / n_a
    float top;          // how far the surface's voxels reach past its plane (level voxels)
    float tan_half;     // tan(half-angle)
    float v0;           // level 0's voxel (m)
    float max_mip;      // the coarsest mip
    float step;         // step in diameters
    float ao_range;     // distance within which opacity counts as occlusion (m)
    int size;           // voxels per side of a level
    int aniso_slab;     // a directional slab's depth (GpuVctParams)
    vec3 c;             // radiance gathered
    float a, occlusion; // opacity, opacity within ao_range
    float t;            // distance of the next step (m)
};

// Texture coordinates of `local` (0..1 within level k) in the stack of
// VCT_CLIP_LEVELS slabs, z kept half a texel of mip `mip` inside the slab,
// so that filtering never reads a neighbouring level.
vec3 vct_stack_uvw(VctCone c, vec3 local, int k, float mip)
{
#if VCT_CLIP_LEVELS == 1
    return local;
#else
    float h = 0.5 / float(max(c.size >> int(ceil(mip)), 1));
    return vec3(local.xy, (float(k) + clamp(local.z, h, 1.0 - h)) / float(VCT_CLIP_LEVELS));
#endif
}

// Level k at mip `mip` (of that level), seen along the cone. Compiled with
// VCT_ANISO (--vct-aniso) or without, not chosen by u_vct.aniso: llvmpipe
// runs the code under a branch whether or not a lane takes it, fetches
// included, so the isotropic trace had also paid for the directional one
// (Cornell 256², one thread: 159 -> 32 ms). For the same reason each
// axis's side is read in one fetch from the texture holding both (with a
// texture per side, both sides' fetches ran: 147 -> 96 ms). The directional
// volumes start at mip 1: below it the sample blends level 0 of the
// isotropic chain in, read only where `below1` (a constant at each call)
// says the step may lie there.
vec4 vct_sample(VctCone c, int k, vec3 local, float mip, const bool below1)
{
#ifdef VCT_ANISO
    // Axis a's side s is slab 2k + s of its texture, whose first N/2 of
    // aniso_slab texels hold the level, z kept half a texel of mip `lod`
    // inside them.
    float lod = max(mip - 1.0, 0.0);
    float slab = float(max(c.aniso_slab >> int(ceil(lod)), 1));
    float f = float(c.size / 2) / float(c.aniso_slab), h = 0.5 / slab;
    float z = max(min(local.z * f, f - h), h);
    vec3 side = vec3(lessThan(c.d, vec3(0.0))), w = c.d * c.d;
    vec3 slab_z = (vec3(2 * k) + side + z) / float(2 * VCT_CLIP_LEVELS);
    vec4 a = w.x * textureLod(u_aniso_x, vec3(local.xy, slab_z.x), lod) +
             w.y * textureLod(u_aniso_y, vec3(local.xy, slab_z.y), lod) +
             w.z * textureLod(u_aniso_z, vec3(local.xy, slab_z.z), lod);
    if (!below1)
        return a;
    vec4 r0 = textureLod(u_radiance, vct_stack_uvw(c, local, k, 0.0), 0.0);
    return mip < 1.0 ? mix(r0, a, mip) : a;
#else
    return textureLod(u_radiance, vct_stack_uvw(c, local, k, mip), mip);
#endif
}

// The diameter of cone c at c.t, at least level 0's voxel.
float vct_cone_diameter(VctCone c) { return max(c.v0, 2.0 * c.t * c.tan_half); }

// Keeping a cone's samples off the surface it leaves (issue 44). A cone
// within its half-angle of the horizon (the diffuse rings) reads, at the
// mip of its diameter, the voxels of the surface it leaves: a box filter
// as wide as the cone, at the height of the cone's axis, reaches down into
// them. Those voxels are opaque and, seen from above, dark (aniso.comp
// sends a voxel's light out of its lit side only), so a surface shadowed
// itself: Cornell 256² read 0.46-0.76 of the reference's bounce on every
// wall. With every side sending, it had lit itself instead (floor 3.2,
// back wall 1.8). Two limits keep the filter clear of the surface's voxels
// (tests/test_vct.c, surfaces_do_not_light_themselves):
//  - the mip is capped where the sample is low (vct_mip_cap), down to mip
//    0: the sample must stand VCT_CLEAR texels of its mip above the
//    surface's voxels, which reach c.top level voxels past its plane
//    (VCT_SURFACE_TOP: 1 with conservative voxelization, ½ with fragment
//    centres) and rise across the filter's
//    footprint (1.5 texels each side) as the plane slopes against its
//    dominant axis (c.spread); a capped sample is a narrower cone there,
//    and steps by its own texel;
//  - where the cap cannot keep it there (a sample below that height at
//    mip 0, or one of a cone near the horizon), the sample is moved along
//    the normal's dominant axis until it does (vct_clear_of_surface).
// The cap and the lift ask the same clearance (issue 44, Sponza). The cap
// had allowed 1.5 texels and stopped at mip 1 while the lift asked
// VCT_CLEAR = 2.5 texels of the mip floor: nearly every sample near a
// surface was lifted, by up to 6 level voxels at mip 1 (1.4 m at 128³),
// past its cone's path and into whatever lay there. Under Sponza's
// arcades the soffit of an arch is 0.75 m above the curtain's rod (3
// voxels at 128³, 6 at 256³); the lift put every cone of the soffit into
// the curtain, which read 0.00-0.04 of the reference's bounce (tests/
// vct_diag-style probes: a cone toward the sunlit floor, clear at level 0
// along its axis, opaque at its first sample, 0.85 m below the soffit).
// Measured (scripts/gi-regions.sh; Cornell 128², 256 spp; Sponza 320×180
// at 256³, blocks above the median): VCT_CLEAR 1.5, 1.75, 2.0, 2.5 gave
// Cornell's whole image 0.87, 1.04, 1.13, 1.19 (relMSE 0.0037, 0.0035,
// 0.0048, 0.0069; before 1.04, 0.0030) and Sponza's lowest block 0.15,
// 0.19, 0.17, 0.12 (before 0.04).
// A clipmap (VCT_CLIP_LEVELS > 1) keeps the cap of before (1.5 texels, at
// least mip 1) and its clearance 2.5: its level is chosen by the cone's
// diameter, not by the capped mip, so a capped sample read a level whose
// voxels are coarser than its cap (Cornell 128², 2 levels of 32³: relMSE
// 0.028 -> 0.054, the floor 2.2 -> 5.7 of the reference's bounce). Open.
// The surface's voxels' reach past its plane: conservative voxelization
// takes every voxel the plane touches, two layers where it passes near a
// voxel boundary (1 voxel); fragment centres (--vct-conservative off) one
// voxel a column, the one holding the plane at the column's centre. The
// ¾ was measured (issue 44, fourth round; scripts/gi-regions.sh, Sponza
// 320×180 at 256³ with fragment centres, the lowest block above the
// median, and test_vct's lone square): 1: 0.331; ¾: 0.340, the square
// adds 1.1% to its own light; ½: 0.350, 1.6% (conservative, 1: 0.8%).
const vec2 VCT_SURFACE_TOP = vec2(0.75, 1.0); // [fragment centres, conservative]
#if VCT_CLIP_LEVELS == 1
const float VCT_CLEAR = 1.75;
#else
const float VCT_CLEAR = 2.5;
#endif

// The coarsest mip (of a level of voxel vk) at which sample q stands the
// clearance vct_clear_of_surface asks above the voxels of the surface cone
// c leaves; at least 0 (a clipmap: at least 1, with 1.5 texels of room).
float vct_mip_cap(VctCone c, vec3 q, float vk)
{
    float h = dot(c.n, q - c.x) / c.n_a; // height above the plane along the dominant axis
#if VCT_CLIP_LEVELS == 1
    float texel = (h - vk * (c.top + 0.5 * c.spread)) / (VCT_CLEAR + 1.5 * c.spread);
    return log2(max(texel, vk) / vk);
#else
    float room = (h - vk * (c.top + 0.5 * c.spread)) / (1.5 * (1.0 + c.spread));
    return room >= 2.0 * vk ? log2(room / vk) : 1.0;
#endif
}

// Sample q moved along the normal's dominant axis, if need be, until it
// stands VCT_CLEAR texels of mip floor(mip) (of a level of voxel vk) above
// the voxels of the surface cone c leaves, their top raised by the plane's
// slope over the filter's footprint (1.5 texels each side across the axis).
vec3 vct_clear_of_surface(VctCone c, vec3 q, float vk, float mip)
{
    float d = vk * exp2(floor(mip));
    float above = dot(c.n, q - c.x) / c.n_a; // the sample's height over the plane along the axis
    float need = c.spread * (1.5 * d + 0.5 * vk) + c.top * vk + VCT_CLEAR * d;
    return q + c.axis * (c.sign_a * max(need - above, 0.0));
}

// One step of cone c: the sample at c.t composited behind what c holds;
// false where the cone ends instead (it left the volume). `below1` as for
// vct_sample. With a clipmap each sample reads the finest level that holds
// it (with the cone's diameter of margin) and whose voxels are no larger
// than the diameter, unless only a coarser one holds it. Past the coarsest
// mip the cone reads that mip. The volumes hold occupancy density
// (shared/gpu_types.h, VCT_OPTICAL_DEPTH), so a sample's opacity over a
// step of dt is 1 − e^(−β·VCT_OPTICAL_DEPTH·dt/vk) at any mip.
bool vct_cone_step(inout VctCone c, const bool below1)
{
    const int last = VCT_CLIP_LEVELS - 1;
    float diameter = vct_cone_diameter(c);
    vec3 q = c.p + c.d * c.t;
    int k = vct_level_at(q, last > 0 ? diameter : 0.0);
    if (k < 0)
        return false;
#if VCT_CLIP_LEVELS == 1
    k = 0; // what the line below gives, said so that level[k] is a constant
#else
    k = max(k, min(int(floor(log2(diameter / c.v0))), last));
#endif
    float vk = u_vct.level[k].w;
    float mip = min(min(log2(max(diameter, vk) / vk), c.max_mip), vct_mip_cap(c, q, vk));
    q = vct_clear_of_surface(c, q, vk, mip);
    vec3 local = (q - u_vct.level[k].xyz) / (vk * float(c.size));
    vec4 s = vct_sample(c, k, local, mip, below1);
    float dt = c.step * vk * exp2(mip); // the sampled texel's size: one diameter unless capped
    if (s.a > 0.0) {
        float sa = 1.0 - exp(-s.a * VCT_OPTICAL_DEPTH * dt / vk);
        c.c += (1.0 - c.a) * s.rgb * (sa / s.a);
        if (c.t < c.ao_range)
            c.occlusion += (1.0 - c.occlusion) * sa;
        c.a += (1.0 - c.a) * sa;
    }
    c.t += dt;
    return true;
}

// Where a surface's cones start: their apex VCT_APEX voxels off the
// surface along its normal, their first sample one voxel further along
// the cone. The clearance above keeps the samples off the surface's own
// voxels; a larger apex offset moves the whole cone off its path (Sponza
// 320×180 at 256³, the lowest block: apex 2.5 voxels 0.19, 1.0 0.27, 0.5
// 0.27; Cornell 128² whole image 1.04, 1.02, 1.02).
#if VCT_CLIP_LEVELS == 1
const float VCT_APEX = 1.0;
#else
const float VCT_APEX = 2.5; // the clipmap's as before (see VCT_CLEAR)
#endif

// Traces a cone along unit d with tan(half-angle) `tan_half` from surface
// point x of unit normal n (voxel: the voxel size there; the apex and the
// first sample as VCT_APEX says). Returns the radiance gathered (rgb) and
// the opacity (a); `occlusion` gets the opacity met within u_vct.ao_range.
vec4 vct_cone(vec3 x, vec3 d, vec3 n, float tan_half, float voxel, out float occlusion)
{
    VctCone c;
    c.p = x + n * (VCT_APEX * voxel);
    c.d = d;
    c.n = n;
    c.x = x;
    vec3 an = abs(n);
    c.axis = an.x >= an.y && an.x >= an.z ? vec3(1.0, 0.0, 0.0) : an.y >= an.z ? vec3(0.0, 1.0, 0.0) : vec3(0.0, 0.0, 1.0);
    float na = dot(c.axis, n);
    c.sign_a = na < 0.0 ? -1.0 : 1.0;
    c.n_a = max(abs(na), 1e-3);
    c.spread = (an.x + an.y + an.z - c.n_a) / c.n_a;
    c.tan_half = tan_half;
    c.top = VCT_SURFACE_TOP[u_vct.conservative != 0 ? 1 : 0];
    c.v0 = u_vct.level[0].w;
    c.max_mip = float(u_vct.mips - 1);
    c.step = u_vct.step;
    c.ao_range = u_vct.ao_range;
    c.size = u_vct.size;
    c.aniso_slab = u_vct.aniso_slab;
    c.c = vec3(0.0);
    c.a = 0.0;
    c.occlusion = 0.0;
    c.t = voxel;
    float max_distance = u_vct.max_distance;
    int i = 0;
#if VCT_CLIP_LEVELS == 1 && defined(VCT_ANISO)
    bool live = true;
    // One volume: the mip grows with the diameter and the cap with the
    // height over the surface, so the steps below mip 1 (diameter < 2·v0,
    // or capped below 1 near the surface) come first, and only they read
    // the isotropic level 0 (3 fetches a step after them instead of 4; Cornell 256², one
    // thread, with the uniforms read once and level 0 constant: vct_trace
    // 88 -> 66 ms).
    for (; i < 4096 && c.a < 0.99 && c.t < max_distance &&
                  (vct_cone_diameter(c) < 2.0 * c.v0 || vct_mip_cap(c, c.p + c.d * c.t, c.v0) < 1.0); i++)
        if (!vct_cone_step(c, true)) {
            live = false;
            break;
        }
    if (live)
        for (; i < 4096 && c.a < 0.99 && c.t < max_distance; i++)
            if (!vct_cone_step(c, false))
                break;
#else
    // One loop: an isotropic sample is one fetch at any mip, and a
    // clipmap's steps read the level whose voxels match the diameter, at a
    // mip in [0, 1) until the coarsest level, so every step may lie below 1.
    for (; i < 4096 && c.a < 0.99 && c.t < max_distance; i++)
        if (!vct_cone_step(c, true))
            break;
#endif
    occlusion = c.occlusion;
    return vec4(c.c, c.a);
}

// Irradiance E (W/m²) at surface point x with unit normal n (voxel: the
// voxel size there) from the diffuse cone set: Σ w_i L_i, w_i = ∫cosθ dω
// over cone i's cell of the hemisphere (Σ w_i = π). `visibility` gets 1 −
// the cosine-weighted occlusion.
vec3 vct_irradiance(vec3 x, vec3 n, float voxel, out float visibility)
{
    vec3 t, b;
    basis(n, t, b);
    vec3 e = vec3(0.0);
    float occluded = 0.0;
    for (int i = 0; i < u_vct.cones; i++) {
        vec3 cd = u_vct.cone[i].xyz;
        vec3 d = normalize(t * cd.x + b * cd.y + n * cd.z);
        float occ;
        vec4 l = vct_cone(x, d, n, u_vct.cone_aperture[i].x, voxel, occ);
        e += u_vct.cone[i].w * l.rgb;
        occluded += u_vct.cone[i].w / PI * occ;
    }
    visibility = 1.0 - occluded;
    return e;
}
