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
 * The four images must have one size, that of the view measured. Not a
 * test: a measuring tool built beside the tests, sharing their helpers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"
#include "metrics.h"

#define MIN_PIXELS 40 /* as test_fidelity.c */

static const char *const k_faces[] = {"+x", "-x", "+y", "-y", "+z", "-z"};

static bool emissive(const Material *m) { return m->emission[0] > 0 || m->emission[1] > 0 || m->emission[2] > 0; }

/* mask[i] = 0 on pixels that see an emitter and their 8 neighbours, else 1. */
static void emitter_mask(const Scene *s, int w, int h, const int32_t *ids, uint8_t *mask)
{
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            bool keep = true;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int u = x + dx, v = y + dy;
                    if (u < 0 || v < 0 || u >= w || v >= h)
                        continue;
                    int32_t id = ids[(size_t)v * w + u];
                    if (id >= 0 && emissive(&s->materials[id / 6]))
                        keep = false;
                }
            mask[(size_t)y * w + x] = keep;
        }
}

int main(int argc, char **argv)
{
    if (argc < 6) {
        fprintf(stderr, "usage: gi_regions SCENE TECH.pfm NONE.pfm REF.pfm DIRECT.pfm [--surfaces]\n");
        return 2;
    }
    bool surfaces = argc > 6 && strcmp(argv[6], "--surfaces") == 0;
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
    emitter_mask(&s, w, h, ids, mask);
    printf("whole %.3f  relmse %.4f  none_relmse %.4f", test_indirect_ratio(tech, none, ref, direct, mask),
           metric_relmse(tech, ref, mask, NULL), metric_relmse(none, ref, mask, NULL));
    double lo, hi;
    test_block_ratio_range(tech, none, ref, direct, 16, 9, &lo, &hi);
    printf("  blocks16x9 %.3f..%.3f\n", lo, hi);
    for (int m = 0; surfaces && m < s.material_count; m++) {
        if (emissive(&s.materials[m]))
            continue;
        for (int face = 0; face < 6; face++) {
            int n = test_surface_mask(&s, w, h, s.materials[m].name, face, mask);
            if (n >= MIN_PIXELS)
                printf("  %-12s %s %6d px  %.3f\n", s.materials[m].name, k_faces[face], n,
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
