// frame/vbuffer.glsl — the visibility buffer's resolve (pass_vbuffer.c):
// from the triangle a pixel sees (frame/vbuffer.frag) to the G-buffer's
// two texels, what frame/gbuffer.frag writes for it. The triangle's
// vertices are read from the scene's buffers, its attributes interpolated
// with perspective-correct barycentrics at the pixel centre, and the uv's
// screen gradient (mip selection) is what a rasterizer's texture() takes:
// the differences of the same interpolation across the pixel's 2×2 quad
// (coarse derivatives, from its lower-left pixel to the one right of it
// and the one above), computed from the triangle's plane as the
// rasterizer's helper invocations compute them, whatever those pixels
// show. Differences at the pixel itself instead (forward, or centred)
// gave an oblique textured plane relMSE 3.8e-6 (1.9e-6) against
// --gbuffer raster on llvmpipe, the quad's 1.0e-9. The includer defines
// MATERIAL_ROW and MATERIAL_GRADIENTS before common/material.glsl is
// included here, and UNTEXTURED (materials without textures, resolved by
// the classification pass) or OPAQUE_DRAW (the per-material pass: the
// raster pass has already discarded masked holes).
#include "common/math.glsl"
#include "common/material.glsl"
#define GBUFFER_WRITER
#include "common/gbuffer.glsl"

// Vertex: two vec4, (position, normal.x) and (normal.yz, uv): two loads
// per vertex where llvmpipe would gather each float.
layout(std430, binding = SSBO_SCENE_VERTICES) readonly buffer Vertices { vec4 vertex_data[]; };
layout(std430, binding = SSBO_SCENE_INDICES) readonly buffer Indices { uint indices[]; };
// Per cluster: its first triangle; its material, bit 31 set where that
// material is resolved by its own dispatch (textured or alpha-masked).
layout(std430, binding = SSBO_VBUFFER_CLUSTERS) readonly buffer Clusters { uvec2 clusters[]; };
layout(std430, binding = SSBO_VBUFFER_MATERIALS) readonly buffer Materials { GpuMaterial materials[]; };
layout(std430, binding = SSBO_VBUFFER_BINS) buffer Bins { uint bins[]; };
layout(std430, binding = SSBO_VBUFFER_PIXELS) buffer Pixels { uint pixels[]; };
layout(binding = IMG_VBUFFER_ID, r32ui) uniform readonly uimage2D u_id;
layout(binding = IMG_OUT, rgba32ui) uniform writeonly uimage2D u_surface;
layout(binding = IMG_OUT2, rgba32ui) uniform writeonly uimage2D u_material;
layout(location = LOC_VIEW_PROJ) uniform mat4 u_view_proj;

// Bins (SSBO_VBUFFER_BINS) of material m among the table's count: its
// indirect dispatch and pixel count, then where its pixels start, then the
// scatter's cursor.
uint material_count() { return uint(materials.length()); }
uint bin_count(uint m) { return 4u * m + 3u; }
uint bin_start(uint m) { return 4u * material_count() + m; }
uint bin_cursor(uint m) { return 5u * material_count() + m; }

// The material of visibility texel id (not 0), and whether it has its own
// resolve dispatch (else the classification pass resolves it: no textures).
uint vbuffer_material(uint id, out bool textured)
{
    uint m = clusters[(id - 1u) >> VBUFFER_TRIANGLE_BITS].y;
    textured = (m >> 31) != 0u;
    return m & 0x7fffffffu;
}


// Writes pixel px's G-buffer texels from visibility texel id (not 0) of
// material m, in an image of `size` pixels.
void vbuffer_resolve(ivec2 px, uint id, uint m, ivec2 size)
{
    uint tri = clusters[(id - 1u) >> VBUFFER_TRIANGLE_BITS].x + ((id - 1u) & ((1u << VBUFFER_TRIANGLE_BITS) - 1u));
    uint v[3] = uint[3](indices[3u * tri], indices[3u * tri + 1u], indices[3u * tri + 2u]);
    vec4 va[3], vb[3];
    for (int i = 0; i < 3; i++) {
        va[i] = vertex_data[2u * v[i]];
        vb[i] = vertex_data[2u * v[i] + 1u];
    }
    vec3 p[3] = vec3[3](va[0].xyz, va[1].xyz, va[2].xyz);
    // A point Σ b_i p_i of the triangle (Σ b_i = 1) lands where its clip
    // coordinates (x, y, w) = M b, M's columns the vertices' (x, y, w): at
    // NDC s with (s, 1)·w = M b. So b ∝ M⁻¹ (s, 1), whose rows are the
    // cross products of M's columns over det M (2D homogeneous
    // rasterization, Olano & Greer 1997); the normalisation to Σ b = 1
    // removes the determinant, and w ≤ 0 vertices need no clipping.
    vec3 a[3];
    for (int i = 0; i < 3; i++)
        a[i] = (u_view_proj * vec4(p[i], 1.0)).xyw;
    mat3 inv = transpose(mat3(cross(a[1], a[2]), cross(a[2], a[0]), cross(a[0], a[1])));
    vec2 step = 2.0 / vec2(size);
    vec3 u = inv * vec3((vec2(px) + 0.5) * step - 1.0, 1.0);
    vec3 uq = inv * vec3((vec2(px & ~1) + 0.5) * step - 1.0, 1.0); // the quad's lower-left pixel
    vec3 ux = uq + inv[0] * step.x, uy = uq + inv[1] * step.y;
    float su = u.x + u.y + u.z, sq = uq.x + uq.y + uq.z, sx = ux.x + ux.y + ux.z, sy = uy.x + uy.y + uy.z;
    vec3 b = su != 0.0 ? u / su : vec3(1.0 / 3.0);
    vec3 bq = sq != 0.0 ? uq / sq : b, bx = sx != 0.0 ? ux / sx : bq, by = sy != 0.0 ? uy / sy : bq;
    vec3 world = b.x * p[0] + b.y * p[1] + b.z * p[2];
    vec3 n = normalize(b.x * vec3(va[0].w, vb[0].xy) + b.y * vec3(va[1].w, vb[1].xy) + b.z * vec3(va[2].w, vb[2].xy));
    vec2 t[3] = vec2[3](vb[0].zw, vb[1].zw, vb[2].zw);
    vec2 uv = b.x * t[0] + b.y * t[1] + b.z * t[2];
    vec2 uvq = bq.x * t[0] + bq.y * t[1] + bq.z * t[2];
    material_dx = bx.x * t[0] + bx.y * t[1] + bx.z * t[2] - uvq;
    material_dy = by.x * t[0] + by.y * t[1] + by.z * t[2] - uvq;
    material_masked = false;
    material_row = materials[m];
    vec3 base = material_albedo(uv);
    vec2 mr = material_metal_rough(uv);
    bool front = dot(n, u_frame.camera.xyz - world) >= 0.0;
    imageStore(u_surface, px, surfel_pack(world, front ? n : -n));
    imageStore(u_material, px, gb_material_pack(base, mr.x, mr.y, u_pbr.z, front ? u_emission : vec3(0.0)));
}
