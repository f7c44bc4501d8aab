// gi/lpv/propagate.comp — one propagation step (Kaplanyan & Dachsbacher
// 2010, §3.3): each cell gathers from its 6 face neighbours. A neighbour's
// light, a point at its centre with intensity I(ω), reaches 5 faces of this
// cell (all but the shared one): the far face, seen from the neighbour's
// centre at solid angle 0.4006696846 sr, and 4 side faces at 0.4234413544
// sr each; the two sum to the 4π/6 of the shared face, so a step keeps the
// flux. The flux onto face f, Φ_f = Δω_f · I(ω_f) (ω_f towards the face's
// centre), attenuated by the geometry volume at the shared face
// (1 − B(ω_f), `occlusion`), is re-emitted from this cell's centre as a
// clamped-cosine lobe Φ_f/π · max(0, n_f·ω) around the face's normal.
// Reads TEX_LPV_SRC+c (the last step's light), the geometry volume; writes
// IMG_LPV_DST+c and adds to IMG_LPV_SUM+c (each cell is one invocation's).
#include "shared/gpu_types.h"
#include "gi/lpv/sh.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(binding = TEX_LPV_SRC + 0) uniform sampler3D s_r;
layout(binding = TEX_LPV_SRC + 1) uniform sampler3D s_g;
layout(binding = TEX_LPV_SRC + 2) uniform sampler3D s_b;
layout(binding = TEX_LPV_GV0) uniform sampler3D s_gv0;
layout(binding = TEX_LPV_GV1) uniform sampler3D s_gv1;
layout(binding = IMG_LPV_DST + 0, rgba32f) uniform writeonly image3D d_r;
layout(binding = IMG_LPV_DST + 1, rgba32f) uniform writeonly image3D d_g;
layout(binding = IMG_LPV_DST + 2, rgba32f) uniform writeonly image3D d_b;
layout(binding = IMG_LPV_SUM + 0, rgba32f) uniform image3D a_r;
layout(binding = IMG_LPV_SUM + 1, rgba32f) uniform image3D a_g;
layout(binding = IMG_LPV_SUM + 2, rgba32f) uniform image3D a_b;

// For each of the 6 neighbours (+x, −x, +y, −y, +z, −z: the direction its
// light travels into this cell) its 5 faces: the far face first, then the
// side faces. FACE_W: unit direction from the neighbour's centre to the
// face's centre; FACE_N: the face's outward normal; FACE_DW: its solid
// angle from the neighbour's centre (0.4006696846 far, 0.4234413544 side).
const vec3 FACE_W[30] = vec3[30](
    vec3(1.000000000, 0.000000000, 0.000000000),
    vec3(0.894427191, 0.447213595, 0.000000000),
    vec3(0.894427191, -0.447213595, 0.000000000),
    vec3(0.894427191, 0.000000000, 0.447213595),
    vec3(0.894427191, 0.000000000, -0.447213595),
    vec3(-1.000000000, 0.000000000, 0.000000000),
    vec3(-0.894427191, 0.447213595, 0.000000000),
    vec3(-0.894427191, -0.447213595, 0.000000000),
    vec3(-0.894427191, 0.000000000, 0.447213595),
    vec3(-0.894427191, 0.000000000, -0.447213595),
    vec3(0.000000000, 1.000000000, 0.000000000),
    vec3(0.000000000, 0.894427191, 0.447213595),
    vec3(0.000000000, 0.894427191, -0.447213595),
    vec3(0.447213595, 0.894427191, 0.000000000),
    vec3(-0.447213595, 0.894427191, 0.000000000),
    vec3(0.000000000, -1.000000000, 0.000000000),
    vec3(0.000000000, -0.894427191, 0.447213595),
    vec3(0.000000000, -0.894427191, -0.447213595),
    vec3(0.447213595, -0.894427191, 0.000000000),
    vec3(-0.447213595, -0.894427191, 0.000000000),
    vec3(0.000000000, 0.000000000, 1.000000000),
    vec3(0.447213595, 0.000000000, 0.894427191),
    vec3(-0.447213595, 0.000000000, 0.894427191),
    vec3(0.000000000, 0.447213595, 0.894427191),
    vec3(0.000000000, -0.447213595, 0.894427191),
    vec3(0.000000000, 0.000000000, -1.000000000),
    vec3(0.447213595, 0.000000000, -0.894427191),
    vec3(-0.447213595, 0.000000000, -0.894427191),
    vec3(0.000000000, 0.447213595, -0.894427191),
    vec3(0.000000000, -0.447213595, -0.894427191));
