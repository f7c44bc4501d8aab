#include "gl/gl_context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/log.h"

struct GlContext {
    EGLDisplay display; /* owned: terminated on destroy */
    EGLContext context; /* owned */
    char renderer[256]; /* GL_RENDERER copied at creation */
};

static void GLAPIENTRY debug_cb(GLenum source, GLenum type, GLuint id, GLenum severity,
                                GLsizei length, const GLchar *msg, const void *user)
{
    (void)source; (void)length; (void)user;
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION)
        return;
    /* Errors and undefined, deprecated or unportable use are "[gl]" lines
     * (the tests fail on any); the driver's performance hints and other
     * notes are "[gl-hint]" info lines: NVIDIA's say which buffers it moved
     * to host memory for a read-back and which shaders it recompiled for
     * the GL state, none of them a fault. */
    bool fault = type == GL_DEBUG_TYPE_ERROR || type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR ||
                 type == GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR || type == GL_DEBUG_TYPE_PORTABILITY;
    if (!fault) {
        log_msg(LOG_INFO, "gl-hint", "debug message %u: %s", id, msg);
        return;
    }
    log_msg(type == GL_DEBUG_TYPE_ERROR ? LOG_ERROR : LOG_WARN, "gl", "debug message %u: %s", id, msg);
}

void gl_install_debug_callback(void)
{
    if (!epoxy_has_gl_extension("GL_KHR_debug") && epoxy_gl_version() < 43)
        return;
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debug_cb, NULL);
}

/* Picks a display: first non-software EGL device, else Mesa surfaceless,
 * else the software device, else the default display. */
static EGLDisplay open_display(void)
{
    const char *force = getenv("RTGI_EGL_PLATFORM"); /* "device" | "surfaceless" */
    EGLDisplay dpy = EGL_NO_DISPLAY;
    bool client_ext = epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base");
    EGLDeviceEXT software = NULL;

    if (client_ext && epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration") &&
        (!force || strcmp(force, "device") == 0)) {
        EGLDeviceEXT devs[16];
        EGLint n = 0;
        if (eglQueryDevicesEXT(16, devs, &n)) {
            for (EGLint i = 0; i < n && dpy == EGL_NO_DISPLAY; i++) {
                const char *ext = eglQueryDeviceStringEXT(devs[i], EGL_EXTENSIONS);
                if (ext && strstr(ext, "EGL_MESA_device_software")) {
                    software = devs[i];
                    continue;
                }
                dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devs[i], NULL);
                if (dpy != EGL_NO_DISPLAY && !eglInitialize(dpy, NULL, NULL))
                    dpy = EGL_NO_DISPLAY;
            }
        }
    }
    if (dpy == EGL_NO_DISPLAY && client_ext &&
        epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless") &&
        (!force || strcmp(force, "surfaceless") == 0)) {
        dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
        if (dpy != EGL_NO_DISPLAY && !eglInitialize(dpy, NULL, NULL))
            dpy = EGL_NO_DISPLAY;
    }
    if (dpy == EGL_NO_DISPLAY && software) {
        dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, software, NULL);
        if (dpy != EGL_NO_DISPLAY && !eglInitialize(dpy, NULL, NULL))
            dpy = EGL_NO_DISPLAY;
    }
    if (dpy == EGL_NO_DISPLAY) {
        dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        if (dpy != EGL_NO_DISPLAY && !eglInitialize(dpy, NULL, NULL))
            dpy = EGL_NO_DISPLAY;
    }
    return dpy;
}

GlContext *gl_context_create(bool debug)
{
    EGLDisplay dpy = open_display();
    if (dpy == EGL_NO_DISPLAY) {
        log_error("gl", "no EGL display could be initialised (no GPU driver and no Mesa surfaceless platform)");
        return NULL;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        log_error("gl", "EGL display does not support desktop OpenGL");
        eglTerminate(dpy);
        return NULL;
    }
    const EGLint cfg_attr[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
    EGLConfig cfg = NULL;
    EGLint ncfg = 0;
    bool no_config = epoxy_has_egl_extension(dpy, "EGL_KHR_no_config_context");
    if (!no_config && (!eglChooseConfig(dpy, cfg_attr, &cfg, 1, &ncfg) || ncfg < 1)) {
        log_error("gl", "EGL has no config for desktop OpenGL");
        eglTerminate(dpy);
        return NULL;
    }
    const EGLint ctx_attr[] = {
        EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
        EGL_CONTEXT_OPENGL_DEBUG, debug ? EGL_TRUE : EGL_FALSE, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, no_config ? EGL_NO_CONFIG_KHR : cfg, EGL_NO_CONTEXT, ctx_attr);
    if (ctx == EGL_NO_CONTEXT) {
        log_error("gl", "OpenGL 4.5 core is not supported by this driver (eglCreateContext failed, 0x%x)",
                  eglGetError());
        eglTerminate(dpy);
        return NULL;
    }
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        log_error("gl", "cannot make the surfaceless GL context current (0x%x)", eglGetError());
        eglDestroyContext(dpy, ctx);
        eglTerminate(dpy);
        return NULL;
    }
    /* RTGI_REQUIRE_GL=46 (say) raises the bar: it exercises this path on
     * drivers that do have 4.5. */
    const char *req_env = getenv("RTGI_REQUIRE_GL");
    int required = req_env && atoi(req_env) > 45 ? atoi(req_env) : 45;
    if (epoxy_gl_version() < required) {
        log_error("gl", "OpenGL %d.%d is required, the driver (%s) gives %d.%d", required / 10, required % 10,
                  (const char *)glGetString(GL_RENDERER), epoxy_gl_version() / 10, epoxy_gl_version() % 10);
        eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(dpy, ctx);
        eglTerminate(dpy);
        return NULL;
    }
    GlContext *g = calloc(1, sizeof *g);
    if (!g) {
        log_error("gl", "out of memory for the context's record");
        eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(dpy, ctx);
        eglTerminate(dpy);
        return NULL;
    }
    g->display = dpy;
    g->context = ctx;
    snprintf(g->renderer, sizeof g->renderer, "%s", (const char *)glGetString(GL_RENDERER));
    if (debug)
        gl_install_debug_callback();
    log_debug("gl", "context on %s", g->renderer);
    return g;
}

void gl_context_destroy(GlContext *g)
{
    if (!g)
        return;
    eglMakeCurrent(g->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(g->display, g->context);
    eglTerminate(g->display);
    free(g);
}

const char *gl_context_renderer(const GlContext *g) { return g ? g->renderer : ""; }

bool gl_renderer_is_software(const char *renderer)
{
    static const char *const names[] = {"llvmpipe", "softpipe", "swrast", "SwiftShader", NULL};
    for (int i = 0; renderer && names[i]; i++)
        if (strstr(renderer, names[i]))
            return true;
    return false;
}
