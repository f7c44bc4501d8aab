/* gpu_types.h — every block, binding point and uniform location shared by
 * the C code and the shaders, declared once. C includes it as
 * "shared/gpu_types.h"; GLSL through the shader loader's #include. Each
 * block is an X-macro list of (type, name) fields, so the C struct, the GLSL
 * struct and the layout test's reflection table (tests/test_layout.c) all
 * come from the same lines. Types are GLSL's; only 4-byte scalars, vec4,
 * ivec4, mat4 and arrays of vec4 are used, so std140 and C agree without
 * hand-placed padding (the layout test checks every offset).
 * Comments inside the lists must be block comments (line continuation). */
#ifndef RTGI_SHARED_GPU_TYPES_H
#define RTGI_SHARED_GPU_TYPES_H

/* ---- Binding points ---------------------------------------------------- */
/* Uniform blocks */
#define UBO_LIGHT 0   /* GpuLight of the light being shaded (a range of the light stage's array) */
#define UBO_SHADOW 1  /* GpuShadowParams */
#define UBO_GI 2      /* GpuGiParams (RSM family, interleaving) */
#define UBO_VPL 3     /* GpuVplParams (many-VPL family) */
#define UBO_FRAME 4   /* GpuFrame: camera, sizes, indirect scale */
#define UBO_LPV 5     /* GpuLpvParams (light propagation volumes) */
#define UBO_VCT 6     /* GpuVctParams (voxel cone tracing) */
#define UBO_ISM 7     /* GpuIsmParams (imperfect shadow maps: visibility of the bounce) */
/* Shader storage blocks */
#define SSBO_PATTERN 0   /* RSM sample pattern: vec4 per sample */
#define SSBO_VPL 1       /* GpuVpl[] */
#define SSBO_COUNTERS 2  /* VPL buffer counters: [0] VPL count, [1] the seed of their ξ */
#define SSBO_VPL_RANGE 3 /* vec2 per VPL: α, culling range */
#define SSBO_TILES 4     /* per-tile VPL counts and lists */
#define SSBO_EVALS 5     /* VPL–pixel evaluations per work group */
#define SSBO_SUBSETS 6   /* interleaved VPL subsets; metalight signatures */
#define SSBO_PIXEL_LIST 7 /* rsm-interp: [0] count, [1..] pixels that need a full gather */
#define SSBO_SAMPLES 8   /* RSM importance sampling: GpuVpl[list_size] with flux Φ/p */
#define SSBO_LPV_FIXED 9  /* lpv compute injection: int[12 · N³] fixed-point SH sums */
#define SSBO_VCT_VOXELS 10 /* vct voxelization: uint[8 · N³] fixed-point albedo, normal, count sums per voxel */
#define SSBO_VCT_OPAQUE 11 /* vct: the opaque voxels: count, 3 words of padding, packed coordinates */
#define SSBO_ISM_POINTS 12 /* ism: vec4[point_count], the scene's point samples (xyz, m) */
#define SSBO_STATS 13     /* gi/count_surfaces.comp: [0] the count (stats read back on request) */
#define SSBO_ISM_REPS 14  /* ism from an RSM: uvec4 per map, its block's representative texel (position bits, oct normal) */
#define SSBO_ISM_CELLS 15 /* ism: uint[grid_n³ + 1], where each cell's points start in SSBO_ISM_POINTS */
#define SSBO_SCENE_VERTICES 16 /* the scene's vertex buffer read as floats (Vertex: 8 each; vct compute voxelization) */
#define SSBO_SCENE_INDICES 17  /* the scene's index buffer read as uints (vct compute voxelization) */
#define SSBO_VCT_WORK 18   /* vct compute voxelization: per submesh and level a header (indirect dispatch, count), then its large triangles */
#define SSBO_VBUFFER_CLUSTERS 19  /* --gbuffer visibility: uint[2] per GpuScene cluster, its first triangle and its material (bit 31: textured) */
#define SSBO_VBUFFER_MATERIALS 20 /* --gbuffer visibility: GpuMaterial per scene material */
#define SSBO_VBUFFER_BINS 21      /* --gbuffer visibility: per material uint[4] (indirect dispatch x y z, pixel count), then start and cursor per material */
#define SSBO_VBUFFER_PIXELS 22    /* --gbuffer visibility: the binned pixels, x | y << 16, material after material */
#define SSBO_VCT_OPAQUE_PREV 23 /* vct region revoxelization: the opaque list before it (as SSBO_VCT_OPAQUE) */
#define SSBO_VCT_ARGS 24        /* vct: uvec4[4], the indirect dispatches over the list or every voxel (gi/vct/args.comp) */
/* (lpv injects from SSBO_VPL, counted by SSBO_COUNTERS) */
/* Texture units */
#define TEX_ALBEDO 0     /* material texture while drawing the scene */
#define TEX_SHADOW_2D 1  /* shadow map of a directional/spot light */
#define TEX_SHADOW_CUBE 2
#define TEX_GB_SURFACE 3  /* G-buffer RGBA32UI: position bits, octahedral normal (common/gbuffer.glsl) */
#define TEX_GB_MATERIAL 4 /* G-buffer RGBA32UI: base colour, roughness, emission, metallic, specular weight */
#define TEX_BRDF_ALBEDO 5 /* RG32F BRDF_ALBEDO_N²: the GGX lobe's directional albedo terms A, B (src/core/brdf.c) */
#define TEX_HDR 7
#define TEX_RSM 8        /* RGBA32UI: position, normal, flux packed (common/rsm_texel.glsl) */
#define TEX_PROBE_MAP 8  /* rtgi probe: its maps k = 0..3 at 8 + k (3: the packed RSM texels); the probe binds nothing else */
#define TEX_GI 11        /* indirect irradiance */
#define TEX_INPUT 12     /* a technique's intermediate image (low-res, de-interleaved, pre-blur) */
#define TEX_REFERENCE 12 /* the window's A/B view: the --compare image (shares TEX_INPUT's unit) */
#define TEX_SPECULAR 13  /* a technique's indirect specular radiance */
#define TEX_LDR 31       /* tone-mapped colour (FXAA's input, linear filtering) */
#define TEX_MATERIAL_MR 33 /* glTF metallicRoughness texture while drawing the scene (G roughness, B metallic); past
                              the 0..31 units a fragment stage has, still below GL 4.5's 80 combined units */
