/* live_reference.c — see live_reference.h. */
#include "ui/live_reference.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/animation.h"
#include "base/log.h"
#include "io/metrics.h"
#include "base/util.h"

/* A renderer being made on a thread of its own. */
struct LiveMake {
    pthread_t thread;
    Scene scene;             /* the window's geometry (borrowed) or `geom`, this make's camera and lights: */
    Light *lights;           /* owned */
    Vertex *geom;            /* owned until adopted: the vertices the renderer borrows (NULL: the scene's) */
    PtSettings set;
    PtProgressive *pt;       /* the result (NULL: failed, it logged) */
    double seconds;          /* what making it took */
    atomic_bool done;
};

static void *make_thread(void *arg)
{
    LiveMake *m = arg;
    double t0 = util_seconds();
    m->pt = pt_progressive_create(&m->scene, &m->set); /* logs a failure */
    m->seconds = util_seconds() - t0;
    atomic_store(&m->done, true);
    return NULL;
}

/* Waits for the make in flight and frees it; its renderer, if wanted
 * (`keep`), becomes l's. */
static void make_end(LiveReference *l, bool keep)
{
    LiveMake *m = l->make;
    if (!m)
        return;
    pthread_join(m->thread, NULL);
    if (keep && m->pt) {
        l->pt = m->pt;
        l->geom = m->geom;
        log_info("view", "live reference: %dx%d, %d threads, up to %d spp (BVH in %.2f s)", m->set.width,
                 m->set.height, m->set.threads, m->set.spp, m->seconds);
    } else {
        pt_progressive_destroy(m->pt);
        free(m->geom);
        l->failed = keep; /* a make that was wanted failed */
    }
    free(m->lights);
    free(m);
    l->make = NULL;
}

/* Starts making the renderer of `s` at l->set's size, over `geom` (taken:
 * s's vertices at its state) or, when NULL, s's own vertices. false after
 * logging. */
static bool make_start(LiveReference *l, const Scene *s, Vertex *geom)
{
    LiveMake *m = calloc(1, sizeof *m);
    size_t n = (size_t)s->light_count * sizeof(Light);
    if (m && n && (m->lights = malloc(n)))
        memcpy(m->lights, s->lights, n);
    if (!m || (n && !m->lights)) {
        log_error("view", "live reference: out of memory for its renderer");
        if (m)
            free(m->lights);
        free(m);
        free(geom);
        return false;
    }
    m->scene = *s;
    m->scene.lights = m->lights;
    m->geom = geom;
    if (geom) {
        m->scene.vertices = geom;
        scene_compute_bounds(&m->scene);
    }
    m->set = l->set;
    atomic_init(&m->done, false);
    if (pthread_create(&m->thread, NULL, make_thread, m) != 0) {
        log_error("view", "live reference: cannot start a thread to make its renderer");
        free(m->lights);
        free(m->geom);
        free(m);
        return false;
    }
    l->make = m;
    return true;
}

void live_reference_init(LiveReference *l, int threads, int spp, bool ordinary_priority, const ImageF *compare)
{
    memset(l, 0, sizeof *l);
    pt_settings_default(&l->set);
    l->set.threads = threads < 1 ? 1 : threads;
    l->set.spp = spp < 1 ? 1 : spp;
    l->set.ordinary_priority = ordinary_priority;
    l->compare = compare;
    l->status.relmse_compare = -1;
}

/* Frees the renderer and the vertices it borrowed. */
static void drop_renderer(LiveReference *l)
{
    pt_progressive_destroy(l->pt);
    l->pt = NULL;
    free(l->geom);
    l->geom = NULL;
}

void live_reference_stop(LiveReference *l)
{
    make_end(l, false);
    drop_renderer(l);
    free(l->pending);
    l->pending = NULL;
    l->failed = false;
    l->stale = false;
    image_free(&l->image);
    free(l->lights);
    l->lights = NULL;
    l->light_count = 0;
    uint64_t restarts = l->status.restarts;
    memset(&l->status, 0, sizeof l->status);
    l->status.restarts = restarts;
    l->status.relmse_compare = -1;
}

/* The state it renders, remembered to see what changes. false after logging. */
static bool remember(LiveReference *l, const Scene *scene, const Camera *camera, double time)
{
    Light *lights = NULL;
    size_t n = (size_t)scene->light_count * sizeof(Light);
    if (n && !(lights = malloc(n))) {
        log_error("view", "live reference: out of memory for %d lights", scene->light_count);
        return false;
    }
    if (n)
        memcpy(lights, scene->lights, n);
    free(l->lights);
    l->lights = lights;
    l->light_count = scene->light_count;
    l->camera = *camera;
    l->time = time;
    return true;
}

/* The renderer of the last make became l's: a state newer than the make's
 * restarts it, or, when its geometry moved meanwhile, is made anew. */
static void adopt(LiveReference *l)
{
    make_end(l, true);
    Scene s = *l->scene;
    s.camera = l->camera;
    s.lights = l->lights;
    s.light_count = l->light_count;
    if (l->pending && !l->failed) {
        drop_renderer(l);
        Vertex *geom = l->pending;
        l->pending = NULL;
        l->stale = false;
        if (!make_start(l, &s, geom)) /* logged */
            l->failed = true;
        return; /* still building */
    }
    if (l->pt && l->stale)
        pt_progressive_restart(l->pt, &s); /* a failure logged: it renders the make's state */
    l->stale = false;
    l->status.building = false;
}

