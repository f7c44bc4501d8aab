/* pt_progressive.c — see pt_progressive.h. One coordinator thread owns the
 * job: it applies restarts between passes, runs the passes (its own thread
 * among the workers) and publishes each complete one; the caller's calls
 * only exchange state with it under `lock`. */
#include "reference/pt_progressive.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "base/log.h"
#include "reference/pt_job.h"
#include "base/util.h"

struct PtProgressive {
    Scene scene;               /* the renderer's: the caller's geometry and textures (borrowed), with
                                  its own camera, lights and materials (owned copies) */
    PtSettings set;
    PtJob *job;                /* owned; touched by the coordinator only */
    pthread_t thread;          /* the coordinator */
    pthread_mutex_t lock;
    pthread_cond_t wake;       /* the coordinator waits here while paused or done */
    atomic_int cancel;         /* raised (restart, destroy): the running pass takes no new tile */
    ImageF back;               /* the coordinator's: the next image to publish */
    /* Under lock. */
    bool quit;
    bool paused;
    bool pending;              /* a restart waits, with this state: */
    Camera pending_camera;
    Light *pending_lights;     /* owned until applied */
    int pending_light_count;
    Material *pending_materials; /* owned until applied */
    int pending_material_count;
    uint64_t restarts;
    ImageF front;              /* the image published last */
    int front_spp;             /* its samples per pixel; 0: none since the (re)start */
    double front_relmse;       /* its estimated relMSE */
    double front_seconds;      /* when it was published, since the (re)start */
    bool done;                 /* PtSettings.spp or the target reached: no more passes */
    bool waiting;              /* the coordinator waits on `wake` (no pass running) */
};

/* Copies of `s`'s lights and materials; false after logging. */
static bool copy_state(const Scene *s, Light **lights, Material **materials)
{
    *lights = NULL;
    *materials = NULL;
    size_t nl = (size_t)s->light_count * sizeof(Light), nm = (size_t)s->material_count * sizeof(Material);
    if (nl)
        *lights = malloc(nl);
    if (nm)
        *materials = malloc(nm);
    if ((nl && !*lights) || (nm && !*materials)) {
        log_error("reference", "progressive: cannot copy %d lights and %d materials", s->light_count,
                  s->material_count);
        free(*lights);
        free(*materials);
        *lights = NULL;
        *materials = NULL;
        return false;
    }
    if (nl)
        memcpy(*lights, s->lights, nl);
    if (nm)
        memcpy(*materials, s->materials, nm);
    return true;
}

/* Under lock, between passes: the pending state becomes the scene's, and
 * the samples so far are forgotten. */
static void apply_restart(PtProgressive *p)
{
    free(p->scene.lights);
    free(p->scene.materials);
    p->scene.camera = p->pending_camera;
    p->scene.lights = p->pending_lights;
    p->scene.light_count = p->pending_light_count;
    p->scene.materials = p->pending_materials;
    p->scene.material_count = p->pending_material_count;
    p->pending_lights = NULL;
    p->pending_materials = NULL;
    p->pending = false;
    p->restarts++;
    p->front_spp = 0;
    p->front_relmse = 0.0;
    p->front_seconds = 0.0;
    p->done = false;
    pt_job_clear(p->job);
    atomic_store(&p->cancel, 0);
}

