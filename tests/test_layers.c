/* test_layers.c — the house rule of docs/developing.md ("Layers"), read
 * from the code: every file under src/ lives in a layer folder, and a file
 * includes only from its own folder or from a layer below it; no two
 * modules (a .c and its .h) include each other, directly or round a circle.
 *
 * `test_layers --report` prints the counts the issue asked for (modules,
 * include arrows between modules, arrows running up, circles) and every
 * offending include or circle, without failing. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#ifndef RTGI_SOURCE_DIR
#error "RTGI_SOURCE_DIR must name the source tree"
#endif

/* The layers, lowest first; a folder may include from its own and lower
 * ranks. gi and reference share a rank: neither includes the other. The
 * C/GLSL blocks (shaders/shared/, "shared/...") and the generated
 * version.h sit below them all. */
static const struct {
    const char *folder;
    int rank;
} k_layers[] = {
    {"base", 0},  /* log, util, JSON helpers */
    {"io", 1},    /* images, EXR, metrics, reports */
    {"core", 2},  /* scene, settings, camera, animation, BRDF */
    {"gl", 3},    /* context, resources, shaders, timers, budget */
    {"gpu", 4},   /* the scene on the GPU, light products, targets, probe */
    {"gi", 5},    /* the techniques */
    {"reference", 5}, /* the path tracer */
    {"frame", 6}, /* the renderer and its passes */
    {"ui", 7},    /* the window */
    {"app", 8},   /* main, commands, options */
};
#define LAYER_COUNT (int)(sizeof k_layers / sizeof k_layers[0])

#define MAX_FILES 512
#define MAX_INCLUDES 64

typedef struct SrcFile {
    char path[256];   /* relative to src/, e.g. "core/scene.c" */
    char module[256]; /* path without its extension */
    int includes[MAX_INCLUDES]; /* file indices */
    char include_text[MAX_INCLUDES][128];
    int include_count;
} SrcFile;

static SrcFile g_files[MAX_FILES];
static int g_count;

static void collect(const char *dir, const char *rel)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        char full[1024], r[256];
        int nf = snprintf(full, sizeof full, "%s/%s", dir, e->d_name);
        int nr = snprintf(r, sizeof r, "%s%s%s", rel, *rel ? "/" : "", e->d_name);
        if (nf < 0 || nf >= (int)sizeof full || nr < 0 || nr >= (int)sizeof r)
            continue;
        struct stat st;
        if (stat(full, &st))
            continue;
        if (S_ISDIR(st.st_mode)) {
            collect(full, r);
            continue;
        }
        const char *dot = strrchr(e->d_name, '.');
        if (!dot || (strcmp(dot, ".c") && strcmp(dot, ".h") && strcmp(dot, ".cpp")))
            continue;
        if (g_count >= MAX_FILES)
            fail_msg("more than %d source files", MAX_FILES);
        SrcFile *f = &g_files[g_count++];
        snprintf(f->path, sizeof f->path, "%s", r);
        snprintf(f->module, sizeof f->module, "%.*s", (int)(strrchr(r, '.') - r), r);
    }
    closedir(d);
}

static int find_file(const char *path)
{
    for (int i = 0; i < g_count; i++)
        if (!strcmp(g_files[i].path, path))
            return i;
    return -1;
}

static void read_includes(void)
{
    for (int i = 0; i < g_count; i++) {
        char full[1024], line[512];
        int nf = snprintf(full, sizeof full, "%s/src/%s", RTGI_SOURCE_DIR, g_files[i].path);
        assert_true(nf > 0 && nf < (int)sizeof full);
        FILE *fp = fopen(full, "r");
        assert_non_null(fp);
        while (fgets(line, sizeof line, fp)) {
            const char *p = line;
            while (*p == ' ' || *p == '\t')
                p++;
            if (strncmp(p, "#include \"", 10))
                continue;
            p += 10;
            const char *q = strchr(p, '"');
            if (!q || g_files[i].include_count >= MAX_INCLUDES)
                continue;
            int n = g_files[i].include_count++;
            snprintf(g_files[i].include_text[n], sizeof g_files[i].include_text[n], "%.*s", (int)(q - p), p);
            g_files[i].includes[n] = find_file(g_files[i].include_text[n]);
        }
        fclose(fp);
    }
}

/* The layer rank of a path relative to src/ ("core/scene.h"); -1 for a
 * file outside every layer folder. */
static int rank_of(const char *path)
{
    for (int k = 0; k < LAYER_COUNT; k++) {
        size_t n = strlen(k_layers[k].folder);
        if (!strncmp(path, k_layers[k].folder, n) && path[n] == '/')
            return k_layers[k].rank;
    }
    return -1;
}

