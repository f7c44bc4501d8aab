// gi/lpv/propagate.comp — one propagation step: each cell gathers from its
// 6 face neighbours, in one of two ways (--lpv-propagation):
//
// DIRECTIONAL (the default): light keeps the direction it travels in; see
// the section below. Rebuilt from the paper's gathering: the paper's step
// turns 4/5 of a cell's light sideways, so light diffused within a few
// cells of its emitter (on the Cornell box the floor lit itself 6× too
// much and the ceiling got 7% of its bounce).
//
// Faces (Kaplanyan & Dachsbacher 2010, §3.3): a neighbour's light, a point
// at its centre with intensity I(ω), reaches 5 faces of this cell (all but
// the shared one): the far face, seen from the neighbour's centre at solid
// angle 0.4006696846 sr, and 4 side faces at 0.4234313544 sr each; the two
// sum to the 4π/6 of the shared face. The flux onto face f, Φ_f = Δω_f ·
// max(0, I(ω_f)) (ω_f towards the face's centre; the clamp adds flux where
// the 2-band SH goes negative), attenuated by the geometry volume at the
// shared face (1 − B(ω_f), `occlusion`), is re-emitted from this cell's
// centre as a clamped-cosine lobe Φ_f/π · max(0, n_f·ω) around the face's
// normal.
//
// Reads IMG_LPV_STEP_SRC (the last step's light of one light group);
// writes IMG_LPV_STEP_DST and adds to IMG_LPV_SUM+c in the group's layers
// (LOC_LPV_GROUP; each cell is one invocation's). With OCCLUSION
// (--lpv-occlusion on) the faces' factors come from IMG_LPV_FACES (faces:
// the 30 attenuated solid angles Δω_f·(1 − B(ω_f))/π per cell;
// directional: the 6 shared faces' open shares), which MODE_FACES fills
// once per build from the geometry volume (TEX_LPV_GV0/1): the geometry
// does not change between steps, and its 12 trilinear fetches per cell had
// been 60% of a step (Cornell 32³, llvmpipe).
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(binding = TEX_LPV_GV0) uniform sampler3D s_gv0;
layout(binding = TEX_LPV_GV1) uniform sampler3D s_gv1;
// 8 texels per cell, side by side in x (8N × N × N; 30 floats used): texel
// d holds neighbour d's faces 0–3, texels 6 and 7 the six neighbours' face
// 4; neighbours d = +x, −x, +y, −y, +z, −z. An image rather than a storage
// buffer: llvmpipe loads it inline (cold lpv_propagate 107 -> 95 ms).
layout(binding = IMG_LPV_FACES, rgba32f) uniform image3D faces;
#ifdef DIRECTIONAL
#define FACE_TEXELS 2 // the 6 neighbours' factors (+x −x +y −y, +z −z)
#else
#define FACE_TEXELS 8
#endif
ivec3 face_texel(ivec3 c, int k) { return ivec3(FACE_TEXELS * c.x + k, c.y, c.z); }
// The last step's light and this step's, R, G, B side by side in x
// (3N × N × N), read as an image: on llvmpipe a texelFetch is a call per
// fetch, an image load inline (18 per cell: the cold lpv_propagate,
// Cornell 32³ × 32 steps, one thread, 139 -> 114 ms). One image each way,
// so that the pass binds 5 images (GL 4.5 guarantees 8 per shader).
layout(binding = IMG_LPV_STEP_SRC, rgba32f) uniform readonly image3D s_light;
layout(binding = IMG_LPV_STEP_DST, rgba32f) uniform writeonly image3D d_light;
layout(binding = IMG_LPV_SUM + 0, rgba32f) uniform image3D a_r;
layout(binding = IMG_LPV_SUM + 1, rgba32f) uniform image3D a_g;
layout(binding = IMG_LPV_SUM + 2, rgba32f) uniform image3D a_b;
// The light group propagated: its layers of the sums (the groups stacked in z).
layout(location = LOC_LPV_GROUP) uniform int u_group;

// A neighbour's 5 faces seen from its centre (§3.3): the far face along the
// travel direction D (solid angle LPV_FAR_DW), and the side faces towards
// +a1, −a1, +a2, −a2 (LPV_SIDE_DW each), at unit direction K·D ± H·a from
// the neighbour's centre with outward normal ±a. Each face is a call with
// constant arguments, so its basis and lobe fold to constants: llvmpipe
// reads a table indexed in a loop lane by lane from memory (a step on
// Cornell 32³: 13 -> 7 ms).
#define LPV_FAR_DW 0.4006696846
#define LPV_SIDE_DW 0.4234313544
#define LPV_K 0.894427191 // 2/√5
#define LPV_H 0.447213595 // 1/√5

