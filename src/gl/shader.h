/* shader.h — GLSL program building with #include and #line, and a cache.
 * Sources are the files under shaders/, embedded into the binary at build
 * time (cmake/embed_shaders.cmake); shader_set_directory() or the
 * RTGI_SHADER_DIR environment variable loads them from disk instead, so a
 * shader can be edited without a rebuild. `#include "common/x.glsl"` is
 * resolved by the loader (paths relative to shaders/, each file once), and
 * each file gets a `#line 1 N` so compile errors are reported as
 * "common/x.glsl:12: ..." rather than as source-string numbers. */
#ifndef RTGI_SHADER_H
#define RTGI_SHADER_H

#include <epoxy/gl.h>
#include <stdbool.h>

/* Directory to read shaders from, or NULL for the embedded copies. */
void shader_set_directory(const char *dir);
/* The directory set by shader_set_directory or RTGI_SHADER_DIR, or NULL
 * (the embedded copies). */
const char *shader_directory(void);
/* Programs linked since start-up (hot reloads included): the window's test
 * checks that an exposure change links none. */
int shader_link_count(void);

/* Returns the text of a shader file (caller frees), or NULL after logging. */
char *shader_read_source(const char *path);

/* A program's stages, as shader file paths under shaders/; NULL means the
 * stage is absent. Either `comp` alone, or `vert` with optional `geom` and
 * `frag` (a vertex-only program rasterizes nothing but can write buffers). */
typedef struct ShaderProgramDesc {
    const char *label;   /* for debuggers and log lines; NULL: the first stage's path */
    const char *vert;    /* e.g. "scene.vert" */
    const char *geom;    /* e.g. "voxelize.geom" */
    const char *frag;    /* e.g. "voxelize.frag" */
    const char *comp;    /* e.g. "lpv_propagate.comp" */
    const char *defines; /* inserted after #version, e.g. "#define PCF_SAMPLES 20\n"; NULL for none */
} ShaderProgramDesc;

/* Builds the program `desc` describes. Returns 0 after logging the compile
 * or link error with file names and lines. The program is labelled for
 * debuggers. Caller frees it with glDeleteProgram. */
GLuint shader_program_build(const ShaderProgramDesc *desc);

/* Builds a vertex+fragment program. `defines` (may be NULL) is inserted after
 * #version, e.g. "#define PCF_SAMPLES 20\n". Returns 0 after logging the
 * compile/link error with file names and lines. The program is labelled for
 * debuggers. Free with glDeleteProgram. */
GLuint shader_program_make(const char *label, const char *vert, const char *frag, const char *defines);
/* Same with a geometry stage between them (`frag` may be NULL). */
GLuint shader_program_make_vgf(const char *label, const char *vert, const char *geom, const char *frag,
                               const char *defines);
/* Same for a compute program. */
GLuint shader_compute_make(const char *label, const char *comp, const char *defines);

/* Programs built once per key (stage files + defines; the label is not part
 * of the key, the first one given is kept). Zero-initialised is an empty
 * cache. The cache owns its programs: callers must not delete a program
 * they got from it, and its names die with program_cache_destroy.
 *
 *   ProgramCache pc;
 *   program_cache_create(&pc);
 *   GLuint p = program_cache_get(&pc, &(ShaderProgramDesc){.comp = "lpv_inject.comp"});
 *   ...  program_cache_reload(&pc);  // e.g. on a key press, with RTGI_SHADER_DIR set
 *   program_cache_destroy(&pc);       // deletes every program */
typedef struct ProgramCacheEntry ProgramCacheEntry;
typedef struct ProgramCache {
    ProgramCacheEntry *entries; /* owned array of `count` entries */
    int count;                  /* programs (built or failed) */
    int capacity;               /* entries allocated */
    int unkept;                 /* programs asked for that could not even be entered (out of memory) */
} ProgramCache;

void program_cache_create(ProgramCache *cache);
/* Deletes every program of the cache and frees it; the cache is empty after. */
void program_cache_destroy(ProgramCache *cache);
/* The program for desc's key, built on first use. Returns 0 if it failed to
 * build; the failure is logged once and remembered (not retried on every
 * call) until program_cache_reload. The strings of `desc` are copied. */
GLuint program_cache_get(ProgramCache *cache, const ShaderProgramDesc *desc);
/* Rebuilds every program from its source files (for hot reload: set
 * RTGI_SHADER_DIR or shader_set_directory to read them from disk). A
 * rebuilt program keeps its GL name, so names held by passes stay valid,
 * but its uniforms are back at their defaults: set them again. A program
 * that fails to compile or link keeps its previous build and its errors are
 * logged; returns false if any failed. Earlier failures are retried (and
 * get a new name if they now build). */
bool program_cache_reload(ProgramCache *cache);
/* Number of keys in the cache. */
int program_cache_count(const ProgramCache *cache);
/* Number of keys whose last build failed, and of programs that could not be
 * entered at all (each logged when it failed). */
int program_cache_failed(const ProgramCache *cache);

#endif
