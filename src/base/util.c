#define _GNU_SOURCE /* syscall(SYS_getdents64): a directory removed from a signal handler */
#include "base/util.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "base/log.h"

/* Opens `path` read-only without blocking (a FIFO with no writer would
 * block a plain open) and fstat()s it; -1 with errno set on failure. */
static int open_regular(const char *path, struct stat *st)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return -1;
    if (fstat(fd, st) != 0) {
        int e = errno;
        close(fd);
        errno = e;
        return -1;
    }
    /* Regular files ignore O_NONBLOCK; clear it anyway for plain reads. */
    int fl = fcntl(fd, F_GETFL);
    if (fl >= 0)
        fcntl(fd, F_SETFL, fl & ~O_NONBLOCK);
    return fd;
}

static const char *file_kind(mode_t m)
{
    if (S_ISDIR(m))
        return "a directory";
    if (S_ISFIFO(m))
        return "a FIFO";
    if (S_ISCHR(m))
        return "a character device";
    if (S_ISBLK(m))
        return "a block device";
    if (S_ISSOCK(m))
        return "a socket";
    return "not a regular file";
}

/* Reads exactly n bytes from fd into a new NUL-terminated buffer. */
static char *read_fd(int fd, size_t n)
{
    char *buf = malloc(n + 1);
    if (!buf) {
        errno = ENOMEM;
        return NULL;
    }
    size_t got = 0;
    while (got < n) {
        ssize_t r = read(fd, buf + got, n - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            break;
        got += (size_t)r;
    }
    if (got != n) {
        int e = errno;
        free(buf);
        errno = e == ENOMEM ? EIO : e;
        return NULL;
    }
    buf[n] = 0;
    return buf;
}

char *util_read_file(const char *path, size_t *size)
{
    struct stat st;
    int fd = open_regular(path, &st);
    if (fd < 0)
        return NULL;
    char *buf = NULL;
    if (S_ISREG(st.st_mode) && (uint64_t)st.st_size <= UTIL_MAX_INPUT_BYTES)
        buf = read_fd(fd, (size_t)st.st_size);
    close(fd);
    if (buf && size)
        *size = (size_t)st.st_size;
    return buf;
}

/* Shared by util_check_input and util_read_input: the open descriptor of a
 * checked input file, or -1 after logging. */
static int open_input(const char *tag, const char *what, const char *path, size_t max_bytes, size_t *size)
{
    struct stat st;
    int fd = open_regular(path, &st);
    if (fd < 0) {
        if (errno == ENOENT || errno == ENOTDIR)
            log_error(tag, "%s: cannot read %s: it does not exist", path, what);
        else
            log_error(tag, "%s: cannot open %s (%s)", path, what, strerror(errno));
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        log_error(tag, "%s: %s is %s, not a regular file", path, what, file_kind(st.st_mode));
        close(fd);
        return -1;
    }
    if ((uint64_t)st.st_size > max_bytes) {
        log_error(tag, "%s: %s is %lld bytes, more than the limit of %zu", path, what, (long long)st.st_size,
                  max_bytes);
        close(fd);
        return -1;
    }
    if (size)
        *size = (size_t)st.st_size;
    return fd;
}

FILE *util_fopen_regular(const char *path, const char **kind)
{
    *kind = NULL;
    struct stat st;
    int fd = open_regular(path, &st);
    if (fd < 0)
        return NULL;
    if (!S_ISREG(st.st_mode)) {
        *kind = file_kind(st.st_mode);
        close(fd);
        errno = EINVAL;
        return NULL;
    }
    FILE *f = fdopen(fd, "rb");
    if (!f)
        close(fd);
    return f;
}

bool util_check_input(const char *tag, const char *what, const char *path, size_t max_bytes, size_t *size)
{
    int fd = open_input(tag, what, path, max_bytes, size);
    if (fd < 0)
        return false;
    close(fd);
    return true;
}

char *util_read_input(const char *tag, const char *what, const char *path, size_t max_bytes, size_t *size)
{
    size_t n = 0;
    int fd = open_input(tag, what, path, max_bytes, &n);
    if (fd < 0)
        return NULL;
    errno = 0;
    char *buf = read_fd(fd, n);
    int e = errno;
    close(fd);
    if (!buf) {
        if (e == ENOMEM)
            log_error(tag, "%s: cannot allocate %zu bytes to read the %s", path, n + 1, what);
        else
            log_error(tag, "%s: cannot read %s (%s)", path, what, e ? strerror(e) : "short read");
        return NULL;
    }
    if (size)
        *size = n;
    return buf;
}

char *util_strndup(const char *s, size_t n)
{
    char *d = util_malloc("util", "a copy of a string", n + 1, 1);
    if (d) {
        memcpy(d, s, n);
        d[n] = 0;
    }
    return d;
}

void util_dirname(const char *path, char *dir, size_t cap)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(dir, cap, ".");
    else if (slash == path)
        snprintf(dir, cap, "/");
    else
        snprintf(dir, cap, "%.*s", (int)(slash - path), path);
}

