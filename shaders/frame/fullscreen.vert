// frame/fullscreen.vert — one triangle covering the viewport; v_uv in [0,1].
// FLAT_UNIFORMS: also the light block as a flat output (common/lights.glsl).
#ifdef FLAT_UNIFORMS
#include "shared/gpu_types.h"
flat out GpuLight v_light;
#endif
out vec2 v_uv;
void main()
{
#ifdef FLAT_UNIFORMS
    v_light = u_light;
#endif
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    v_uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