/* TEX_SHADOW_2D's and TEX_SHADOW_CUBE's maps again, through a depth-compare
 * sampler object (the grid PCF's taps): units no other pass binds, as the
 * sampler object stays bound to them. */
#define TEX_SHADOW_COMPARE_2D 34
#define TEX_SHADOW_COMPARE_CUBE 35
#define TEX_ISM 36       /* ism: R32UI atlas of paraboloid depth maps (distance's float bits), read by the gathers */
#define TEX_LPV_GV0 14   /* lpv: geometry volume, normal tensor xx yy zz */
#define TEX_LPV_GV1 15   /* lpv: geometry volume, normal tensor xy xz yz */
#define TEX_LPV_SUM 16   /* lpv lookup: accumulated SH of every VPL in cascade k: 16 + 3k + channel (16..24) */
#define TEX_LPV_OUTER 25 /* lpv lookup: same, only VPLs outside cascade k-1: 25 + 3(k-1) + channel (25..30) */
#define TEX_VCT_ALBEDO 14   /* vct: voxel albedo (rgb) and opacity (a), N³ */
#define TEX_VCT_NORMAL 15   /* vct: voxel normal (xyz, sign-canonical: two-sided) */
#define TEX_VCT_RADIANCE 16 /* vct: premultiplied outgoing radiance (rgb) and opacity (a), N³ with mips */
#define TEX_VCT_ANISO 17    /* vct: directional volumes of x, y, z (each both signs, GpuVctParams), 17..19 */
/* Image units */
#define IMG_OUT 0        /* image written by GI compute passes */
#define IMG_HDR 0        /* the frame's compute passes: radiance (RGBA32F) read and written */
#define IMG_LDR 1        /* the frame's compute passes: display image written (RGBA8, sRGB-encoded bytes) */
#define IMG_OUT2 1       /* second image (de-interleaving writes two) */
#define IMG_VBUFFER_ID 2 /* --gbuffer visibility: the R32UI visibility image its compute passes read (frame/vbuffer.glsl) */
#define IMG_LPV_STEP_SRC 0 /* lpv propagation: the last step's SH light, R, G, B side by side in x (3N × N × N) */
#define IMG_LPV_STEP_DST 1 /* lpv propagation: this step's, the same layout */
#define IMG_LPV_FACES 2  /* lpv propagation with occlusion: vec4[8] per cell side by side in x (8N × N × N), the faces' factors */
#define IMG_LPV_DST 2    /* lpv injection and geometry resolves: the volumes written (R, G, B), 2..4 */
#define IMG_LPV_SUM 5    /* lpv propagation: 3 accumulated SH volumes (R, G, B), 5..7 */
#define IMG_RSM 7        /* an RSM read texel by texel (common/rsm_layers.glsl); never beside lpv propagation */
#define IMG_VCT_DST 2    /* vct: volume level written (resolve, injection, mips (first directional level: x), bounce) */
#define IMG_VCT_DST2 3   /* vct: second volume written (resolve: normals; the first directional level: y) */
#define IMG_VCT_SRC 4    /* vct mips: volume level read */
#define IMG_VCT_DST3 5   /* vct mips: third volume written (the first directional level: z) */
/* Sizes */
#define VPL_TILE 16          /* culling tile size in pixels */
/* Importance-sampled RSM gathers: a pixel spends half its N samples on the
 * paper's disk around its own projection and the rest on one of this many
 * independently shifted sets of flux-importance samples (a constant: the
 * gathers pick a pixel's set with a mask, not a division). */
