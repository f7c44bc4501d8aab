#include "image.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include "log.h"
#include "util.h"

bool image_alloc(ImageF *img, int width, int height)
{
    img->width = width;
    img->height = height;
    img->rgb = calloc((size_t)width * (size_t)height * 3, sizeof(float));
    if (!img->rgb) {
        log_error("image", "cannot allocate a %dx%d image", width, height);
        return false;
    }
    return true;
}

void image_free(ImageF *img)
{
    free(img->rgb);
    img->rgb = NULL;
    img->width = img->height = 0;
}

float srgb_encode(float c)
{
    c = c < 0.f ? 0.f : (c > 1.f ? 1.f : c);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.f / 2.4f) - 0.055f;
}

float srgb_decode(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

bool image_write_pfm(const char *path, const ImageF *img)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        log_error("image", "%s: cannot open for writing", path);
        return false;
    }
    fprintf(f, "PF\n%d %d\n-1.0\n", img->width, img->height);
    bool ok = true;
    for (int y = img->height - 1; y >= 0 && ok; y--)
        ok = fwrite(image_px(img, 0, y), sizeof(float), (size_t)img->width * 3, f) ==
             (size_t)img->width * 3;
    if (fclose(f) != 0 || !ok) {
        log_error("image", "%s: write failed", path);
        return false;
    }
    return true;
}

bool image_read_pfm(const char *path, ImageF *img)
{
    size_t size = 0;
    char *data = util_read_file(path, &size);
    if (!data) {
        log_error("image", "%s: cannot read file", path);
        return false;
    }
    int w = 0, h = 0, off = 0;
    float scale = 0;
    char magic[3] = {0};
    if (sscanf(data, "%2s %d %d %f%n", magic, &w, &h, &scale, &off) != 4 || strcmp(magic, "PF") != 0 ||
        w <= 0 || h <= 0 || w > 65536 || h > 65536) {
        log_error("image", "%s: not an RGB PFM file", path);
        free(data);
        return false;
    }
    off++; /* single whitespace after the scale */
    size_t need = (size_t)w * (size_t)h * 3 * sizeof(float);
    if ((size_t)off + need > size) {
        log_error("image", "%s: PFM data truncated (%zu of %zu bytes)", path, size - (size_t)off, need);
        free(data);
        return false;
    }
    if (scale > 0) {
        log_error("image", "%s: big-endian PFM is not supported", path);
        free(data);
        return false;
    }
    if (!image_alloc(img, w, h)) {
        free(data);
        return false;
    }
    for (int y = 0; y < h; y++)
        memcpy(image_px(img, 0, h - 1 - y), data + off + (size_t)y * w * 3 * sizeof(float),
               (size_t)w * 3 * sizeof(float));
    free(data);
    return true;
}

bool image_write_png8(const char *path, int width, int height, const uint8_t *rgb)
{
    if (!stbi_write_png(path, width, height, 3, rgb, width * 3)) {
        log_error("image", "%s: cannot write PNG", path);
        return false;
    }
    return true;
}

bool image_write_png(const char *path, const ImageF *img, float exposure)
{
    size_t n = (size_t)img->width * (size_t)img->height * 3;
    uint8_t *px = malloc(n);
    for (size_t i = 0; i < n; i++)
        px[i] = (uint8_t)lrintf(255.f * srgb_encode(img->rgb[i] * exposure));
    bool ok = image_write_png8(path, img->width, img->height, px);
    free(px);
    return ok;
}

bool image_read(const char *path, ImageF *img)
{
    if (util_ends_with(path, ".pfm"))
        return image_read_pfm(path, img);
    int w, h, n;
    unsigned char *px = stbi_load(path, &w, &h, &n, 3);
    if (!px) {
        log_error("image", "%s: cannot read image (%s)", path, stbi_failure_reason());
        return false;
    }
    bool ok = image_alloc(img, w, h);
    for (long i = 0; ok && i < (long)w * h * 3; i++)
        img->rgb[i] = srgb_decode(px[i] / 255.f);
    stbi_image_free(px);
    return ok;
}

bool image_write(const char *path, const ImageF *img, float exposure)
{
    if (util_ends_with(path, ".pfm"))
        return image_write_pfm(path, img);
    if (util_ends_with(path, ".png"))
        return image_write_png(path, img, exposure);
    log_error("image", "%s: unknown output format (use .png or .pfm)", path);
    return false;
}
