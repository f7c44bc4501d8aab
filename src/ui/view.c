/* view.c — see view.h. */
#include "ui/view.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "base/log.h"

double view_estimate_ms(const View *v, int gi)
{
    int n = renderer_ssaa(&v->settings);
    double px = (double)v->settings.width * v->settings.height * n * n;
    const ViewStats *m = &v->stats;
    if (m->measured_px[gi] > 0)
        return m->measured_ms[gi] * px / m->measured_px[gi];
    double base = m->measured_px[GI_NONE] > 0 ? m->measured_ms[GI_NONE] * px / m->measured_px[GI_NONE] : 0;
    double rate = m->evals_per_s > 0 ? m->evals_per_s : GI_COST_DEFAULT_EVALS_PER_S;
    return base + 1e3 * gi_cost_seconds(gi, &v->settings.set.gi, v->scene, px, rate);
}

bool view_gi_is_slow(const View *v, int gi)
{
    return gi != GI_NONE && view_estimate_ms(v, gi) > v->slow_ms;
}

/* The confirm text of a pending technique leaves the status line with it
 * (it had stayed after "Switch anyway"); a newer message stays. */
static void clear_pending(View *v)
{
    v->pending_gi = -1;
    if (!v->status_pending)
        return;
    v->status_pending = false;
    pthread_mutex_lock(&v->status->lock);
    if (!v->status->error)
        v->status->text[0] = 0;
    pthread_mutex_unlock(&v->status->lock);
}

bool view_select_gi(View *v, int gi, bool confirmed)
{
    if (gi == (int)v->settings.gi) {
        clear_pending(v);
        return true;
    }
    if (!confirmed && view_gi_is_slow(v, gi)) {
        v->pending_gi = gi;
        view_status(v->status, false, "%s: about %.1f s per frame at %dx%d; confirm in the panel to switch",
                    gi_techniques[gi]->name, view_estimate_ms(v, gi) / 1e3, v->settings.width, v->settings.height);
        v->status_pending = true;
        v->show_panel = true;
        return false;
    }
    clear_pending(v);
    v->settings.gi = (GiMode)gi;
    log_info("view", "GI: %s", gi_techniques[gi]->name);
    return true;
}

void view_cancel_gi(View *v) { clear_pending(v); }

void view_cycle_gi(View *v, int step)
{
    int from = v->pending_gi >= 0 ? v->pending_gi : (int)v->settings.gi;
    view_select_gi(v, (from + step + GI_MODE_COUNT) % GI_MODE_COUNT, false);
}

void view_status(ViewStatus *s, bool error, const char *fmt, ...)
{
    /* Formatted apart from the status: the window's log hook rewrites it
     * while the line is logged (it had printed "[view] [view] ..."). */
    char msg[sizeof s->text];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (error)
        log_error("view", "%s", msg);
    else
        log_info("view", "%s", msg);
    pthread_mutex_lock(&s->lock);
    snprintf(s->text, sizeof s->text, "%s", msg);
    s->error = error;
    pthread_mutex_unlock(&s->lock);
}

void view_status_log_hook(LogLevel level, const char *tag, const char *message, void *user)
{
    ViewStatus *s = user;
    if (level < LOG_ERROR)
        return;
    pthread_mutex_lock(&s->lock);
    size_t len = strlen(s->text);
    if (s->reloading && s->error && len + 4 < sizeof s->text) /* a reload's errors, first one first */
        snprintf(s->text + len, sizeof s->text - len, " | [%s] %s", tag, message);
    else
        snprintf(s->text, sizeof s->text, "[%s] %s", tag, message);
    s->error = true;
    pthread_mutex_unlock(&s->lock);
}

void view_status_get(ViewStatus *s, char *out, size_t cap, bool *error)
{
    pthread_mutex_lock(&s->lock);
    snprintf(out, cap, "%s", s->text);
    if (error)
        *error = s->error;
    pthread_mutex_unlock(&s->lock);
}

void view_camera_json(const View *v, char *out, size_t cap)
{
    const Camera *c = &v->camera;
    float t[3];
    for (int i = 0; i < 3; i++)
        t[i] = c->position[i] + c->forward[i];
    snprintf(out, cap,
             "\"camera\": {\"position\": [%.4f, %.4f, %.4f], \"target\": [%.4f, %.4f, %.4f], "
             "\"fov_y_deg\": %.2f}",
             (double)c->position[0], (double)c->position[1], (double)c->position[2], (double)t[0], (double)t[1],
             (double)t[2], (double)(c->fov_y * 180.f / GLM_PIf));
}

float view_heat_scale(const View *v)
{
    return v->ab && v->ab->diff_auto && v->ab_auto_scale > 0 ? v->ab_auto_scale : v->ab ? v->ab->diff_scale : 0;
}

void view_heat_labels(float scale, char labels[4][16])
{
    for (int i = 0; i < 4; i++)
        snprintf(labels[i], sizeof labels[0], "%.3g", (double)(scale * (float)i / 3.f));
}

void view_busy_text(const View *v, char *out, size_t cap)
{
    out[0] = 0;
    if (!v->busy || v->busy_s < 0.25)
        return;
    double est = view_estimate_ms(v, (int)v->settings.gi) / 1e3;
    if (est >= 0.5 && est >= v->busy_s)
        snprintf(out, cap, "rendering... %.1f s (~%.0f s per frame)", v->busy_s, est);
    else
        snprintf(out, cap, "rendering... %.1f s", v->busy_s);
}

void view_set_angles(View *v, const Camera *c)
{
    v->yaw = atan2f(c->forward[0], c->forward[2]);
    v->pitch = asinf(fmaxf(-1.f, fminf(1.f, c->forward[1])));
}

void view_update_camera(View *v)
{
    Camera *c = &v->camera;
    c->forward[0] = cosf(v->pitch) * sinf(v->yaw);
    c->forward[1] = sinf(v->pitch);
    c->forward[2] = cosf(v->pitch) * cosf(v->yaw);
    vec3 right;
    glm_vec3_cross(c->forward, (vec3){0, 1, 0}, right);
    glm_vec3_normalize(right);
    glm_vec3_cross(right, c->forward, c->up);
}