void util_join_path(const char *base_dir, const char *rel, char *out, size_t cap)
{
    if (rel[0] == '/' || !base_dir || !base_dir[0])
        snprintf(out, cap, "%s", rel);
    else
        snprintf(out, cap, "%s/%s", base_dir, rel);
}

bool util_decimal_text(const char *s)
{
    if (!s || !*s)
        return false;
    for (; *s; s++)
        if (!strchr("0123456789.eE+-", *s))
            return false;
    return true;
}

bool util_ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    if (b > a)
        return false;
    for (size_t i = 0; i < b; i++) {
        char c = s[a - b + i];
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != suffix[i])
            return false;
    }
    return true;
}

double util_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double util_cpu_seconds(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0)
        return 0.0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

size_t util_physical_memory(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    return pages > 0 && page > 0 ? (size_t)pages * (size_t)page : 0;
}

void strbuf_append(StrBuf *b, const char *s, size_t n)
{
    if (b->failed)
        return;
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 256;
        while (cap < b->len + n + 1)
            cap *= 2;
        void *p = b->data;
        if (!util_realloc("util", "a text buffer", &p, cap, 1)) {
            b->failed = true;
            return;
        }
        b->data = p;
        b->cap = cap;
    }
    memcpy(b->data + b->len, s, n);
    b->len += n;
    b->data[b->len] = 0;
}

void strbuf_printf(StrBuf *b, const char *fmt, ...)
{
    if (b->failed)
        return;
    char tmp[1024];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (n < 0)
        return;
    if (n < (int)sizeof tmp) {
        strbuf_append(b, tmp, (size_t)n);
        return;
    }
    char *big = util_malloc("util", "a text buffer", (size_t)n + 1, 1);
    if (!big) {
        b->failed = true;
        return;
    }
    va_start(ap, fmt);
    vsnprintf(big, (size_t)n + 1, fmt, ap);
    va_end(ap);
    strbuf_append(b, big, (size_t)n);
    free(big);
}

void util_ensure_parent_dir(const char *path)
{
    char dir[UTIL_PATH_MAX];
    if (strlen(path) >= sizeof dir)
        return; /* a cut name would make another directory; the open fails */
    util_dirname(path, dir, sizeof dir);
    struct stat st;
    if (stat(dir, &st) != 0)
        mkdir(dir, 0777);
}

uint64_t util_hash_bytes(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* One line naming what could not be allocated and its size. */
static void log_alloc_failure(const char *tag, const char *what, size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size)
        log_error(tag, "cannot allocate %s: %zu x %zu bytes overflows", what, count, size);
    else
        log_error(tag, "cannot allocate %s: %zu bytes", what, count * size);
}

void *util_malloc(const char *tag, const char *what, size_t count, size_t size)
{
    void *p = NULL;
    if (size == 0 || count <= SIZE_MAX / size)
        p = malloc((count * size) != 0 ? count * size : 1);
    if (!p)
        log_alloc_failure(tag, what, count, size);
    return p;
}

void *util_calloc(const char *tag, const char *what, size_t count, size_t size)
{
    void *p = NULL;
    if (size == 0 || count <= SIZE_MAX / size)
        p = calloc(count ? count : 1, size ? size : 1);
    if (!p)
        log_alloc_failure(tag, what, count, size);
    return p;
}

bool util_realloc(const char *tag, const char *what, void **p, size_t count, size_t size)
{
    void *q = NULL;
    if (size == 0 || count <= SIZE_MAX / size)
        q = realloc(*p, (count * size) != 0 ? count * size : 1);
    if (!q) {
        if (size && count > SIZE_MAX / size)
            log_error(tag, "cannot allocate %s: %zu x %zu bytes overflows", what, count, size);
        else
            log_error(tag, "cannot allocate %s: %zu bytes", what, count * size);
        return false;
    }
    *p = q;
    return true;
}

