#include "renderer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cglm/cglm.h>

#include "log.h"

const char *const gi_mode_names[] = {"none",        "rsm",       "rsm-interp",      "rsm-interleaved",
                                     "vpl-all",     "vpl-clamped", "vpl-slc",       "vpl-interleaved",
                                     "vpl-metalights", NULL};

static bool is_vpl_mode(GiMode m) { return m >= GI_VPL_ALL && m <= GI_VPL_METALIGHTS; }

int renderer_rsm_size_for_vpls(const Light *l, int vpls)
{
    /* Texels that can hold a lit surface: a 2D map, half a cube for a
     * one-sided quad (one face and four half faces), a whole cube. */
    float layers = l->type == LIGHT_QUAD ? 3.f : l->type == LIGHT_POINT ? 6.f : 1.f;
    int size = (int)lrintf(sqrtf((float)vpls / layers));
    return size < 4 ? 4 : size;
}

static bool gi_create(Renderer *r, const Scene *s, const RenderSettings *rs)
{
    const GiParams *gp = &rs->gi_params;
    if (!pass_rsm_create(&r->pass_rsm) || !pass_vpl_create(&r->pass_vpl) ||
        !pass_rsm_gather_create(&r->pass_gather, gp, rs->width, rs->height) ||
        !pass_composite_create(&r->pass_composite))
        return false;
    r->rsm_maps = calloc((size_t)(s->light_count ? s->light_count : 1), sizeof(RsmMap));
    uint32_t capacity = 0, total = 0;
    for (int i = 0; i < s->light_count; i++) {
        bool cube = s->lights[i].type == LIGHT_POINT || s->lights[i].type == LIGHT_QUAD;
        int size = is_vpl_mode(rs->gi) && gp->vpl_count > 0 ? renderer_rsm_size_for_vpls(&s->lights[i], gp->vpl_count)
                                                           : gp->rsm_size;
        if (!rsm_map_create(&r->rsm_maps[i], cube, size))
            return false;
        uint32_t n = (uint32_t)size * (uint32_t)size * (cube ? 6u : 1u);
        capacity = n > capacity ? n : capacity;
        total += n;
    }
    /* VPL techniques gather every light's VPLs into one buffer. */
    vpl_buffer_create(&r->vpls, is_vpl_mode(rs->gi) ? total : capacity, (uint32_t)rs->width * (uint32_t)rs->height);
    if (is_vpl_mode(rs->gi) && !pass_vpl_shade_create(&r->pass_vpl_shade, rs->width, rs->height, total))
        return false;
    glCreateBuffers(1, &r->gi_ubo);
    glNamedBufferStorage(r->gi_ubo, sizeof(GpuGiParams), NULL, GL_DYNAMIC_STORAGE_BIT);
    glCreateTextures(GL_TEXTURE_2D, 1, &r->irradiance);
    glTextureStorage2D(r->irradiance, 1, GL_RGBA32F, rs->width, rs->height);
    glObjectLabel(GL_TEXTURE, r->irradiance, -1, "gi.irradiance");
    return true;
}

static void gi_destroy(Renderer *r)
{
    if (r->rsm_maps)
        for (int i = 0; i < r->scene->light_count; i++)
            if (r->rsm_maps[i].fbo)
                rsm_map_destroy(&r->rsm_maps[i]);
    free(r->rsm_maps);
    if (r->vpls.vpls)
        vpl_buffer_destroy(&r->vpls);
    glDeleteBuffers(1, &r->gi_ubo);
    glDeleteTextures(1, &r->irradiance);
    pass_composite_destroy(&r->pass_composite);
    if (is_vpl_mode(r->settings.gi))
        pass_vpl_shade_destroy(&r->pass_vpl_shade);
    pass_rsm_gather_destroy(&r->pass_gather);
    pass_vpl_destroy(&r->pass_vpl);
    pass_rsm_destroy(&r->pass_rsm);
}