#define RSM_LIST_SETS 16
/* SSBO_TILES: counts[ntiles], the overflow count, padding to a multiple of
 * 4 words, then ntiles lists of tile_capacity (a multiple of 4) indices,
 * each padded with index 0 to a multiple of 4 entries: the shading loop
 * reads them as uvec4s, one load per 4 candidates. */
#define VPL_TILE_LIST_BASE(ntiles) (((ntiles) + 4u) & ~3u)
#define SHADOW_MAX_SAMPLES 64 /* Poisson disk entries */
#define LPV_MAX_CASCADES 3   /* nested LPV grids */
#define LPV_GEOMETRY_RUN 32  /* lpv compute geometry: texels of a row per invocation (gi/lpv/geometry_fixed.comp) */
#define LPV_INJECT_RUN 32     /* lpv compute injection: consecutive VPLs per invocation (gi/lpv/inject_fixed.comp) */
#define VCT_MAX_CONES 16     /* diffuse cones of the largest set */
#define VCT_MAX_LEVELS 4     /* clipmap levels */
#define VBUFFER_TRIANGLE_BITS 11 /* a visibility texel: (cluster << 11 | triangle in it) + 1 (0: no surface); 2^11 = GPU_CLUSTER_TRIANGLES */
#define VBUFFER_GROUP 64         /* frame/vbuffer_resolve.comp: binned pixels per work group */
#define ISM_EMPTY 0x7f7fffffu /* an ISM texel no point reached: FLT_MAX's bits (visible from any distance) */

/* ---- Uniform locations -------------------------------------------------- */
/* Every program that draws the scene's meshes (scene.vert + a fragment shader). */
#define LOC_MATERIAL_ALBEDO 0   /* vec3 */
#define LOC_MATERIAL_HAS_TEX 1  /* int */
#define LOC_MATERIAL_CUTOFF 2   /* float; < 0: no alpha mask */
#define LOC_MATERIAL_EMISSION 3 /* vec3 */
#define LOC_VIEW_PROJ 4         /* mat4 */
#define LOC_EYE 5               /* vec3: camera or light position (for facing) */
#define LOC_MATERIAL_PBR 6      /* vec4: metallic, roughness, specular weight, 1 if it has a metallicRoughness texture */
#define LOC_VBUFFER_DRAW 7      /* frame/vbuffer.frag: uint, the GpuScene cluster drawn (gpu_scene_draw_view's draw ids) */
#define LOC_VBUFFER_MATERIAL 8  /* frame/vbuffer_resolve.comp: uint, the material whose pixels it resolves */
/* Per-program uniforms (each program's own locations, from 10 up). */
#define LOC_RSM_FACE_AXIS 12    /* rsm.frag: vec3 unit axis of the face / spot (past scene.vert's FLAT_UNIFORMS locations) */
#define LOC_RSM_TEXEL_AREA 13   /* rsm.frag: float texel area on the projection plane */
#define LOC_DIRECT_EMISSION 10  /* forward.frag: int, first light of the frame: add emitted radiance, unblended */
#define LOC_DIRECT_AREA_LIGHT 11 /* forward.frag, shade.comp: int, AREA_LIGHT_EXACT or AREA_LIGHT_POINT */
#define LOC_SHADE_STEPS 10      /* frame/shade.comp: int, SHADE_* bits: what this dispatch does */
#define LOC_COMPOSITE_SPECULAR 12 /* frame/shade.comp: int, add the technique's specular image */
#define LOC_FINISH_FACTOR 10    /* frame/finish.comp: int, supersampling factor N (1: tone map only) */
#define LOC_FINISH_RADIANCE 11  /* frame/finish.comp: int, 1: write the resolved radiance too */
/* frame/shade.comp's steps (LOC_SHADE_STEPS): a frame of one light and no
 * supersampling is one dispatch with every bit but SHADE_ACCUMULATE. */
