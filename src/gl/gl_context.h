/* gl_context.h — a headless OpenGL 4.5 core context through EGL.
 * Tries a hardware EGL device (NVIDIA through its EGL vendor library) first,
 * then Mesa's surfaceless platform (llvmpipe on machines without a GPU).
 * Rendering goes to framebuffer objects only; there is no default surface. */
#ifndef RTGI_GL_CONTEXT_H
#define RTGI_GL_CONTEXT_H

#include <stdbool.h>

typedef struct GlContext GlContext;

/* Creates and makes current a GL 4.5 core context. `debug` asks for a debug
 * context and routes KHR_debug messages into the logger. NULL on failure,
 * after one error line that says why. */
GlContext *gl_context_create(bool debug);
void gl_context_destroy(GlContext *ctx);
/* GL_RENDERER string of the current context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)". */
const char *gl_context_renderer(const GlContext *ctx);
/* Whether a GL_RENDERER string names a software rasterizer (llvmpipe,
 * softpipe, swrast, SwiftShader). Such a driver runs compute dispatches at
 * the call and rasterizes draws later, at a flush, so timestamp queries
 * that are not fenced by glFinish land in other passes' work: per-pass
 * timings there need GpuTimer's `sync`. */
bool gl_renderer_is_software(const char *renderer);
/* Installs the KHR_debug callback on the current context (also used by the window). */
void gl_install_debug_callback(void);

#endif
