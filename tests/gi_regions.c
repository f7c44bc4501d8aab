/* gi_regions.c — where a GI image's light lands, from the command line
 * (scripts/gi-regions.sh runs it): the indirect ratio (test_util.h:
 * Σ(tech − none) / Σ(ref − direct), luminance) of the whole image, of
 * every surface the camera sees by material and face (pt_surface_map, the
 * masks test_fidelity.c checks; with --surfaces), and the lowest and
 * highest of the 16×9 blocks whose reference indirect light is above the
 * median (test_block_ratio_range); and the relMSE of TECH and of NONE
 * against REF, emitter pixels and their neighbours left out.
 *
 * usage: gi_regions SCENE TECH.pfm NONE.pfm REF.pfm DIRECT.pfm [--surfaces]
 *        [--row LABEL] [--header] [--digits N] [--min-pixels N]
 * (--row: one Markdown table row; --header: the table's header first;
 * --digits: the relMSEs' decimals, 4 unless told.)
 * The four images must have one size, that of the view measured. Not a
 * test: a measuring tool built beside the tests, sharing their helpers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"
#include "io/metrics.h"

static int min_pixels = 40; /* as test_fidelity.c (--min-pixels) */

static const char *const k_faces[] = {"+x", "-x", "+y", "-y", "+z", "-z"};

static bool emissive(const Material *m) { return m->emission[0] > 0 || m->emission[1] > 0 || m->emission[2] > 0; }

/* The surfaces checked: (material, face) seen by MIN_PIXELS eroded pixels
 * or more, every non-emissive material; returns the count (≤ max). */
typedef struct Surface {
    int material, face;
} Surface;
static int surfaces_seen(const Scene *s, int w, int h, uint8_t *mask, Surface *out, int max)
{
    int count = 0;
    for (int m = 0; m < s->material_count; m++) {
        if (emissive(&s->materials[m]))
            continue;
        for (int face = 0; face < 6 && count < max; face++)
            if (test_surface_mask(s, w, h, s->materials[m].name, face, mask) >= min_pixels)
                out[count++] = (Surface){m, face};
    }
    return count;
}

int main(int argc, char **argv)
{
    if (argc < 6) {
        fprintf(stderr, "usage: gi_regions SCENE TECH.pfm NONE.pfm REF.pfm DIRECT.pfm [--surfaces] [--row LABEL] "
                        "[--header]\n");
        return 2;
    }
    bool surfaces = false, header = false;
    const char *row = NULL;
    int digits = 4; /* of the relMSEs */
    for (int i = 6; i < argc; i++) {
        if (strcmp(argv[i], "--surfaces") == 0)
            surfaces = true;
        else if (strcmp(argv[i], "--header") == 0)
            header = true;
        else if (strcmp(argv[i], "--row") == 0 && i + 1 < argc)
            row = argv[++i];
        else if (strcmp(argv[i], "--min-pixels") == 0 && i + 1 < argc)
            min_pixels = atoi(argv[++i]) < 1 ? 1 : atoi(argv[i]);
        else if (strcmp(argv[i], "--digits") == 0 && i + 1 < argc)
            digits = atoi(argv[++i]) < 1 ? 1 : atoi(argv[i]) > 9 ? 9 : atoi(argv[i]);
        else {
            fprintf(stderr, "gi_regions: unknown argument %s\n", argv[i]);
            return 2;
        }
    }
    Scene s;
    if (!scene_load(&s, argv[1]))
        return 1;
    ImageF img[4];
    for (int i = 0; i < 4; i++)
        if (!image_read(argv[2 + i], &img[i]))
            return 1;
    int w = img[0].width, h = img[0].height;
    for (int i = 1; i < 4; i++)
        if (img[i].width != w || img[i].height != h) {
            fprintf(stderr, "gi_regions: %s is %dx%d, %s %dx%d\n", argv[2 + i], img[i].width, img[i].height, argv[2],
                    w, h);
            return 1;
        }
    const ImageF *tech = &img[0], *none = &img[1], *ref = &img[2], *direct = &img[3];
    int32_t *ids = malloc(sizeof *ids * (size_t)w * h);
    uint8_t *mask = malloc((size_t)w * h);
    if (!ids || !mask || !pt_surface_map(&s, w, h, ids))
        return 1;
    test_emitter_mask(&s, w, h, ids, mask);
    double whole = test_indirect_ratio(tech, none, ref, direct, mask), rel = metric_relmse(tech, ref, mask, NULL),
           rel_none = metric_relmse(none, ref, mask, NULL), lo, hi;
    test_block_ratio_range(tech, none, ref, direct, 16, 9, &lo, &hi);
    Surface seen[64];
    int n = surfaces ? surfaces_seen(&s, w, h, mask, seen, 64) : 0;
    if (header) {
        printf("| | whole | relMSE (none's) | 16x9 blocks |");
        for (int i = 0; i < n; i++)
            printf(" %s %s |", s.materials[seen[i].material].name, k_faces[seen[i].face]);
        printf("\n|---|---|---|---|");
        for (int i = 0; i < n; i++)
            printf("---|");
        printf("\n");
    }
    if (row) {
        printf("| %s | %.3f | %.*f (%.*f) | %.2f .. %.2f |", row, whole, digits, rel, digits, rel_none, lo, hi);
        for (int i = 0; i < n; i++) {
            test_surface_mask(&s, w, h, s.materials[seen[i].material].name, seen[i].face, mask);
            printf(" %.3f |", test_indirect_ratio(tech, none, ref, direct, mask));
        }
        printf("\n");
    } else {
        printf("whole %.3f  relmse %.4f  none_relmse %.4f  blocks16x9 %.3f..%.3f\n", whole, rel, rel_none, lo, hi);
        for (int i = 0; i < n; i++) {
            int m = test_surface_mask(&s, w, h, s.materials[seen[i].material].name, seen[i].face, mask);
            printf("  %-12s %s %6d px  %.3f\n", s.materials[seen[i].material].name, k_faces[seen[i].face], m,
                   test_indirect_ratio(tech, none, ref, direct, mask));
        }
    }
    free(ids);
    free(mask);
    for (int i = 0; i < 4; i++)
        image_free(&img[i]);
    scene_free(&s);
    return 0;
}
