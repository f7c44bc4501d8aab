// gi/lpv/layer.geom — routes an injected point to its slice of a layered
// 3D-texture framebuffer (gl_Layer = the cell's z) with its three payloads.
// Points the vertex stage rejected (layer < 0) are dropped.
layout(points) in;
layout(points, max_vertices = 1) out;

flat in int v_layer[];
flat in vec4 v_a[];
flat in vec4 v_b[];
flat in vec4 v_c[];

flat out vec4 g_a;
flat out vec4 g_b;
flat out vec4 g_c;

void main()
{
    if (v_layer[0] < 0)
        return;
    gl_Layer = v_layer[0];
    gl_Position = gl_in[0].gl_Position;
    gl_PointSize = 1.0;
    g_a = v_a[0];
    g_b = v_b[0];
    g_c = v_c[0];
    EmitVertex();
    EndPrimitive();
}