#define SHADE_ACCUMULATE 1 /* add to the radiance image (lights after the first) */
#define SHADE_EMISSION 2   /* add the surfaces' emitted radiance (the first light's dispatch) */
#define SHADE_LIGHT 4      /* the light bound at UBO_LIGHT (none: a frame without lights) */
#define SHADE_COMPOSITE 8  /* add the GI technique's indirect light (the last dispatch) */
#define SHADE_TONEMAP 16   /* write the display image at IMG_LDR (the last dispatch, no supersampling) */
#define SHADE_GROUP 8      /* work group: SHADE_GROUP² pixels (shade, finish, fxaa) */
#define LOC_VPL_STRIDE 10       /* vpl_extract.comp: int, texels per side of the block one VPL stands for */
#define LOC_AB_MODE 10          /* ui/ab_view.frag: int, 0 render, 1 reference, 2 split, 3 difference */
#define LOC_AB_SPLIT 11         /* ui/ab_view.frag: float, split position in [0, 1] of the width */
#define LOC_AB_EXPOSURE 12      /* ui/ab_view.frag: float, the reference's exposure */
#define LOC_AB_DIFF_SCALE 13    /* ui/ab_view.frag: float, |difference| shown as full heat */
#define LOC_AB_REF_DISPLAY 14   /* ui/ab_view.frag: int, 1 if the reference is display-referred (PNG/JPEG) */
#define LOC_GATHER_ACCUMULATE 11 /* rsm gather: int, add to the image (lights after the first) */
#define LOC_IMPORTANCE_LEVEL 10 /* gi/rsm/importance.comp: int, pyramid level written / top level */
#define LOC_CHUNK 12            /* rsm gather (exhaustive), vpl shade: uint, first index of this dispatch's chunk */

/* The opaque-voxel list holds up to 1/VCT_OPAQUE_SHARE of the voxels (a
 * surface fills a few percent of a fine grid); fuller volumes inject over
 * every voxel instead. */
#define VCT_OPAQUE_SHARE 8
/* The voxel volumes' alpha is occupancy density β: optical depth
 * β·VCT_OPTICAL_DEPTH per level-0 voxel of path, so that a full voxel
 * (β = 1) lets e^-4.6 = 1% through and box filtering (mips, trilinear
 * taps) keeps a wall's optical depth across it at every mip (gi/vct/
 * cone.glsl); rgb is radiance × β. */
#define VCT_OPTICAL_DEPTH 4.6

/* Sums over VPLs run as one dispatch per LOOP_CHUNK of them, each adding to
 * the image: llvmpipe ends any one shader loop after 65535 iterations
 * (gallivm's guard against endless loops), nested or not. */
#define LOOP_CHUNK 32768
#define LOC_LPV_CASCADE 10      /* lpv inject/geometry/propagate: int, the cascade being built */
#define LOC_LPV_SURFEL_AREA 11  /* lpv geometry: float, max surfel area (m^2) */
#define LOC_LPV_EXCLUDE 12      /* lpv inject: int, skip VPLs inside this (finer) cascade; -1: none */
#define LOC_LPV_FIXED_SCALE 13  /* lpv compute injection: float, fixed-point units per W/sr */
#define LOC_LPV_GROUP 14        /* lpv inject/propagate: int, the light group built (gi/lpv/sh.glsl, lpv_group); -1: one group */
#define LOC_VCT_AXIS 10         /* vct mips: int, the directional volumes' axis 0..2 (x y z) */
#define LOC_VCT_MIP 12          /* vct mips: int, the directional level written (1..: its children are 2^level level-0 voxels) */
#define LOC_VCT_ACCUMULATE 10   /* vct inject: int, add to the level written (lights after the first) */
#define LOC_VCT_AO_OUT 10       /* vct trace: int, 1 writes ambient visibility into the irradiance alpha */
#define LOC_VCT_SCALE 11        /* vct trace, upsample: int, cones traced at every scale-th pixel per axis */
#define LOC_VCT_LEVEL 20        /* vct voxelize: int, the clipmap level drawn */
#define LOC_VCT_RUN 21          /* vct voxelize.comp: uvec4, first triangle, triangles, header, list start */
#define LOC_VCT_REGION_LO 22    /* vct voxelize, resolve: ivec4, xyz the region's first voxel (resolve: stacked) */
#define LOC_VCT_REGION_HI 23    /* vct voxelize, resolve: ivec4, xyz past its last voxel, w 1 (0: no region, every voxel) */
#define LOC_VCT_REGIONS 24      /* vct list.comp (LIST_FILTER): ivec4[2 · VCT_MAX_LEVELS], per level the region's lo, hi (stacked) */
#define LOC_COUNT_STEP 10       /* gi/count_surfaces.comp: int, the lattice's step */
#define LOC_ISM_MAP_BASE 15     /* rsm gathers, ism passes: uint, the first map of the light being gathered */
#define LOC_ISM_PUSH 16         /* gi/visibility/pull_push.comp: int, 0 pull, 1 push */
#define LOC_TEMPORAL_PREV_VIEW_PROJ 10 /* temporal/accumulate.comp: mat4 (10..13), the previous frame's camera */
#define LOC_TEMPORAL_PARAMS 14  /* temporal/accumulate.comp: vec4, x: least blend weight α of the new frame,
                                   y: 1 with a history, z: plane tolerance (fraction of the distance), w: clamp γ */
