/* test_textures.c — base-colour textures and alpha masks against closed
 * forms, in both renderers (issue 49). A 2 m square at y = 0 under a sun
 * straight down (irradiance E), seen straight down by a camera whose view
 * is exactly the square, repeats its texture `tiles` times across it:
 *   - textured plane: the radiance is ρ(uv)·E/π, so the image mean is
 *     E/π times the mean of the texture's decoded texels (whole tiles fill
 *     the image), and each block of whole tiles the same. At 1, 4 and 16
 *     texels per pixel the rasterizer reads mip levels 0, 2 and 4.
 *   - alpha-masked square: an 8×8 cell with a 4×4 opaque block (white
 *     base colour on it and one texel around it, black beyond), nothing
 *     behind. The alpha test keeps bilinear alpha ≥ 0.5: the block's
 *     inside and its edges up to the texel boundary, and at each corner
 *     (alpha (1 − x)(1 − y) from the opaque texel's centre) an area
 *     (1 − ln 2)/2 of the quarter texel the nearest texel would keep: a
 *     coverage of (16 − 4·(1/4 − (1 − ln 2)/2))/64 = 0.24397 (nearest:
 *     0.25), seen magnified (4 pixels a texel) and minified (7.3 texels a
 *     pixel: the mip levels' alpha averages the block away, and their
 *     colour mixes in the black texels).
 * Before the fixes the rasterizer decoded sRGB texels with the driver's
 * approximation (llvmpipe: +0.7% at codes 80-100) and generated biased
 * mip levels; tested the mip chain's alpha (the minified mask vanished);
 * the path tracer tested the nearest texel's alpha (2.5% more coverage). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_util.h"

enum { W = 128, H = 128, TEX = 64 };
static const float k_e = 3.f; /* the sun's irradiance, W/m² */

/* Writes NAME.obj and NAME.json to RTGI_TEST_TMP: the square with
 * material `mtl` (the lines of NAME.mtl, written too), uv 0..tiles, the
 * camera and the sun; returns the scene file's path. */
static const char *square_scene(const char *name, const char *mtl, double tiles)
{
    char file[128], text[2048];
    snprintf(file, sizeof file, "%s.mtl", name);
    test_tmp_file(file, mtl);
    snprintf(text, sizeof text,
             "mtllib %s.mtl\n"
             "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
             "vt 0 0\nvt %.9g 0\nvt %.9g %.9g\nvt 0 %.9g\nvn 0 1 0\n"
             "usemtl m\nf 1/1/1 4/4/1 3/3/1 2/2/1\n",
             name, tiles, tiles, tiles, tiles);
    snprintf(file, sizeof file, "%s.obj", name);
    test_tmp_file(file, text);
    /* fov 60°: at height 1/tan 30° the view spans exactly x, z in [-1, 1]. */
    snprintf(text, sizeof text,
             "{ \"mesh\": \"%s.obj\",\n"
             "  \"camera\": { \"position\": [0, 1.7320508075688772, 0], \"target\": [0, 0, 0],"
             " \"up\": [0, 0, -1], \"fov_y_deg\": 60 },\n"
             "  \"lights\": [ { \"type\": \"directional\", \"direction\": [0, -1, 0],"
             " \"irradiance\": [%g, %g, %g], \"angular_diameter_deg\": 0 } ] }\n",
             name, k_e, k_e, k_e);
    snprintf(file, sizeof file, "%s.json", name);
    return test_tmp_file(file, text);
}

/* The rasterizer's direct light (no shadows: nothing can cast one) with
 * N×N supersampling, and the path tracer's (box-filtered pixels, spp). */
static void render_both(const char *scene_file, int ssaa, int spp, ImageF *raster, ImageF *ref)
{
    Scene s;
    assert_true(scene_load(&s, scene_file));
    RenderSettings rs = test_settings(&s, W, H, SHADOW_MODE_NONE);
    rs.ssaa = ssaa;
    test_render(&s, &rs, raster);
    test_reference_ex(&s, W, H, PT_DIRECT, spp, true, ref);
    scene_free(&s);
}

/* Mean of channel c over pixels [x0, x0 + n) × [y0, y0 + n). */
static double block_mean(const ImageF *img, int x0, int y0, int n, int c)
{
    double sum = 0;
    for (int y = y0; y < y0 + n; y++)
        for (int x = x0; x < x0 + n; x++)
            sum += image_px(img, x, y)[c];
    return sum / ((double)n * n);
}

/* Fails unless every channel of img's mean over each block of `block`
 * pixels is want[c] within `tol` (relative); prints the worst. */
static void expect_blocks(const ImageF *img, const char *what, int block, const double want[3], double tol)
{
    double worst = 0;
    for (int y = 0; y < H; y += block)
        for (int x = 0; x < W; x += block)
            for (int c = 0; c < 3; c++)
                worst = fmax(worst, fabs(block_mean(img, x, y, block, c) / want[c] - 1.0));
    print_message("%s: blocks of %d px: worst %.3f%%\n", what, block, 100 * worst);
    if (worst > tol)
        fail_msg("%s: a block of %d pixels is %.3f%% off the closed form (bound %.2f%%)", what, block, 100 * worst,
                 100 * tol);
}

