/* usage.c — the one style of usage errors every command shares. */
#include "base/usage.h"

#include <stdarg.h>
#include <stdio.h>

#include "base/log.h"

static const char *g_command; /* NULL: rtgi itself */

void usage_set_command(const char *cmd) { g_command = cmd; }

const char *usage_command(void) { return g_command ? g_command : "rtgi"; }

void usage_error(const char *near, const char *fmt, ...)
{
    char what[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    char see[96] = "rtgi --help"; /* where the command's options are */
    if (g_command)
        snprintf(see, sizeof see, "rtgi %s --help", g_command);
    const char *cmd = g_command ? g_command : "rtgi";
    if (near)
        log_error("cli", "%s: %s; did you mean '%s'? (see %s)", cmd, what, near, see);
    else
        log_error("cli", "%s: %s (see %s)", cmd, what, see);
}