static void gi_upload_params(Renderer *r, const Camera *cam)
{
    const GiParams *gp = &r->settings.gi_params;
    const PassRsmGather *g = &r->pass_gather;
    GpuGiParams u = {0};
    u.rsm[0] = gp->r_max;
    u.rsm[1] = (float)gp->samples;
    u.rsm[2] = gp->weighting == RSM_WEIGHT_UNBIASED ? 1.f : 0.f;
    u.rsm[3] = (float)gp->rsm_size;
    u.rsm2[0] = rsm_disk_texels(gp);
    u.rsm2[3] = gp->scale;
    u.interp[0] = (float)gp->interp_factor;
    u.interp[1] = gp->interp_normal;
    u.interp[2] = gp->interp_dist;
    u.interleave[0] = (float)gp->interleave_n;
    u.interleave[1] = (float)gp->interleave_m;
    u.interleave[2] = (float)g->sub_w;
    u.interleave[3] = (float)g->sub_h;
    glm_vec3_copy((float *)cam->position, u.camera);
    u.size[0] = r->settings.width;
    u.size[1] = r->settings.height;
    u.size[2] = g->low_w;
    u.size[3] = g->low_h;
    glNamedBufferSubData(r->gi_ubo, 0, sizeof u, &u);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_GI, r->gi_ubo);
}

/* Exhaustive gathers read the VPLs of light i from the VPL buffer. */
static void gi_prepare_light(Renderer *r, int i)
{
    if (!r->settings.gi_params.exhaustive)
        return;
    const uint32_t zero = 0;
    glNamedBufferSubData(r->vpls.counters, 0, sizeof zero, &zero);
    pass_vpl_run(&r->pass_vpl, &r->rsm_maps[i], 1, r->settings.gi_params.vpl_seed, &r->vpls);
}

/* One bounce of indirect light into r->irradiance, by the chosen technique. */
static void gi_gather(Renderer *r)
{
    const Scene *s = r->scene;
    GpuTimer *t = &r->timer;
    PassRsmGather *g = &r->pass_gather;
    bool exh = r->settings.gi_params.exhaustive;
    switch (r->settings.gi) {
    case GI_RSM:
        gpu_timer_begin(t, "rsm_gather");
        for (int i = 0; i < s->light_count; i++) {
            gi_prepare_light(r, i);
            pass_rsm_gather_run(g, GATHER_FULL, &r->rsm_maps[i], exh, i > 0, &r->gbuffer, &r->vpls, r->irradiance);
        }
        gpu_timer_end(t);
        break;
    case GI_RSM_INTERP: {
        gpu_timer_begin(t, "rsm_gather_lowres");
        for (int i = 0; i < s->light_count; i++) {
            gi_prepare_light(r, i);
            pass_rsm_gather_run(g, GATHER_LOWRES, &r->rsm_maps[i], exh, i > 0, &r->gbuffer, &r->vpls, r->irradiance);
        }
        gpu_timer_end(t);
        gpu_timer_begin(t, "rsm_interp");
        const uint32_t zero = 0;
        glNamedBufferSubData(r->vpls.counters, sizeof(uint32_t), sizeof zero, &zero);
        pass_rsm_interp_run(g, &r->gbuffer, &r->vpls, r->irradiance);
        gpu_timer_end(t);
        gpu_timer_begin(t, "rsm_gather_full");
        for (int i = 0; i < s->light_count; i++) {
            gi_prepare_light(r, i);
            pass_rsm_gather_run(g, GATHER_LIST, &r->rsm_maps[i], exh, i > 0, &r->gbuffer, &r->vpls, r->irradiance);
        }
        gpu_timer_end(t);
        break;
    }
    case GI_RSM_INTERLEAVED:
        gpu_timer_begin(t, "interleave_split");
        pass_interleave_split(g, &r->gbuffer);
        gpu_timer_end(t);
        gpu_timer_begin(t, "rsm_gather_interleaved");
        for (int i = 0; i < s->light_count; i++) {
            gi_prepare_light(r, i);
            pass_rsm_gather_run(g, GATHER_INTERLEAVED, &r->rsm_maps[i], exh, i > 0, &r->gbuffer, &r->vpls,
                                r->irradiance);
        }
        gpu_timer_end(t);
        gpu_timer_begin(t, "interleave_merge_blur");
        pass_interleave_merge(g, &r->gbuffer, r->settings.gi_params.interleave_blur, r->irradiance);
        gpu_timer_end(t);
        break;
    default:
        break;
    }
}

