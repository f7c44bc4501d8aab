/* live_reference.c — see live_reference.h. */
#include "ui/live_reference.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "metrics.h"
#include "util.h"

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

void live_reference_stop(LiveReference *l)
{
    pt_progressive_destroy(l->pt);
    l->pt = NULL;
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

int live_reference_update(LiveReference *l, const Scene *scene, const Camera *camera, double time, int w, int h)
{
    bool size = !l->pt || l->set.width != w || l->set.height != h;
    if (!size && !memcmp(&l->camera, camera, sizeof *camera) && l->time == time &&
        l->light_count == scene->light_count &&
        (!l->light_count || !memcmp(l->lights, scene->lights, sizeof(Light) * (size_t)l->light_count)))
        return 0;
    Scene s = *scene; /* the geometry borrowed; the camera the window's */
    s.camera = *camera;
    bool was = l->pt != NULL;
    if (size) {
        pt_progressive_destroy(l->pt);
        l->pt = NULL;
        image_free(&l->image);
        l->set.width = w;
        l->set.height = h;
        if (!image_alloc(&l->image, w, h)) {
            log_error("view", "live reference: out of memory for a %dx%d image", w, h);
            live_reference_stop(l);
            return -1;
        }
        double t0 = util_seconds();
        l->pt = pt_progressive_create(&s, &l->set); /* logs a failure */
        if (!l->pt) {
            live_reference_stop(l);
            return -1;
        }
        log_info("view", "live reference: %dx%d, %d threads, up to %d spp (BVH in %.2f s)", w, h, l->set.threads,
                 l->set.spp, util_seconds() - t0);
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
    else if (st->spp <= 0)
        snprintf(out, cap, "first pass of %dx%d on %d threads...", st->width, st->height, st->threads);
    else
        snprintf(out, cap, "%d spp in %.1f s, relMSE ~%.3g (est.)%s", st->spp, st->seconds, st->relmse_estimate,
                 st->done ? ", done" : "");
}