static void *coordinator(void *arg)
{
    PtProgressive *p = arg;
    const PtSettings *set = &p->set;
    int pass_spp = pt_job_pass_spp(p->job), spp = 0;
    double t0 = util_seconds();
    pthread_mutex_lock(&p->lock);
    while (!p->quit) {
        if (p->pending) {
            apply_restart(p);
            spp = 0;
            t0 = util_seconds();
            continue;
        }
        if (p->paused || p->done) {
            p->waiting = true;
            pthread_cond_wait(&p->wake, &p->lock);
            p->waiting = false;
            continue;
        }
        /* The first passes double the samples (1, 2, 4, ...) up to a whole
         * pass: an image within a fraction of a pass after a restart. */
        int step = spp == 0 ? 1 : spp < pass_spp ? spp : pass_spp;
        int s1 = spp + step < set->spp ? spp + step : set->spp;
        pthread_mutex_unlock(&p->lock);
        bool whole = pt_job_pass(p->job, spp, s1, set->threads, !set->ordinary_priority, &p->cancel, NULL, NULL);
        double relmse = 0.0;
        if (whole) {
            pt_job_resolve(p->job, s1, &p->back, NULL);
            relmse = pt_job_relmse_estimate(p->job, s1);
        }
        pthread_mutex_lock(&p->lock);
        /* A pass cut short belongs to a state that a restart or the end
         * replaces: the loop's top applies it. */
        if (!whole || p->pending || p->quit)
            continue;
        spp = s1;
        ImageF t = p->front;
        p->front = p->back;
        p->back = t;
        p->front_spp = spp;
        p->front_relmse = relmse;
        p->front_seconds = util_seconds() - t0;
        p->done = spp >= set->spp || (set->target_relmse > 0.0 && spp >= PT_TARGET_MIN_SPP && relmse <= set->target_relmse);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

/* Frees what create made (the thread is not running). */
static void free_parts(PtProgressive *p)
{
    pt_job_destroy(p->job);
    image_free(&p->front);
    image_free(&p->back);
    free(p->scene.lights);
    free(p->scene.materials);
    free(p->pending_lights);
    free(p->pending_materials);
    free(p);
}

PtProgressive *pt_progressive_create(const Scene *scene, const PtSettings *set)
{
    PtProgressive *p = calloc(1, sizeof *p);
    if (!p) {
        log_error("reference", "progressive: cannot allocate the renderer");
        return NULL;
    }
    p->set = *set;
    p->set.threads = set->threads < 1 ? 1 : set->threads;
    p->set.spp = set->spp < 1 ? 1 : set->spp;
    p->set.progress = false;
    p->set.stop = NULL;
    p->set.time_budget = 0.0;
    p->scene = *scene; /* the geometry's pointers: borrowed */
    p->scene.lights = NULL;
    p->scene.materials = NULL;
    if (!copy_state(scene, &p->scene.lights, &p->scene.materials) ||
        !image_alloc(&p->front, set->width, set->height) || !image_alloc(&p->back, set->width, set->height) ||
        !(p->job = pt_job_create(&p->scene, &p->set))) { /* each logs */
        free_parts(p);
        return NULL;
    }
    atomic_init(&p->cancel, 0);
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->wake, NULL);
    if (!pt_thread_start(&p->thread, coordinator, p, !p->set.ordinary_priority)) {
        log_error("reference", "progressive: cannot start the renderer's thread");
        pthread_mutex_destroy(&p->lock);
        pthread_cond_destroy(&p->wake);
        free_parts(p);
        return NULL;
    }
    return p;
}

bool pt_progressive_restart(PtProgressive *p, const Scene *scene)
{
    Light *lights;
    Material *materials;
    if (!copy_state(scene, &lights, &materials))
        return false;
    pthread_mutex_lock(&p->lock);
    free(p->pending_lights);
    free(p->pending_materials);
    p->pending_camera = scene->camera;
    p->pending_lights = lights;
    p->pending_light_count = scene->light_count;
    p->pending_materials = materials;
    p->pending_material_count = scene->material_count;
    p->pending = true;
    /* What was published belongs to the old state. */
    p->front_spp = 0;
    atomic_store(&p->cancel, 1);
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
    return true;
}

void pt_progressive_pause(PtProgressive *p, bool paused)
{
    pthread_mutex_lock(&p->lock);
    p->paused = paused;
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
}

/* Under lock. */
static void fill_status(const PtProgressive *p, PtProgressiveStatus *st)
{
    st->spp = p->front_spp;
    st->relmse_estimate = p->front_spp > 0 ? p->front_relmse : 0.0;
    st->seconds = p->front_seconds;
    st->restarts = p->restarts + (p->pending ? 1 : 0);
    st->done = p->done && !p->pending;
    st->paused = p->paused;
    st->idle = p->waiting;
}

void pt_progressive_status(PtProgressive *p, PtProgressiveStatus *st)
{
    pthread_mutex_lock(&p->lock);
    fill_status(p, st);
    pthread_mutex_unlock(&p->lock);
}

bool pt_progressive_read(PtProgressive *p, ImageF *mean, PtProgressiveStatus *st)
{
    if (!mean->rgb || mean->width != p->set.width || mean->height != p->set.height) {
        log_error("reference", "progressive: the image to read into is not %dx%d", p->set.width, p->set.height);
        return false;
    }
    pthread_mutex_lock(&p->lock);
    bool ok = p->front_spp > 0;
    if (ok)
        memcpy(mean->rgb, p->front.rgb, sizeof(float) * 3 * (size_t)p->set.width * (size_t)p->set.height);
    if (st)
        fill_status(p, st);
    pthread_mutex_unlock(&p->lock);
    return ok;
}

void pt_progressive_destroy(PtProgressive *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->lock);
    p->quit = true;
    atomic_store(&p->cancel, 1);
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
    pthread_join(p->thread, NULL);
    pthread_mutex_destroy(&p->lock);
    pthread_cond_destroy(&p->wake);
    free_parts(p);
}
