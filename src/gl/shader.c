#include "gl/shader.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/log.h"
#include "base/util.h"

typedef struct {
    const char *path;
    const char *text;
    size_t length;
} EmbeddedShader;
extern const EmbeddedShader rtgi_embedded_shaders[];

static char g_dir[1024];
static int g_links; /* programs linked so far (shader_link_count) */

int shader_link_count(void) { return g_links; }

void shader_set_directory(const char *dir)
{
    snprintf(g_dir, sizeof g_dir, "%s", dir ? dir : "");
}

static const char *shader_dir(void)
{
    if (g_dir[0])
        return g_dir;
    const char *env = getenv("RTGI_SHADER_DIR");
    return (env && env[0]) ? env : NULL;
}

const char *shader_directory(void) { return shader_dir(); }

char *shader_read_source(const char *path)
{
    const char *dir = shader_dir();
    if (dir) {
        char full[2048];
        snprintf(full, sizeof full, "%s/%s", dir, path);
        char *text = util_read_file(full, NULL);
        if (!text)
            log_error("shader", "%s: cannot read shader file", full);
        return text;
    }
    for (const EmbeddedShader *s = rtgi_embedded_shaders; s->path; s++)
        if (strcmp(s->path, path) == 0)
            return util_strndup(s->text, s->length);
    log_error("shader", "%s: no such embedded shader", path);
    return NULL;
}

/* Files pulled into one compilation; index = GLSL source-string number. */
typedef struct {
    char *names[32];
    int count;
} FileTable;

/* The file's index, or -1 after logging (too many, or out of memory). */
static int file_table_add(FileTable *t, const char *name)
{
    if (t->count == 32) {
        log_error("shader", "%s: too many included files", name);
        return -1;
    }
    if (!(t->names[t->count] = util_strndup(name, strlen(name)))) /* logs */
        return -1;
    return t->count++;
}

static void file_table_free(FileTable *t)
{
    for (int i = 0; i < t->count; i++)
        free(t->names[i]);
    t->count = 0;
}

static bool expand(const char *path, FileTable *files, StrBuf *out, int depth)
{
    if (depth > 16) {
        log_error("shader", "%s: #include nested too deeply", path);
        return false;
    }
    for (int i = 0; i < files->count; i++)
        if (strcmp(files->names[i], path) == 0)
            return true; /* each file once */
    int id = file_table_add(files, path);
    if (id < 0)
        return false;
    char *text = shader_read_source(path);
    if (!text)
        return false;
    strbuf_printf(out, "#line 1 %d\n", id);
    int line = 1;
    bool ok = true;
    for (char *p = text; *p && ok;) {
        char *eol = strchr(p, '\n');
        size_t len = eol ? (size_t)(eol - p) : strlen(p);
        const char *q = p;
        while (*q == ' ' || *q == '\t')
            q++;
        bool include = strncmp(q, "#include", 8) == 0;
        const char *r = include ? q + 8 : q;
        while (include && (*r == ' ' || *r == '\t'))
            r++;
        if (include && *r == '<') {
            /* A C system header in a file shared with C (shaders/shared/):
             * GLSL has none, and such lines sit in the C-only branch. */
            strbuf_append(out, "\n", 1);
        } else if (strncmp(q, "#include", 8) == 0) {
            const char *a = strchr(q, '"');
            const char *b = a ? strchr(a + 1, '"') : NULL;
            if (!a || !b || b > p + len) {
                log_error("shader", "%s:%d: malformed #include", path, line);
                ok = false;
                break;
            }
            char inc[256];
            snprintf(inc, sizeof inc, "%.*s", (int)(b - a - 1), a + 1);
            ok = expand(inc, files, out, depth + 1);
            strbuf_printf(out, "#line %d %d\n", line + 1, id);
        } else {
            strbuf_append(out, p, len);
            strbuf_append(out, "\n", 1);
        }
        line++;
        p = eol ? eol + 1 : p + len;
    }
    free(text);
    return ok;
}

