/* pathtracer.h — the CPU reference: unidirectional path tracing on Embree 3
 * over the same Scene the rasterizer draws (SPEC §7).
 * Next-event estimation for every light type, MIS (power heuristic) with
 * BSDF sampling for quad area lights (the only emitters BSDF rays can hit),
 * bounces that sample the BRDF of brdf.h (GGX visible normals or the
 * cosine lobe, chosen by the ratio of Fresnel to diffuse reflectance),
 * Russian roulette after `rr_depth` bounces with survival probability from
 * the path throughput (compensated by 1/p). Multithreaded over 16×16 tiles;
 * a pixel's samples depend only on (seed, pixel, sample index) — Owen-
 * scrambled Sobol' pairs by default, or independent numbers (sampler.h) —
 * so the result is identical for a given seed whatever the thread count.
 * The image is rendered in passes of a few samples per pixel each (about
 * 2^18 samples a pass), summed in double precision; `stop`, a target
 * relMSE or a time budget end it after a pass with the samples reached.
 * Rays leave surfaces offset by 256 ulps of each coordinate along the
 * geometric normal (Wächter & Binder 2019; pt_scene.h).
 *
 * Light models are those of the rasterizer (light_intensity in scene.c):
 * size 0 gives point/directional lights with exactly the rasterizer's
 * intensity; a size makes a real emitter: quad (hit by BSDF rays, MIS),
 * sphere (point), disk facing the axis (spot), cone of directions (sun). */
#ifndef RTGI_PATHTRACER_H
#define RTGI_PATHTRACER_H

#include <stdbool.h>
#include <stdint.h>

#include "io/image.h"
#include "core/scene.h"
#include "reference/pt_settings.h"

extern const char *const pt_mode_names[]; /* NULL-terminated, in PtMode order */
extern const char *const pt_sampler_names[]; /* NULL-terminated, in PtSampler order */

void pt_settings_default(PtSettings *s);

/* Renders `scene` from its camera. `mean` receives radiance; `variance`
 * (optional) the per-pixel variance of that mean (sample variance / spp);
 * both are allocated here (the caller frees them with image_free) and are
 * empty on failure. false after logging (an allocation that fails is
 * named, with its size, in one 'reference' line). */
bool pt_render(const Scene *scene, const PtSettings *ps, ImageF *mean, ImageF *variance, PtStats *stats);

/* The pixels of a w×h image of the scene's camera that see an emitter (a
 * front face of emissive geometry) through their centre, and their 8
 * neighbours (the emitter's aliased edge): 0 there, 255 elsewhere, row 0 =
 * top. `render --emitter-mask` and `reference --emitter-mask` both write it,
 * so `compare --mask` can leave emitters out of the error. false after
 * logging. */
bool pt_emitter_mask(const Scene *scene, int w, int h, uint8_t *mask);
/* What each pixel of a w×h image of the scene's camera sees through its
 * centre (row 0 = top): material · 6 + face, where face is the dominant
 * axis of the geometric normal facing the camera, PT_FACE_* (+x, −x, +y,
 * −y, +z, −z); −1 where the ray leaves the scene. For measuring a
 * technique over one surface (tests/test_fidelity.c). false after logging. */
enum { PT_FACE_POS_X, PT_FACE_NEG_X, PT_FACE_POS_Y, PT_FACE_NEG_Y, PT_FACE_POS_Z, PT_FACE_NEG_Z };
bool pt_surface_map(const Scene *scene, int w, int h, int32_t *ids);
/* Writes that mask as an 8-bit PNG (black: excluded). false after logging. */
bool pt_write_emitter_mask(const Scene *scene, int w, int h, const char *path);

#endif
