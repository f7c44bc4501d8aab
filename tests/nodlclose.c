/* nodlclose.c — LD_PRELOAD shim for `make test-asan`: dlclose does nothing,
 * so the GL driver that libEGL loads stays mapped at exit and
 * LeakSanitizer can name it in reports (tests/lsan.supp suppresses it by
 * name). Without it, the driver's allocations show as "<unknown module>"
 * and cannot be told apart from anything else. */
int dlclose(void *handle);
int dlclose(void *handle)
{
    (void)handle;
    return 0;
}
