#include "renderer.h"

#include <stdlib.h>
#include <string.h>

#include "log.h"

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
    return ok;
}

void renderer_destroy(Renderer *r)
{
    if (r->shadow_maps)
        for (int i = 0; i < r->scene->light_count; i++)
            if (r->shadow_maps[i].fbo)
                shadow_map_destroy(&r->shadow_maps[i]);
    free(r->shadow_maps);
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

    gpu_timer_begin(t, "tonemap");
    pass_tonemap_run(&r->pass_tonemap, &r->hdr, r->settings.exposure, &r->ldr);
    gpu_timer_end(t);

    gpu_timer_end_frame(t);
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
