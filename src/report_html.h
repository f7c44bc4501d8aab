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

#include <cjson/cJSON.h>

#include "image.h"

typedef struct ReportImage {
    const char *id;     /* "reference" or the technique's "id" in the JSON */
    const ImageF *img;  /* radiance */
    const float *flip;  /* per-pixel FLIP in [0,1], or NULL */
} ReportImage;

/* Writes the page atomically; false after logging. */
bool report_html_write(const char *path, const cJSON *bench, const ReportImage *imgs, int n);

#endif
