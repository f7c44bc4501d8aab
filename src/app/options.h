/* options.h — a command's options as a table: each row an option name, the
 * value it sets (base/value.h: the same parser and validator as the
 * settings table's rows), its help line. The command's loop hands each
 * option to options_take, and its --help prints the table; what a table
 * cannot say (options that depend on each other, files checked before the
 * work) stays in the command, after the loop. */
#ifndef RTGI_OPTIONS_H
#define RTGI_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "app/cli.h"
#include "base/value.h"
#include "core/settings.h"

#define OPTION_NO_FLAG ((size_t)-1)

typedef struct OptionDesc {
    const char *name;  /* "--spp" */
    ValueSpec value;   /* what it sets, in the command's struct */
    const char *help;  /* one line, with its unit */
    size_t given;      /* offset of a bool set when it is given, or OPTION_NO_FLAG */
    /* An extra check of a text value (e.g. cli_scene); NULL: none. */
    bool (*check)(const char *opt, const char *text);
    const char *arg;   /* the argument's name in --help; NULL: from its type ("N", "X", "WxH", "FILE") */
} OptionDesc;

/* The rows, NULL name last. Helpers for the common kinds: */
#define OPT_INT(n, T, f, lo, hi, h) {n, {VALUE_INT, offsetof(T, f), 0, lo, hi, NULL, NULL}, h, OPTION_NO_FLAG, NULL, NULL}
#define OPT_FLOAT(n, T, f, lo, hi, h) {n, {VALUE_FLOAT, offsetof(T, f), 0, lo, hi, NULL, NULL}, h, OPTION_NO_FLAG, NULL, NULL}
#define OPT_DOUBLE(n, T, f, lo, hi, h) {n, {VALUE_DOUBLE, offsetof(T, f), 0, lo, hi, NULL, NULL}, h, OPTION_NO_FLAG, NULL, NULL}
#define OPT_FLAG(n, T, f, h) {n, {VALUE_FLAG, offsetof(T, f), 0, 0, 1, NULL, NULL}, h, OPTION_NO_FLAG, NULL, NULL}
#define OPT_CHOICE(n, T, f, names, h) {n, {VALUE_CHOICE, offsetof(T, f), 0, 0, 0, names, NULL}, h, OPTION_NO_FLAG, NULL, NULL}
#define OPT_SIZE(n, T, w, hh, max, h) {n, {VALUE_SIZE, offsetof(T, w), offsetof(T, hh), 1, max, NULL, NULL}, h, OPTION_NO_FLAG, NULL, NULL}
#define OPT_TEXT(n, T, f, endings, h) {n, {VALUE_TEXT, offsetof(T, f), 0, 0, 0, NULL, endings}, h, OPTION_NO_FLAG, NULL, NULL}
#define OPT_SCENE(n, T, f, h) {n, {VALUE_TEXT, offsetof(T, f), 0, 0, 0, NULL, NULL}, h, OPTION_NO_FLAG, cli_scene, NULL}
#define OPT_WORD(n, T, f, argname, h) {n, {VALUE_TEXT, offsetof(T, f), 0, 0, 0, NULL, NULL}, h, OPTION_NO_FLAG, NULL, argname}
#define OPT_END {NULL, {0}, NULL, 0, NULL, NULL}

/* The row of `table` named `opt`, or NULL. */
const OptionDesc *options_find(const OptionDesc *table, const char *opt);
/* If `opt` (from cli_next) is a row of `table`: takes its value from `a`
 * (none for a flag), parses it into `out` and returns 1, or -1 after
 * logging a usage error. 0 if it is not a row. */
int options_take(const OptionDesc *table, const char *opt, CliArgs *a, void *out);
/* Appends the rows' names to out[*n..cap-2] and NULL-terminates (for "did
 * you mean"). */
void options_names(const OptionDesc *table, const char **out, int *n, int cap);
/* If `opt` is a settings-table row's option (core/settings.h): parses its
 * value into `set`, marks given[row] and returns 1, or -1 after logging; 0
 * if it is none. */
int options_take_setting(const char *opt, CliArgs *a, Settings *set, bool given[]);
/* "Did you mean" over the tables (NULL-terminated) and, with `settings`,
 * every settings row: logs "unknown option" for `opt`. */
void options_unknown(const char *opt, const OptionDesc *const *tables, bool settings);
/* What a command's option loop reads: its tables (NULL-terminated), with
 * `set` every settings row (into set, marking given[]), and the options of
 * another command, refused by name ("--x is an option of 'rtgi view'"). */
typedef struct OptionSet {
    const OptionDesc *const *tables;
    Settings *set;
    bool *given;
    const OptionDesc *elsewhere;  /* may be NULL */
    const char *elsewhere_command;
    void (*help)(void);
} OptionSet;
/* A command's whole option loop: --help (help(), then -1), every row of
 * its tables and settings rows, an option of the other command, unknown
 * options. 0: go on; -1: help was shown; 2: a usage error was logged. */
int options_parse(int argc, char **argv, const OptionSet *os, void *out);
/* Prints the rows' help, with each value's default from `defaults` (the
 * command's struct as initialised). */
void options_print_help(FILE *f, const OptionDesc *table, const void *defaults);

#endif