// Δω·(1 − B(w))/π for the face at direction w with solid angle dw, through
// the geometry volume's normal tensor (gd: xx yy zz, go: xy xz yz) at the
// shared face.
float face_factor(vec3 gd, vec3 go, vec3 w, float dw)
{
#ifdef OCCLUSION
    float block = clamp(dot(w * w, gd) + 2.0 * (w.x * w.y * go.x + w.x * w.z * go.y + w.y * w.z * go.z), 0.0, 1.0);
#else
    float block = 0.0;
#endif
    return dw * (1.0 - block) / LPV_PI;
}

#ifdef MODE_FACES
// The 5 factors of the neighbour c − e (its light travels along e): the
// geometry volume at the shared face's centre (the volume's texels sit at
// the cells' corners).
void neighbour_faces(ivec3 c, int n, ivec3 e, vec3 a1, vec3 a2, out vec4 f0123, out float f4)
{
    vec3 t = (vec3(c) + 1.0 - 0.5 * vec3(e)) / float(n + 1);
    vec3 gd = texture(s_gv0, t).xyz, go = texture(s_gv1, t).xyz, d = vec3(e);
    f0123 = vec4(face_factor(gd, go, d, LPV_FAR_DW), face_factor(gd, go, LPV_K * d + LPV_H * a1, LPV_SIDE_DW),
                 face_factor(gd, go, LPV_K * d - LPV_H * a1, LPV_SIDE_DW),
                 face_factor(gd, go, LPV_K * d + LPV_H * a2, LPV_SIDE_DW));
    f4 = face_factor(gd, go, LPV_K * d - LPV_H * a2, LPV_SIDE_DW);
}
#else
// Light I = (sr, sg, sb) onto the face at direction w (outward normal nf),
// times its factor, re-emitted as a clamped-cosine lobe.
void face(vec4 sr, vec4 sg, vec4 sb, vec3 w, vec3 nf, float factor, inout vec4 r, inout vec4 g, inout vec4 b)
{
    vec4 y = sh_eval(w);
    vec4 lobe = sh_clamped_cos(nf) * factor;
    r += max(0.0, dot(sr, y)) * lobe;
    g += max(0.0, dot(sg, y)) * lobe;
    b += max(0.0, dot(sb, y)) * lobe;
}

// The light of the neighbour c − e that travels along e into cell c, over
// its faces with factors (f0123, f4). A neighbour outside the grid sends
// nothing: its clamped fetch is weighed 0, without a branch (llvmpipe runs
// both arms of one).
void neighbour(ivec3 c, int n, ivec3 e, vec3 a1, vec3 a2, vec4 f0123, float f4, inout vec4 r, inout vec4 g,
               inout vec4 b)
{
    ivec3 src = c - e;
    float live = lpv_inside(src, n) ? 1.0 : 0.0;
    ivec3 at = clamp(src, ivec3(0), ivec3(n - 1));
    ivec3 gx = ivec3(n, 0, 0);
    vec4 sr = imageLoad(s_light, at) * live, sg = imageLoad(s_light, at + gx) * live, sb = imageLoad(s_light, at + 2 * gx) * live;
    vec3 d = vec3(e);
    face(sr, sg, sb, d, d, f0123.x, r, g, b);
    face(sr, sg, sb, LPV_K * d + LPV_H * a1, a1, f0123.y, r, g, b);
    face(sr, sg, sb, LPV_K * d - LPV_H * a1, -a1, f0123.z, r, g, b);
    face(sr, sg, sb, LPV_K * d + LPV_H * a2, a2, f0123.w, r, g, b);
    face(sr, sg, sb, LPV_K * d - LPV_H * a2, -a2, f4, r, g, b);
}
#endif

#ifdef DIRECTIONAL
// --lpv-propagation directional. A cell's light (one colour channel) read
// as a lobe (sh.glsl, lpv_lobe: a clamped-cosine lobe around its first
// moment plus isotropic light, never negative) moves towards each of its 6
// neighbours e the part κ·∫ I(ω) max(0, e·ω) dω: the share of each
// direction ω that crosses face e in a step at κ = LPV_SPEED cells a step,
// with that part's own first moment (its direction kept, not turned to the
// face's normal); the rest stays. Summed over the 6 faces a direction ω
// leaves at κ·(|ωx| + |ωy| + |ωz|) ≤ κ√3 = 1, so what stays is never
// negative, and the light moves κ·ω cells a step on average, in every
// direction alike: a plane wave keeps its shape, and flux and first moment
// are conserved exactly (tests/test_lpv.c, propagation_free_space). What
// the geometry volume blocks at the shared face (B = eᵀMe, the share of
// the face that surfaces facing along e cover) is lost: a surface absorbs
// it. Per unit flux, a cosine lobe along d sends κ·g0(d·e) with moment
// κ·(1 + d·e)/8·(d + e), isotropic light κ/4 with moment κ/6·e (the
// closed forms of those integrals; test_lpv.c computes the step from them
// in doubles). The part of (lobe reading l of) a cell's light that crosses
// face e, as SH:
vec4 send(LpvLobe l, vec3 e)
{
    float mu = clamp(dot(l.d, e), -1.0, 1.0);
    vec3 moment = l.cos * (1.0 + mu) * 0.125 * (l.d + e) + (1.0 - l.cos) / 6.0 * e;
    return LPV_SPEED * vec4(lpv_lobe_toward(l, e) / LPV_SH_FLUX, l.p * moment / LPV_SH_MOMENT);
}

