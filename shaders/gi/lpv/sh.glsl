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

// Cell of cascade k containing world point p (may be outside the grid).
ivec3 lpv_cell(int k, vec3 p)
{
    return ivec3(floor((p - u_lpv.cascade[k].xyz) / u_lpv.cascade[k].w));
}
bool lpv_inside(ivec3 c, int n) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, ivec3(n))); }

#endif
