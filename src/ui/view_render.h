/* view_render.h — the render thread of `rtgi view`.
 *
 * On a software rasterizer (llvmpipe) a compute dispatch runs at the call,
 * on the calling thread: a Sponza frame of a VPL technique held the window
 * for over ten seconds, each key waiting for it. So the renderer lives on a
 * thread of its own, with its own GL context shared with the window's (a
 * hidden GLFW window made on the main thread, its context made current on
 * this thread: textures, programs and fences are shared, FBOs and VAOs are
 * not), and the window's thread only polls events, draws the panel and the
 * last finished image, and asks for frames:
 *
 *   window thread                       render thread
 *   view_render_submit(scene, jobs) ──▶ takes the newest request, applies its
 *                                       settings, draws the frame, copies it
 *                                       into a free presentation slot (fence),
 *   view_render_take(&image)       ◀── publishes it, wakes the window
 *   draws it (fence when released)      (glfwPostEmptyEvent)
 *
 * A request is the scene state a frame is drawn from (settings, camera,
 * time) plus one-off jobs (P, F5, T, RMSE, ...); the thread draws a frame
 * only when that state changed since the last frame (or `force`), so an
 * idle window draws nothing. Requests made while a frame is in flight
 * replace each other: the next frame is drawn from the newest one, which a
 * key pressed during a slow frame therefore reaches. Three presentation
 * slots (front: shown; pending: handed over; back: being written) let
 * either side go on without waiting for the other.
 *
 * Scripted runs (--frames N, --ui-test) call view_render_wait after each
 * submit: one frame per window frame, as deterministic as a single thread.
 *
 * Two later additions have their places here:
 *  - an animation time (play/pause/scrub) and the lights' edits are part
 *    of the scene state (ViewScene.time, .lights): the window's loop
 *    advances View.time while playing (as it moves the camera while a key
 *    is held), so each pass asks for a new frame, and draw_frame writes
 *    the scene at req->scene.time with the edits before renderer_frame
 *    (view_anim_apply: animation_apply, renderer_scene_changed);
 *  - the live reference (src/ui/live_reference.h: the path tracer of
 *    pt_progressive.h on threads of its own, at the lowest priority) is
 *    restarted by the window's loop when the camera, the lights, the size
 *    or the time change, and polled there; each newer image goes to the
 *    A/B view (ab_view_set_reference, the window's texture) and to this
 *    thread (view_render_set_reference: its own copy, which RMSE and the
 *    heat map's scale read, so neither side waits for the other). It
 *    gets the window's scene (View.scene: ViewAnim.shown, whose lights
 *    are the ones this thread draws at the request's time, edits
 *    included). */
#ifndef RTGI_VIEW_RENDER_H
#define RTGI_VIEW_RENDER_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "frame/renderer.h"
#include "core/scene.h"
#include "ui/ab_view.h"
#include "ui/view.h"

typedef struct GLFWwindow GLFWwindow;

/* One-off work for the render thread, done once after the request's frame
 * (RESET_TIMER and RELOAD before it). */
typedef enum ViewJob {
    VIEW_JOB_SAVE = 1u << 0,          /* save the image to ViewRequest.save_path (P) */
    VIEW_JOB_RELOAD = 1u << 1,        /* rebuild every program from the shader files (F5); draws a frame */
    VIEW_JOB_RMSE = 1u << 2,          /* RMSE of the image against the reference (ViewRenderState.rmse) */
    VIEW_JOB_PRINT_TIMINGS = 1u << 3, /* T: the timings table on stdout */
    VIEW_JOB_RESET_TIMER = 1u << 4,   /* the timer starts again with the next frame */
    VIEW_JOB_PASS_TABLE = 1u << 5,    /* publish the timer's pass table now (the script) */
} ViewJob;

/* What a scene frame is drawn from. */
typedef struct ViewScene {
    RenderSettings settings;
    Camera camera;
    double time;        /* animation time (s) */
    ViewLightEdits lights; /* the lights' edits in the window (view_anim.h) */
} ViewScene;

typedef struct ViewRequest {
    ViewScene scene;
    bool force;             /* draw a frame even if the scene is the last frame's (scripted runs) */
    unsigned jobs;          /* ViewJob bits */
    char save_path[256];    /* VIEW_JOB_SAVE: .png as shown, .pfm/.exr radiance */
    bool half;              /* VIEW_JOB_SAVE: .exr as half floats */
    bool diff_scale;        /* the heat map's automatic scale is wanted for each frame */
    bool hold_timer;        /* the timer keeps its frames (the script's table of frames 1-2) */
    double test_sleep_s;    /* test hook (the --ui-test script only): the next frame sleeps this
                               long on the render thread before it is drawn, a slow frame */
} ViewRequest;

