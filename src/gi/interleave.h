/* interleave.h — interleaved sampling around a GI pass (Keller & Heidrich
 * 2001; Segovia et al. 2006), shared by rsm-interleaved and the interleaved
 * VPL techniques:
 *   split  G-buffer → n×m de-interleaved sub-images (pixel (x, y) goes to
 *          sub-image (x mod n, y mod m) at (x / n, y / m))
 *   merge  the shaded sub-images back to the interleaved layout (with
 *          the blur: both in one pass)
 *   blur   geometry-aware blur over the n×m window: neighbours whose normal
 *          and position agree (the interpolation's thresholds, GpuGiParams)
 * Reads UBO_GI (interleave_pattern_n/m, sub size, thresholds) and UBO_FRAME.
 * Owns: the de-interleaved textures (when made with
 * `deinterleave`) or the pre-blur image (without). Shader: shaders/gi/interleave.comp. */
#ifndef RTGI_GI_INTERLEAVE_H
#define RTGI_GI_INTERLEAVE_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "gl/shader.h"
#include "gpu/targets.h"

typedef struct GiInterleave {
    GLuint split, merge, blur;     /* programs from the cache (split/merge only with de-interleaving) */
    GLuint merge_blur;             /* merge and blur in one pass (with de-interleaving) */
    int n, m;                      /* pattern */
    int width, height;             /* full resolution */
    int sub_w, sub_h;              /* sub-image size */
    int di_w, di_h;                /* de-interleaved layout: n·sub_w × m·sub_h */
    GLuint di_surface;             /* de-interleaved G-buffer surface texels (RGBA32UI) */
    GLuint di_irradiance;          /* de-interleaved result */
    GLuint merged;                 /* without de-interleaving: shaded, before the blur */
} GiInterleave;

/* The n × m pattern as shader defines (INTERLEAVE_N, INTERLEAVE_M) after
 * the line `mode` (e.g. "#define MODE_BLUR"): programs that divide by the
 * pattern take it compiled in (llvmpipe divides by a value it cannot see
 * lane by lane). */
void gi_interleave_defines(char *out, size_t size, const char *mode, int n, int m);

/* Programs come from `pc`. */
bool gi_interleave_create(GiInterleave *g, ProgramCache *pc, int n, int m, int width, int height, bool deinterleave);
void gi_interleave_destroy(GiInterleave *g);
/* GPU memory of its images (gl_texture_bytes). */
uint64_t gi_interleave_bytes(const GiInterleave *g);
void gi_interleave_split(GiInterleave *g, const GBuffer *gb);
/* Reassembles di_irradiance into `out`; with `blur`, blurred in the same pass. */
void gi_interleave_merge(GiInterleave *g, const GBuffer *gb, bool blur, GLuint out);
/* Geometry-aware blur of `in` into `out` (in ≠ out). */
void gi_interleave_blur(GiInterleave *g, const GBuffer *gb, GLuint in, GLuint out);

#endif
