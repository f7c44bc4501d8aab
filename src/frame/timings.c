/* timings.c — the --timings report of a renderer's frames. */
#include "frame/timings.h"

#include <stdio.h>
#include <string.h>

#include "gl/gpu_timer.h"

static struct {
    const char *path;  /* --probe: a `rtgi probe --json` file, "run", or NULL */
    ProbeResult file;  /* its result when it names a file (read once, at parse time) */
} s_probe;

void timings_use_probe(const char *path, const ProbeResult *file)
{
    s_probe.path = path;
    if (file)
        s_probe.file = *file;
}

/* The gather's evaluations/s over its passes' time in their fastest frame
 * (each pass's, summed; as rtgi probe takes its kernels' fastest run, so
 * that the load of a shared machine does not lower one side only): of
 * every gather pass the technique listed (pass < 0) or of one. */
static double gather_rate(const Renderer *r, const RenderStats *st, int pass)
{
    double ms = renderer_gather_ms(r, st, pass, true);
    uint64_t evaluations = pass < 0 ? st->gather_evaluations : st->gather_passes[pass].evaluations;
    return evaluations == 0 || ms <= 0 ? 0 : (double)evaluations / (ms * 1e-3);
}

/* With a probe result, the fraction of two bounds: issue 11's yardstick,
 * the two-fetch kernel (PROBE_RSM_FETCHES RGBA32F fetches per RSM sample; a
 * VPL's three vec4 from a storage buffer for VPL loops), and for RSM
 * gathers the kernel that reads what they read, one packed texel per
 * sample. `--probe run` measures on maps of the gather's RSM size: the
 * rate of a fetch depends on the size of the map it reads. Each gather
 * pass's own lines (gather_pass_NAME_*) follow the whole gather's. */
static GatherRates print_gather_efficiency(const Renderer *r, const RenderStats *st, const char *probe_path)
{
    GatherRates rates = {gather_rate(r, st, -1), {0}};
    double rate = rates.total;
    if (rate <= 0)
        return rates;
    printf("gather_evaluations: %llu\n", (unsigned long long)st->gather_evaluations);
    printf("gather_evals_per_s: %.4g\n", rate);
    ProbeResult pr = s_probe.file;
    bool probed = probe_path && (strcmp(probe_path, "run") || probe_run(&pr, st->gather_vpl ? 0 : st->gather_map_size));
    const char *map = st->gather_cube ? "cube" : "2d", *list = st->gather_from_list > 0 ? " + ssbo_vpl" : "";
    double bound = probed ? probe_bound(&pr, st->gather_vpl, st->gather_cube, st->gather_from_list, false) : 0;
    double texel = probed && !st->gather_vpl ? probe_bound(&pr, false, st->gather_cube, st->gather_from_list, true) : 0;
    if (probed) {
        if (st->gather_vpl) {
            printf("gather_probe_bound: %.4g (ssbo_vpl)\n", bound);
        } else {
            printf("gather_probe_map_size: %d\n", pr.map_size);
            printf("gather_probe_bound: %.4g (%s_fetch2%s)\n", bound, map, list);
        }
        printf("gather_fraction_of_bound: %.3f\n", rate / bound);
        if (texel > 0) {
            printf("gather_texel_bound: %.4g (%s_texel%s)\n", texel, map, list);
            printf("gather_fraction_of_texel_bound: %.3f\n", rate / texel);
        }
    }
    for (int i = 0; i < st->gather_pass_count; i++) {
        const GiGatherPass *p = &st->gather_passes[i];
        double pass_rate = rates.pass[i] = gather_rate(r, st, i);
        printf("gather_pass_%s_evaluations: %llu\n", p->name, (unsigned long long)p->evaluations);
        if (pass_rate <= 0)
            continue;
        printf("gather_pass_%s_evals_per_s: %.4g\n", p->name, pass_rate);
        if (bound > 0)
            printf("gather_pass_%s_fraction_of_bound: %.3f\n", p->name, pass_rate / bound);
        if (texel > 0)
            printf("gather_pass_%s_fraction_of_texel_bound: %.3f\n", p->name, pass_rate / texel);
    }
    return rates;
}