// What light `l` sends across all 6 faces together, as SH: per unit flux
// the lobe κ·Σ_e g0(d·e) with moment κ·d (Σ_e (1 + d·e)(d + e)/8 = d),
// isotropic light 6κ/4 with moment 0; g0(μ) + g0(−μ) =
// (2/(3π))·((π − 2θ)·μ + 2·sin θ), θ = acos μ, one acos per axis.
vec4 send_all(LpvLobe l)
{
    vec3 mu = l.d, th = acos(clamp(mu, -1.0, 1.0));
    vec3 pair = 0.212206591 * ((LPV_PI - 2.0 * th) * mu + 2.0 * sin(th));
    float flux = l.cos * (pair.x + pair.y + pair.z) + 1.5 * (1.0 - l.cos);
    return LPV_SPEED * l.p * vec4(flux / LPV_SH_FLUX, l.cos * l.d / LPV_SH_MOMENT);
}

// One colour channel of cell c: what stays of its light `own` and what
// comes in from the 6 neighbours (their light `nb`, the faces' factors f).
vec4 step_channel(vec4 own, vec4 nb[6], float f[6])
{
    const vec3 E[6] = vec3[6](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0), vec3(0, 0, 1), vec3(0, 0, -1));
    vec4 r = own - send_all(lpv_lobe(own));
    for (int k = 0; k < 6; k++)
        r += f[k] * send(lpv_lobe(nb[k]), E[k]);
    // No light travels more than all one way: |F| ≤ P. What stays of light
    // more directional than its lobe reading keeps the moment the lobe did
    // not send, and over steps that piled up to |F| ≫ P where little light
    // was left, a state no light has (test_lpv.c, propagation_closed_box).
    float p = max(r.x, 0.0) * LPV_SH_FLUX, fl = length(r.yzw) * LPV_SH_MOMENT;
    if (fl > p)
        r.yzw *= p / fl;
    return r;
}
#endif

