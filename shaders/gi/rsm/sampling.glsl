// rsm.glsl — gathering one bounce from a reflective shadow map
// (Dachsbacher & Stamminger 2005), SPEC §3.
// Project x into the RSM at (s, t); take samples at (s, t) + r_max·ξ1·
// (sin 2πξ2, cos 2πξ2) from one pattern shared by every pixel and frame: a
// Fibonacci set, sample i of n at ξ1 = (i + ½)/n, ξ2 = frac(i·φ),
// generated in the loop. It was a Hammersley set read from a storage buffer:
// on llvmpipe that load was 30% of the gather (a per-lane gather although
// every lane reads the same entry) and computing Hammersley's angle needs a
// sin/cos per sample, where the golden angle needs one rotation (rsm_spot
// 960×540 low-res gather 91 -> 73 ms, min of 4 alternated). A subset
// first + k·stride (interleaved sub-images) still covers every angle, where
// a decimated Hammersley set covered a 1/stride wedge (interleaved 4×4
// against exhaustive without the blur: relMSE 0.0517 -> 0.0212). Weighting:
//  - paper: Σ ξ1²·E_p / Σ ξ1², times K, the number of texels in the disk
//    (so that a constant field sums exactly);
//  - unbiased: Σ E_p / (N·P(texel)), P = texel area × polar pdf
//    1/(2π r_max² ξ1), i.e. a weight 2·ξ1·K/N per sample: converges to the sum
//    over the disk's texels. On a cube RSM, samples that leave the face go
//    through the face plane; a Jacobian ratio (texels per plane area there
//    relative to the face's own) keeps the estimate unbiased, and also keeps
//    the paper's normalisation from counting texels the disk does not cover.
// Requires: shared/gpu_types.h, math.glsl, vpl.glsl; RSM_CUBE defined for point and
// quad lights (cube RSM), undefined for directional and spot lights.

layout(std430, binding = SSBO_SAMPLES) readonly buffer SampleBlock { GpuVpl rsm_samples[]; };

#if !defined(RSM_CUBE) && !defined(RSM_2D)
#define RSM_2D
#endif
#include "common/rsm_texel.glsl"
#include "common/vpl_record.glsl"
// One RGBA32UI texel per sample: position, normal and flux (the area follows).
#ifdef RSM_CUBE
layout(binding = TEX_RSM) uniform usamplerCube rsm_map;
#else
layout(binding = TEX_RSM) uniform usampler2D rsm_map;
#endif

// Signed major axis of d.
vec3 major_axis(vec3 d)
{
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z)
        return vec3(sign(d.x), 0.0, 0.0);
    if (a.y >= a.z)
        return vec3(0.0, sign(d.y), 0.0);
    return vec3(0.0, 0.0, sign(d.z));
}

// Where x falls in the RSM, computed once per pixel: the map coordinates of
// x (cube: on the face plane of x's major axis a at distance 1, in [-1, 1],
// spanned by r and u; 2D: the light's projection) and the disk's radius
// in those units.
struct RsmFrame {
    vec3 a, r, u; // cube: the face's axis and its plane's basis
    vec2 st;      // x's coordinates
    float scale;  // the disk's radius (cube: the face is 2 wide)
    // Uniforms the sample loops need, read once: in a loop, every uniform
    // read is a per-lane gather on llvmpipe (16 of them for the matrix).
    vec3 light;          // cube: the light's position
    mat4 view_proj;      // 2D: the light's projection (rsm_in_disk)
    float r2_per_area;   // the texel disk's r² per texel area
    RsmTexelFrame texel; // how the map's texels unpack
#ifdef ISM_FROM_RSM
    IsmRsmFrame ism;     // the visibility of each sample (gi/visibility/ism.glsl)
#endif
};

RsmFrame rsm_frame(vec3 x)
{
    RsmFrame f;
    float r_max = u_gi.rsm_r_max;
    f.r2_per_area = u_gi.disk_r2_per_area;
    f.texel = rsm_texel_frame();
#ifdef ISM_FROM_RSM
    f.ism = ism_rsm_frame();
#endif
#ifdef RSM_CUBE
    f.light = u_light.position_type.xyz;
    f.view_proj = mat4(1.0);
    vec3 dir = x - f.light;
    f.a = major_axis(dir);
    f.r = abs(f.a.y) > 0.5 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    f.u = cross(f.a, f.r);
    f.st = vec2(dot(dir, f.r), dot(dir, f.u)) / abs(dot(dir, f.a));
    f.scale = 2.0 * r_max;
#else
    f.light = vec3(0.0);
    f.view_proj = u_light.shadow_view_proj;
    vec4 c = f.view_proj * vec4(x, 1.0);
    f.a = f.r = f.u = vec3(0.0);
    f.st = c.xy / c.w * 0.5 + 0.5;
    f.scale = r_max;
#endif
    return f;
}