/* The temporary files being written, so that a signal that ends the
 * program (on_ending_signal) leaves none of them behind. A slot is
 * marked used only once its name is complete. */
enum { LIVE_TEMPORARIES = 16 };
static char s_live_tmp[LIVE_TEMPORARIES][sizeof(((AtomicFile *)0)->tmp)];
static volatile sig_atomic_t s_live_used[LIVE_TEMPORARIES];

static void live_add(const char *tmp)
{
    for (int i = 0; i < LIVE_TEMPORARIES; i++)
        if (!s_live_used[i]) {
            memcpy(s_live_tmp[i], tmp, strlen(tmp) + 1);
            s_live_used[i] = 1;
            return;
        }
}

static void live_remove(const char *tmp)
{
    for (int i = 0; i < LIVE_TEMPORARIES; i++)
        if (s_live_used[i] && !strcmp(s_live_tmp[i], tmp))
            s_live_used[i] = 0;
}

/* Directories an ending signal removes (util_live_dir_add): a staging
 * directory with what is in it (`tree`), or a directory the command made,
 * if it is empty by then. Entries are removed in reverse order of adding. */
enum { LIVE_DIRS = 4 };
static char s_live_dir[LIVE_DIRS][UTIL_PATH_MAX];
static volatile sig_atomic_t s_live_dir_used[LIVE_DIRS], s_live_dir_tree[LIVE_DIRS];

void util_live_dir_add(const char *dir, bool tree)
{
    size_t n = strlen(dir);
    for (int i = 0; i < LIVE_DIRS && n < UTIL_PATH_MAX; i++)
        if (!s_live_dir_used[i]) {
            memcpy(s_live_dir[i], dir, n + 1);
            s_live_dir_tree[i] = tree;
            s_live_dir_used[i] = 1;
            return;
        }
}

void util_live_dir_remove(const char *dir)
{
    for (int i = 0; i < LIVE_DIRS; i++)
        if (s_live_dir_used[i] && !strcmp(s_live_dir[i], dir))
            s_live_dir_used[i] = 0;
}

/* Removes the files of `dir` and of its subdirectories, `depth` levels
 * down, then the directories, with system calls alone (async-signal-safe:
 * no opendir, no allocation). */
static void remove_tree_signal_safe(const char *dir, int depth)
{
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0)
        return;
    char buf[4096] __attribute__((aligned(8)));
    for (long n; (n = syscall(SYS_getdents64, fd, buf, sizeof buf)) > 0;)
        for (long off = 0; off < n;) {
            const struct linux_dirent64 {
                uint64_t ino;
                int64_t off;
                unsigned short reclen;
                unsigned char type;
                char name[];
            } *e = (const void *)(buf + off);
            off += e->reclen;
            if (!strcmp(e->name, ".") || !strcmp(e->name, ".."))
                continue;
            if (unlinkat(fd, e->name, 0) == 0 || errno != EISDIR || depth <= 0)
                continue;
            char sub[UTIL_PATH_MAX];
            size_t a = strlen(dir), b = strlen(e->name);
            if (a + 1 + b >= sizeof sub)
                continue;
            memcpy(sub, dir, a);
            sub[a] = '/';
            memcpy(sub + a + 1, e->name, b + 1);
            remove_tree_signal_safe(sub, depth - 1);
        }
    close(fd);
    rmdir(dir);
}

static void remove_temporaries(void)
{
    for (int i = 0; i < LIVE_TEMPORARIES; i++)
        if (s_live_used[i])
            unlink(s_live_tmp[i]); /* async-signal-safe */
    for (int i = LIVE_DIRS - 1; i >= 0; i--)
        if (s_live_dir_used[i]) {
            if (s_live_dir_tree[i])
                remove_tree_signal_safe(s_live_dir[i], 2);
            else
                rmdir(s_live_dir[i]);
        }
}

/* An ending signal that came while the outputs were being written: it is
 * raised again once they are whole (util_end_deferral). Any thread may
 * take it (Embree's workers too), so a flag rather than a signal mask. */
static volatile sig_atomic_t s_defer_ending, s_ending_pending;

static void on_ending_signal(int sig)
{
    if (s_defer_ending) {
        s_ending_pending = sig;
        return;
    }
    remove_temporaries();
    signal(sig, SIG_DFL);
    raise(sig);
}