/* Where objects or quad-light emitters can move, the renderer borrows
 * vertices of its own at its state (the render thread rewrites the
 * scene's): *geom gets scene's at `time` when they differ from those of
 * the newest renderer, made or being made (*regeom: it is made anew, its
 * BVH over them), or when `keep` (a new size makes it anew anyway); else
 * NULL. false after logging (out of memory). */
static bool state_geometry(const LiveReference *l, const Scene *scene, double time, bool keep, Vertex **geom,
                           bool *regeom)
{
    *geom = NULL;
    *regeom = false;
    if (!animation_geometry_moves(scene))
        return true;
    size_t bytes = sizeof(Vertex) * scene->vertex_count;
    Vertex *g = malloc(bytes ? bytes : 1);
    if (!g)
        log_error("view", "live reference: out of memory for %u vertices", scene->vertex_count);
    if (!g || !animation_vertices_at(scene, time, scene->lights, g)) { /* logged */
        free(g);
        return false;
    }
    const Vertex *newest = l->pending ? l->pending : l->make ? l->make->geom : l->geom;
    *regeom = !newest || memcmp(newest, g, bytes) != 0;
    if (*regeom || keep)
        *geom = g;
    else
        free(g);
    return true;
}

int live_reference_update(LiveReference *l, const Scene *scene, const Camera *camera, double time, int w, int h)
{
    l->scene = scene;
    if (l->make && atomic_load(&l->make->done))
        adopt(l);
    if (l->failed) {
        live_reference_stop(l);
        return -1;
    }
    bool size = (!l->pt && !l->make) || l->set.width != w || l->set.height != h;
    if (!size && !memcmp(&l->camera, camera, sizeof *camera) && l->time == time &&
        l->light_count == scene->light_count &&
        (!l->light_count || !memcmp(l->lights, scene->lights, sizeof(Light) * (size_t)l->light_count)))
        return 0;
    Scene s = *scene; /* the geometry borrowed; the camera the window's */
    s.camera = *camera;
    bool was = l->pt != NULL || l->make != NULL;
    Vertex *geom = NULL;
    bool regeom = false;
    if (!state_geometry(l, scene, time, size, &geom, &regeom)) {
        live_reference_stop(l);
        return -1;
    }
    if (size) {
        make_end(l, false); /* a make of another size: waited for (a resize during a BVH build) */
        free(l->pending);
        l->pending = NULL;
        image_free(&l->image);
        l->set.width = w;
        l->set.height = h;
        l->stale = false;
        if (!image_alloc(&l->image, w, h)) {
            log_error("view", "live reference: out of memory for a %dx%d image", w, h);
            free(geom);
            live_reference_stop(l);
            return -1;
        }
    }
    if ((size || regeom) && !l->make) { /* made anew */
        drop_renderer(l);
        if (!make_start(l, &s, geom)) {
            live_reference_stop(l);
            return -1;
        }
        l->status.building = true;
    } else if (regeom) {
        free(l->pending); /* made anew once the make in flight ends (adopt) */
        l->pending = geom;
        l->stale = true;
    } else if (l->make) {
        l->stale = true; /* restarted with this state once made */
    } else if (!pt_progressive_restart(l->pt, &s)) { /* logged; it goes on with the old state */
        return 0;
    }
    if (!remember(l, scene, camera, time)) {
        live_reference_stop(l);
        return -1;
    }
    l->read_restarts = UINT64_MAX;
    if (was)
        l->status.restarts++;
    l->status.running = true;
    l->status.width = w;
    l->status.height = h;
    l->status.threads = l->set.threads;
    l->status.spp = 0;
    l->status.relmse_estimate = 0;
    l->status.seconds = 0;
    l->status.done = false;
    l->status.relmse_compare = -1;
    return 1;
}

bool live_reference_poll(LiveReference *l)
{
    if (l->make && atomic_load(&l->make->done))
        adopt(l);
    if (!l->pt)
        return false;
    PtProgressiveStatus st;
    pt_progressive_status(l->pt, &st);
    l->status.done = st.done;
    if (st.spp <= 0 || (st.spp == l->status.spp && st.restarts == l->read_restarts))
        return false;
    if (!pt_progressive_read(l->pt, &l->image, &st)) /* a restart came between the two */
        return false;
    l->read_restarts = st.restarts;
    l->status.spp = st.spp;
    l->status.relmse_estimate = st.relmse_estimate;
    l->status.seconds = st.seconds;
    l->status.done = st.done;
    l->status.relmse_compare = -1;
    if (l->compare && l->compare->width == l->image.width && l->compare->height == l->image.height)
        l->status.relmse_compare = metric_relmse(&l->image, l->compare, NULL, NULL);
    return true;
}

void live_reference_text(const LiveStatus *st, char *out, size_t cap)
{
    if (!st->running)
        snprintf(out, cap, "off");
    else if (st->building)
        snprintf(out, cap, "building its BVH (%dx%d, %d threads)...", st->width, st->height, st->threads);
    else if (st->spp <= 0)
        snprintf(out, cap, "first pass of %dx%d on %d threads...", st->width, st->height, st->threads);
    else if (st->spp < 2) /* no variance of one sample */
        snprintf(out, cap, "%d spp in %.1f s", st->spp, st->seconds);
    else
        snprintf(out, cap, "%d spp in %.1f s, relMSE ~%.3g (est.)%s", st->spp, st->seconds, st->relmse_estimate,
                 st->done ? ", done" : "");
}
