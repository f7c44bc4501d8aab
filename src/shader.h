/* shader.h — GLSL program building with #include and #line.
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

/* Returns the text of a shader file (caller frees), or NULL after logging. */
char *shader_read_source(const char *path);

/* Builds a vertex+fragment program. `defines` (may be NULL) is inserted after
 * #version, e.g. "#define PCF_SAMPLES 20\n". Returns 0 after logging the
 * compile/link error with file names and lines. The program is labelled for
 * debuggers. Free with glDeleteProgram. */
GLuint shader_program_make(const char *label, const char *vert, const char *frag, const char *defines);
/* Same for a compute program. */
GLuint shader_compute_make(const char *label, const char *comp, const char *defines);

#endif