void main()
{
    ivec3 c = ivec3(gl_GlobalInvocationID);
    int n = u_lpv.size;
    if (!lpv_inside(c, n))
        return;
#ifdef DIRECTIONAL
    // Neighbour k sits at c − E[k] and sends along E[k] (+x, −x, +y, −y,
    // +z, −z) through the face it shares with c.
    const ivec3 E[6] = ivec3[6](ivec3(1, 0, 0), ivec3(-1, 0, 0), ivec3(0, 1, 0), ivec3(0, -1, 0), ivec3(0, 0, 1),
                                ivec3(0, 0, -1));
#ifdef MODE_FACES
    // The faces' factors 1 − B, B = eᵀMe the share of the shared face
    // that surfaces facing along e cover (the normal tensor M at the
    // face's centre; the volume's texels sit at the cells' corners).
    float b[6];
    for (int k = 0; k < 6; k++) {
        vec3 t = (vec3(c) + 1.0 - 0.5 * vec3(E[k])) / float(n + 1);
        vec3 gd = texture(s_gv0, t).xyz;
        b[k] = 1.0 - clamp(k < 2 ? gd.x : k < 4 ? gd.y : gd.z, 0.0, 1.0);
    }
    imageStore(faces, face_texel(c, 0), vec4(b[0], b[1], b[2], b[3]));
    imageStore(faces, face_texel(c, 1), vec4(b[4], b[5], 0.0, 0.0));
#else
#ifdef OCCLUSION
    vec4 f0 = imageLoad(faces, face_texel(c, 0)), f1 = imageLoad(faces, face_texel(c, 1));
    float f[6] = float[6](f0.x, f0.y, f0.z, f0.w, f1.x, f1.y);
#else
    float f[6] = float[6](1.0, 1.0, 1.0, 1.0, 1.0, 1.0);
#endif
    // Neighbours outside the grid send nothing (weighed 0, no branch).
    vec4 nr[6], ng[6], nbl[6];
    ivec3 gx = ivec3(n, 0, 0);
    for (int k = 0; k < 6; k++) {
        ivec3 src = c - E[k];
        float live = lpv_inside(src, n) ? 1.0 : 0.0;
        ivec3 at = clamp(src, ivec3(0), ivec3(n - 1));
        nr[k] = imageLoad(s_light, at) * live;
        ng[k] = imageLoad(s_light, at + gx) * live;
        nbl[k] = imageLoad(s_light, at + 2 * gx) * live;
    }
    vec4 r = step_channel(imageLoad(s_light, c), nr, f);
    vec4 g = step_channel(imageLoad(s_light, c + gx), ng, f);
    vec4 bl = step_channel(imageLoad(s_light, c + 2 * gx), nbl, f);
    imageStore(d_light, c, r);
    imageStore(d_light, c + gx, g);
    imageStore(d_light, c + 2 * gx, bl);
    ivec3 sc = c + ivec3(0, 0, lpv_group_layer(u_group, n));
    imageStore(a_r, sc, imageLoad(a_r, sc) + r);
    imageStore(a_g, sc, imageLoad(a_g, sc) + g);
    imageStore(a_b, sc, imageLoad(a_b, sc) + bl);
#endif
#else
    const vec3 X = vec3(1.0, 0.0, 0.0), Y = vec3(0.0, 1.0, 0.0), Z = vec3(0.0, 0.0, 1.0);
    // Neighbours +x, −x, +y, −y, +z, −z with their side axes.
#ifdef MODE_FACES
    vec4 f4a, f4b; // the neighbours' face 4: +x −x +y −y, +z −z
    vec4 fk0, fk1, fk2, fk3, fk4, fk5;
    neighbour_faces(c, n, ivec3(1, 0, 0), Y, Z, fk0, f4a.x);
    neighbour_faces(c, n, ivec3(-1, 0, 0), Y, Z, fk1, f4a.y);
    neighbour_faces(c, n, ivec3(0, 1, 0), Z, X, fk2, f4a.z);
    neighbour_faces(c, n, ivec3(0, -1, 0), Z, X, fk3, f4a.w);
    neighbour_faces(c, n, ivec3(0, 0, 1), X, Y, fk4, f4b.x);
    neighbour_faces(c, n, ivec3(0, 0, -1), X, Y, fk5, f4b.y);
    imageStore(faces, face_texel(c, 0), fk0);
    imageStore(faces, face_texel(c, 1), fk1);
    imageStore(faces, face_texel(c, 2), fk2);
    imageStore(faces, face_texel(c, 3), fk3);
    imageStore(faces, face_texel(c, 4), fk4);
    imageStore(faces, face_texel(c, 5), fk5);
    imageStore(faces, face_texel(c, 6), f4a);
    imageStore(faces, face_texel(c, 7), vec4(f4b.xy, 0.0, 0.0));
#else
#ifdef OCCLUSION
    vec4 t[6] = vec4[6](imageLoad(faces, face_texel(c, 0)), imageLoad(faces, face_texel(c, 1)),
                        imageLoad(faces, face_texel(c, 2)), imageLoad(faces, face_texel(c, 3)),
                        imageLoad(faces, face_texel(c, 4)), imageLoad(faces, face_texel(c, 5)));
    vec4 f4a = imageLoad(faces, face_texel(c, 6)), f4b = imageLoad(faces, face_texel(c, 7));
#else
    float far = face_factor(vec3(0.0), vec3(0.0), X, LPV_FAR_DW), side = face_factor(vec3(0.0), vec3(0.0), X, LPV_SIDE_DW);
    vec4 t0 = vec4(far, side, side, side), f4a = vec4(side), f4b = vec4(side);
    vec4 t[6] = vec4[6](t0, t0, t0, t0, t0, t0);
#endif
    vec4 r = vec4(0.0), g = vec4(0.0), b = vec4(0.0);
    neighbour(c, n, ivec3(1, 0, 0), Y, Z, t[0], f4a.x, r, g, b);
    neighbour(c, n, ivec3(-1, 0, 0), Y, Z, t[1], f4a.y, r, g, b);
    neighbour(c, n, ivec3(0, 1, 0), Z, X, t[2], f4a.z, r, g, b);
    neighbour(c, n, ivec3(0, -1, 0), Z, X, t[3], f4a.w, r, g, b);
    neighbour(c, n, ivec3(0, 0, 1), X, Y, t[4], f4b.x, r, g, b);
    neighbour(c, n, ivec3(0, 0, -1), X, Y, t[5], f4b.y, r, g, b);
    imageStore(d_light, c, r);
    imageStore(d_light, c + ivec3(n, 0, 0), g);
    imageStore(d_light, c + ivec3(2 * n, 0, 0), b);
    ivec3 sc = c + ivec3(0, 0, lpv_group_layer(u_group, n));
    imageStore(a_r, sc, imageLoad(a_r, sc) + r);
    imageStore(a_g, sc, imageLoad(a_g, sc) + g);
    imageStore(a_b, sc, imageLoad(a_b, sc) + b);
#endif
#endif
}
