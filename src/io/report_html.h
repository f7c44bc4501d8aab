/* report_html.h — the self-contained HTML page of `rtgi bench`: plain
 * HTML/SVG/JS with every image embedded (no network, no CDN). Images are
 * embedded as half-float radiance and tone-mapped in the page, so an
 * exposure slider re-exposes them; FLIP maps as 8-bit values drawn with a
 * colour bar. The page draws the metrics table, per-pass stacked bars and
 * a quality-versus-cost scatter with its Pareto front from the bench JSON,
 * then sets document.title to "ok:<points drawn>" (or "error: ..." after an
 * uncaught error or console.error), which the tests read back. */
#ifndef RTGI_REPORT_HTML_H
#define RTGI_REPORT_HTML_H

#include <stdbool.h>
#include <stdint.h>

#include <cjson/cJSON.h>

#include "io/image.h"

typedef struct ReportImage {
    const char *id;     /* "reference" or the technique's "id" in the JSON */
    const ImageF *img;  /* radiance */
    const float *flip;  /* per-pixel FLIP in [0,1], or NULL */
} ReportImage;

/* The page's default exposure for a reference (radiance multiplier): a
 * photographic key, the log-average luminance of the pixels `mask` selects
 * (all if NULL) at 18% grey, but no brighter than puts their 90th
 * percentile at white (so at most about a tenth of them clip). 0 if the
 * image is black. Sponza's sunlit atrium, keyed on its 99th percentile,
 * left the median pixel at sRGB 0.04; keyed so, at 0.23. */
double report_display_exposure(const ImageF *ref, const uint8_t *mask);

/* Writes the page atomically; false after logging. */
bool report_html_write(const char *path, const cJSON *bench, const ReportImage *imgs, int n);

#endif