/* The thread's published state, copied out by view_render_state. */
typedef struct ViewRenderState {
    bool made;              /* the renderer was made */
    bool failed;            /* the renderer could not be made or take a request's settings (it
                               logged one line): the window ends */
    bool busy;              /* a scene frame is being drawn ... */
    double busy_since;      /* ... since (glfwGetTime) */
    unsigned version;       /* changes whenever anything below does */
    unsigned frames;        /* scene frames drawn */
    unsigned stats_version; /* changes when stats do */
    ViewStats stats;
    int remakes;            /* the renderer's remakes (what an apply remade) */
    int links;              /* programs linked (shader_link_count) */
    bool whole;             /* renderer_frames_whole: every program built, every technique run ok */
    unsigned rmse_count;    /* RMSE jobs done; the last one's result: */
    double rmse;            /* -1: sizes differ, the reference is display-referred, or no memory */
    unsigned saves;         /* SAVE jobs done; the last one's outcome: */
    bool save_ok;
    unsigned diff_frame;    /* the frame (1-based count) the heat map's auto scale is for (0: none) */
    float diff_scale;       /* that scale: the 99th percentile of the frame's difference */
    unsigned reloads;       /* RELOAD jobs done; with one: */
    GLuint ab_program;      /* the A/B view's program rebuilt by the last reload (0: kept the old);
                               the window takes it over (ab_view_set_program) */
    float last_exposure;    /* the last frame's exposure (the script checks which request it drew) */
    double last_frame_s;    /* the last frame's wall time on the thread */
} ViewRenderState;

/* The image the window shows: a presentation slot's textures (shared,
 * made and owned by the render thread). */
typedef struct ViewImage {
    GLuint ldr;             /* SRGB8_ALPHA8, the final image (0: none yet) */
    GLuint hdr;             /* RGBA32F radiance with a reference (the A/B view), else 0 */
    int width, height;
    float exposure;         /* the frame's */
    unsigned frame;         /* its number (ViewRenderState.frames when it was published) */
} ViewImage;

typedef struct ViewRenderDesc {
    GLFWwindow *context;    /* a hidden window with a context shared with the window's */
    Scene *scene;           /* borrowed; the thread writes the animation's state and the lights' edits into it */
    const AbView *ab;       /* the A/B view (a reload rebuilds its program; its reference, if any, is
                               copied at the start for RMSE and the heat map's scale), or NULL */
    ViewStatus *status;     /* the panel's status line */
    const ViewRequest *first; /* the first frame's request (its settings make the renderer) */
    const char *gl_renderer; /* GL_RENDERER, for the timings table */
    bool debug;             /* --debug: the KHR_debug callback on the thread's context too */
} ViewRenderDesc;

typedef struct ViewRender ViewRender;

/* Starts the thread, which makes the renderer and draws the first frame
 * (view_render_state: made or failed). NULL after logging if the thread
 * cannot start. */
ViewRender *view_render_start(const ViewRenderDesc *d);
/* Ends the thread (it finishes the frame in flight, destroys what it made
 * and releases its context) and frees vr. The window must not draw the
 * taken image afterwards. A thread that failed keeps its objects until
 * this call, so the image taken last stays valid until then. */
void view_render_stop(ViewRender *vr);
/* Asks for a frame of req->scene (drawn if it differs from the last
 * frame's, or with req->force) and req's jobs. Never waits for a frame. */
void view_render_submit(ViewRender *vr, const ViewRequest *req);
/* Adds jobs to what is asked, the scene left as it is (`save_path`:
 * VIEW_JOB_SAVE's, else NULL). */
void view_render_jobs(ViewRender *vr, unsigned jobs, const char *save_path, bool half);
/* Waits until the thread has done everything asked of it (or failed). */
void view_render_wait(ViewRender *vr);
/* A copy of the published state. */
void view_render_state(ViewRender *vr, ViewRenderState *out);
/* The newest finished image, if one came since the last take: *out is
 * then it and the previous one is released (the window's thread, its
 * context current: it waits for the image's fence on the GPU). */
bool view_render_take(ViewRender *vr, ViewImage *out);
/* Replaces the reference that RMSE and the heat map's scale read (a copy
 * of `img` is taken; NULL or an empty image: none); `display`: already
 * exposed and clamped. The thread takes it before its next request and
 * measures the heat map's scale again. false after logging (memory). */
bool view_render_set_reference(ViewRender *vr, const ImageF *img, bool display);
/* The A/B view's program rebuilt by a reload (the caller takes it over:
 * ab_view_set_program), or 0. */
GLuint view_render_take_program(ViewRender *vr);

#endif
