// gi/vct/voxelize.geom — dominant-axis projection of each triangle for the
// voxelization (Crassin & Green 2012, OpenGL Insights ch. 22). Works in
// voxel units: p = (world − origin) / voxel, so the N×N viewport's pixels
// are voxel columns. The triangle is swizzled so that its dominant normal
// axis becomes depth; with u_vct.conservative it is enlarged so that every
// pixel square it touches is rasterized (each edge moved out by the pixel's
// half extent along the edge normal, 0.5·(|nx| + |ny|); Hasselgren et al.
// 2005), and the fragment shader clips to the triangle's bounds and tests
// each candidate voxel exactly. Edges and bounds move VCT_COVER_MARGIN
// further, more than the rasterizer's snapping of vertices to sub-pixels
// (1/256 on llvmpipe): a column that the triangle only touches along its
// side (the Cornell box's side walls ending on the back wall's voxel face)
// is then drawn, and the voxel test alone decides, as in the compute path.
#include "shared/gpu_types.h"
#define VCT_SETUP_ONLY
#include "gi/vct/voxelize.glsl"

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in vec3 v_world[];
in vec3 v_normal[];
in vec2 v_uv[];

layout(location = LOC_VCT_LEVEL) uniform int u_level;

out vec2 g_uv;
out vec3 g_normal;
flat out vec3 g_t0; // the triangle in swizzled voxel coordinates
flat out vec3 g_t1;
flat out vec3 g_t2;
flat out vec4 g_bounds; // its 2D bounds in pixels, grown by half a pixel
flat out int g_axis;    // dominant axis 0..2

const float VCT_COVER_MARGIN = 1.0 / 64.0; // pixels

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

void main()
{
    vec3 p[3];
    for (int i = 0; i < 3; i++)
        p[i] = (v_world[i] - u_vct.level[u_level].xyz) / u_vct.level[u_level].w;
    vec3 n = cross(p[1] - p[0], p[2] - p[0]);
    vec3 an = abs(n);
    if (max(an.x, max(an.y, an.z)) <= 0.0)
        return; // degenerate
    int axis = vct_dominant_axis(n);
    vec3 s[3];
    for (int i = 0; i < 3; i++)
        s[i] = vct_swizzle(p[i], axis);
    vec2 a[3] = vec2[3](s[0].xy, s[1].xy, s[2].xy);
    float area = cross2(a[1] - a[0], a[2] - a[0]);
    vec2 q[3] = a;
    if (u_vct.conservative != 0 && abs(area) > 0.0) {
        vec3 l[3];
        for (int i = 0; i < 3; i++) {
            l[i] = cross(vec3(a[i], 1.0), vec3(a[(i + 1) % 3], 1.0));
            if (dot(l[i], vec3(a[(i + 2) % 3], 1.0)) < 0.0)
                l[i] = -l[i]; // inside positive
            l[i].z += (0.5 + VCT_COVER_MARGIN) * (abs(l[i].x) + abs(l[i].y));
        }
        for (int i = 0; i < 3; i++) {
            vec3 v = cross(l[(i + 2) % 3], l[i]);
            if (abs(v.z) > 1e-12 * (abs(v.x) + abs(v.y)))
                q[i] = v.xy / v.z;
        }
    }
    vec2 lo = min(a[0], min(a[1], a[2])) - 0.5 - VCT_COVER_MARGIN;
    vec2 hi = max(a[0], max(a[1], a[2])) + 0.5 + VCT_COVER_MARGIN;
    for (int i = 0; i < 3; i++) {
        // Barycentrics of the moved vertex in the original triangle, for its uv and normal.
        vec3 b = vec3(1.0, 0.0, 0.0);
        if (abs(area) > 0.0) {
            b.y = cross2(a[0] - q[i], a[2] - q[i]) / -area;
            b.z = cross2(a[1] - a[0], q[i] - a[0]) / area;
            b.x = 1.0 - b.y - b.z;
        }
        g_uv = b.x * v_uv[0] + b.y * v_uv[1] + b.z * v_uv[2];
        g_normal = b.x * v_normal[0] + b.y * v_normal[1] + b.z * v_normal[2];
        g_t0 = s[0];
        g_t1 = s[1];
        g_t2 = s[2];
        g_bounds = vec4(lo, hi);
        g_axis = axis;
        gl_Position = vec4(q[i] / float(u_vct.size) * 2.0 - 1.0, 0.5, 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
