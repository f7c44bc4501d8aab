// frame/depth.frag — the G-buffer pass's depth pre-pass (pass_gbuffer.c):
// nothing to shade; with MASKED, alpha-masked materials discard their holes
// (material_albedo) so the depth they leave is the G-buffer's. Every
// program gpu_scene_draw_view draws with declares the material's uniforms
// (common/material.glsl), used or not: it sets them per material, and GL
// ignores an explicit location a program declares but does not use, where
// one it does not declare at all is an error (GL_INVALID_OPERATION).
#include "shared/gpu_types.h"
#include "common/material.glsl"
#ifdef MASKED
in vec2 v_uv;
#endif

void main()
{
#ifdef MASKED
    material_albedo(v_uv);
#endif
}
