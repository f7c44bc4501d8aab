// gi/lpv/sh.glsl — 2-band real spherical harmonics as the LPV stores them:
// vec4(c00, c1x, c1y, c1z) per colour channel, basis
// Y00 = 1/(2√π), Y1(ω) = √(3/(4π))·(x, y, z). A cell holds the radiant
// intensity I(ω) (W/sr) of the light that passes through it, travelling
// in direction ω.
#ifndef LPV_SH_GLSL
#define LPV_SH_GLSL

#define LPV_PI 3.14159265358979
#define SH_C0 0.282094792   // 1/(2√π)
#define SH_C1 0.488602512   // √(3/(4π))
#define SH_COS0 0.886226925 // ∫ max(0, n·ω) Y00 dω = √π/2
#define SH_COS1 1.023326708 // ∫ max(0, n·ω) Y1 dω = √(π/3)·n

// The basis evaluated in unit direction w.
vec4 sh_eval(vec3 w) { return vec4(SH_C0, SH_C1 * w); }
// Projection of the clamped cosine lobe max(0, n·ω) around unit n.
vec4 sh_clamped_cos(vec3 n) { return vec4(SH_COS0, SH_COS1 * n); }

// Moments of an SH intensity: flux P = ∫ I dω = c00·2√π (W) and first
// moment F = ∫ I(ω) ω dω = c1·√(4π/3) (W).
#define LPV_SH_FLUX 3.544907702   // 2√π
#define LPV_SH_MOMENT 2.046653415 // √(4π/3)
// --lpv-propagation directional: cells a step that light travels (κ; see
// propagate.comp). The lookup scales by it: light crossing a cell of side
// s at κ cells a step stays 1/κ steps per cell length, so the sum over
// steps of its intensity is I/κ and its radiance κ·I_sum/s².
#define LPV_SPEED 0.577350269 // 1/√3

// --lpv-propagation directional: a cell's light read as a clamped-cosine
// lobe of share `cos` around the axis d of its first moment plus isotropic
// light: a cosine lobe of flux P has |F| = 2P/3, so cos = min(1,
// 1.5·|F|/P); light as directional as a cosine lobe or more is all lobe.
// Never negative, unlike the 2-band SH itself (a clamped-cosine lobe's SH
// sends −1/8 of its peak backwards). P ≤ 0 reads as no light.
struct LpvLobe {
    float p;   // flux (W), ≥ 0
    vec3 d;    // the axis (unit; 0 where F = 0)
    float cos; // the cosine lobe's share (the rest is isotropic)
};
LpvLobe lpv_lobe(vec4 sh)
{
    float p = max(sh.x * LPV_SH_FLUX, 0.0);
    vec3 f = sh.yzw * LPV_SH_MOMENT;
    float fl = length(f);
    LpvLobe l;
    l.p = p;
    l.d = fl > 0.0 ? f / fl : vec3(0.0);
    l.cos = p > 0.0 ? min(1.5 * fl / p, 1.0) : 0.0;
    return l;
}
// 1/π ∫ max(0, d·ω) max(0, e·ω) dω for unit d, e with d·e = mu: the
// irradiance a unit-flux cosine lobe along d gives a surface facing −e,
// (2/(3π))·((π − θ)·cos θ + sin θ), θ the angle between d and e.
float lpv_g0(float mu)
{
    return 0.212206591 * ((LPV_PI - acos(mu)) * mu + sqrt(1.0 - mu * mu));
}
// ∫ I(ω) max(0, e·ω) dω of the lobe reading of `l`: what a surface whose
// normal is −e receives of it (times κ/s², the caller's), and, times κ,
// what crosses a cell face of normal e in a step (propagate.comp).
// Isotropic light of unit flux gives 1/4.
float lpv_lobe_toward(LpvLobe l, vec3 e)
{
    float mu = clamp(dot(l.d, e), -1.0, 1.0);
    return l.p * (l.cos * lpv_g0(mu) + 0.25 * (1.0 - l.cos));
}

// Cell of cascade k containing world point p (may be outside the grid).
ivec3 lpv_cell(int k, vec3 p)
{
    return ivec3(floor((p - u_lpv.cascade[k].xyz) / u_lpv.cascade[k].w));
}
// With --lpv-groups 2 the light of surfaces facing +x, +y or +z (n·(1,1,1)
// ≥ 0) and that of surfaces facing the other way are propagated apart, as
// group 0 and 1: light read as one lobe per cell merges where flows meet,
// and flows from facing surfaces (a floor and a ceiling, two opposite
// walls) meet head-on. Whether a VPL of normal n is in group g (−1: one
// group, all of them).
bool lpv_in_group(vec3 n, int g) { return g < 0 || (dot(n, vec3(1.0)) < 0.0 ? 1 : 0) == g; }
// The first z layer of group g (< 0: 0) in volumes that stack the groups.
int lpv_group_layer(int g, int size) { return max(g, 0) * size; }
bool lpv_inside(ivec3 c, int n) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, ivec3(n))); }

#endif