/* temporal/accumulate.comp (renderer's temporal accumulation, pass_temporal.h): */
#define TEX_TEMPORAL_HISTORY 9   /* RGBA32F: the accumulated irradiance of the last frame (a: frames in it) */
#define TEX_TEMPORAL_SURFACE 10  /* RGBA32UI: the last frame's G-buffer surface (common/gbuffer.glsl) */

/* ---- Constants ------------------------------------------------------------ */
#ifdef GL_core_profile
/* C has these as enums: LightType (scene.h) and ShadowMode (pass_direct.h),
 * with the same values (checked in tests/test_layout.c). */
#define LIGHT_DIRECTIONAL 0
#define LIGHT_SPOT 1
#define LIGHT_POINT 2
#define LIGHT_QUAD 3
#define SHADOW_NONE 0
#define SHADOW_HARD 1
#define SHADOW_PCF 2
#define SHADOW_PCSS 3
/* RSM weightings (gi/rsm/gather.comp compiles one in: WEIGHTING) */
#define RSM_WEIGHT_PAPER 0
#define RSM_WEIGHT_UNBIASED 1
#define RSM_WEIGHT_IMPORTANCE 2
#define SHADOW_BIAS_RECEIVER_PLANE 0
#define SHADOW_BIAS_LEGACY 1
/* GpuShadowParams.pcf_filter: PCF's taps (SHADOW_PCF only; PCSS filters on the disk) */
#define SHADOW_FILTER_DISK 0 /* pcf_samples depth tests on a Poisson disk turned per pixel */
#define SHADOW_FILTER_GRID 1 /* a square of bilinear depth-compare taps one texel apart (radius 1: 3x3 tent) */
#define AREA_LIGHT_EXACT 0
#define AREA_LIGHT_POINT 1
#endif

/* ---- Blocks ------------------------------------------------------------- */

/* One light as the shaders see it (std140; also the light stage's array). */
#define GPU_LIGHT_FIELDS(F, A)                                                                        \
    F(vec4, position_type)    /* xyz: position; w: LightType */                                      \
    F(vec4, direction_width)  /* xyz: unit direction; w: PCSS width (m), or tan of the sun's angular diameter */ \
    F(vec4, color)            /* rgb: E (directional), I (spot, point), L·A (quad) */                \
    F(vec4, spot)             /* x: cos outer, y: cos inner */                                       \
    F(mat4, shadow_view_proj) /* directional/spot: world → shadow clip space */                      \
    F(vec4, shadow_origin)    /* directional: point on the ortho near plane; others: light position */ \
    F(vec4, shadow_info)      /* x: far (stored depth × far = m), y: texel factor k, z: map resolution, w: 1 for a cube */ \
    F(vec4, quad_u)           /* quad: full edge vector u at the light's size (m); rgb of color is then L·A */ \
    F(vec4, quad_v)           /* quad: full edge vector v; corners = position ± u/2 ± v/2; w: area A (m²) */ \
    F(vec4, rsm_box_min)      /* RSM texels (common/rsm_texel.glsl): xyz min corner of the position box; w: flux unit (W) */ \
    F(vec4, rsm_box_step)     /* xyz: the position quantum per axis (m), the box over 2^21 − 1 */

/* Shadow filtering (std140). */
#define GPU_SHADOW_PARAMS_FIELDS(F, A)                                          \
    F(float, bias_const)      /* constant bias (m) */                          \
    F(float, bias_slope)      /* slope-scaled bias (texels × tanθ) */          \
    F(float, normal_offset)   /* receiver offset along the normal (texels) */  \
    F(int, mode)              /* SHADOW_NONE .. SHADOW_PCSS */                 \
    F(float, pcf_radius)      /* PCF filter radius (texels) */                 \
    F(int, pcf_samples)       /* Poisson samples of the PCF filter */          \
    F(int, blocker_samples)   /* PCSS blocker-search samples */                \
    F(float, pcss_max_radius) /* PCSS search/filter radius cap (texels) */     \
    A(vec4, poisson, SHADOW_MAX_SAMPLES) /* xy: Poisson disk in the unit disk */ \
    F(int, filter_bias)       /* SHADOW_BIAS_RECEIVER_PLANE or SHADOW_BIAS_LEGACY (PCF/PCSS) */ \
    F(int, pcf_filter)        /* SHADOW_FILTER_DISK or SHADOW_FILTER_GRID */

