/* report_temporal.h — the part of bench's page (report_html.c) that shows
 * `bench --animate`: relMSE over the frames per technique (an SVG plot),
 * a table of mean relMSE, flicker and the reference's flicker, and each
 * technique's kymograph beside the reference's. A script that runs after
 * the page's own (it reads BENCH.animation and the page's decoded images);
 * it does nothing for a bench without --animate. */
#ifndef RTGI_REPORT_TEMPORAL_H
#define RTGI_REPORT_TEMPORAL_H

extern const char report_temporal_script[];

#endif
