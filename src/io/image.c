#include "io/image.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include "base/log.h"
#include "base/util.h"

bool image_alloc(ImageF *img, int width, int height)
{
    img->rgb = NULL;
    img->width = img->height = 0;
    size_t px = (size_t)(width > 0 ? width : 0) * (size_t)(height > 0 ? height : 0);
    if (width < 1 || height < 1 || px > IMAGE_MAX_PIXELS) {
        log_error("image", "cannot allocate a %dx%d image: more than the limit of %zu pixels", width, height,
                  (size_t)IMAGE_MAX_PIXELS);
        return false;
    }
    img->rgb = calloc(px * 3, sizeof(float));
    if (!img->rgb) {
        log_error("image", "cannot allocate a %dx%d image: %zu bytes", width, height, px * 3 * sizeof(float));
        return false;
    }
    img->width = width;
    img->height = height;
    return true;
}

size_t image_count_nonfinite(const ImageF *img, int *first_x, int *first_y)
{
    size_t n = 0, np = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < np; i++) {
        const float *p = img->rgb + 3 * i;
        if (isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]))
            continue;
        if (n++ == 0) {
            if (first_x)
                *first_x = (int)(i % (size_t)img->width);
            if (first_y)
                *first_y = (int)(i / (size_t)img->width);
        }
    }
    return n;
}

bool image_check_finite(const ImageF *img, const char *name)
{
    int x = 0, y = 0;
    size_t n = image_count_nonfinite(img, &x, &y);
    if (n == 0)
        return true;
    const float *p = image_px(img, x, y);
    log_error("image", "%s: %zu of %zu pixels are NaN or infinite (first at x=%d y=%d: %g %g %g); not written",
              name, n, (size_t)img->width * img->height, x, y, (double)p[0], (double)p[1], (double)p[2]);
    return false;
}

static void warn_black(const char *tag, const char *name)
{
    log_warn(tag, "%s: the image is black: no light reaches a surface the camera sees (check the lights, the "
             "camera and the exposure)", name);
}

void image_warn_if_black(const ImageF *img, const char *tag, const char *name)
{
    size_t n = (size_t)img->width * img->height * 3;
    for (size_t i = 0; i < n; i++)
        if (img->rgb[i] > 0.f)
            return;
    warn_black(tag, name);
}

void image_warn_if_black8(const uint8_t *rgb, int width, int height, const char *tag, const char *name)
{
    if (!rgb)
        return;
    size_t n = (size_t)width * height * 3;
    for (size_t i = 0; i < n; i++)
        if (rgb[i])
            return;
    warn_black(tag, name);
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
    if (!image_check_finite(img, path))
        return false;
    AtomicFile af;
    if (!util_atomic_open(&af, "image", path))
        return false;
    fprintf(af.f, "PF\n%d %d\n-1.0\n", img->width, img->height);
    bool ok = true;
    for (int y = img->height - 1; y >= 0 && ok; y--)
        ok = fwrite(image_px(img, 0, y), sizeof(float), (size_t)img->width * 3, af.f) == (size_t)img->width * 3;
    af.failed = !ok;
    return util_atomic_commit(&af, "image");
}