static void textured_plane_under_sun(void **state)
{
    (void)state;
    /* Random codes in 80..100 (linear 0.08-0.13), where llvmpipe's sRGB
     * decoding was 0.5-0.7% high. */
    static uint8_t rgb[TEX * TEX * 3];
    double mean[3] = {0, 0, 0};
    srand(49);
    for (int i = 0; i < TEX * TEX * 3; i++) {
        rgb[i] = (uint8_t)(80 + rand() % 21);
        mean[i % 3] += srgb_decode(rgb[i] / 255.f) / (TEX * TEX);
    }
    char path[512];
    snprintf(path, sizeof path, "%s/tex_plane.png", RTGI_TEST_TMP);
    assert_true(image_write_png8(path, TEX, TEX, rgb));
    double want[3];
    for (int c = 0; c < 3; c++)
        want[c] = mean[c] * k_e / GLM_PI;
    /* 2, 8, 32 tiles over 128 pixels: 1, 4, 16 texels a pixel. */
    const int tiles[] = {2, 8, 32};
    for (int k = 0; k < 3; k++) {
        char name[64], what[96];
        snprintf(name, sizeof name, "tex_plane_%d", tiles[k]);
        ImageF raster, ref;
        render_both(square_scene(name, "newmtl m\nKd 1 1 1\nmap_Kd tex_plane.png\n", tiles[k]), 1, 16, &raster,
                    &ref);
        /* Each block holds whole tiles from 8 tiles across. */
        int block = tiles[k] >= 8 ? W / 8 : W;
        snprintf(what, sizeof what, "textured plane, %d texels a pixel, rasterizer", TEX * tiles[k] / W);
        expect_blocks(&raster, what, block, want, 0.001);
        snprintf(what, sizeof what, "textured plane, %d texels a pixel, path tracer", TEX * tiles[k] / W);
        expect_blocks(&ref, what, W, want, 0.001);
        expect_blocks(&ref, what, block, want, 0.01); /* 16 spp of a random texture: 0.2% noise a block */
        image_free(&raster);
        image_free(&ref);
    }
}

static void alpha_masked_square(void **state)
{
    (void)state;
    static uint8_t colour[TEX * TEX * 3], alpha[TEX * TEX * 3];
    for (int y = 0; y < TEX; y++)
        for (int x = 0; x < TEX; x++) {
            int cx = x % 8, cy = y % 8;
            bool opaque = cx >= 2 && cx < 6 && cy >= 2 && cy < 6, white = cx >= 1 && cx < 7 && cy >= 1 && cy < 7;
            for (int c = 0; c < 3; c++) {
                colour[3 * (y * TEX + x) + c] = white ? 255 : 0;
                alpha[3 * (y * TEX + x) + c] = opaque ? 255 : 0;
            }
        }
    char path[512];
    snprintf(path, sizeof path, "%s/tex_mask_colour.png", RTGI_TEST_TMP);
    assert_true(image_write_png8(path, TEX, TEX, colour));
    snprintf(path, sizeof path, "%s/tex_mask_alpha.png", RTGI_TEST_TMP);
    assert_true(image_write_png8(path, TEX, TEX, alpha));
    const char *mtl = "newmtl m\nKd 1 1 1\nmap_Kd tex_mask_colour.png\nmap_d tex_mask_alpha.png\n";
    const double coverage = (16.0 - 4.0 * (0.25 - (1.0 - log(2.0)) / 2.0)) / 64.0;
    double want[3];
    for (int c = 0; c < 3; c++)
        want[c] = coverage * k_e / GLM_PI;
    /* Magnified: 32 texels (4 cells) over 128 pixels, SSAA 2. Minified:
     * 936 texels (117 cells) over 128 pixels, 7.3125 texels a pixel, whose
     * centres fall on every 1/16 of a texel of the cell. */
    const struct {
        double texels;
        int ssaa;
        const char *what;
    } views[] = {{32, 2, "magnified"}, {936, 1, "minified"}};
    for (int k = 0; k < 2; k++) {
        char name[64], what[96];
        snprintf(name, sizeof name, "tex_mask_%d", k);
        ImageF raster, ref;
        render_both(square_scene(name, mtl, views[k].texels / TEX), views[k].ssaa, 16, &raster, &ref);
        snprintf(what, sizeof what, "alpha-masked square, %s, rasterizer", views[k].what);
        expect_blocks(&raster, what, W, want, 0.01);
        snprintf(what, sizeof what, "alpha-masked square, %s, path tracer", views[k].what);
        expect_blocks(&ref, what, W, want, 0.01);
        image_free(&raster);
        image_free(&ref);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(textured_plane_under_sun),
                                       cmocka_unit_test(alpha_masked_square)};
    return cmocka_run_group_tests_name("textures", tests, test_gl_setup, test_gl_teardown);
}
