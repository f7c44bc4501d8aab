// frame/vbuffer.glsl — the visibility buffer's resolve (pass_vbuffer.c):
// from the triangle a pixel sees (frame/vbuffer.frag) to the G-buffer's
// two texels, what frame/gbuffer.frag writes for it. The triangle's
// vertices are read from the scene's buffers, its attributes interpolated
// with perspective-correct barycentrics at the pixel centre, and the uv's
// screen gradient (mip selection) is the change of the same interpolation
// one pixel to the right and one up: the differences a rasterizer takes
// between neighbouring pixels, computed from the triangle rather than from
// the neighbours (which may show another triangle). The includer defines
// MATERIAL_ROW and MATERIAL_GRADIENTS before common/material.glsl is
// included here, and UNTEXTURED (materials without textures, resolved by
// the classification pass) or OPAQUE_DRAW (the per-material pass: the
// raster pass has already discarded masked holes).
#include "common/math.glsl"
#include "common/material.glsl"
#define GBUFFER_WRITER
#include "common/gbuffer.glsl"

layout(std430, binding = SSBO_SCENE_VERTICES) readonly buffer Vertices { float vertex_data[]; }; // Vertex: 8 floats
layout(std430, binding = SSBO_SCENE_INDICES) readonly buffer Indices { uint indices[]; };
layout(std430, binding = SSBO_VBUFFER_CLUSTERS) readonly buffer Clusters { uvec2 clusters[]; }; // first triangle, material
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

// The material of visibility texel id (not 0).
uint vbuffer_material(uint id) { return clusters[(id - 1u) >> VBUFFER_TRIANGLE_BITS].y; }

// Whether material m is resolved without textures (gpu_scene.c's untextured()).
bool material_plain(uint m)
{
    GpuMaterial r = materials[m];
    return r.albedo.w == 0.0 && r.pbr.w == 0.0 && r.emission.w < 0.0;
}

vec3 vertex_vec3(uint v, uint at) { return vec3(vertex_data[8u * v + at], vertex_data[8u * v + at + 1u], vertex_data[8u * v + at + 2u]); }
vec2 vertex_uv(uint v) { return vec2(vertex_data[8u * v + 6u], vertex_data[8u * v + 7u]); }

// Writes pixel px's G-buffer texels from visibility texel id (not 0) of
// material m, in an image of `size` pixels.
void vbuffer_resolve(ivec2 px, uint id, uint m, ivec2 size)
{
    uint tri = clusters[(id - 1u) >> VBUFFER_TRIANGLE_BITS].x + ((id - 1u) & ((1u << VBUFFER_TRIANGLE_BITS) - 1u));
    uint v[3] = uint[3](indices[3u * tri], indices[3u * tri + 1u], indices[3u * tri + 2u]);
    vec3 p[3] = vec3[3](vertex_vec3(v[0], 0u), vertex_vec3(v[1], 0u), vertex_vec3(v[2], 0u));
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
    vec3 ux = u + inv[0] * step.x, uy = u + inv[1] * step.y;
    float su = u.x + u.y + u.z, sx = ux.x + ux.y + ux.z, sy = uy.x + uy.y + uy.z;
    vec3 b = su != 0.0 ? u / su : vec3(1.0 / 3.0);
    vec3 bx = sx != 0.0 ? ux / sx : b, by = sy != 0.0 ? uy / sy : b;
    vec3 world = b.x * p[0] + b.y * p[1] + b.z * p[2];
    vec3 n = normalize(b.x * vertex_vec3(v[0], 3u) + b.y * vertex_vec3(v[1], 3u) + b.z * vertex_vec3(v[2], 3u));
    vec2 t[3] = vec2[3](vertex_uv(v[0]), vertex_uv(v[1]), vertex_uv(v[2]));
    vec2 uv = b.x * t[0] + b.y * t[1] + b.z * t[2];
    material_dx = bx.x * t[0] + bx.y * t[1] + bx.z * t[2] - uv;
    material_dy = by.x * t[0] + by.y * t[1] + by.z * t[2] - uv;
    material_masked = false;
    material_row = materials[m];
    vec3 base = material_albedo(uv);
    vec2 mr = material_metal_rough(uv);
    bool front = dot(n, u_frame.camera.xyz - world) >= 0.0;
    imageStore(u_surface, px, surfel_pack(world, front ? n : -n));
    imageStore(u_material, px, gb_material_pack(base, mr.x, mr.y, u_pbr.z, front ? u_emission : vec3(0.0)));
}