/* Rewrites "N:L(C): msg" (Mesa) and "N(L) : msg" (NVIDIA) to name the file. */
static void log_compile_errors(const char *label, const char *log, const FileTable *files)
{
    const char *p = log;
    while (*p) {
        const char *eol = strchr(p, '\n');
        int len = eol ? (int)(eol - p) : (int)strlen(p);
        char *end = NULL;
        long id = strtol(p, &end, 10);
        if (end != p && (*end == ':' || *end == '(') && id >= 0 && id < files->count) {
            int lno = atoi(end + 1);
            const char *msg = end + 1;
            while (msg < p + len && *msg != ' ')
                msg++;
            while (msg < p + len && *msg == ' ')
                msg++;
            log_error("shader", "%s:%d: %.*s (program %s)", files->names[id], lno,
                      (int)(p + len - msg), msg, label);
        } else if (len > 0) {
            log_error("shader", "%.*s (program %s)", len, p, label);
        }
        p = eol ? eol + 1 : p + len;
    }
}

static GLuint compile_stage(const char *label, GLenum stage, const char *path, const char *defines)
{
    FileTable files = {0};
    StrBuf src = {0};
    strbuf_printf(&src, "#version 450 core\n%s", defines ? defines : "");
    if (!expand(path, &files, &src, 0) || src.failed) { /* each logs its failure (the buffer's: util.c) */
        free(src.data);
        file_table_free(&files);
        return 0;
    }
    GLuint sh = glCreateShader(stage);
    const char *text = src.data;
    glShaderSource(sh, 1, &text, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[8192];
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        log_compile_errors(label, log, &files);
        glDeleteShader(sh);
        sh = 0;
    }
    free(src.data);
    file_table_free(&files);
    return sh;
}

/* Compiles every stage of `d` into `st` (count in *n). On failure deletes
 * what it compiled and returns false; the log lines name file and line. */
static bool compile_stages(const ShaderProgramDesc *d, const char *label, GLuint st[4], int *n)
{
    const struct { GLenum stage; const char *path; } stages[4] = {
        {GL_VERTEX_SHADER, d->vert}, {GL_GEOMETRY_SHADER, d->geom},
        {GL_FRAGMENT_SHADER, d->frag}, {GL_COMPUTE_SHADER, d->comp}};
    *n = 0;
    for (int i = 0; i < 4; i++) {
        if (!stages[i].path)
            continue;
        GLuint sh = compile_stage(label, stages[i].stage, stages[i].path, d->defines);
        if (!sh) {
            for (int k = 0; k < *n; k++)
                glDeleteShader(st[k]);
            *n = 0;
            return false;
        }
        st[(*n)++] = sh;
    }
    return true;
}

/* true if `prog` linked; else logs its info log on one line. */
static bool link_ok(GLuint prog, const char *label, const char *note)
{
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (ok)
        return true;
    char log[8192] = "";
    glGetProgramInfoLog(prog, sizeof log, NULL, log);
    for (char *c = log; *c; c++)
        if (*c == '\n')
            *c = ' ';
    log_error("shader", "program %s failed to link%s: %s", label, note, log);
    return false;
}

/* Attaches `stages` to `prog` and links it. The shaders are flagged for
 * deletion, so they go away with the program or when detached. */
static bool link_into(GLuint prog, const char *label, const GLuint *stages, int n)
{
    for (int i = 0; i < n; i++)
        glAttachShader(prog, stages[i]);
    glLinkProgram(prog);
    g_links++;
    for (int i = 0; i < n; i++)
        glDeleteShader(stages[i]);
    return link_ok(prog, label, "");
}

static const char *desc_label(const ShaderProgramDesc *d)
{
    if (d->label)
        return d->label;
    return d->comp ? d->comp : d->vert ? d->vert : "(unnamed)";
}

