#include "gl/gpu_timer.h"

#include <string.h>

#include "gl/gl_context.h"
#include "base/util.h"

void gpu_timer_create(GpuTimer *t, bool enabled, bool sync)
{
    memset(t, 0, sizeof *t);
    t->enabled = enabled;
    t->sync = sync;
    t->open_pass = -1;
    t->exact = enabled && !gl_renderer_is_software((const char *)glGetString(GL_RENDERER));
    if (enabled)
        glCreateQueries(GL_TIMESTAMP, GPU_TIMER_MAX_QUERIES, t->queries);
}

void gpu_timer_destroy(GpuTimer *t)
{
    if (t->enabled)
        glDeleteQueries(GPU_TIMER_MAX_QUERIES, t->queries);
    memset(t, 0, sizeof *t);
}

/* The index of pass `name` in `list` (count entries of at most max), added
 * if new; the last entry when the list is full. */
static int pass_index(GpuTimerPass *list, int *count, int max, const char *name)
{
    for (int i = 0; i < *count; i++)
        if (strcmp(list[i].name, name) == 0)
            return i;
    if (*count == max)
        return max - 1;
    GpuTimerPass *p = &list[*count];
    memset(p, 0, sizeof *p);
    strncpy(p->name, name, sizeof p->name - 1);
    return (*count)++;
}

/* Records `ms` of GPU (cpu false) or wall time for pass `index` (as in
 * query_pass): summed for a per-frame pass, the last run's for a one-time
 * pass. */
static void record(GpuTimer *t, int index, bool cpu, double ms)
{
    bool once = index >= GPU_TIMER_MAX_PASSES;
    GpuTimerPass *p = once ? &t->once[index - GPU_TIMER_MAX_PASSES] : &t->passes[index];
    double *v = cpu ? &p->cpu_ms : &p->gpu_ms;
    *v = once ? ms : *v + ms;
    if (!once)
        *(cpu ? &p->frame_cpu_ms : &p->frame_gpu_ms) += ms;
}

static void begin(GpuTimer *t, const char *pass, bool once)
{
    glPushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, (GLuint)t->debug_groups, -1, pass);
    t->debug_groups++;
    if (!t->enabled || t->query_count + 2 > GPU_TIMER_MAX_QUERIES)
        return;
    t->open_pass = once ? GPU_TIMER_MAX_PASSES + pass_index(t->once, &t->once_count, GPU_TIMER_MAX_ONCE, pass)
                        : pass_index(t->passes, &t->pass_count, GPU_TIMER_MAX_PASSES, pass);
    if (t->sync) {
        glFinish();
        t->cpu_begin = util_seconds();
    }
    t->query_pass[t->query_count / 2] = t->open_pass;
    glQueryCounter(t->queries[t->query_count], GL_TIMESTAMP);
}

void gpu_timer_begin(GpuTimer *t, const char *pass) { begin(t, pass, false); }

void gpu_timer_begin_once(GpuTimer *t, const char *pass) { begin(t, pass, true); }

void gpu_timer_end(GpuTimer *t)
{
    if (t->enabled && t->open_pass >= 0) {
        glQueryCounter(t->queries[t->query_count + 1], GL_TIMESTAMP);
        t->query_count += 2;
        if (t->sync) {
            glFinish();
            record(t, t->open_pass, true, 1e3 * (util_seconds() - t->cpu_begin));
        }
        t->open_pass = -1;
    }
    if (t->debug_groups > 0) { /* an unmatched end must not underflow the GL stack */
        glPopDebugGroup();
        t->debug_groups--;
    }
}

void gpu_timer_end_frame(GpuTimer *t)
{
    if (!t->enabled)
        return;
    for (int q = 0; q < t->query_count; q += 2) {
        GLuint64 a = 0, b = 0;
        glGetQueryObjectui64v(t->queries[q], GL_QUERY_RESULT, &a);
        glGetQueryObjectui64v(t->queries[q + 1], GL_QUERY_RESULT, &b);
        record(t, t->query_pass[q / 2], false, (double)(b - a) * 1e-6);
    }
    for (int i = 0; i < t->pass_count; i++) {
        GpuTimerPass *p = &t->passes[i];
        if (p->frame_gpu_ms > 0 && (p->min_gpu_ms == 0 || p->frame_gpu_ms < p->min_gpu_ms))
            p->min_gpu_ms = p->frame_gpu_ms;
        if (p->frame_cpu_ms > 0 && (p->min_cpu_ms == 0 || p->frame_cpu_ms < p->min_cpu_ms))
            p->min_cpu_ms = p->frame_cpu_ms;
        p->frame_gpu_ms = p->frame_cpu_ms = 0;
    }
    t->query_count = 0;
    t->frames++;
}

void gpu_timer_reset(GpuTimer *t)
{
    t->pass_count = 0;
    t->frames = 0;
    t->query_count = 0;
}

void gpu_timer_forget_once(GpuTimer *t) { t->once_count = 0; }

double gpu_timer_mean_ms(const GpuTimer *t, const char *pass, bool cpu)
{
    for (int i = 0; i < t->pass_count; i++)
        if (strcmp(t->passes[i].name, pass) == 0 && t->frames > 0)
            return (cpu ? t->passes[i].cpu_ms : t->passes[i].gpu_ms) / t->frames;
    return -1.0;
}

double gpu_timer_min_ms(const GpuTimer *t, const char *pass, bool cpu)
{
    for (int i = 0; i < t->pass_count; i++)
        if (strcmp(t->passes[i].name, pass) == 0) {
            double m = cpu ? t->passes[i].min_cpu_ms : t->passes[i].min_gpu_ms;
            return m > 0 ? m : -1.0;
        }
    return -1.0;
}

void gpu_timer_print(const GpuTimer *t, FILE *f)
{
    if (!t->enabled || t->frames == 0)
        return;
    double tg = 0, tc = 0;
    fprintf(f, "timings: mean of %d frame%s (gpu: timer queries%s)\n", t->frames, t->frames > 1 ? "s" : "",
            t->sync ? ", cpu: wall time with glFinish" : "");
    fprintf(f, "  %-20s %10s %10s\n", "pass", "gpu_ms", t->sync ? "cpu_ms" : "");
    for (int i = 0; i < t->pass_count; i++) {
        double g = t->passes[i].gpu_ms / t->frames, c = t->passes[i].cpu_ms / t->frames;
        tg += g;
        tc += c;
        if (t->sync)
            fprintf(f, "  %-20s %10.3f %10.3f\n", t->passes[i].name, g, c);
        else
            fprintf(f, "  %-20s %10.3f\n", t->passes[i].name, g);
    }
    if (t->sync)
        fprintf(f, "  %-20s %10.3f %10.3f\n", "total", tg, tc);
    else
        fprintf(f, "  %-20s %10.3f\n", "total", tg);
    for (int i = 0; i < t->once_count; i++) {
        if (t->sync)
            fprintf(f, "  %-20s %10.3f %10.3f  once\n", t->once[i].name, t->once[i].gpu_ms, t->once[i].cpu_ms);
        else
            fprintf(f, "  %-20s %10.3f  once\n", t->once[i].name, t->once[i].gpu_ms);
    }
}
