/* json_util.h — checks shared by every reader of JSON objects (the scene
 * file now; the settings table and CLI options may reuse them).
 *
 *   static const char *const k_camera_keys[] = {"position", "target", NULL};
 *   if (!json_check_keys(cam, k_camera_keys, path, "camera"))
 *       return false;
 *
 * Unknown keys are errors that name the key, where it is and the nearest
 * known key ("did you mean 'position'?", by util_nearest's edit distance);
 * with json_set_lenient(true) (`--lenient` on the command line) they are
 * warnings instead. Duplicate keys are always errors: cJSON keeps both and
 * lookups see the first, so the second would be silently ignored. */
#ifndef RTGI_JSON_UTIL_H
#define RTGI_JSON_UTIL_H

#include <stdbool.h>

#include <cjson/cJSON.h>

/* The most keys one object may hold (a cap that keeps the duplicate check
 * cheap on hostile input). */
#define JSON_MAX_KEYS 256

/* Whether unknown keys are warnings (true) or errors (false, the default). */
void json_set_lenient(bool lenient);
bool json_get_lenient(void);

/* Checks that `obj` (a JSON object) has only keys from the NULL-terminated
 * `known`, none twice, and at most JSON_MAX_KEYS. `file` and `where` (e.g.
 * "lights[2]", "" for the top level) only name the place in messages.
 * false after logging one line under tag "scene"; unknown keys in lenient
 * mode log a warning and pass. */
bool json_check_keys(const cJSON *obj, const char *const *known, const char *file, const char *where);

#endif