void util_handle_ending_signals(void)
{
    struct sigaction sa = {0};
    sa.sa_handler = on_ending_signal;
    sigemptyset(&sa.sa_mask);
    const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
    for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++)
        sigaction(sigs[i], &sa, NULL);
}

void util_defer_ending_signals(void) { s_defer_ending = 1; }

void util_end_deferral(void)
{
    s_defer_ending = 0;
    int sig = s_ending_pending;
    if (sig) {
        signal(sig, SIG_DFL);
        raise(sig);
    }
}

/* Where an output at `path` is written: `path`, or, when it is a symbolic
 * link, the file the link names, followed through up to 16 links (as the
 * shell's > writes it; renaming over the link had replaced it with a plain
 * file and left its target as it was). A dangling link names a file that
 * does not exist yet. A name too long to follow stays as it is. */
static void output_target(const char *path, char *out, size_t cap)
{
    snprintf(out, cap, "%s", path);
    struct stat st;
    for (int hops = 0; hops < 16 && lstat(out, &st) == 0 && S_ISLNK(st.st_mode); hops++) {
        char link[UTIL_PATH_MAX], next[UTIL_PATH_MAX];
        ssize_t n = readlink(out, link, sizeof link - 1);
        if (n <= 0)
            return;
        link[n] = 0;
        const char *slash = strrchr(out, '/');
        int dir_len = link[0] == '/' || !slash ? 0 : (int)(slash - out) + 1; /* a relative link: from its directory */
        if ((size_t)dir_len + (size_t)n >= sizeof next)
            return;
        memcpy(next, out, (size_t)dir_len);
        memcpy(next + dir_len, link, (size_t)n + 1);
        snprintf(out, cap, "%s", next);
    }
}

bool util_atomic_open(AtomicFile *af, const char *tag, const char *path)
{
    memset(af, 0, sizeof *af);
    af->path = path;
    output_target(path, af->target, sizeof af->target);
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        /* Renaming over a device or FIFO would replace it; writing into it
         * could block or lose the data. */
        log_error(tag, "%s: output is %s, not a regular file; not written", path, file_kind(st.st_mode));
        return false;
    }
    const char *target = af->target;
    if (strlen(target) + sizeof ".tmp-XXXXXX" > sizeof af->tmp) {
        log_error(tag, "%s: output path is too long (%zu bytes; at most %zu)", path, strlen(target),
                  sizeof af->tmp - sizeof ".tmp-XXXXXX");
        return false;
    }
    util_ensure_parent_dir(target);
    /* NAME.tmp-XXXXXX beside it; where NAME is too long for that (a file
     * name is at most 255 bytes), .rtgi.tmp-XXXXXX in its directory. */
    const char *slash = strrchr(target, '/'), *base = slash ? slash + 1 : target;
    if (strlen(base) + sizeof ".tmp-XXXXXX" - 1 <= 255)
        snprintf(af->tmp, sizeof af->tmp, "%s.tmp-XXXXXX", target);
    else
        snprintf(af->tmp, sizeof af->tmp, "%.*s.rtgi.tmp-XXXXXX", (int)(base - target), target);
    int fd = mkstemp(af->tmp);
    if (fd < 0) {
        log_error(tag, "%s: cannot create output file (%s)", path, strerror(errno));
        af->tmp[0] = 0;
        return false;
    }
    live_add(af->tmp);
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask); /* as fopen would create it */
    af->f = fdopen(fd, "wb");
    if (!af->f) {
        log_error(tag, "%s: cannot open output file (%s)", path, strerror(errno));
        close(fd);
        unlink(af->tmp);
        live_remove(af->tmp);
        af->tmp[0] = 0;
        return false;
    }
    return true;
}

bool util_atomic_commit(AtomicFile *af, const char *tag)
{
    if (!af->f)
        return false;
    int e = 0;
    if (af->failed || ferror(af->f))
        e = errno ? errno : EIO;
    if (!e && fflush(af->f) != 0)
        e = errno;
    if (!e && fsync(fileno(af->f)) != 0 && errno != EINVAL && errno != EROFS)
        e = errno;
    if (fclose(af->f) != 0 && !e)
        e = errno;
    af->f = NULL;
    if (!e && rename(af->tmp, af->target) != 0)
        e = errno;
    if (e) {
        log_error(tag, "%s: write failed (%s); not written", af->path, strerror(e));
        unlink(af->tmp);
    }
    live_remove(af->tmp);
    af->tmp[0] = 0;
    return !e;
}

