// gi/lpv/accumulate.frag — writes a point's payloads; the framebuffer
// blends additively (ONE, ONE), so every point adds to its cell.
flat in vec4 g_a;
flat in vec4 g_b;
flat in vec4 g_c;

layout(location = 0) out vec4 o_a;
layout(location = 1) out vec4 o_b;
layout(location = 2) out vec4 o_c;

void main()
{
    o_a = g_a;
    o_b = g_b;
    o_c = g_c;
}
