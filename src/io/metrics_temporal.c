/* metrics_temporal.c — flicker and kymographs (metrics_temporal.h). */
#include "io/metrics_temporal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/log.h"
#include "base/util.h"

/* Copies frame and mask into slot k, allocated on first use. */
static bool keep(FlickerSum *f, int k, const ImageF *frame, const uint8_t *mask)
{
    size_t np = (size_t)frame->width * frame->height;
    if (!f->prev[k].rgb && !image_alloc(&f->prev[k], frame->width, frame->height))
        return false;
    memcpy(f->prev[k].rgb, frame->rgb, sizeof(float) * 3 * np);
    free(f->mask[k]);
    f->mask[k] = NULL;
    if (mask) {
        if (!(f->mask[k] = util_malloc("metrics", "a flicker mask", np, 1)))
            return false;
        memcpy(f->mask[k], mask, np);
    }
    return true;
}

void flicker_add(FlickerSum *f, const ImageF *frame, const uint8_t *mask)
{
    if (f->failed)
        return;
    size_t np = (size_t)frame->width * frame->height;
    for (size_t i = 0; i < np; i++)
        if (!mask || mask[i])
            for (int c = 0; c < 3; c++) {
                f->radiance_sum += frame->rgb[3 * i + c];
                f->radiance_count += 1;
            }
    if (f->frames >= 2) {
        const ImageF *a = &f->prev[0], *b = &f->prev[1];
        for (size_t i = 0; i < np; i++) {
            if ((mask && !mask[i]) || (f->mask[0] && !f->mask[0][i]) || (f->mask[1] && !f->mask[1][i]))
                continue;
            for (int c = 0; c < 3; c++) {
                double d = b->rgb[3 * i + c] - 0.5 * ((double)a->rgb[3 * i + c] + frame->rgb[3 * i + c]);
                f->abs_sum += fabs(d);
                f->abs_count += 1;
            }
        }
    }
    /* Slide the window: t−1 becomes t−2, this frame t−1. */
    ImageF oldest = f->prev[0];
    uint8_t *oldest_mask = f->mask[0];
    f->prev[0] = f->prev[1];
    f->mask[0] = f->mask[1];
    f->prev[1] = oldest;
    f->mask[1] = oldest_mask;
    if (!keep(f, 1, frame, mask))
        f->failed = true;
    f->frames++;
}

double flicker_value(const FlickerSum *f)
{
    if (f->failed || f->frames < 3 || !(f->abs_count > 0) || !(f->radiance_count > 0))
        return NAN;
    double mean = f->radiance_sum / f->radiance_count;
    return mean > 0 ? f->abs_sum / f->abs_count / mean : NAN;
}

void flicker_free(FlickerSum *f)
{
    for (int k = 0; k < 2; k++) {
        image_free(&f->prev[k]);
        free(f->mask[k]);
    }
    memset(f, 0, sizeof *f);
}

void kymograph_add(ImageF *kymo, int t, const ImageF *frame, int row)
{
    if (t < 0 || t >= kymo->height || row < 0 || row >= frame->height || frame->width != kymo->width)
        return;
    memcpy(image_px(kymo, 0, t), image_px(frame, 0, row), sizeof(float) * 3 * (size_t)frame->width);
}
