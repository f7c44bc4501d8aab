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

#include "image.h"

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

/* Averages `img` over block×block pixel blocks (the pixels `mask` selects;
 * NULL: all) into `out` (ceil(w/block) × ceil(h/block)); `*out_mask`
 * (caller frees) marks the blocks that held any selected pixel. Comparing
 * block averages separates bias from per-pixel noise and edge aliasing.
 * false after logging. */
bool metric_block_average(const ImageF *img, const uint8_t *mask, int block, ImageF *out, uint8_t **out_mask);

/* Writes a heat map of values in [0,1] (clamped) as a PNG, magma-like colours. */
int metric_write_heatmap(const char *path, const float *map, int width, int height);

#endif
