/* util.h — small helpers: file reading, growable strings, parsing. */
#ifndef RTGI_UTIL_H
#define RTGI_UTIL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <stdio.h>

/* The bits of x in reverse order (x / 2^32 is then x's van der Corput
 * radical inverse in base 2: Hammersley points, Sobol' sampling). */
static inline uint32_t util_reverse_bits(uint32_t x)
{
    x = __builtin_bswap32(x);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    return ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
}

/* Reads a whole regular file, NUL-terminated; NULL if it is missing,
 * unreadable or not a regular file (never blocks on a FIFO). Caller frees.
 * Silent: for input named by the user, use util_read_input. */
char *util_read_file(const char *path, size_t *size);

/* Input files named by the user (scene files, meshes, images). */
#define UTIL_MAX_INPUT_BYTES ((size_t)1 << 31) /* 2 GiB: the largest input file read */
/* Checks without blocking (open O_NONBLOCK, then fstat) that `path` is a
 * readable regular file of at most `max_bytes` bytes; stores its size in
 * `*size` (may be NULL). false after logging one line under `tag`:
 * "<path>: <what> does not exist", "... is a FIFO, not a regular file",
 * "... is N bytes, more than the limit of M", ... `what` names its role
 * ("scene file", "image"). */
bool util_check_input(const char *tag, const char *what, const char *path, size_t max_bytes, size_t *size);
/* util_check_input, then reads the whole file, NUL-terminated (caller
 * frees); NULL after logging. */
char *util_read_input(const char *tag, const char *what, const char *path, size_t max_bytes, size_t *size);
/* fopen(path, "rb") for a file some other file names (a mesh's materials,
 * buffers, textures), without blocking on a FIFO: NULL, silently, when it
 * cannot be opened (errno set) or is no regular file (then *kind says what
 * it is: "a FIFO", "a directory", ...; else *kind is NULL). */
FILE *util_fopen_regular(const char *path, const char **kind);

/* malloc/calloc of `count` × `size` bytes for something image- or
 * scene-sized: NULL after logging "cannot allocate <what>: N bytes" under
 * `tag` (also when count × size overflows). */
void *util_malloc(const char *tag, const char *what, size_t count, size_t size);
void *util_calloc(const char *tag, const char *what, size_t count, size_t size);
/* realloc that keeps `*p` on failure: false after logging as above. */
bool util_realloc(const char *tag, const char *what, void **p, size_t count, size_t size);

/* The longest path rtgi writes or makes a directory for (Linux's PATH_MAX). */
#define UTIL_PATH_MAX 4096

/* Output files are written atomically: to a temporary file in the same
 * directory, renamed over `path` only after every write, fflush, fsync and
 * fclose succeeded. An error removes the temporary file and leaves no
 * partial output (an existing file at `path` is untouched). A `path` that
 * is a symbolic link is written where the link points. */
typedef struct AtomicFile {
    FILE *f;                      /* write here between open and commit/abort */
    const char *path;             /* final name (not owned) */
    char target[UTIL_PATH_MAX];   /* where it goes: `path`, or the file a link there names */
    char tmp[UTIL_PATH_MAX + 16]; /* temporary file's name, beside `target` */
    bool failed;      /* set by writers that failed (e.g. a callback) */
} AtomicFile;
/* Creates the parent directory if missing (one level) and the temporary
 * file; refuses a `path` that exists but is not a regular file (a device,
 * FIFO or directory). false after logging under `tag`. */
bool util_atomic_open(AtomicFile *af, const char *tag, const char *path);
/* Flushes, syncs, closes and renames into place; false after logging
 * "<path>: write failed (<reason>)" and removing the temporary file. */
bool util_atomic_commit(AtomicFile *af, const char *tag);
/* Closes and removes the temporary file (after an error elsewhere). */
void util_atomic_abort(AtomicFile *af);
/* SIGINT, SIGTERM and SIGHUP end the program as by default, but first
 * remove the temporary file of every AtomicFile being written (main.c
 * installs this; `reference` takes SIGINT for itself while it renders). */
