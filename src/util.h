/* util.h — small helpers: file reading, growable strings, parsing. */
#ifndef RTGI_UTIL_H
#define RTGI_UTIL_H

#include <stdbool.h>
#include <stddef.h>

/* Reads a whole file, NUL-terminated; NULL if unreadable. Caller frees. */
char *util_read_file(const char *path, size_t *size);
char *util_strndup(const char *s, size_t n);
/* Directory part of `path` ("." if none) into `dir`. */
void util_dirname(const char *path, char *dir, size_t cap);
/* Joins a path relative to `base_dir` (absolute paths are kept). */
void util_join_path(const char *base_dir, const char *rel, char *out, size_t cap);
bool util_ends_with(const char *s, const char *suffix);
/* Creates the parent directory of `path` if it is missing (one level). */
void util_ensure_parent_dir(const char *path);
/* Monotonic wall-clock seconds. */
double util_seconds(void);

/* Growable string buffer; zero-initialise, free .data when done. */
typedef struct StrBuf {
    char *data; /* NUL-terminated, owned */
    size_t len; /* bytes used, excluding NUL */
    size_t cap; /* bytes allocated */
} StrBuf;
void strbuf_append(StrBuf *b, const char *s, size_t n);
void strbuf_printf(StrBuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
