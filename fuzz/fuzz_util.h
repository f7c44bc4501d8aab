/* fuzz_util.h — helpers shared by the libFuzzer targets: the fuzz input as
 * a temporary file (the loaders take paths, as the CLI does). */
#ifndef RTGI_FUZZ_UTIL_H
#define RTGI_FUZZ_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

/* Writes data to $TMPDIR (or /tmp)/rtgi-fuzz-<pid>-<name>; the path in
 * `path`. false if it cannot (the target then skips the input). */
static inline int fuzz_write_temp(const char *name, const uint8_t *data, size_t size, char *path, size_t cap)
{
    const char *dir = getenv("TMPDIR");
    snprintf(path, cap, "%s/rtgi-fuzz-%d-%s", dir && dir[0] ? dir : "/tmp", (int)getpid(), name);
    FILE *f = fopen(path, "wb");
    if (!f)
        return 0;
    int ok = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && ok;
}

#endif