/* Per-frame values every screen-space pass may read (std140). */
#define GPU_FRAME_FIELDS(F, A)                                              \
    F(vec4, camera)          /* xyz: camera position */                    \
    F(int, width)            /* output size in pixels */                   \
    F(int, height)                                                         \
    F(float, indirect_scale) /* multiplies the GI technique's irradiance */ \
    F(float, exposure)       /* radiance multiplier before tone mapping */

/* RSM gathers and the screen-space interpolation / interleaving (std140).
 * A member holding a setting is named family_field (rsm.samples:
 * rsm_samples); in the one-family blocks below, field (lpv.offset: u_lpv.offset). */
#define GPU_GI_PARAMS_FIELDS(F, A)                                                  \
    F(float, rsm_r_max)     /* rsm.r_max: sampling radius, RSM widths (cube: face widths) */ \
    F(int, rsm_samples)     /* rsm.samples: N samples per gather */                \
    F(int, rsm_size)        /* rsm.size, or what vpl.count sets: RSM resolution */ \
    F(float, disk_texels)   /* texels in the sampling disk, K = π (r_max·res)² */   \
    F(int, rsm_interp_factor) /* rsm-interp: low-res = full / factor */            \
    F(float, rsm_interp_normal) /* min cosine between normals of usable samples */ \
    F(float, rsm_interp_dist) /* max distance, fraction of the view distance */    \
    F(int, low_width)       /* rsm-interp low-resolution size */                   \
    F(int, low_height)                                                             \
    F(int, interleave_pattern_n) /* interleave.pattern n × m */                       \
    F(int, interleave_pattern_m)                                                   \
    F(int, sub_width)       /* de-interleaved sub-image size */                    \
    F(int, sub_height)                                                             \
    F(int, list_size)       /* importance: entries in the sample list (sets × set) */ \
    F(int, list_set)        /* importance: points per set (the far-field samples of a pixel) */ \
    F(float, disk_r2_per_area) /* --vpl-disk: 1/π (samples fall off as 1/(d² + A/π)); 0: points */

/* One virtual point light (std430). The shading loops read surface and flux
 * only (common/vpl_record.glsl): two loads per VPL, where llvmpipe loads
 * each per lane (issue 11); culling, ranges and injection read normal_xi. */
#define GPU_VPL_FIELDS(F, A)                                          \
    F(uvec4, surface)  /* xyz: position (m, the floats' bits); w: lit side's normal, pack_oct16 */ \
    F(vec4, flux)      /* rgb: reflected flux Φ (W); w: area of the surface it stands for (m²) */     \
    F(vec4, normal_xi) /* xyz: the same unit normal, unpacked; w: its fixed random ξ in (0,1] */

/* Many-VPL shading (std140). */
#define GPU_VPL_PARAMS_FIELDS(F, A)                                               \
    F(float, slc_emax)      /* stochastic light culling error bound e_max */     \
    F(float, slc_exposure)  /* exposure E of the SLC error bound */              \
    F(float, near_clamp)    /* falloff 1/max(d², c), c in m²; 0 = off */         \
    F(float, range)         /* vpl.range, or 0.15 x the scene diagonal where 0: vpl-clamped range R (m) */ \
    F(float, keep)          /* vpl-all: kept fraction q */                       \
    F(uint, tile_capacity)  /* list entries per culling tile */                  \
    F(uint, subset_count)   /* K = n·m interleaved subsets */                    \
    F(uint, subset_len)     /* L VPLs per subset */                              \
    F(int, tiles_x)         /* culling tile counts */                            \
    F(int, tiles_y)                                                              \
    F(int, signature_w)     /* metalight signature grid */                       \
    F(int, signature_h)                                                          \
    F(int, disk)            /* 1: VPLs fall off as disks of their area, 1/(d² + A/π) */

/* Light propagation volumes (std140). Cell (i,j,k) of cascade c spans
 * origin + [i, i+1)·cell; its geometry volume is offset by half a cell
 * (GV cell (i,j,k) is centred on LPV corner (i,j,k), N+1 per side). */
#define GPU_LPV_PARAMS_FIELDS(F, A)                                                   \
    F(int, size)            /* N cells per side */                                  \
    F(int, pad3)            /* (occlusion is compiled in: OCCLUSION, propagate.comp) */ \
    F(float, offset)        /* VPLs move this many cells along their normal */      \
    F(int, vpl_count_max)   /* entries the injection may read (capacity) */        \
    F(float, blend)         /* cascade blend band, fraction of a cascade's extent */ \
    F(float, pad0)          /* (the cascade count is compiled in: LPV_CASCADES) */  \
    F(float, pad1)                                                                   \
    F(float, pad2)                                                                   \
    A(vec4, cascade, LPV_MAX_CASCADES) /* xyz: grid origin (min corner, m); w: cell size (m) */

