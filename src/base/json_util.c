/* json_util.c — unknown and duplicate key checks for JSON objects. */
#include "base/json_util.h"

#include <stdio.h>
#include <string.h>

#include "base/log.h"
#include "base/util.h"

static bool g_lenient;

void json_set_lenient(bool lenient) { g_lenient = lenient; }
bool json_get_lenient(void) { return g_lenient; }

/* "where.key" or "key" for the top level. */
static void key_path(char *buf, size_t cap, const char *where, const char *key)
{
    if (where && where[0])
        snprintf(buf, cap, "%s.%s", where, key);
    else
        snprintf(buf, cap, "%s", key);
}

bool json_check_keys(const cJSON *obj, const char *const *known, const char *file, const char *where)
{
    char kp[320];
    int n = 0;
    for (const cJSON *e = obj ? obj->child : NULL; e; e = e->next)
        if (++n > JSON_MAX_KEYS) {
            log_error("scene", "%s: %s has more than %d keys", file, where && where[0] ? where : "the top level",
                      JSON_MAX_KEYS);
            return false;
        }
    for (const cJSON *e = obj ? obj->child : NULL; e; e = e->next) {
        const char *key = e->string ? e->string : "";
        for (const cJSON *d = obj->child; d != e; d = d->next)
            if (d->string && strcmp(d->string, key) == 0) {
                key_path(kp, sizeof kp, where, key);
                log_error("scene", "%s: duplicate key \"%s\"", file, kp);
                return false;
            }
        bool ok = false;
        for (int i = 0; known[i] && !ok; i++)
            ok = strcmp(known[i], key) == 0;
        if (ok)
            continue;
        key_path(kp, sizeof kp, where, key);
        const char *near = util_nearest(key, known);
        char hint[160];
        if (near) {
            snprintf(hint, sizeof hint, "did you mean \"%s\"?", near);
        } else {
            /* No likely typo: list the known keys. */
            size_t len = (size_t)snprintf(hint, sizeof hint, "known keys:");
            for (int i = 0; known[i] && len < sizeof hint; i++)
                len += (size_t)snprintf(hint + len, sizeof hint - len, "%s %s", i ? "," : "", known[i]);
        }
        if (g_lenient) {
            log_warn("scene", "%s: unknown key \"%s\" ignored; %s", file, kp, hint);
            continue;
        }
        log_error("scene", "%s: unknown key \"%s\"; %s (--lenient ignores unknown keys)", file, kp, hint);
        return false;
    }
    return true;
}
