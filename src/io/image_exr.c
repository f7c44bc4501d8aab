/* image_exr.c — OpenEXR files through the library's C API (OpenEXRCore,
 * Debian libopenexr-dev): RGB scanline images, float32 or half, written
 * atomically through a custom write callback and read from memory (so the
 * input checks of util_read_input apply). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <openexr.h>

#include "io/image.h"
#include "base/log.h"
#include "base/util.h"

/* The library reports errors through a callback: keep the first message of
 * the current operation for the one line that names the file. */
static _Thread_local char g_exr_msg[256];

static void exr_on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    if (!g_exr_msg[0])
        snprintf(g_exr_msg, sizeof g_exr_msg, "%s", msg ? msg : exr_get_default_error_message(code));
}

static const char *exr_reason(exr_result_t rv)
{
    return g_exr_msg[0] ? g_exr_msg : exr_get_default_error_message(rv);
}

static int64_t exr_write_cb(exr_const_context_t ctxt, void *user, const void *buf, uint64_t sz, uint64_t off,
                            exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    AtomicFile *af = user;
    const uint8_t *p = buf;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t n = pwrite(fileno(af->f), p + done, sz - done, (off_t)(off + done));
        if (n <= 0) {
            af->failed = true;
            return -1;
        }
        done += (uint64_t)n;
    }
    return (int64_t)sz;
}

typedef struct ExrMemory {
    const uint8_t *data;
    size_t size;
} ExrMemory;

static int64_t exr_read_cb(exr_const_context_t ctxt, void *user, void *buf, uint64_t sz, uint64_t off,
                           exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    const ExrMemory *m = user;
    if (off >= m->size)
        return 0;
    uint64_t n = sz < m->size - off ? sz : m->size - off;
    memcpy(buf, m->data + off, n);
    return (int64_t)n;
}

static int64_t exr_size_cb(exr_const_context_t ctxt, void *user)
{
    (void)ctxt;
    return (int64_t)((const ExrMemory *)user)->size;
}

