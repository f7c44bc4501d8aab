/* fuzz_image.c — libFuzzer target: the image readers (PFM, PNG through
 * stb_image, and OpenEXR through OpenEXRCore). The first byte picks the
 * format (its low two bits: 0 PFM, 2 EXR, odd PNG); the rest is the file. A
 * decoded image is also checked for non-finite pixels and written back as
 * PFM when finite (the writers' checks). */
#include "fuzz_util.h"
#include "io/image.h"
#include "base/log.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    log_set_level(LOG_QUIET);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    char path[512], out[512];
    const char *name = data[0] & 1 ? "image.png" : data[0] & 2 ? "image.exr" : "image.pfm";
    if (!fuzz_write_temp(name, data + 1, size - 1, path, sizeof path))
        return 0;
    ImageF img = {0};
    if (image_read(path, &img)) {
        snprintf(out, sizeof out, "%s.out.pfm", path);
        if (img.width * img.height <= 4096 && image_write_pfm(out, &img))
            unlink(out);
        image_free(&img);
    }
    unlink(path);
    return 0;
}
