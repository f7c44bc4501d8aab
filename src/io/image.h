/* image.h — linear RGB float images and their files.
 * Row 0 is the top row everywhere in memory; PFM files store rows bottom-up
 * and are converted on read/write. PNG is 8-bit sRGB: written from radiance
 * through exposure and the sRGB curve, read back to linear. EXR is linear,
 * float32 or half. */
#ifndef RTGI_IMAGE_H
#define RTGI_IMAGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct ImageF {
    int width, height;
    float *rgb; /* width*height*3 floats, owned; row 0 = top */
} ImageF;

/* The largest image, in pixels (16384², 3 GiB of floats): larger ones are
 * refused with a message naming the size. */
#define IMAGE_MAX_PIXELS ((size_t)1 << 28)

/* Zero-filled; false after logging the size if it is over IMAGE_MAX_PIXELS
 * or the allocation fails. */
bool image_alloc(ImageF *img, int width, int height);
void image_free(ImageF *img);
static inline float *image_px(const ImageF *img, int x, int y)
{
    return img->rgb + 3 * ((long)y * img->width + x);
}

/* Pixels with a NaN or infinite channel; the first one's position. */
size_t image_count_nonfinite(const ImageF *img, int *first_x, int *first_y);
/* true if every value is finite; else false after logging "<name>: N of M
 * pixels are NaN or infinite (first at ...); not written". */
bool image_check_finite(const ImageF *img, const char *name);
/* Warns, under `tag`, when an image about to be written to `name` is black
 * (no value above 0; an 8-bit image: every byte 0): no silent black image.
 * Not an error: a camera may rightly look at nothing lit. */
void image_warn_if_black(const ImageF *img, const char *tag, const char *name);
void image_warn_if_black8(const uint8_t *rgb, int width, int height, const char *tag, const char *name);

/* Writers: refuse non-finite pixels, write atomically (util_atomic_*): an
 * error leaves no file behind. Readers: regular files only (never block on
 * a FIFO), sizes checked before allocating. */
bool image_write_pfm(const char *path, const ImageF *img);
bool image_read_pfm(const char *path, ImageF *img);
/* Writes 8-bit RGB (row 0 = top) as PNG. rgb NULL (an allocation that
 * failed and logged): false, nothing written, nothing more logged. */
bool image_write_png8(const char *path, int width, int height, const uint8_t *rgb);
/* Tone maps (radiance × exposure, clamp, sRGB) and writes a PNG. */
bool image_write_png(const char *path, const ImageF *img, float exposure);
/* Reads PFM or EXR (by the .pfm and .exr extensions) as is, or PNG/JPEG (by their
 * signatures; other formats are refused) decoded from sRGB to linear [0,1]. */
bool image_read(const char *path, ImageF *img);
/* Writes .pfm or .exr as linear (EXR: float32, or half floats with `half`)
 * or .png tone-mapped, by the file's extension. */
bool image_write(const char *path, const ImageF *img, float exposure, bool half);

/* OpenEXR (Debian libopenexr-dev, its C API `openexr.h`): one scanline part,
 * channels R, G, B, ZIP compression. An integer attribute of the header,
 * e.g. {"rtgi_spp", 256}. */
typedef struct ImageAttr {
    const char *name;
    int value;
} ImageAttr;
/* Writes RGB as float32 or (half) float16: half refuses values beyond its
 * range (65504) instead of writing infinities. `attrs` (n of them, may be
 * NULL) go into the header. Atomic, as the other writers. */
bool image_write_exr(const char *path, const ImageF *img, bool half, const ImageAttr *attrs, int nattrs);
/* Reads the first part of a scanline EXR: channels R, G, B, else one
 * layer's LAYER.R, .G, .B (of several, the one named ...Combined, as
 * Blender writes them), else Y (or one layer's) copied to all three; any
 * pixel type, converted to float. Tiled/deep and luminance/chroma files,
 * and files without such channels, are refused with one line naming the
 * file and the reason. */
bool image_read_exr(const char *path, ImageF *img);
/* The integer attribute `name` of an EXR's header; false after logging if
 * the file is not an EXR or has no such integer attribute. */
bool image_read_exr_attr(const char *path, const char *name, int *value);

float srgb_encode(float linear); /* linear [0,1] → sRGB [0,1] */
float srgb_decode(float encoded);
static inline float luminance(const float *rgb)
{
    return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2];
}

#endif
