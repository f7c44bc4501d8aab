// rsm_layers.glsl — an RSM's texels by layer, for the passes that walk the
// map texel by texel (the importance pyramid, VPL extraction, the LPV
// geometry volume): a cube map's faces +X −X +Y −Y +Z −Z are layers 0–5, a
// 2D map is one layer. Read as an image of the map itself, bound by
// light_stage_bind_rsm_layers; RSM_CUBE (point and quad lights) picks the
// kind, so these programs are built per kind, as the gathers are. They had
// read a 2D-array view of the map: on llvmpipe a dispatch that sampled the
// view waited in proportion to the map's size whatever it read (7.7 ms for
// a 512² cube, 31 ms for 1024²), where one that loads the image does not.
#ifndef RSM_LAYERS_GLSL
#define RSM_LAYERS_GLSL

#ifdef RSM_CUBE
layout(rgba32ui, binding = IMG_RSM) uniform readonly uimageCube rsm_layers;
ivec3 rsm_layers_size() { return ivec3(imageSize(rsm_layers), 6); }
uvec4 rsm_layer_texel(ivec3 t) { return imageLoad(rsm_layers, t); }
#else
layout(rgba32ui, binding = IMG_RSM) uniform readonly uimage2D rsm_layers;
ivec3 rsm_layers_size() { return ivec3(imageSize(rsm_layers), 1); }
uvec4 rsm_layer_texel(ivec3 t) { return imageLoad(rsm_layers, t.xy); }
#endif

#endif