const vec3 FACE_N[30] = vec3[30](
    vec3(1.000000000, 0.000000000, 0.000000000),
    vec3(0.000000000, 1.000000000, 0.000000000),
    vec3(0.000000000, -1.000000000, 0.000000000),
    vec3(0.000000000, 0.000000000, 1.000000000),
    vec3(0.000000000, 0.000000000, -1.000000000),
    vec3(-1.000000000, 0.000000000, 0.000000000),
    vec3(0.000000000, 1.000000000, 0.000000000),
    vec3(0.000000000, -1.000000000, 0.000000000),
    vec3(0.000000000, 0.000000000, 1.000000000),
    vec3(0.000000000, 0.000000000, -1.000000000),
    vec3(0.000000000, 1.000000000, 0.000000000),
    vec3(0.000000000, 0.000000000, 1.000000000),
    vec3(0.000000000, 0.000000000, -1.000000000),
    vec3(1.000000000, 0.000000000, 0.000000000),
    vec3(-1.000000000, 0.000000000, 0.000000000),
    vec3(0.000000000, -1.000000000, 0.000000000),
    vec3(0.000000000, 0.000000000, 1.000000000),
    vec3(0.000000000, 0.000000000, -1.000000000),
    vec3(1.000000000, 0.000000000, 0.000000000),
    vec3(-1.000000000, 0.000000000, 0.000000000),
    vec3(0.000000000, 0.000000000, 1.000000000),
    vec3(1.000000000, 0.000000000, 0.000000000),
    vec3(-1.000000000, 0.000000000, 0.000000000),
    vec3(0.000000000, 1.000000000, 0.000000000),
    vec3(0.000000000, -1.000000000, 0.000000000),
    vec3(0.000000000, 0.000000000, -1.000000000),
    vec3(1.000000000, 0.000000000, 0.000000000),
    vec3(-1.000000000, 0.000000000, 0.000000000),
    vec3(0.000000000, 1.000000000, 0.000000000),
    vec3(0.000000000, -1.000000000, 0.000000000));
const float FACE_DW[30] = float[30](0.4006696846, 0.4234413544, 0.4234413544, 0.4234413544, 0.4234413544, 0.4006696846, 0.4234413544, 0.4234413544, 0.4234413544, 0.4234413544, 0.4006696846, 0.4234413544, 0.4234413544, 0.4234413544, 0.4234413544, 0.4006696846, 0.4234413544, 0.4234413544, 0.4234413544, 0.4234413544, 0.4006696846, 0.4234413544, 0.4234413544, 0.4234413544, 0.4234413544, 0.4006696846, 0.4234413544, 0.4234413544, 0.4234413544, 0.4234413544);

const ivec3 NEIGHBOUR[6] = ivec3[6](ivec3(1, 0, 0), ivec3(-1, 0, 0), ivec3(0, 1, 0), ivec3(0, -1, 0),
                                   ivec3(0, 0, 1), ivec3(0, 0, -1));

void main()
{
    ivec3 c = ivec3(gl_GlobalInvocationID);
    int n = u_lpv.size;
    if (!lpv_inside(c, n))
        return;
    bool occlusion = u_lpv.occlusion != 0;
    vec4 r = vec4(0.0), g = vec4(0.0), b = vec4(0.0);
    for (int d = 0; d < 6; d++) {
        ivec3 src = c - NEIGHBOUR[d]; // the neighbour whose light travels along NEIGHBOUR[d] into c
        if (!lpv_inside(src, n))
            continue;
        vec4 sr = texelFetch(s_r, src, 0), sg = texelFetch(s_g, src, 0), sb = texelFetch(s_b, src, 0);
        if (sr == vec4(0.0) && sg == vec4(0.0) && sb == vec4(0.0))
            continue; // no light yet: nothing to send (saves the 5 faces)
        // The geometry volume at the shared face's centre (in cells).
        vec3 gd = vec3(0.0), go = vec3(0.0);
        if (occlusion) {
            vec3 t = (vec3(c) + 1.0 - 0.5 * vec3(NEIGHBOUR[d])) / float(n + 1);
            gd = texture(s_gv0, t).xyz;
            go = texture(s_gv1, t).xyz;
        }
        for (int f = 0; f < 5; f++) {
            int i = 5 * d + f;
            vec3 w = FACE_W[i];
            float block = clamp(dot(w * w, gd) + 2.0 * (w.x * w.y * go.x + w.x * w.z * go.y + w.y * w.z * go.z), 0.0, 1.0);
            vec4 y = sh_eval(w);
            vec4 lobe = sh_clamped_cos(FACE_N[i]) * (FACE_DW[i] * (1.0 - block) / LPV_PI);
            r += max(0.0, dot(sr, y)) * lobe;
            g += max(0.0, dot(sg, y)) * lobe;
            b += max(0.0, dot(sb, y)) * lobe;
        }
    }
    imageStore(d_r, c, r);
    imageStore(d_g, c, g);
    imageStore(d_b, c, b);
    imageStore(a_r, c, imageLoad(a_r, c) + r);
    imageStore(a_g, c, imageLoad(a_g, c) + g);
    imageStore(a_b, c, imageLoad(a_b, c) + b);
}