const float GOLDEN = 0.61803398874989485; // (√5 − 1)/2

// Subset `first` of an n-point pattern dealt to `stride` interleaved
// subsets (points first, first + stride, ...): its first point and size.
// Over the subsets every point is taken exactly once, so each pixel of a
// sub-image still sees radii ξ1 spread over all of (0, 1) and the list
// sets' points are never read past their end; with n < stride, subset k
// takes point k mod n alone.
ivec2 rsm_subset(int n, int first, int stride)
{
    int f = first - div_small(first, n) * n;
    return ivec2(f, max(div_small(n - f + stride - 1, stride), 1));
}

// The texel at map coordinates q of frame f, and its Jacobian weight.
uvec4 rsm_fetch(RsmFrame f, vec2 q, out float jac)
{
#ifdef RSM_CUBE
    // Texels per plane area where D meets its own face, relative to the
    // face of x: (|D·a| / |D·major(D)|)³ with D·a = 1, i.e. m⁻³ for
    // m = max(1, |q.x|, |q.y|) (D's components along a, r, u are 1, q).
    float m = max(1.0, max(abs(q.x), abs(q.y)));
    jac = 1.0 / (m * m * m);
    return textureLod(rsm_map, f.a + q.x * f.r + q.y * f.u, 0.0);
#else
    // A sample off the map is empty space: it reads nothing (the border
    // texel is weighted 0) but, with the paper's weights, still counts in
    // the average.
    bool inside = all(greaterThanEqual(q, vec2(0.0))) && all(lessThanEqual(q, vec2(1.0)));
    jac = inside ? 1.0 : 0.0;
    return textureLod(rsm_map, q, 0.0);
#endif
}

#ifdef READS_ONLY
// `render --timings --probe run`'s twin of a gather (src/gi/rsm/rsm.c): the
// same samples read in the same order, every bit of them kept, and no
// arithmetic on them; the rate of its reads is the limit of the gather's
// own access pattern. The image it makes is meaningless.
vec3 rsm_reads_fold(uvec4 t) { return vec3(float(t.x ^ t.y ^ t.z ^ t.w) * 1e-15); }
// A VPL record as the loops read it: its surface and its flux.
vec3 rsm_reads_fold_vpl(uvec4 surface, vec4 flux) { return rsm_reads_fold(surface) + rsm_reads_fold(floatBitsToUint(flux)); }
#endif

// Irradiance at x (normal n) from RSM texel t. An empty texel unpacks to
// flux 0 and a finite area: it adds 0.
vec3 rsm_texel_irradiance(RsmFrame f, uvec4 t, vec3 x, vec3 n)
{
#ifdef READS_ONLY
    return rsm_reads_fold(t);
#else
    vec3 e = rsm_texel_irradiance_at(f.texel, t, x, n, f.r2_per_area);
#ifdef ISM_FROM_RSM
    if (e != vec3(0.0))
        e *= ism_visibility_rsm(f.ism, rsm_texel_position(f.texel, t), x, n);
#endif
    return e;
#endif
}

// Sums E over samples first, first+stride, ... (count of them) of the
// n_pattern-sample pattern, with the paper's weights or (unbiased) those of
// the polar pdf. Two samples a step, both texels fetched before either is
// evaluated, so that their reads overlap: a gather's reads miss the
// caches when neighbouring lanes' disks lie apart (sparse gathers, large
// maps), and on llvmpipe each fetch is a call that waits on its loads
// (256², one thread: rsm-interleaved 29 -> 26 ms, rsm-interp's low-res
// gather 22 -> 19 ms, rsm 310 -> 244 ms). An odd count's last step
// fetches one sample past the subset and weighs it 0.
// Pattern point i's ξ1 (inv_n = 1/n) and its map coordinates in frame f at
// the angle (sin, cos) sc, which then turns by rot to the next point's.
float rsm_pattern_point(RsmFrame f, int i, float inv_n, inout vec2 sc, vec2 rot, out vec2 q)
{
    float xi1 = (float(i) + 0.5) * inv_n;
    q = f.st + f.scale * (xi1 * sc);
    sc = vec2(sc.x * rot.y + sc.y * rot.x, sc.y * rot.y - sc.x * rot.x);
    return xi1;
}