/* Voxel cone tracing (std140). Level k of the clipmap (k = 0 finest; one
 * level: the volume over the scene bounds) has N³ voxels, voxel (i,j,k')
 * spanning level[k].xyz + [i, i+1)·level[k].w; the levels are stacked
 * along z in one N × N × N·L texture. The directional volumes start at mip
 * 1: one N/2 × N/2 × 2·S·L texture per axis, slab 2k + s (S deep) holding
 * level k seen along the axis (s = 0) or against it (s = 1), its N/2
 * voxels at the front of the slab; S is N/2 rounded up so that every mip
 * halves it exactly (S = N/2 for a power-of-two N). One texture for both
 * signs lets a cone read the side it faces in one fetch per axis. */
#define GPU_VCT_PARAMS_FIELDS(F, A)                                                        \
    F(int, size)             /* N voxels per side of a level */                             \
    F(int, mips)             /* mips of a level: log2(N) + 1 */                             \
    F(int, aniso)            /* 1: the directional volumes are built (tracers: VCT_ANISO) */ \
    F(int, cones)            /* diffuse cones in use */                                     \
    F(float, step)           /* sampling step, in cone diameters */                         \
    F(float, ao_range)       /* occlusion counts up to this distance (m) */                 \
    F(int, conservative)     /* 1: conservative voxelization */                             \
    F(float, roughness)      /* perceptual roughness of every surface when f0 > 0 */        \
    F(float, f0)             /* > 0: F0 of every surface (tests); 0: the G-buffer's */       \
    F(float, max_distance)   /* cones stop after this distance (m) */                       \
    F(int, levels)           /* vct.levels: L clipmap levels (1: one volume over the bounds) */                 \
    F(int, aniso_slab)       /* S: a directional slab's depth at its mip 0 (texels) */      \
    A(vec4, level, VCT_MAX_LEVELS) /* xyz: min corner of level k (m); w: its voxel size (m) */ \
    A(vec4, cone, VCT_MAX_CONES) /* xyz: unit direction in the normal's frame (z = normal); w: weight ∫cosθ dω of its cell */ \
    A(vec4, cone_aperture, VCT_MAX_CONES) /* x: tan of the half-angle */

/* Imperfect shadow maps (std140; src/gi/visibility/ism.c): map m is an
 * size × size paraboloid depth map at (m mod per_row, m / per_row)·size
 * in the atlas, seen from its source (a VPL, or the representative texel
 * of an RSM block) along the source's normal. Its points: far_points of
 * the whole scene's (SSBO_ISM_POINTS, sorted by the cells of a grid_n³
 * grid), and near_points of those in the 3×3×3 cells around the source
 * (SSBO_ISM_CELLS: cell c's points are [start[c], start[c + 1])). */
#define GPU_ISM_PARAMS_FIELDS(F, A)                                                    \
    F(int, size)            /* texels per side of one map */                          \
    F(int, per_row)         /* maps per atlas row (a power of two) */                 \
    F(uint, far_points)     /* points of the whole scene splatted into each map */    \
    F(uint, point_count)    /* points in SSBO_ISM_POINTS (a power of two) */           \
    F(float, far_area)      /* scene area one far point stands for (m²) */            \
    F(float, bias_rel)      /* visible while distance <= stored + bias (ism.glsl) */  \
    F(float, bias_abs)      /* (m) */                                                  \
    F(uint, maps)           /* maps in the atlas */                                    \
    F(int, blocks)          /* from an RSM: blocks per side of each layer */           \
    F(int, block_texels)    /* from an RSM: texels per side of a block */              \
    F(int, rsm_size)        /* from an RSM: its texels per side */                     \
    F(uint, maps_per_light) /* from an RSM: maps of each light (light i's start at i times this) */ \
    F(uint, near_points)    /* points of the cells around the source splatted into each map */ \
    F(int, grid_n)          /* cells per side of the points' grid */                   \
    F(float, point_area)    /* scene area one point of the buffer stands for (m²) */  \
    F(uint, far_stride)     /* far points: odd step through the sorted buffer */       \
    F(vec4, grid)           /* xyz: the grid's min corner (m); w: its cell size (m) */

/* A scene material as the visibility buffer's resolve reads it (std430;
 * frame/vbuffer_*.comp, common/material.glsl's MATERIAL_ROW): the
 * constants gpu_scene_bind_material sets as uniforms. */
#define GPU_MATERIAL_FIELDS(F, A)                                                        \
    F(vec4, albedo)   /* rgb: base colour factor; w: 1 if it has a base colour texture */ \
    F(vec4, emission) /* rgb: emitted radiance; w: alpha cutoff, < 0: no alpha mask */    \
    F(vec4, pbr)      /* metallic, roughness, specular weight, 1 if it has a metallicRoughness texture */