/* Environment-independent checks on a desc; logs and returns false. */
static bool desc_valid(const ShaderProgramDesc *d, const char *label)
{
    bool graphics = d->vert || d->geom || d->frag;
    if (d->comp && graphics) {
        log_error("shader", "program %s: a compute stage cannot be combined with graphics stages", label);
        return false;
    }
    if (!d->comp && !d->vert) {
        log_error("shader", "program %s: needs a vertex or a compute stage", label);
        return false;
    }
    return true;
}

/* `defines` ("#define A\n#define B 2\n") as "A, B 2", for the debug line. */
static void defines_text(const char *defines, char *out, size_t size)
{
    size_t len = 0;
    out[0] = '\0';
    for (const char *p = defines; p && *p && len + 1 < size;) {
        const char *end = strchr(p, '\n');
        size_t n = end ? (size_t)(end - p) : strlen(p);
        const char *name = p;
        if (n > 8 && strncmp(p, "#define ", 8) == 0) {
            name += 8;
            n -= 8;
        }
        int w = snprintf(out + len, size - len, "%s%.*s", len ? ", " : "", (int)n, name);
        if (w < 0)
            break;
        len += (size_t)w < size - len ? (size_t)w : size - len - 1;
        p = end ? end + 1 : p + strlen(p);
    }
}

GLuint shader_program_build(const ShaderProgramDesc *d)
{
    const char *label = desc_label(d);
    if (!desc_valid(d, label))
        return 0;
    if (log_get_level() <= LOG_DEBUG) { /* --verbose: which programs a run builds */
        char defs[256];
        defines_text(d->defines, defs, sizeof defs);
        log_debug("shader", "building %s:%s%s%s%s%s%s%s%s [%s]", label, d->vert ? " " : "", d->vert ? d->vert : "",
                  d->geom ? " " : "", d->geom ? d->geom : "", d->frag ? " " : "", d->frag ? d->frag : "",
                  d->comp ? " " : "", d->comp ? d->comp : "", defs);
    }
    GLuint st[4];
    int n = 0;
    if (!compile_stages(d, label, st, &n))
        return 0;
    GLuint prog = glCreateProgram();
    if (!link_into(prog, label, st, n)) {
        glDeleteProgram(prog);
        return 0;
    }
    glObjectLabel(GL_PROGRAM, prog, -1, label);
    return prog;
}

GLuint shader_program_make(const char *label, const char *vert, const char *frag, const char *defines)
{
    return shader_program_build(
        &(ShaderProgramDesc){.label = label, .vert = vert, .frag = frag, .defines = defines});
}

GLuint shader_program_make_vgf(const char *label, const char *vert, const char *geom, const char *frag,
                               const char *defines)
{
    return shader_program_build(
        &(ShaderProgramDesc){.label = label, .vert = vert, .geom = geom, .frag = frag, .defines = defines});
}

GLuint shader_compute_make(const char *label, const char *comp, const char *defines)
{
    return shader_program_build(&(ShaderProgramDesc){.label = label, .comp = comp, .defines = defines});
}

/* Rebuilds `prog` in place from `d`, keeping its name. The new sources are
 * first linked into a scratch program: a failed link loses a program's
 * executable, so `prog` is relinked only once the sources are known good. */
static bool shader_program_rebuild(GLuint prog, const ShaderProgramDesc *d)
{
    const char *label = desc_label(d);
    GLuint st[4];
    int n = 0;
    if (!compile_stages(d, label, st, &n))
        return false;
    GLuint scratch = glCreateProgram();
    for (int i = 0; i < n; i++)
        glAttachShader(scratch, st[i]);
    glLinkProgram(scratch);
    bool ok = link_ok(scratch, label, ", keeping the previous build");
    /* Swap the stages of `prog` for the new ones and relink it. */
    if (ok) {
        GLuint old[8];
        GLsizei nold = 0;
        glGetAttachedShaders(prog, 8, &nold, old);
        for (int i = 0; i < nold; i++)
            glDetachShader(prog, old[i]);
        ok = link_into(prog, label, st, n);
    } else {
        for (int i = 0; i < n; i++)
            glDeleteShader(st[i]);
    }
    glDeleteProgram(scratch); /* the new shaders live on only where attached: in prog on success */
    return ok;
}