vec3 rsm_gather(RsmFrame f, vec3 x, vec3 n, int first, int stride, int count, bool unbiased, int n_pattern)
{
    float K = u_gi.disk_texels;
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    // Fibonacci pattern: sample i at ξ1 = (i + ½)/n, angle 2π·frac(iφ); the
    // subset i = first + k·stride turns by a fixed angle per step.
    float inv_n = 1.0 / float(n_pattern);
    float a0 = TWO_PI * fract(float(first) * GOLDEN), da = TWO_PI * fract(float(stride) * GOLDEN);
    vec2 sc = vec2(sin(a0), cos(a0)), rot = vec2(sin(da), cos(da));
    for (int k = 0; k < count; k += 2) {
        vec2 qa, qb;
        float xa = rsm_pattern_point(f, first + k * stride, inv_n, sc, rot, qa);
        float xb = rsm_pattern_point(f, first + (k + 1) * stride, inv_n, sc, rot, qb);
        float ja, jb;
        uvec4 ta = rsm_fetch(f, qa, ja), tb = rsm_fetch(f, qb, jb);
        float live = k + 1 < count ? 1.0 : 0.0;
        sum += rsm_texel_irradiance(f, ta, x, n) * ((unbiased ? 2.0 * xa : xa * xa) * ja);
        wsum += xa * xa;
        sum += rsm_texel_irradiance(f, tb, x, n) * ((unbiased ? 2.0 * xb : xb * xb) * jb * live);
        wsum += xb * xb * live;
    }
    if (unbiased)
        return sum * (K / float(max(count, 1)));
    return wsum > 0.0 ? sum * (K / wsum) : vec3(0.0);
}

// Whether world point xp lies in the disk rsm_gather samples for the pixel
// of frame f: its direction from the light through f's face plane (cube),
// or its map coordinates (2D), within the disk's radius of x's own.
bool rsm_in_disk(RsmFrame f, vec3 xp)
{
#ifdef RSM_CUBE
    vec3 dp = xp - f.light;
    float h = dot(dp, f.a);
    vec2 q = vec2(dot(dp, f.r), dot(dp, f.u));
    return h > 0.0 && distance(q, f.st * h) <= f.scale * h;
#else
    vec4 cp = f.view_proj * vec4(xp, 1.0);
    return distance(cp.xy / cp.w * 0.5 + 0.5, f.st) <= f.scale;
#endif
}

// Importance weighting: the map split in two parts that together cover it
// once. Near x (the disk of the paper's pattern) the polar pattern with its
// unbiased weights, dense where 1/d² is steep, from the N/2-point pattern
// stored after the paper's N; the rest from one set of the light's sample
// list (gi/rsm/importance.comp): VPLs drawn ∝ flux luminance over the whole
// map, with flux Φ/p, of which those inside the disk are dropped. Unbiased
// for the sum over every RSM texel.
vec3 rsm_gather_importance(vec3 x, vec3 n, uint set, int first, int stride, int count)
{
    int n_near = max(u_gi.rsm_samples / 2, 1), n_far = u_gi.list_set;
    ivec2 near_k = ivec2(0, max(count / 2, 1)), far_k = ivec2(0, max(count - near_k.y, 1));
    if (stride > 1) { // interleaved: subset `first` of the near pattern and of the list set
        near_k = rsm_subset(n_near, first, stride);
        far_k = rsm_subset(n_far, first, stride);
    }
    RsmFrame f = rsm_frame(x);
    vec3 near = rsm_gather(f, x, n, near_k.x, stride, near_k.y, true, n_near);
    vec3 far = vec3(0.0);
    uint base = set * uint(n_far);
    int global = far_k.y;
    for (int k = 0; k < global; k++) {
        GpuVpl v = rsm_samples[base + uint(far_k.x + k * stride)];
#ifdef READS_ONLY
        far += rsm_reads_fold_vpl(v.surface, v.flux);
#else
        vec3 xp = vpl_position(v);
        vec3 e = vpl_irradiance_disk(x, n, xp, vpl_shading_normal(v), v.flux.rgb, v.flux.w * f.r2_per_area);
        e = rsm_in_disk(f, xp) ? vec3(0.0) : e;
#ifdef ISM_FROM_RSM
        if (e != vec3(0.0))
            e *= ism_visibility_rsm(f.ism, xp, x, n);
#endif
        far += e;
#endif
    }
    return near + far / float(global);
}