/* What the metalight grouping depends on: lights, camera, VPL settings. */
static uint64_t grouping_key(const Renderer *r, const Camera *cam)
{
    uint64_t h = 1469598103934665603ull;
    const unsigned char *parts[3] = {(const unsigned char *)r->scene->lights, (const unsigned char *)cam,
                                     (const unsigned char *)&r->settings.gi_params};
    size_t sizes[3] = {sizeof(Light) * (size_t)r->scene->light_count, sizeof *cam, sizeof r->settings.gi_params};
    for (int k = 0; k < 3; k++)
        for (size_t i = 0; i < sizes[k]; i++)
            h = (h ^ parts[k][i]) * 1099511628211ull;
    return h;
}

/* Many-VPL techniques: VPLs of every light, then the chosen shading. */
static void gi_vpl(Renderer *r, const Camera *cam)
{
    const Scene *s = r->scene;
    const GiParams *gp = &r->settings.gi_params;
    GpuTimer *t = &r->timer;
    PassVplShade *v = &r->pass_vpl_shade;
    VplMethod method = (VplMethod)(r->settings.gi - GI_VPL_ALL);
    uint64_t key = grouping_key(r, cam);
    /* A kept metalight grouping indexes the VPL buffer it was made from. */
    if (!pass_vpl_grouping_current(v, method, key)) {
        gpu_timer_begin(t, "vpl_generate");
        vpl_buffer_reset(&r->vpls);
        for (int i = 0; i < s->light_count; i++)
            pass_vpl_run(&r->pass_vpl, &r->rsm_maps[i], 1, gp->vpl_seed, &r->vpls);
        gpu_timer_end(t);
    }
    float range = gp->vpl_range > 0.f ? gp->vpl_range
                                      : 0.15f * glm_vec3_distance((float *)s->bounds_min, (float *)s->bounds_max);
    pass_vpl_shade_set_params(v, gp, r->settings.exposure, range);
    if (method == VPL_CLAMPED || method == VPL_SLC) {
        gpu_timer_begin(t, method == VPL_SLC ? "slc_cull" : "vpl_cull");
        pass_vpl_cull_run(v, method, &r->gbuffer, &r->vpls);
        gpu_timer_end(t);
    } else if (method == VPL_INTERLEAVED || method == VPL_METALIGHTS) {
        gpu_timer_begin(t, method == VPL_METALIGHTS ? "metalights_group" : "vpl_subsets");
        pass_vpl_subsets_run(v, method, key, gp, &r->gbuffer, &r->vpls);
        gpu_timer_end(t);
    }
    bool interleaved = method == VPL_INTERLEAVED || method == VPL_METALIGHTS;
    gpu_timer_begin(t, "vpl_shade");
    pass_vpl_shade_run(v, method, &r->gbuffer, &r->vpls,
                       interleaved && gp->interleave_blur ? r->pass_gather.merged : r->irradiance);
    gpu_timer_end(t);
    if (interleaved && gp->interleave_blur) {
        gpu_timer_begin(t, "interleave_blur");
        pass_interleave_blur(&r->pass_gather, &r->gbuffer, r->pass_gather.merged, r->irradiance);
        gpu_timer_end(t);
    }
}

