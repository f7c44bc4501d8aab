#include "shader.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "util.h"

typedef struct {
    const char *path;
    const char *text;
    size_t length;
} EmbeddedShader;
extern const EmbeddedShader rtgi_embedded_shaders[];

static char g_dir[1024];

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

static int file_table_add(FileTable *t, const char *name)
{
    if (t->count == 32)
        return -1;
    t->names[t->count] = util_strndup(name, strlen(name));
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
    if (id < 0) {
        log_error("shader", "%s: too many included files", path);
        return false;
    }
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
        const char *r = q + 8;
        while (*r == ' ' || *r == '\t')
            r++;
        if (strncmp(q, "#include", 8) == 0 && *r == '<') {
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
    if (!expand(path, &files, &src, 0)) {
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

static GLuint link_program(const char *label, GLuint *stages, int n)
{
    GLuint prog = glCreateProgram();
    for (int i = 0; i < n; i++)
        glAttachShader(prog, stages[i]);
    glLinkProgram(prog);
    for (int i = 0; i < n; i++)
        glDeleteShader(stages[i]);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[8192];
        glGetProgramInfoLog(prog, sizeof log, NULL, log);
        log_error("shader", "program %s failed to link: %s", label, log);
        glDeleteProgram(prog);
        return 0;
    }
    glObjectLabel(GL_PROGRAM, prog, -1, label);
    return prog;
}

GLuint shader_program_make(const char *label, const char *vert, const char *frag, const char *defines)
{
    GLuint st[2];
    st[0] = compile_stage(label, GL_VERTEX_SHADER, vert, defines);
    if (!st[0])
        return 0;
    st[1] = compile_stage(label, GL_FRAGMENT_SHADER, frag, defines);
    if (!st[1]) {
        glDeleteShader(st[0]);
        return 0;
    }
    return link_program(label, st, 2);
}

GLuint shader_compute_make(const char *label, const char *comp, const char *defines)
{
    GLuint st = compile_stage(label, GL_COMPUTE_SHADER, comp, defines);
    return st ? link_program(label, &st, 1) : 0;
}
