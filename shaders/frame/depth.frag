// frame/depth.frag — the G-buffer pass's depth pre-pass (pass_gbuffer.c):
// nothing to shade; with MASKED, alpha-masked materials discard their holes
// (material_albedo) so the depth they leave is the G-buffer's.
#include "shared/gpu_types.h"
#ifdef MASKED
#include "common/material.glsl"
in vec2 v_uv;
#endif

void main()
{
#ifdef MASKED
    material_albedo(v_uv);
#endif
}