/* Counts of the last frame's GI work (waits for the GPU). */
static void gi_collect_stats(Renderer *r)
{
    RenderStats *st = &r->stats;
    memset(st, 0, sizeof *st);
    if (r->settings.gi == GI_NONE)
        return;
    st->vpl_count = vpl_buffer_counter(&r->vpls, 0);
    if (is_vpl_mode(r->settings.gi)) {
        st->vpl_evaluations = pass_vpl_shade_evaluations(&r->pass_vpl_shade, &st->vpl_candidates);
        st->gathered_pixels = (uint32_t)(r->settings.width * r->settings.height);
        if (r->settings.gi == GI_VPL_SLC || r->settings.gi == GI_VPL_CLAMPED)
            st->tile_overflow = pass_vpl_cull_overflow(&r->pass_vpl_shade);
        st->metalight_regroups = r->pass_vpl_shade.regroups;
    } else if (r->settings.gi == GI_RSM_INTERP) {
        st->lowres_gathers = (uint32_t)(r->pass_gather.low_w * r->pass_gather.low_h);
        st->full_gathers = vpl_buffer_counter(&r->vpls, 1);
        st->gathered_pixels = st->lowres_gathers + st->full_gathers;
    } else {
        st->gathered_pixels = (uint32_t)(r->settings.width * r->settings.height);
    }
}

bool renderer_create(Renderer *r, const Scene *s, const RenderSettings *rs)
{
    memset(r, 0, sizeof *r);
    r->scene = s;
    r->settings = *rs;
    gpu_timer_create(&r->timer, rs->timings, rs->timing_sync);
    bool ok = gpu_scene_create(&r->gpu_scene, s) && gbuffer_create(&r->gbuffer, rs->width, rs->height) &&
              color_target_create(&r->hdr, GL_RGBA32F, rs->width, rs->height, "hdr") &&
              color_target_create(&r->ldr, GL_SRGB8_ALPHA8, rs->width, rs->height, "ldr") &&
              pass_shadow_create(&r->pass_shadow) && pass_gbuffer_create(&r->pass_gbuffer) &&
              pass_direct_create(&r->pass_direct) && pass_tonemap_create(&r->pass_tonemap);
    if (!ok)
        return false;
    int n = s->light_count > 0 ? s->light_count : 1;
    r->shadow_maps = calloc((size_t)n, sizeof(ShadowMap));
    for (int i = 0; i < s->light_count && ok; i++) {
        bool cube = s->lights[i].type == LIGHT_POINT || s->lights[i].type == LIGHT_QUAD;
        ok = shadow_map_create(&r->shadow_maps[i], cube, rs->shadow_params.map_size);
    }
    pass_direct_set_shadow(&r->pass_direct, rs->shadow, &rs->shadow_params);
    if (ok && rs->gi != GI_NONE)
        ok = gi_create(r, s, rs);
    return ok;
}

void renderer_destroy(Renderer *r)
{
    if (r->shadow_maps)
        for (int i = 0; i < r->scene->light_count; i++)
            if (r->shadow_maps[i].fbo)
                shadow_map_destroy(&r->shadow_maps[i]);
    free(r->shadow_maps);
    if (r->settings.gi != GI_NONE)
        gi_destroy(r);
    pass_tonemap_destroy(&r->pass_tonemap);
    pass_direct_destroy(&r->pass_direct);
    pass_gbuffer_destroy(&r->pass_gbuffer);
    pass_shadow_destroy(&r->pass_shadow);
    color_target_destroy(&r->ldr);
    color_target_destroy(&r->hdr);
    gbuffer_destroy(&r->gbuffer);
    gpu_scene_destroy(&r->gpu_scene);
    gpu_timer_destroy(&r->timer);
    memset(r, 0, sizeof *r);
}