bool image_write_exr(const char *path, const ImageF *img, bool half, const ImageAttr *attrs, int nattrs)
{
    if (!image_check_finite(img, path))
        return false;
    size_t n = (size_t)img->width * (size_t)img->height * 3;
    for (size_t i = 0; half && i < n; i++)
        if (fabsf(img->rgb[i]) > 65504.f) {
            log_error("image", "%s: pixel value %g at x=%zu y=%zu is beyond half precision's range (65504); "
                      "write float32 instead", path, (double)img->rgb[i], i / 3 % (size_t)img->width,
                      i / 3 / (size_t)img->width);
            return false;
        }
    AtomicFile af;
    if (!util_atomic_open(&af, "image", path))
        return false;
    g_exr_msg[0] = 0;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_on_error;
    init.user_data = &af;
    init.write_fn = exr_write_cb;
    exr_context_t f = NULL;
    int part = 0;
    exr_pixel_type_t type = half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
    exr_result_t rv = exr_start_write(&f, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_add_part(f, "rgb", EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(f, part, img->width, img->height, EXR_COMPRESSION_ZIP);
    static const char *const names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3 && rv == EXR_ERR_SUCCESS; c++)
        rv = exr_add_channel(f, part, names[c], type, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    for (int i = 0; i < nattrs && rv == EXR_ERR_SUCCESS; i++)
        rv = exr_attr_set_int(f, part, attrs[i].name, attrs[i].value);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(f);
    int32_t lines = 1;
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_scanlines_per_chunk(f, part, &lines);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool started = false;
    for (int y = 0; y < img->height && rv == EXR_ERR_SUCCESS; y += lines) {
        exr_chunk_info_t cinfo;
        rv = exr_write_scanline_chunk_info(f, part, y, &cinfo);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = started ? exr_encoding_update(f, part, &cinfo, &enc) : exr_encoding_initialize(f, part, &cinfo, &enc);
        if (rv != EXR_ERR_SUCCESS)
            break;
        for (int c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ch = &enc.channels[c];
            int k = ch->channel_name[0] == 'R' ? 0 : ch->channel_name[0] == 'G' ? 1 : 2;
            ch->encode_from_ptr = (const uint8_t *)(image_px(img, 0, cinfo.start_y) + k);
            ch->user_pixel_stride = 3 * sizeof(float);
            ch->user_line_stride = 3 * sizeof(float) * img->width;
            ch->user_bytes_per_element = sizeof(float);
            ch->user_data_type = EXR_PIXEL_FLOAT;
        }
        if (!started) {
            rv = exr_encoding_choose_default_routines(f, part, &enc);
            started = true;
            if (rv != EXR_ERR_SUCCESS)
                break;
        }
        rv = exr_encoding_run(f, part, &enc);
    }
    if (started)
        exr_encoding_destroy(f, &enc);
    exr_result_t fin = f ? exr_finish(&f) : EXR_ERR_SUCCESS;
    if (rv == EXR_ERR_SUCCESS)
        rv = fin;
    if (rv != EXR_ERR_SUCCESS || af.failed) {
        log_error("image", "%s: cannot write EXR (%s)", path, af.failed ? "write failed" : exr_reason(rv));
        util_atomic_abort(&af);
        return false;
    }
    return util_atomic_commit(&af, "image");
}

/* Opens an EXR held in memory; on failure logs one line naming the file. */
static bool exr_open(const char *path, ExrMemory *m, exr_context_t *f)
{
    size_t size = 0;
    char *data = util_read_input("image", "image", path, UTIL_MAX_INPUT_BYTES, &size);
    if (!data)
        return false;
    m->data = (const uint8_t *)data;
    m->size = size;
    if (size < 4 || memcmp(data, "\x76\x2f\x31\x01", 4) != 0) {
        log_error("image", "%s: not an OpenEXR file (no EXR magic number)", path);
        free(data);
        return false;
    }
    g_exr_msg[0] = 0;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_on_error;
    init.user_data = m;
    init.read_fn = exr_read_cb;
    init.size_fn = exr_size_cb;
    init.max_image_width = init.max_image_height = 65536;
    exr_result_t rv = exr_start_read(f, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        log_error("image", "%s: cannot read EXR header (%s)", path, exr_reason(rv));
        free(data);
        *f = NULL;
        return false;
    }
    return true;
}

/* The channel named PREFIX + name, or -1. */
static int exr_channel(const exr_attr_chlist_t *chl, const char *prefix, size_t plen, const char *name)
{
    for (int i = 0; i < chl->num_channels; i++) {
        const char *nm = chl->entries[i].name.str;
        if (!strncmp(nm, prefix, plen) && !strcmp(nm + plen, name))
            return i;
    }
    return -1;
}

/* Whether PREFIX + names[k] exist for k = 0..2; their indices in got. */
static bool exr_layer(const exr_attr_chlist_t *chl, const char *prefix, size_t plen, const char *const names[3],
                      int got[3])
{
    for (int k = 0; k < 3; k++)
        if ((got[k] = exr_channel(chl, prefix, plen, names[k])) < 0)
            return false;
    return true;
}

/* The channels read into R, G and B (want): R, G, B; else one layer's
 * LAYER.R, .G, .B (Blender's multilayer files: of several, the one whose
 * name ends in "Combined", the beauty image); else Y, or one layer's
 * LAYER.Y, into all three. NULL, or why the file cannot be read (in msg). */
static const char *exr_pick_channels(const exr_attr_chlist_t *chl, int want[3], char *msg, size_t cap)
{
    static const char *const rgb[3] = {"R", "G", "B"}, *const luma[3] = {"Y", "Y", "Y"};
    for (int pass = 0; pass < 2; pass++) {
        const char *const *names = pass ? luma : rgb;
        if (pass && (exr_channel(chl, "", 0, "RY") >= 0 || exr_channel(chl, "", 0, "BY") >= 0)) {
            snprintf(msg, cap, "luminance/chroma channels (Y, RY, BY) are not supported");
            return msg;
        }
        if (exr_layer(chl, "", 0, names, want))
            return NULL;
        int layers = 0, beauties = 0, first[3], beauty[3];
        char list[160] = "";
        for (int i = 0; i < chl->num_channels; i++) {
            const char *nm = chl->entries[i].name.str, *dot = strrchr(nm, '.');
            int got[3];
            if (!dot || strcmp(dot + 1, names[0])) /* channel i is not LAYER.R (LAYER.Y) */
                continue;
            size_t plen = (size_t)(dot - nm) + 1;
            if (!exr_layer(chl, nm, plen, names, got))
                continue;
            if (layers == 0)
                memcpy(first, got, sizeof got);
            if (plen >= 9 && !strncmp(dot - 8, "Combined", 8) && beauties++ == 0)
                memcpy(beauty, got, sizeof got);
            size_t len = strlen(list);
            snprintf(list + len, sizeof list - len, "%s%.*s", layers++ ? ", " : "", (int)plen - 1, nm);
        }
        if (layers == 1 || (layers > 1 && beauties == 1)) {
            memcpy(want, layers == 1 ? first : beauty, sizeof first);
            return NULL;
        }
        if (layers > 1) {
            snprintf(msg, cap, "%d layers hold %s (%s) and %s named ...Combined: save the one to read on its own",
                     layers, pass ? "Y" : "R, G, B", list, beauties ? "more than one is" : "none is");
            return msg;
        }
    }
    snprintf(msg, cap, "no R, G, B (or Y) channels, nor one layer of them");
    return msg;
}

bool image_read_exr(const char *path, ImageF *img)
{
    ExrMemory m;
    exr_context_t f = NULL;
    memset(img, 0, sizeof *img);
    if (!exr_open(path, &m, &f))
        return false;
    const char *problem = NULL;
    char why[256];
    exr_storage_t storage;
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *chl = NULL;
    exr_result_t rv = exr_get_storage(f, 0, &storage);
    if (rv == EXR_ERR_SUCCESS && storage != EXR_STORAGE_SCANLINE)
        problem = "only scanline images are read (this one is tiled or deep)";
    if (!problem && rv == EXR_ERR_SUCCESS)
        rv = exr_get_data_window(f, 0, &dw);
    if (!problem && rv == EXR_ERR_SUCCESS)
        rv = exr_get_channels(f, 0, &chl);
    int w = 0, h = 0, want[3] = {-1, -1, -1};
    if (!problem && rv == EXR_ERR_SUCCESS) {
        w = dw.max.x - dw.min.x + 1;
        h = dw.max.y - dw.min.y + 1;
        problem = exr_pick_channels(chl, want, why, sizeof why);
        for (int k = 0; k < 3 && !problem; k++)
            if (chl->entries[want[k]].x_sampling != 1 || chl->entries[want[k]].y_sampling != 1)
                problem = "subsampled channels are not supported";
        if (!problem && (w < 1 || h < 1 || (size_t)w * (size_t)h > IMAGE_MAX_PIXELS))
            problem = "image size out of range";
    }
    if (!problem && rv == EXR_ERR_SUCCESS && !image_alloc(img, w, h)) {
        exr_finish(&f);
        free((void *)m.data);
        return false;
    }
    int32_t lines = 1;
    if (!problem && rv == EXR_ERR_SUCCESS)
        rv = exr_get_scanlines_per_chunk(f, 0, &lines);
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    bool started = false;
    for (int y = dw.min.y; !problem && rv == EXR_ERR_SUCCESS && y <= dw.max.y; y += lines) {
        exr_chunk_info_t cinfo;
        rv = exr_read_scanline_chunk_info(f, 0, y, &cinfo);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = started ? exr_decoding_update(f, 0, &cinfo, &dec) : exr_decoding_initialize(f, 0, &cinfo, &dec);
        if (rv != EXR_ERR_SUCCESS)
            break;
        int row = cinfo.start_y - dw.min.y;
        for (int c = 0; c < dec.channel_count; c++) {
            exr_coding_channel_info_t *ch = &dec.channels[c];
            ch->decode_to_ptr = NULL;
            for (int k = 0; k < 3; k++)
                if (!strcmp(ch->channel_name, chl->entries[want[k]].name.str) && !ch->decode_to_ptr) {
                    ch->decode_to_ptr = (uint8_t *)(image_px(img, 0, row) + k);
                    ch->user_pixel_stride = 3 * sizeof(float);
                    ch->user_line_stride = 3 * sizeof(float) * w;
                    ch->user_bytes_per_element = sizeof(float);
                    ch->user_data_type = EXR_PIXEL_FLOAT;
                }
        }
        if (!started) {
            started = true;
            rv = exr_decoding_choose_default_routines(f, 0, &dec);
            if (rv != EXR_ERR_SUCCESS)
                break;
        }
        rv = exr_decoding_run(f, 0, &dec);
    }
    if (started)
        exr_decoding_destroy(f, &dec);
    exr_finish(&f);
    free((void *)m.data);
    if (!problem && rv == EXR_ERR_SUCCESS && want[0] == want[1]) /* Y: copied into G and B */
        for (size_t i = 0; i < (size_t)w * h; i++)
            img->rgb[3 * i + 1] = img->rgb[3 * i + 2] = img->rgb[3 * i];
    if (problem || rv != EXR_ERR_SUCCESS) {
        log_error("image", "%s: cannot read EXR (%s)", path, problem ? problem : exr_reason(rv));
        image_free(img);
        return false;
    }
    return true;
}

bool image_read_exr_attr(const char *path, const char *name, int *value)
{
    ExrMemory m;
    exr_context_t f = NULL;
    if (!exr_open(path, &m, &f))
        return false;
    int32_t v = 0;
    exr_result_t rv = exr_attr_get_int(f, 0, name, &v);
    exr_finish(&f);
    free((void *)m.data);
    if (rv != EXR_ERR_SUCCESS) {
        log_error("image", "%s: no integer attribute '%s' in the EXR header", path, name);
        return false;
    }
    *value = v;
    return true;
}
