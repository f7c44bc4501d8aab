/* fuzz_image.c — libFuzzer target: the image readers (PFM, and PNG through
 * stb_image). The first byte picks the format; the rest is the file. A
 * decoded image is also checked for non-finite pixels and written back as
 * PFM when finite (the writers' checks). */
#include "fuzz_util.h"
#include "image.h"
#include "log.h"

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
    if (!fuzz_write_temp(data[0] & 1 ? "image.png" : "image.pfm", data + 1, size - 1, path, sizeof path))
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