void util_handle_ending_signals(void);
/* Directories that such a signal removes before it ends the program: with
 * what is in them, two levels down (`tree`: a staging directory), or only
 * if empty by then (a directory the command made for its outputs). Up to
 * four; removed in reverse order of adding. */
void util_live_dir_add(const char *dir, bool tree);
void util_live_dir_remove(const char *dir);
/* Between these two such a signal waits: a command's set of outputs is
 * written whole (all of them or none), then the signal ends the program. */
void util_defer_ending_signals(void);
void util_end_deferral(void);

/* Optimal-string-alignment (restricted Damerau-Levenshtein) distance
 * between a and b: inserting, deleting or substituting one byte, or
 * swapping two adjacent ones ("pfc" for "pcf"), each cost 1; strings longer
 * than 255 bytes count as far away. */
int util_edit_distance(const char *a, const char *b);
/* The name in the NULL-terminated `names` nearest to `s` by edit distance,
 * or NULL when none is near enough to be a likely typo (distance more than
 * 1 for names up to 4 bytes, else max(2, strlen(s)/3)). A name that differs
 * only in ASCII case is the nearest ("PCSS": "pcss"). For "unknown key 'x', did you mean 'y'?". */
const char *util_nearest(const char *s, const char *const *names);
/* Writes `s` as a JSON string literal (quotes, escapes) to f; bytes that
 * do not start valid UTF-8 are written as \ufffd. */
void util_json_string(FILE *f, const char *s);
/* A copy of `s` (free it) with every byte that util_json_string writes as
 * \ufffd replaced by U+FFFD's UTF-8, for text that goes into JSON through
 * cJSON (which copies bytes as they are); NULL after logging if memory runs
 * out. */
char *util_utf8_sanitize(const char *s);
/* The first n bytes of s as a string (free it); NULL after logging if
 * memory runs out. */
char *util_strndup(const char *s, size_t n);
/* Directory part of `path` ("." if none) into `dir`. */
void util_dirname(const char *path, char *dir, size_t cap);
/* Joins a path relative to `base_dir` (absolute paths are kept). */
void util_join_path(const char *base_dir, const char *rel, char *out, size_t cap);
/* Whether `s` is written as a decimal number may be: digits, '.', 'e',
 * signs and nothing else (strtod also takes hex, "inf", "nan" and leading
 * blanks, which the options refuse, as --spp always has). */
bool util_decimal_text(const char *s);
bool util_ends_with(const char *s, const char *suffix);
/* Creates the parent directory of `path` if it is missing (one level). */
void util_ensure_parent_dir(const char *path);
/* FNV-1a over n bytes, continuing from h (start with UTIL_HASH_SEED): for
 * "what was this made from" keys compared for equality. */
#define UTIL_HASH_SEED 1469598103934665603ull
uint64_t util_hash_bytes(uint64_t h, const void *p, size_t n);
/* Monotonic wall-clock seconds. */
double util_seconds(void);
/* CPU seconds of this process so far, every thread (0 if unknown): a
 * benchmark's cost on a machine it shares. */
double util_cpu_seconds(void);
/* This machine's physical memory in bytes (0 if unknown): the commands
 * refuse buffers over half of it before they allocate. */
size_t util_physical_memory(void);

/* Growable string buffer; zero-initialise, free .data when done. If memory
 * runs out, .failed is set (and logged once) and later appends do nothing:
 * check it before using .data. */
typedef struct StrBuf {
    char *data;  /* NUL-terminated, owned; NULL until the first append */
    size_t len;  /* bytes used, excluding NUL */
    size_t cap;  /* bytes allocated */
    bool failed; /* an allocation failed: .data holds what came before */
} StrBuf;
void strbuf_append(StrBuf *b, const char *s, size_t n);
void strbuf_printf(StrBuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
