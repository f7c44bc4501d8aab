// frame/vbuffer.frag — the visibility buffer's thin raster pass
// (pass_vbuffer.c; Burns & Hunt 2013, "The Visibility Buffer"): per pixel
// only which triangle it sees, (cluster << VBUFFER_TRIANGLE_BITS |
// gl_PrimitiveID) + 1, the cluster being the draw (LOC_VBUFFER_DRAW, set
// per draw by gpu_scene_draw_view) and gl_PrimitiveID the triangle within
// it. With MASKED, alpha-masked materials discard their holes as the
// G-buffer's depth pre-pass does (common/material.glsl, the base level's
// alpha), so the surfaces are the raster G-buffer's. Every material uniform
// is declared (frame/depth.frag says why).
#include "shared/gpu_types.h"
#include "common/material.glsl"

#ifdef MASKED
in vec2 v_uv;
#else
layout(early_fragment_tests) in;
#endif

layout(location = LOC_VBUFFER_DRAW) uniform uint u_draw;
layout(location = 0) out uint o_id;

void main()
{
#ifdef MASKED
    material_albedo(v_uv);
#endif
    o_id = ((u_draw << VBUFFER_TRIANGLE_BITS) | uint(gl_PrimitiveID)) + 1u;
}
