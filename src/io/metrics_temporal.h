/* metrics_temporal.h — measures of an image sequence over time (SPEC §10):
 * flicker, and a kymograph that shows it.
 *  - flicker: the mean over frames t = 1 .. n−2, the pixels every one of
 *    frames t−1, t, t+1 selects, and the channels of
 *    |x_t − (x_{t−1} + x_{t+1}) / 2|, divided by the mean radiance (over
 *    every frame, selected pixel and channel). The second difference in
 *    time: a light or camera moving at a steady pace adds little, noise
 *    that changes from frame to frame adds its full size. A static
 *    sequence of equal frames has flicker 0.
 *  - kymograph: one row of every frame stacked, frame t as row t: boiling
 *    and crawling show as speckle down the columns.
 * Frames are added one at a time (a sequence need not be held whole). */
#ifndef RTGI_METRICS_TEMPORAL_H
#define RTGI_METRICS_TEMPORAL_H

#include <stdbool.h>
#include <stdint.h>

#include "io/image.h"

typedef struct FlickerSum {
    ImageF prev[2];      /* frames t−2 and t−1 (copies) */
    uint8_t *mask[2];    /* their masks (NULL: all pixels) */
    double abs_sum;      /* Σ of the second differences */
    double abs_count;    /* values in abs_sum */
    double radiance_sum; /* Σ of every frame's selected values */
    double radiance_count;
    int frames;          /* frames added */
    bool failed;         /* a copy could not be allocated (logged) */
} FlickerSum;

/* Adds the next frame (all frames of one size) with its mask (NULL: every
 * pixel). */
void flicker_add(FlickerSum *f, const ImageF *frame, const uint8_t *mask);
/* The flicker of the frames added: 0 for a sequence of equal frames; NaN
 * with fewer than 3 frames, a black sequence or after a failed copy. */
double flicker_value(const FlickerSum *f);
void flicker_free(FlickerSum *f);

/* Row `row` of `frame` into row `t` of `kymo` (width × frames, made by the
 * caller with image_alloc). */
void kymograph_add(ImageF *kymo, int t, const ImageF *frame, int row);

#endif