bool image_read_pfm(const char *path, ImageF *img)
{
    size_t size = 0;
    char *data = util_read_input("image", "image", path, UTIL_MAX_INPUT_BYTES, &size);
    if (!data)
        return false;
    /* "PF", width, height, scale, each after whitespace, parsed whole
     * (sscanf's %d had wrapped a width of 4294967297 to 1). */
    char *p = data, *end;
    long dims[2] = {0, 0};
    bool ok = size >= 2 && p[0] == 'P' && p[1] == 'F' && isspace((unsigned char)p[2]);
    p += 2;
    for (int k = 0; ok && k < 2; k++) {
        errno = 0;
        dims[k] = strtol(p, &end, 10);
        ok = end != p && errno == 0 && dims[k] > 0 && dims[k] <= 65536 && isspace((unsigned char)*end);
        p = end;
    }
    double scale = ok ? strtod(p, &end) : 0;
    if (!ok || end == p || !isfinite(scale) || scale == 0 || !isspace((unsigned char)*end)) {
        log_error("image", "%s: not an RGB PFM file (want \"PF\", width and height in [1, 65536], scale)", path);
        free(data);
        return false;
    }
    int w = (int)dims[0], h = (int)dims[1];
    size_t off = (size_t)(end - data) + 1; /* single whitespace after the scale */
    size_t need = (size_t)w * (size_t)h * 3 * sizeof(float);
    if (off > size || need != size - off) {
        if (off <= size && size - off > need)
            log_error("image", "%s: %zu bytes after the PFM's %dx%d pixels (a wrong size in its header?)", path,
                      size - off - need, w, h);
        else
            log_error("image", "%s: PFM data truncated (%zu of %zu bytes)", path, off > size ? 0 : size - off, need);
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

static void png_to_file(void *ctx, void *data, int size)
{
    AtomicFile *af = ctx;
    if (size > 0 && fwrite(data, 1, (size_t)size, af->f) != (size_t)size)
        af->failed = true;
}

bool image_write_png8(const char *path, int width, int height, const uint8_t *rgb)
{
    if (!rgb) /* the read-back that should have made it failed, and logged */
        return false;
    AtomicFile af;
    if (!util_atomic_open(&af, "image", path))
        return false;
    if (!stbi_write_png_to_func(png_to_file, &af, width, height, 3, rgb, width * 3)) {
        log_error("image", "%s: cannot encode PNG (%dx%d)", path, width, height);
        util_atomic_abort(&af);
        return false;
    }
    return util_atomic_commit(&af, "image");
}

bool image_write_png(const char *path, const ImageF *img, float exposure)
{
    if (!image_check_finite(img, path))
        return false;
    size_t n = (size_t)img->width * (size_t)img->height * 3;
    uint8_t *px = util_malloc("image", "an 8-bit image", n, 1);
    if (!px)
        return false;
    for (size_t i = 0; i < n; i++) {
        float v = 255.f * srgb_encode(img->rgb[i] * exposure); /* inf × 0 is NaN */
        px[i] = (uint8_t)(v >= 0.f && v <= 255.f ? lrintf(v) : 0);
    }
    bool ok = image_write_png8(path, img->width, img->height, px);
    free(px);
    return ok;
}

/* Why stb_image refused a file that starts as a PNG or JPEG: its terse
 * reasons ("IDA", "", "bad huffman code") said nothing to a user. */
static const char *stb_reason(bool png)
{
    static char text[160];
    const char *r = stbi_failure_reason();
    snprintf(text, sizeof text, "corrupt or truncated %s data; stb_image: %s", png ? "PNG" : "JPEG",
             r && r[0] ? r : "no detail");
    return text;
}

bool image_read(const char *path, ImageF *img)
{
    if (util_ends_with(path, ".pfm"))
        return image_read_pfm(path, img);
    if (util_ends_with(path, ".exr"))
        return image_read_exr(path, img);
    size_t size = 0;
    char *data = util_read_input("image", "image", path, UTIL_MAX_INPUT_BYTES, &size);
    if (!data)
        return false;
    /* PNG or JPEG by signature only: stb_image also takes headerless formats
     * (TGA) in which a few bytes can claim a huge image (found by
     * fuzz_image: 20 bytes decoded as 2^27 pixels). */
    const unsigned char *u = (const unsigned char *)data;
    bool png = size >= 8 && memcmp(u, "\x89PNG\r\n\x1a\n", 8) == 0;
    bool jpeg = size >= 3 && u[0] == 0xff && u[1] == 0xd8 && u[2] == 0xff;
    if (!png && !jpeg) {
        log_error("image", "%s: cannot read image (not a PNG or JPEG file, nor .pfm or .exr)", path);
        free(data);
        return false;
    }
    int w = 0, h = 0, n;
    if (size > INT32_MAX || !stbi_info_from_memory((const unsigned char *)data, (int)size, &w, &h, &n)) {
        log_error("image", "%s: cannot read image (%s)", path, size > INT32_MAX ? "too large" : stb_reason(png));
        free(data);
        return false;
    }
    if ((size_t)w * (size_t)h > IMAGE_MAX_PIXELS) {
        log_error("image", "%s: image is %dx%d, more than the limit of %zu pixels", path, w, h,
                  (size_t)IMAGE_MAX_PIXELS);
        free(data);
        return false;
    }
    unsigned char *px = stbi_load_from_memory((const unsigned char *)data, (int)size, &w, &h, &n, 3);
    free(data);
    if (!px) {
        log_error("image", "%s: cannot read image (%s)", path, stb_reason(png));
        return false;
    }
    bool ok = image_alloc(img, w, h);
    for (size_t i = 0; ok && i < (size_t)w * h * 3; i++)
        img->rgb[i] = srgb_decode(px[i] / 255.f);
    stbi_image_free(px);
    return ok;
}

bool image_write(const char *path, const ImageF *img, float exposure, bool half)
{
    if (util_ends_with(path, ".pfm"))
        return image_write_pfm(path, img);
    if (util_ends_with(path, ".exr"))
        return image_write_exr(path, img, half, NULL, 0);
    if (util_ends_with(path, ".png"))
        return image_write_png(path, img, exposure);
    log_error("image", "%s: unknown output format (use .png, .pfm or .exr)", path);
    return false;
}
