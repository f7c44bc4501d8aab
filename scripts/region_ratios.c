/* region_ratios.c — where a GI technique's light lands, from images on
 * disk: the indirect ratio (tests/test_util.h: Σ luminance(tech − none) /
 * Σ luminance(ref − direct)) over the whole image, over each surface the
 * camera sees (material and dominant face, as pt_surface_map names what
 * each pixel's centre sees; a pixel counts when its 8 neighbours see the
 * same surface, as test_surface_mask), and the lowest and highest ratio of
 * the 16×9 blocks whose reference indirect light is above the median
 * block's. Emitter pixels never count. A measuring tool for scripts
 * (scripts/vct-regions.sh); the suite's checks are tests/test_fidelity.c.
 *
 * usage: region_ratios SCENE TECH NONE REF DIRECT [MIN_PIXELS]
 *   SCENE   cornell or a scene file (the camera the images were made with)
 *   TECH    the technique's render, NONE the render with --gi none, REF the
 *           reference (e.g. one-bounce), DIRECT the reference's direct light;
 *           PFM or EXR, all of one size
 *   MIN_PIXELS  surfaces seen by fewer pixels are not listed (default 40)
 * Prints "whole: R", one "surface MATERIAL FACE PIXELS R at X Y" line per
 * surface (largest first; X Y one of its pixels, row 0 = top) and
 * "blocks16x9: LO HI". Exit 1 on bad input. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image.h"
#include "reference/pathtracer.h"
#include "scene.h"

typedef struct Region {
    int id;          /* material · 6 + face */
    int pixels;      /* eroded pixels */
    int at;          /* one of them, the middle one in scan order (for probing) */
    double num, den; /* Σ tech − none, Σ ref − direct */
} Region;

static int by_pixels(const void *a, const void *b)
{
    const Region *x = a, *y = b;
    return (y->pixels > x->pixels) - (y->pixels < x->pixels);
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    if (argc < 6) {
        fprintf(stderr, "usage: region_ratios SCENE TECH NONE REF DIRECT [MIN_PIXELS]\n");
        return 1;
    }
    int min_pixels = argc > 6 ? atoi(argv[6]) : 40;
    ImageF img[4];
    for (int i = 0; i < 4; i++) {
        if (!image_read(argv[2 + i], &img[i]))
            return 1;
        if (img[i].width != img[0].width || img[i].height != img[0].height) {
            fprintf(stderr, "region_ratios: %s is %dx%d, %s %dx%d\n", argv[2 + i], img[i].width, img[i].height,
                    argv[2], img[0].width, img[0].height);
            return 1;
        }
    }
    int w = img[0].width, h = img[0].height;
    Scene s;
    if (!scene_load(&s, argv[1]))
        return 1;
    int32_t *ids = malloc(sizeof *ids * (size_t)w * h);
    uint8_t *emit = malloc((size_t)w * h);
    int nreg = s.material_count * 6;
    Region *reg = calloc((size_t)nreg, sizeof *reg);
    if (!ids || !emit || !reg || !pt_surface_map(&s, w, h, ids) || !pt_emitter_mask(&s, w, h, emit)) {
        fprintf(stderr, "region_ratios: no surface map\n");
        return 1;
    }
    for (int r = 0; r < nreg; r++)
        reg[r].id = r;
    enum { BX = 16, BY = 9 };
    double bnum[BX * BY] = {0}, bden[BX * BY] = {0}, num = 0, den = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            if (!emit[i])
                continue;
            double t = luminance(img[0].rgb + 3 * i) - luminance(img[1].rgb + 3 * i);
            double r = luminance(img[2].rgb + 3 * i) - luminance(img[3].rgb + 3 * i);
            num += t, den += r;
            int b = (y * BY / h) * BX + x * BX / w;
            bnum[b] += t, bden[b] += r;
            int32_t id = ids[i];
            bool in = id >= 0;
            for (int dy = -1; dy <= 1 && in; dy++)
                for (int dx = -1; dx <= 1 && in; dx++) {
                    int u = x + dx, v = y + dy;
                    in = u >= 0 && v >= 0 && u < w && v < h && ids[(size_t)v * w + u] == id;
                }
            if (in) {
                reg[id].pixels++;
                reg[id].num += t, reg[id].den += r;
            }
        }
    /* Each region's middle pixel in scan order. */
    int *seen = calloc((size_t)nreg, sizeof *seen);
    for (int y = 1; seen && y + 1 < h; y++)
        for (int x = 1; x + 1 < w; x++) {
            int32_t id = ids[(size_t)y * w + x];
            if (id < 0 || !emit[(size_t)y * w + x])
                continue;
            bool in = true;
            for (int dy = -1; dy <= 1 && in; dy++)
                for (int dx = -1; dx <= 1 && in; dx++)
                    in = ids[(size_t)(y + dy) * w + x + dx] == id;
            if (in && seen[id]++ == reg[id].pixels / 2)
                reg[id].at = y * w + x;
        }
    free(seen);
    static const char *const faces[] = {"+x", "-x", "+y", "-y", "+z", "-z"};
    printf("whole: %.3f\n", num / den);
    qsort(reg, (size_t)nreg, sizeof *reg, by_pixels);
    for (int r = 0; r < nreg && reg[r].pixels >= min_pixels; r++)
        printf("surface %-16s %s %6d %.3f  at %d %d\n", s.materials[reg[r].id / 6].name, faces[reg[r].id % 6],
               reg[r].pixels, reg[r].den > 0 ? reg[r].num / reg[r].den : NAN, reg[r].at % w, reg[r].at / w);
    double sorted[BX * BY];
    memcpy(sorted, bden, sizeof sorted);
    qsort(sorted, BX * BY, sizeof *sorted, by_value);
    double median = sorted[BX * BY / 2], lo = INFINITY, hi = -INFINITY;
    for (int b = 0; b < BX * BY; b++)
        if (bden[b] > median && bden[b] > 0) {
            lo = fmin(lo, bnum[b] / bden[b]);
            hi = fmax(hi, bnum[b] / bden[b]);
        }
    printf("blocks16x9: %.3f %.3f\n", lo, hi);
    free(ids);
    free(emit);
    free(reg);
    for (int i = 0; i < 4; i++)
        image_free(&img[i]);
    scene_free(&s);
    return 0;
}