/* ---- Declarations --------------------------------------------------------- */
#ifdef GL_core_profile /* GLSL */
#define GPU_MEMBER(t, n) t n;
#define GPU_ARRAY(t, n, c) t n[c];
#define GPU_STRUCT(name, LIST) struct name { LIST(GPU_MEMBER, GPU_ARRAY) };
#else /* C */
#include <assert.h>
#include <stdint.h>
typedef float GPU_C_float;
typedef int32_t GPU_C_int;
typedef uint32_t GPU_C_uint;
typedef float GPU_C_vec4[4] __attribute__((aligned(16)));
typedef int32_t GPU_C_ivec4[4] __attribute__((aligned(16)));
typedef uint32_t GPU_C_uvec4[4] __attribute__((aligned(16)));
typedef float GPU_C_mat4[16] __attribute__((aligned(16)));
#define GPU_MEMBER(t, n) GPU_C_##t n;
#define GPU_ARRAY(t, n, c) GPU_C_##t n[c];
#define GPU_STRUCT(name, LIST) typedef struct name { LIST(GPU_MEMBER, GPU_ARRAY) } name;
#endif

GPU_STRUCT(GpuLight, GPU_LIGHT_FIELDS)
GPU_STRUCT(GpuShadowParams, GPU_SHADOW_PARAMS_FIELDS)
GPU_STRUCT(GpuFrame, GPU_FRAME_FIELDS)
GPU_STRUCT(GpuGiParams, GPU_GI_PARAMS_FIELDS)
GPU_STRUCT(GpuVpl, GPU_VPL_FIELDS)
GPU_STRUCT(GpuVplParams, GPU_VPL_PARAMS_FIELDS)
GPU_STRUCT(GpuLpvParams, GPU_LPV_PARAMS_FIELDS)
GPU_STRUCT(GpuVctParams, GPU_VCT_PARAMS_FIELDS)
GPU_STRUCT(GpuIsmParams, GPU_ISM_PARAMS_FIELDS)
GPU_STRUCT(GpuMaterial, GPU_MATERIAL_FIELDS)

#ifdef GL_core_profile
/* The blocks, as every shader names them. */
layout(std140, binding = UBO_LIGHT) uniform LightBlock { GpuLight u_light; };
layout(std140, binding = UBO_SHADOW) uniform ShadowBlock { GpuShadowParams u_shadow; };
layout(std140, binding = UBO_FRAME) uniform FrameBlock { GpuFrame u_frame; };
layout(std140, binding = UBO_GI) uniform GiBlock { GpuGiParams u_gi; };
layout(std140, binding = UBO_VPL) uniform VplParamBlock { GpuVplParams u_vpl; };
layout(std140, binding = UBO_LPV) uniform LpvBlock { GpuLpvParams u_lpv; };
layout(std140, binding = UBO_VCT) uniform VctBlock { GpuVctParams u_vct; };
layout(std140, binding = UBO_ISM) uniform IsmBlock { GpuIsmParams u_ism; };
#else
static_assert(sizeof(GpuLight) == 14 * 16, "GpuLight: std140 size");
static_assert(sizeof(GpuShadowParams) == 3 * 16 + SHADOW_MAX_SAMPLES * 16, "GpuShadowParams: std140 size");
static_assert(sizeof(GpuFrame) == 2 * 16, "GpuFrame: std140 size");
static_assert(sizeof(GpuGiParams) == 16 * 4, "GpuGiParams: 16 scalars (std140 rounds the block to 64)");
static_assert(sizeof(GpuVpl) == 48, "GpuVpl: std430 size");
static_assert(sizeof(GpuVplParams) == 13 * 4, "GpuVplParams: 13 scalars (std140 rounds the block to 64)");
static_assert(sizeof(GpuLpvParams) == 2 * 16 + LPV_MAX_CASCADES * 16, "GpuLpvParams: std140 size");
static_assert(sizeof(GpuIsmParams) == 5 * 16, "GpuIsmParams: std140 size");
static_assert(sizeof(GpuMaterial) == 3 * 16, "GpuMaterial: std430 size");
static_assert(sizeof(GpuVctParams) == 3 * 16 + VCT_MAX_LEVELS * 16 + 2 * VCT_MAX_CONES * 16, "GpuVctParams: std140 size");

#include <string.h>
/* A GpuVpl's position, stored as the floats' bits. */
static inline void gpu_vpl_position(const GpuVpl *v, float p[3]) { memcpy(p, v->surface, 3 * sizeof(float)); }
static inline void gpu_vpl_set_position(GpuVpl *v, const float p[3]) { memcpy(v->surface, p, 3 * sizeof(float)); }
#endif

#endif
