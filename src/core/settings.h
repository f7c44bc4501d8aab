/* settings.h — the table of technique settings: one row per setting with
 * its scene-file key, command-line option, type, place, range, default and
 * help. One parser and one validator serve the command line and the scene
 * file (so the two cannot disagree), `--help` is printed from the table, and
 * tests check the guide (docs/guide.md) against it. Adding a setting is adding a row (and
 * its field in ShadowParams/GiParams, scene.h). */
#ifndef RTGI_SETTINGS_H
#define RTGI_SETTINGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <cjson/cJSON.h>

#include "core/scene.h"

/* Everything the table stores. */
typedef struct Settings {
    ShadowParams shadow;
    GiParams gi;
} Settings;

typedef enum SettingType {
    SETTING_INT,   /* integer; CLI N, JSON integer */
    SETTING_UINT,  /* unsigned integer (seeds) */
    SETTING_FLOAT, /* finite number */
    SETTING_BOOL,  /* CLI on|off, JSON true/false */
    SETTING_FLAG,  /* CLI flag without a value (sets true), JSON true/false */
    SETTING_ENUM,  /* CLI/JSON one of `choices`, stored as int */
    SETTING_PAIR,  /* two ints: CLI NxM, JSON [n, m] */
} SettingType;

typedef struct SettingDesc {
    const char *group;           /* scene-file object holding it: "shadow" or "gi" */
    const char *key;             /* its key there */
    const char *option;          /* command-line option */
    SettingType type;
    size_t offset;               /* in Settings */
    size_t offset2;              /* SETTING_PAIR: the second int */
    double min, max;             /* inclusive range (pairs: each; enum/bool: unused) */
    double def;                  /* default (pairs: both values) */
    const char *const *choices;  /* SETTING_ENUM: names, index = stored value; NULL-terminated */
    const char *help;            /* one line, with its unit */
} SettingDesc;

extern const SettingDesc settings_table[];
extern const int settings_count;

/* Every setting at its default. */
void settings_default(Settings *s);
/* The row whose option is `option` (e.g. "--pcf-samples"), or NULL. */
const SettingDesc *settings_find_option(const char *option);
/* The row of `group`.`key`, or NULL. */
const SettingDesc *settings_find_key(const char *group, const char *key);

/* The keys of `group`'s rows (NULL: every row's) into out[0..cap-1],
 * NULL-terminated (for "did you mean"); returns how many. */
int settings_keys(const char *group, const char **out, int cap);

/* Parses a command-line value (NULL for SETTING_FLAG) into `s`, range
 * checked. false after logging a usage error (cli_error) "<option>: '<value>'
 * <problem> (allowed: <range>)", with the nearest choice of an enum. */
bool settings_parse_cli(const SettingDesc *d, const char *value, Settings *s);
/* Reads the scene file's `group` object into `s`: every key must be a row
 * of the group (unknown keys are an error naming the nearest known key),
 * no key twice, each value of the row's type and in its range. false after
 * logging "<file>: <group>.<key>: <problem>". */
bool settings_parse_json(const cJSON *obj, const char *group, const char *file, Settings *s);
/* Copies the value of row `d` from `src` to `dst`. */
void settings_copy(const SettingDesc *d, Settings *dst, const Settings *src);
/* The value of row `d` in `s` as text ("20", "0.0005", "4x4", "paper", "on"). */
void settings_format(const SettingDesc *d, const Settings *s, char *out, size_t cap);
/* Prints the option help of one group, from the table. */
void settings_print_help(FILE *f, const char *group);

#endif
