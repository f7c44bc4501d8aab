#include "log.h"

#include <stdarg.h>
#include <stdio.h>

static LogLevel g_level = LOG_INFO;

void log_set_level(LogLevel level) { g_level = level; }
LogLevel log_get_level(void) { return g_level; }

void log_msg(LogLevel level, const char *tag, const char *fmt, ...)
{
    static const char *names[] = {"debug", "info", "warning", "error"};
    if (level < g_level || level >= LOG_QUIET)
        return;
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "rtgi: %s [%s] ", names[level], tag);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}
