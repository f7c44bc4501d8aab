/* alloc_failure_shim.c — LD_PRELOAD'ed by scripts/alloc-failure-sweep.sh:
 * makes the OOM_AT-th malloc, calloc or realloc that the executable itself
 * calls (its return address in the executable's code; the GL driver's,
 * libc's and the other libraries' are left alone) return NULL, and writes
 * 1 to OOM_REPORT at exit if it did, and to OOM_COUNT how many it counted
 * (OOM_AT=0: every one, none failed); OOM_BACKTRACE=1 prints where the
 * refused one was asked for. A test tool, not part of rtgi. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <execinfo.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include <unistd.h>

static void *(*real_malloc)(size_t), *(*real_calloc)(size_t, size_t), *(*real_realloc)(void *, size_t);
static long countdown = -1, counted;
static uintptr_t lo, hi;
static int inited, fired;

static void init(void)
{
    inited = 1;
    const char *e = getenv("OOM_AT");
    countdown = e ? atol(e) : 0;
    FILE *f = fopen("/proc/self/maps", "r");
    char line[512], exe[256] = "";
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) exe[n] = 0;
    while (f && fgets(line, sizeof line, f)) {
        if (strstr(line, exe) && strstr(line, "r-xp")) {
            unsigned long a, b;
            sscanf(line, "%lx-%lx", &a, &b);
            if (!lo) lo = a;
            hi = b;
        }
    }
    if (f) fclose(f);
}

static int should_fail(void *ret)
{
    if (!inited) return 0;
    uintptr_t r = (uintptr_t)ret;
    if (r < lo || r >= hi) return 0;
    counted++;
    if (countdown <= 0) return 0;
    if (--countdown == 0) {
        fired = 1;
        if (getenv("OOM_BACKTRACE")) {
            void *frames[24];
            int n = backtrace(frames, 24);
            backtrace_symbols_fd(frames, n, 2);
        }
        return 1;
    }
    return 0;
}

__attribute__((destructor)) static void report(void)
{
    const char *o = getenv("OOM_REPORT");
    if (o) { FILE *f = fopen(o, "w"); if (f) { fprintf(f, "%d\n", fired); fclose(f); } }
    const char *c = getenv("OOM_COUNT");
    if (c) { FILE *f = fopen(c, "w"); if (f) { fprintf(f, "%ld\n", counted); fclose(f); } }
}

void *malloc(size_t s)
{
    if (!real_malloc) real_malloc = dlsym(RTLD_NEXT, "malloc");
    if (should_fail(__builtin_return_address(0))) return NULL;
    return real_malloc(s);
}
void *calloc(size_t a, size_t b)
{
    if (!real_calloc) {
        /* dlsym may call calloc: serve that one from a static buffer */
        static char buf[4096]; static int busy;
        if (busy) { memset(buf, 0, sizeof buf); return buf; }
        busy = 1; real_calloc = dlsym(RTLD_NEXT, "calloc"); busy = 0;
    }
    if (should_fail(__builtin_return_address(0))) return NULL;
    return real_calloc(a, b);
}
void *realloc(void *p, size_t s)
{
    if (!real_realloc) real_realloc = dlsym(RTLD_NEXT, "realloc");
    if (should_fail(__builtin_return_address(0))) return NULL;
    return real_realloc(p, s);
}
__attribute__((constructor)) static void ctor(void) { init(); }