/* --- Program cache ------------------------------------------------------ */

struct ProgramCacheEntry {
    ShaderProgramDesc desc; /* every string an owned copy */
    GLuint program;         /* owned; 0 if the last build failed */
};

static char *dup_or_null(const char *s) { return s ? util_strndup(s, strlen(s)) : NULL; }

static bool same_str(const char *a, const char *b)
{
    return (a == NULL || b == NULL) ? a == b : strcmp(a, b) == 0;
}

static bool same_key(const ShaderProgramDesc *a, const ShaderProgramDesc *b)
{
    const char *da = a->defines ? a->defines : "", *db = b->defines ? b->defines : "";
    return same_str(a->vert, b->vert) && same_str(a->geom, b->geom) && same_str(a->frag, b->frag) &&
           same_str(a->comp, b->comp) && strcmp(da, db) == 0;
}

void program_cache_create(ProgramCache *c) { memset(c, 0, sizeof *c); }

/* Frees the strings of a cache entry's own copy. */
static void desc_free(ShaderProgramDesc *d)
{
    free((char *)d->label);
    free((char *)d->vert);
    free((char *)d->geom);
    free((char *)d->frag);
    free((char *)d->comp);
    free((char *)d->defines);
}

void program_cache_destroy(ProgramCache *c)
{
    for (int i = 0; i < c->count; i++) {
        ProgramCacheEntry *e = &c->entries[i];
        if (e->program)
            glDeleteProgram(e->program);
        desc_free(&e->desc);
    }
    free(c->entries);
    memset(c, 0, sizeof *c);
}

GLuint program_cache_get(ProgramCache *c, const ShaderProgramDesc *desc)
{
    for (int i = 0; i < c->count; i++)
        if (same_key(&c->entries[i].desc, desc))
            return c->entries[i].program;
    if (c->count == c->capacity) {
        int cap = c->capacity ? 2 * c->capacity : 16;
        ProgramCacheEntry *grown = realloc(c->entries, (size_t)cap * sizeof *grown);
        if (!grown) {
            log_error("shader", "program cache: out of memory for %s", desc_label(desc));
            c->unkept++;
            return 0;
        }
        c->entries = grown;
        c->capacity = cap;
    }
    ShaderProgramDesc copy = {
        .label = dup_or_null(desc_label(desc)), .vert = dup_or_null(desc->vert),
        .geom = dup_or_null(desc->geom), .frag = dup_or_null(desc->frag),
        .comp = dup_or_null(desc->comp), .defines = dup_or_null(desc->defines)};
    if (!copy.label || (desc->vert && !copy.vert) || (desc->geom && !copy.geom) || (desc->frag && !copy.frag) ||
        (desc->comp && !copy.comp) || (desc->defines && !copy.defines)) { /* util_strndup logged */
        desc_free(&copy);
        c->unkept++;
        return 0;
    }
    ProgramCacheEntry *e = &c->entries[c->count++];
    e->desc = copy;
    e->program = shader_program_build(&e->desc);
    return e->program;
}

bool program_cache_reload(ProgramCache *c)
{
    int failed = 0;
    for (int i = 0; i < c->count; i++) {
        ProgramCacheEntry *e = &c->entries[i];
        bool ok;
        if (e->program) {
            ok = shader_program_rebuild(e->program, &e->desc);
        } else {
            e->program = shader_program_build(&e->desc);
            ok = e->program != 0;
        }
        failed += !ok;
    }
    if (failed)
        log_error("shader", "reload: %d of %d programs failed, kept their previous builds", failed, c->count);
    return failed == 0;
}

int program_cache_count(const ProgramCache *c) { return c->count; }

int program_cache_failed(const ProgramCache *c)
{
    int failed = c->unkept;
    for (int i = 0; i < c->count; i++)
        failed += c->entries[i].program == 0;
    return failed;
}
