#include "base/log.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

static LogLevel g_level = LOG_INFO;
static LogHook g_hook;
static void *g_hook_user;

void log_set_hook(LogHook hook, void *user)
{
    g_hook = hook;
    g_hook_user = user;
}

void log_set_level(LogLevel level) { g_level = level; }
LogLevel log_get_level(void) { return g_level; }

void log_msg(LogLevel level, const char *tag, const char *fmt, ...)
{
    static const char *names[] = {"debug", "info", "warning", "error"};
    if (g_hook && level < LOG_QUIET) {
        char text[1024];
        va_list hp;
        va_start(hp, fmt);
        vsnprintf(text, sizeof text, fmt, hp);
        va_end(hp);
        g_hook(level, tag, text, g_hook_user);
    }
    if (level < g_level || level >= LOG_QUIET)
        return;
    va_list ap, ap2;
    va_start(ap, fmt);
    va_copy(ap2, ap);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    char small[512], *text = n >= 0 && (size_t)n < sizeof small ? small : malloc(n >= 0 ? (size_t)n + 1 : 1);
    if (text)
        vsnprintf(text, n >= 0 ? (size_t)n + 1 : 1, fmt, ap2);
    va_end(ap2);
    fprintf(stderr, "rtgi: %s [%s] ", names[level], tag);
    /* One message, one line: a control character (a newline in a file
     * name, say) is written as an escape, so that it cannot end the line
     * or forge another one. */
    for (const char *c = text ? text : "(message lost: out of memory)"; *c; c++) {
        unsigned char u = (unsigned char)*c;
        if (u == '\n')
            fputs("\\n", stderr);
        else if (u == '\r')
            fputs("\\r", stderr);
        else if (u < 0x20 || u == 0x7f)
            fprintf(stderr, "\\x%02x", u);
        else
            fputc(u, stderr);
    }
    fputc('\n', stderr);
    if (text != small)
        free(text);
}

void log_progress(const char *fmt, ...)
{
    if (g_level > LOG_INFO)
        return;
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    fflush(stderr);
}

double log_progress_seconds(double dflt)
{
    const char *v = getenv("RTGI_PROGRESS_S");
    char *end = NULL;
    double s = v && *v ? strtod(v, &end) : -1.0;
    return end && !*end && s >= 0.0 ? s : dflt;
}