GatherRates timings_print(Renderer *r, const char *gl_renderer, double frame_ms)
{
    const RenderSettings *rs = &r->settings;
    printf("renderer: %s\n", gl_renderer);
    gpu_timer_print(&r->timer, stdout);
    printf("frame_wall_ms: %.3f\n", frame_ms);
    const RenderStats *st = renderer_collect_stats(r);
    RenderMemory mem = renderer_gpu_memory(r);
    printf("light_memory_mib: %.3f\nframe_memory_mib: %.3f\nscene_memory_mib: %.3f\ngpu_memory_mib: %.3f\n",
           render_mib(mem.lights), render_mib(mem.frame), render_mib(mem.scene), render_mib(render_memory_total(&mem)));
    if (rs->gi == GI_NONE)
        return (GatherRates){0};
    double pixels = (double)rs->width * rs->height * renderer_ssaa(rs) * renderer_ssaa(rs); /* shaded pixels */
    printf("gathered_pixels: %u\n", st->gathered_pixels);
    const GiTechnique *row = gi_techniques[rs->gi];
    if (row->print_stats)
        row->print_stats(st, pixels, stdout);
    if (st->gpu_bytes)
        printf("gi_memory_mib: %.3f\n", render_mib(st->gpu_bytes));
    if (st->visibility_bytes) /* --gi-visibility: its maps, points and buffers (in gi_memory_mib too) */
        printf("visibility_memory_mib: %.3f\nvisibility_builds: %d\n", render_mib(st->visibility_bytes),
               st->visibility_builds);
    return print_gather_efficiency(r, st, s_probe.path);
}

bool timings_reads_twin(const RenderSettings *rs, const GatherRates *gather)
{
    return s_probe.path && gather->total > 0 && (gi_techniques[rs->gi]->flags & GI_READS_TWIN);
}

void timings_print_reads_twin(Renderer *r, const GatherRates *gather)
{
    const RenderStats *st = renderer_collect_stats(r);
    double rate = gather_rate(r, st, -1);
    if (rate <= 0)
        return;
    printf("gather_reads_only_evals_per_s: %.4g\n", rate);
    printf("gather_fraction_of_reads_only: %.3f\n", gather->total / rate);
    for (int i = 0; i < st->gather_pass_count; i++) {
        double twin = gather_rate(r, st, i);
        if (twin <= 0)
            continue;
        printf("gather_pass_%s_reads_only_evals_per_s: %.4g\n", st->gather_passes[i].name, twin);
        if (gather->pass[i] > 0)
            printf("gather_pass_%s_fraction_of_reads_only: %.3f\n", st->gather_passes[i].name, gather->pass[i] / twin);
    }
}

void timings_print_steady(const Renderer *r, double cold_ms, double steady_ms)
{
    const GpuTimer *t = &r->timer;
    printf("frame_cold_ms: %.3f\n", cold_ms);
    printf("frame_steady_ms: %.3f\n", steady_ms);
    double total = 0, gpu = 0;
    for (int i = 0; i < t->pass_count && t->frames > 0; i++) {
        double ms = (t->sync ? t->passes[i].cpu_ms : t->passes[i].gpu_ms) / t->frames;
        total += ms;
        gpu += t->passes[i].gpu_ms / t->frames;
        printf("steady_%s_ms: %.3f\n", t->passes[i].name, ms);
    }
    printf("steady_total_ms: %.3f\n", total);
    /* The passes' timer queries alone: on a GPU the wall time above adds a
     * glFinish round trip per pass, tens of microseconds of a ms frame. */
    if (t->frames > 0)
        printf("frame_steady_gpu_ms: %.3f\n", gpu);
}
