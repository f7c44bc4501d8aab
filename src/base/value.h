/* value.h — one typed value of the command line or a scene file, and the
 * one parser and validator of them all: the settings table's rows
 * (core/settings.h) and every command's option table (app/options.h) are
 * read by this code, so a type reads, checks its range and words its
 * errors the same wherever it is given.
 *
 * A ValueSpec says where in a struct the value goes (`offset`, and
 * `offset2` for the second int of a pair or size), its type and range. */
#ifndef RTGI_VALUE_H
#define RTGI_VALUE_H

#include <stdbool.h>
#include <stddef.h>

typedef enum ValueType {
    VALUE_INT,    /* int; CLI N, JSON integer */
    VALUE_UINT,   /* unsigned (seeds) */
    VALUE_FLOAT,  /* finite float */
    VALUE_DOUBLE, /* finite double */
    VALUE_BOOL,   /* bool; CLI on|off, JSON true/false */
    VALUE_FLAG,   /* bool set true by a CLI flag without a value; JSON true/false */
    VALUE_CHOICE, /* int: index of one of `choices` */
    VALUE_PAIR,   /* two ints: CLI NxM, JSON [n, m]; each in [min, max] */
    VALUE_SIZE,   /* two ints: CLI WxH, each in [1, max] */
    VALUE_TEXT,   /* const char * (the argument itself); with `endings`, one of them ("png|pfm|exr") */
} ValueType;

typedef struct ValueSpec {
    ValueType type;
    size_t offset;              /* in the struct written */
    size_t offset2;             /* VALUE_PAIR, VALUE_SIZE: the second int */
    double min, max;            /* inclusive range (pairs: each; size: max) */
    const char *const *choices; /* VALUE_CHOICE: names, index = stored value; NULL-terminated */
    const char *endings;        /* VALUE_TEXT: the file endings allowed, '|'-separated, or NULL */
} ValueSpec;

/* Whether the value takes an argument (all but VALUE_FLAG). */
static inline bool value_takes_argument(const ValueSpec *v) { return v->type != VALUE_FLAG; }
/* Parses a command-line argument (NULL for VALUE_FLAG) of option `opt`
 * into `base`, range checked. false after one usage error (usage_error):
 * "<opt>: '<text>' <problem> (allowed: <range>)", or for a choice
 * "<opt>: unknown value '<text>' (one of a|b); did you mean 'a'?". */
bool value_parse_text(const ValueSpec *v, const char *opt, const char *text, void *base);
/* Stores the number x (already checked) in `base` (pairs: both ints). */
void value_store_number(const ValueSpec *v, void *base, double x);
/* NULL if x is a valid number for v, else the problem ("is out of range"). */
const char *value_check_number(const ValueSpec *v, double x);
/* What v takes, in the words of the command line or (json) of a scene file. */
void value_describe(const ValueSpec *v, bool json, char *out, size_t cap);
/* The value in `base` as text ("20", "0.0005", "4x4", "paper", "on"). */
void value_format(const ValueSpec *v, const void *base, char *out, size_t cap);
/* The argument's placeholder in help text ("N", "X", "on|off", "a|b", "NxM", "WxH", "FILE"). */
void value_placeholder(const ValueSpec *v, char *out, size_t cap);
/* Copies the value from `src` to `dst` (structs of the same type). */
void value_copy(const ValueSpec *v, void *dst, const void *src);

#endif