void util_atomic_abort(AtomicFile *af)
{
    if (af->f)
        fclose(af->f);
    af->f = NULL;
    if (af->tmp[0]) {
        unlink(af->tmp);
        live_remove(af->tmp);
    }
    af->tmp[0] = 0;
}

int util_edit_distance(const char *a, const char *b)
{
    size_t n = strlen(a), m = strlen(b);
    if (n > 255 || m > 255)
        return 1 << 20;
    /* Three rows of the table: i-2, i-1 and i. */
    int rows[3][256], *prev2 = rows[0], *prev = rows[1], *row = rows[2];
    for (size_t j = 0; j <= m; j++)
        prev[j] = (int)j;
    for (size_t i = 1; i <= n; i++) {
        row[0] = (int)i;
        for (size_t j = 1; j <= m; j++) {
            int best = prev[j - 1] + (a[i - 1] != b[j - 1]); /* substitute (or keep) */
            if (prev[j] + 1 < best)
                best = prev[j] + 1; /* delete */
            if (row[j - 1] + 1 < best)
                best = row[j - 1] + 1; /* insert */
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && prev2[j - 2] + 1 < best)
                best = prev2[j - 2] + 1; /* swap two adjacent bytes */
            row[j] = best;
        }
        int *t = prev2;
        prev2 = prev;
        prev = row;
        row = t;
    }
    return prev[m];
}

const char *util_nearest(const char *s, const char *const *names)
{
    for (int i = 0; names && names[i]; i++)
        if (!strcasecmp(s, names[i]))
            return names[i]; /* "PCSS" for "pcss", however long the word */
    const char *best = NULL;
    int best_d = 1 << 30;
    for (int i = 0; names && names[i]; i++) {
        int d = util_edit_distance(s, names[i]);
        if (d < best_d) {
            best_d = d;
            best = names[i];
        }
    }
    /* One edit in a short word, two (a swapped pair) or a third of a long one. */
    size_t len = strlen(s);
    int limit = len <= 4 ? 1 : len / 3 > 2 ? (int)(len / 3) : 2;
    return best_d <= limit ? best : NULL;
}

/* Length of the UTF-8 sequence at p (p[0] >= 0x80) if it is one that
 * util_json_string and util_utf8_sanitize pass through (a lead byte
 * 0xc2..0xf4 and its continuation bytes), else 0. */
static int utf8_sequence_length(const unsigned char *p)
{
    int len = (*p & 0xe0) == 0xc0 ? 2 : (*p & 0xf0) == 0xe0 ? 3 : (*p & 0xf8) == 0xf0 ? 4 : 0;
    int k = 1;
    while (len && k < len && (p[k] & 0xc0) == 0x80)
        k++;
    return len && k == len && *p >= 0xc2 && *p <= 0xf4 ? len : 0;
}

char *util_utf8_sanitize(const char *s)
{
    StrBuf b = {0};
    strbuf_append(&b, "", 0);
    for (const unsigned char *p = (const unsigned char *)s; *p;) {
        int len = *p < 0x80 ? 1 : utf8_sequence_length(p);
        if (len)
            strbuf_append(&b, (const char *)p, (size_t)len);
        else
            strbuf_append(&b, "\xef\xbf\xbd", 3); /* U+FFFD */
        p += len ? len : 1;
    }
    if (b.failed) {
        free(b.data);
        return NULL;
    }
    return b.data;
}

void util_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        switch (*p) {
        case '"': fputs("\\\"", f); break;
        case '\\': fputs("\\\\", f); break;
        case '\n': fputs("\\n", f); break;
        case '\r': fputs("\\r", f); break;
        case '\t': fputs("\\t", f); break;
        default:
            if (*p < 0x20 || *p == 0x7f) {
                fprintf(f, "\\u%04x", *p);
            } else if (*p < 0x80) {
                fputc(*p, f);
            } else { /* valid UTF-8 passes through, anything else is U+FFFD */
                int len = utf8_sequence_length(p);
                if (len) {
                    fwrite(p, 1, (size_t)len, f);
                    p += len - 1;
                } else {
                    fputs("\\ufffd", f);
                }
            }
        }
    }
    fputc('"', f);
}
