/* metrics.h — image error metrics between a test image and a reference
 * (SPEC §8). Inputs are linear RGB images of equal size; `mask` (may be
 * NULL) selects the pixels that count (non-zero = counts).
 *  - RMSE: sqrt of the mean over pixels and channels of (t − r)².
 *  - relMSE: mean of (t − r)² / (r² + 0.01) over pixels and channels.
 *  - SSIM (Wang et al. 2004) on the luminance of the display-encoded images
 *    (× exposure, clamped, sRGB), Gaussian window σ = 1.5 px, C1 = 0.01²,
 *    C2 = 0.03².
 *  - FLIP (Andersson et al. 2020), LDR-FLIP on the display-encoded images at
 *    `ppd` pixels per degree (67.0: a 0.7 m wide 4K monitor at 0.7 m).
 * The *_map outputs (may be NULL) receive w·h per-pixel values.
 * SSIM and FLIP return NaN after logging if their image-sized scratch
 * buffers cannot be allocated; metric_alloc_failures counts such failures
 * (so a caller can tell them from a NaN input). */
#ifndef RTGI_METRICS_H
#define RTGI_METRICS_H

#include <stdbool.h>
#include <stdint.h>

#include "io/image.h"

#define FLIP_DEFAULT_PPD 67.0205f /* 0.7·3840/0.7 · π/180 */

int metric_alloc_failures(void);
double metric_rmse(const ImageF *test, const ImageF *ref, const uint8_t *mask, float *map);
double metric_relmse(const ImageF *test, const ImageF *ref, const uint8_t *mask, float *map);
double metric_ssim(const ImageF *test, const ImageF *ref, float exposure, const uint8_t *mask, float *map);
double metric_flip(const ImageF *test, const ImageF *ref, float exposure, float ppd, const uint8_t *mask, float *map);

/* Mean of `test` over mean of `ref` on the pixels `mask` selects (NULL:
 * all): of luminance as the result, per channel in rgb (may be NULL). A
 * ratio whose reference mean is 0 is NaN. Energy agreement: noise averages
 * out of it, a scale error (a lost factor π, a missing bounce) does not. */
double metric_mean_ratio(const ImageF *test, const ImageF *ref, const uint8_t *mask, double rgb[3]);

/* Shadow artefacts as measured quantities (SPEC §2: acne and
 * peter-panning), from a direct-light test image, the direct-light reference
 * of the same view and the test renderer's image of it without shadows
 * (`render --shadow none`). Visibility V = luminance(image) /
 * luminance(unshadowed) where the unshadowed luminance is above 1e-4 of its
 * mean (elsewhere no light reaches and nothing is counted). Pixels the
 * reference sees fully lit (V_ref >= 0.95) or fully shadowed (V_ref <=
 * 0.05) are classified; penumbrae are left out, so that an area light's
 * soft edge and a point light's hard one measure alike. */
typedef struct ShadowArtefacts {
    size_t lit, shadowed; /* pixels the reference sees fully lit, fully shadowed */
    double false_shadow;  /* share of the lit ones with test V < 0.5: acne, over-wide filters */
    double false_lit;     /* share of the shadowed ones with test V > 0.5: peter-panning, leaks */
} ShadowArtefacts;

/* NaN shares where no pixel is of that class. */
ShadowArtefacts metric_shadow_artefacts(const ImageF *test, const ImageF *ref, const ImageF *unshadowed,
                                        const uint8_t *mask);

/* Averages `img` over block×block pixel blocks (the pixels `mask` selects;
 * NULL: all) into `out` (ceil(w/block) × ceil(h/block)); `*out_mask`
 * (caller frees) marks the blocks that held any selected pixel. Comparing
 * block averages separates bias from per-pixel noise and edge aliasing.
 * false after logging. */
bool metric_block_average(const ImageF *img, const uint8_t *mask, int block, ImageF *out, uint8_t **out_mask);

/* Writes a heat map of values in [0,1] (clamped) as a PNG, magma-like colours. */
int metric_write_heatmap(const char *path, const float *map, int width, int height);
/* The same with a colour bar below the map (a band from 0 to 1, labelled
 * "0", `name` and `full`, the metric's value at full heat; the band alone
 * under 60 pixels wide): the PNG is width × (height + bar) pixels, the map
 * in its top `height` rows. */
int metric_write_heatmap_bar(const char *path, const float *map, int width, int height, const char *name,
                             double full);

#endif