static bool same_folder(const char *a, const char *b)
{
    const char *sa = strchr(a, '/'), *sb = strchr(b, '/');
    return sa && sb && sa - a == sb - b && !strncmp(a, b, (size_t)(sa - a));
}

typedef struct Census {
    int modules, arrows, upward, outside, unresolved, circles;
} Census;

/* ---- modules and their circles (Tarjan over the module graph) ---------- */

static char g_mods[MAX_FILES][256];
static int g_mod_count;
static bool g_edge[MAX_FILES][MAX_FILES];

static int module_index(const char *m)
{
    for (int i = 0; i < g_mod_count; i++)
        if (!strcmp(g_mods[i], m))
            return i;
    snprintf(g_mods[g_mod_count], sizeof g_mods[0], "%s", m);
    return g_mod_count++;
}

static int t_index[MAX_FILES], t_low[MAX_FILES], t_stack[MAX_FILES], t_sp, t_next;
static bool t_on[MAX_FILES];

static void strongconnect(int v, Census *c, bool print)
{
    t_index[v] = t_low[v] = t_next++;
    t_stack[t_sp++] = v;
    t_on[v] = true;
    for (int w = 0; w < g_mod_count; w++) {
        if (!g_edge[v][w])
            continue;
        if (t_index[w] < 0) {
            strongconnect(w, c, print);
            if (t_low[w] < t_low[v])
                t_low[v] = t_low[w];
        } else if (t_on[w] && t_index[w] < t_low[v])
            t_low[v] = t_index[w];
    }
    if (t_low[v] != t_index[v])
        return;
    int members[MAX_FILES], n = 0, w;
    do {
        w = t_stack[--t_sp];
        t_on[w] = false;
        members[n++] = w;
    } while (w != v);
    if (n > 1) {
        c->circles++;
        if (print) {
            printf("circle:");
            for (int i = 0; i < n; i++)
                printf(" %s", g_mods[members[i]]);
            printf("\n");
        }
    }
}

static Census census(bool print)
{
    Census c = {0};
    g_count = 0;
    g_mod_count = 0;
    memset(g_edge, 0, sizeof g_edge);
    char src[512];
    snprintf(src, sizeof src, "%s/src", RTGI_SOURCE_DIR);
    collect(src, "");
    read_includes();
    for (int i = 0; i < g_count; i++)
        module_index(g_files[i].module);
    c.modules = g_mod_count;
    for (int i = 0; i < g_count; i++) {
        const SrcFile *f = &g_files[i];
        int from = rank_of(f->path);
        if (from < 0) {
            c.outside++;
            if (print)
                printf("outside every layer folder: src/%s\n", f->path);
        }
        for (int k = 0; k < f->include_count; k++) {
            const char *inc = f->include_text[k];
            if (f->includes[k] < 0) {
                /* The C/GLSL blocks and the generated version header sit
                 * below every layer; anything else must resolve under src/. */
                if (strncmp(inc, "shared/", 7) && strcmp(inc, "version.h") && !strstr(inc, ".glsl")) {
                    c.unresolved++;
                    if (print)
                        printf("unresolved: src/%s includes \"%s\" (spell includes from src/)\n", f->path, inc);
                }
                continue;
            }
            const SrcFile *g = &g_files[f->includes[k]];
            int a = module_index(f->module), b = module_index(g->module);
            if (a != b && !g_edge[a][b]) {
                g_edge[a][b] = true;
                c.arrows++;
            }
            int to = rank_of(g->path);
            if (same_folder(f->path, g->path) || (from >= 0 && to >= 0 && to < from))
                continue;
            c.upward++;
            if (print)
                printf("up or across: src/%s (layer %d) includes %s (layer %d)\n", f->path, from, inc, to);
        }
    }
    memset(t_index, -1, sizeof t_index);
    memset(t_on, 0, sizeof t_on);
    t_sp = t_next = 0;
    for (int v = 0; v < g_mod_count; v++)
        if (t_index[v] < 0)
            strongconnect(v, &c, print);
    return c;
}

static void layers_hold(void **state)
{
    (void)state;
    Census c = census(true);
    assert_true(c.modules > 50); /* the walk found the tree */
    assert_int_equal(c.outside, 0);
    assert_int_equal(c.unresolved, 0);
    assert_int_equal(c.upward, 0);
    assert_int_equal(c.circles, 0);
}

int main(int argc, char **argv)
{
    if (argc > 1 && !strcmp(argv[1], "--report")) {
        Census c = census(true);
        printf("modules %d, arrows %d, up or across %d, circles %d, outside %d, unresolved %d\n", c.modules,
               c.arrows, c.upward, c.circles, c.outside, c.unresolved);
        return 0;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(layers_hold),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