void renderer_frame(Renderer *r, const Camera *cam)
{
    const Scene *s = r->scene;
    GpuTimer *t = &r->timer;

    if (r->settings.shadow != SHADOW_MODE_NONE) {
        gpu_timer_begin(t, "shadow");
        for (int i = 0; i < s->light_count; i++)
            pass_shadow_run(&r->pass_shadow, &r->shadow_maps[i], &r->gpu_scene, s, &s->lights[i]);
        gpu_timer_end(t);
    } else {
        /* No maps rendered, but the light blocks still need their frames. */
        for (int i = 0; i < s->light_count; i++) {
            ShadowMap *m = &r->shadow_maps[i];
            shadow_frame_compute(&s->lights[i], s->bounds_min, s->bounds_max, m->size, &m->frame);
            shadow_frame_to_gpu(&s->lights[i], &m->frame, m->size, &m->gpu);
        }
    }

    if (r->settings.gi != GI_NONE) {
        gpu_timer_begin(t, "rsm");
        for (int i = 0; i < s->light_count; i++)
            pass_rsm_run(&r->pass_rsm, &r->rsm_maps[i], &r->gpu_scene, s, &s->lights[i]);
        gpu_timer_end(t);
    }

    gpu_timer_begin(t, "gbuffer");
    pass_gbuffer_run(&r->pass_gbuffer, &r->gpu_scene, s, cam, &r->gbuffer);
    gpu_timer_end(t);

    gpu_timer_begin(t, "direct");
    const float black[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(r->hdr.fbo, GL_COLOR, 0, black);
    if (s->light_count == 0) {
        ShadowMap none = {0}; /* zero light colour: adds emission only */
        pass_direct_run(&r->pass_direct, &r->pass_shadow, &none, &r->gbuffer, true, &r->hdr);
    }
    for (int i = 0; i < s->light_count; i++)
        pass_direct_run(&r->pass_direct, &r->pass_shadow, &r->shadow_maps[i], &r->gbuffer, i == 0, &r->hdr);
    gpu_timer_end(t);

    if (r->settings.gi != GI_NONE) {
        gi_upload_params(r, cam);
        if (is_vpl_mode(r->settings.gi))
            gi_vpl(r, cam);
        else
            gi_gather(r);
        gpu_timer_begin(t, "composite");
        pass_composite_run(&r->pass_composite, &r->gbuffer, r->irradiance, &r->hdr);
        gpu_timer_end(t);
    }

    gpu_timer_begin(t, "tonemap");
    pass_tonemap_run(&r->pass_tonemap, &r->hdr, r->settings.exposure, &r->ldr);
    gpu_timer_end(t);

    gpu_timer_end_frame(t);
    gi_collect_stats(r);
}

bool renderer_read_hdr(Renderer *r, ImageF *out)
{
    int w = r->hdr.width, h = r->hdr.height;
    float *rgba = malloc(sizeof(float) * 4 * (size_t)w * h);
    if (!rgba || !image_alloc(out, w, h)) {
        free(rgba);
        return false;
    }
    glGetTextureImage(r->hdr.texture, 0, GL_RGBA, GL_FLOAT, (GLsizei)(sizeof(float) * 4 * (size_t)w * h), rgba);
    for (int y = 0; y < h; y++) /* GL rows are bottom-up */
        for (int x = 0; x < w; x++)
            memcpy(image_px(out, x, h - 1 - y), rgba + 4 * ((size_t)y * w + x), 3 * sizeof(float));
    free(rgba);
    return true;
}

uint8_t *renderer_read_ldr(Renderer *r)
{
    int w = r->ldr.width, h = r->ldr.height;
    uint8_t *rgba = malloc(4 * (size_t)w * h), *rgb = malloc(3 * (size_t)w * h);
    glGetTextureImage(r->ldr.texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, (GLsizei)(4 * (size_t)w * h), rgba);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            memcpy(rgb + 3 * ((size_t)(h - 1 - y) * w + x), rgba + 4 * ((size_t)y * w + x), 3);
    free(rgba);
    return rgb;
}
