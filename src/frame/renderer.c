#include "frame/renderer.h"

#include "core/brdf.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <stddef.h>
#include <string.h>

#include <cglm/cglm.h>

#include "gl/gl_context.h"
#include "gl/gl_resources.h"
#include "gl/gpu_budget.h"
#include "base/log.h"
#include "shared/gpu_types.h"
#include "base/util.h"

/* ---- What each part depends on ------------------------------------------ */

static LightStageDesc light_desc(const RenderSettings *rs)
{
    const GiTechnique *t = gi_techniques[rs->gi];
    const GiParams *gp = &rs->set.gi;
    LightStageDesc d;
    memset(&d, 0, sizeof d);
    d.needs = t->needs(gp) | (rs->shadow != SHADOW_MODE_NONE ? LIGHT_NEEDS_SHADOW_MAPS : 0u);
    d.shadow_map_size = rs->set.shadow.map_size;
    d.rsm_size = gp->rsm.size;
    d.vpl_count = t->rsm_from_vpl_count ? gp->vpl.count : 0;
    d.vpl_supersample = gp->vpl.supersample;
    d.vpl_seed = gp->vpl.seed;
    d.cache = rs->cache;
    d.no_cull = rs->no_cull;
    return d;
}

/* ---- Targets (size-dependent) -------------------------------------------- */

int renderer_ssaa(const RenderSettings *rs)
{
    return rs->ssaa > 1 ? rs->ssaa : 1;
}

/* Where the shading passes write radiance. */
static ColorTarget *shading_target(Renderer *r)
{
    return renderer_ssaa(&r->settings) > 1 ? &r->hdr_ss : &r->hdr;
}

/* Forward or deferred, for frames without GI. Forward skips the G-buffer's
 * 32 bytes per pixel written and read back and its full-screen pass, but
 * shades per triangle: llvmpipe runs the shader over whole SIMD rows of
 * each small triangle's pixels where the full-screen pass keeps them full.
 * The Cornell box (36 triangles) at 800x600 with PCF: forward 24 ms,
 * deferred 35; Sponza (262K) at 1280x720 with PCSS: forward 235-252 ms,
 * deferred 191-226 (steady frames, llvmpipe). Auto: forward below one
 * triangle per 64 shading pixels. */
bool renderer_forward(const Renderer *r)
{
    const RenderSettings *rs = &r->settings;
    if (gi_techniques[rs->gi]->create || rs->shading == SHADING_DEFERRED)
        return false;
    if (rs->shading == SHADING_FORWARD)
        return true;
    double pixels = (double)rs->width * rs->height * renderer_ssaa(rs) * renderer_ssaa(rs);
    return (double)(r->scene->index_count / 3) * 64.0 < pixels;
}

/* The G-buffer pass per device class, for GBUFFER_AUTO (measured with
 * scripts/gbuffer-ab.sh; docs/performance.md). A software rasterizer
 * (llvmpipe): the visibility buffer draws the triangles once with no
 * material work where the raster pass draws them twice, and pays a compute
 * resolve per pixel instead, so it wins where triangles are many per pixel
 * (Sponza's nave, 262K triangles, at 640×360: G-buffer wall time 0.4-0.7×,
 * frame CPU time 0.78×) and loses where they are few (1920×1080: 1.2×;
 * the Cornell box at 256²: 2-10×, frame CPU 1.5×); 1280×720 is about even
 * (wall 0.6-1.0×, CPU 1.08×): visibility from one triangle per 2 shading
 * pixels.
 * A GPU: raster, unmeasured (no GPU was lent; scripts/gpu-check.sh
 * measures both). */
bool renderer_gbuffer_visibility(const Renderer *r)
{
    const RenderSettings *rs = &r->settings;
    if (rs->gbuffer != GBUFFER_AUTO)
        return rs->gbuffer == GBUFFER_VISIBILITY;
    if (!r->software)
        return false;
    double pixels = (double)rs->width * rs->height * renderer_ssaa(rs) * renderer_ssaa(rs);
    return (double)(r->scene->index_count / 3) * 2.0 >= pixels;
}

/* The visibility buffer's pass and targets while it is in use, sized
 * with the G-buffer; freed when it is not. */
static bool vbuffer_prepare(Renderer *r)
{
    if (!renderer_gbuffer_visibility(r)) {
        if (r->vbuffer_made)
            pass_vbuffer_destroy(&r->pass_vbuffer);
        r->vbuffer_made = false;
        return true;
    }
    if (!r->vbuffer_made) {
        r->vbuffer_made = true; /* destroyed as made, even half-way */
        if (!pass_vbuffer_create(&r->pass_vbuffer, &r->programs, &r->gpu_scene, r->scene))
            return false;
    }
    return pass_vbuffer_resize(&r->pass_vbuffer, &r->gbuffer);
}

static void targets_destroy(Renderer *r)
{
    gbuffer_destroy(&r->gbuffer);
    color_target_destroy(&r->hdr);
    color_target_destroy(&r->hdr_ss); /* a half-made one too (its texture without its framebuffer) */
    color_target_destroy(&r->ldr);
    glDeleteFramebuffers(1, &r->forward_fbo);
    glDeleteFramebuffers(1, &r->forward_display_fbo);
    glDeleteFramebuffers(1, &r->forward_ldr_fbo);
    r->forward_fbo = r->forward_display_fbo = r->forward_ldr_fbo = 0;
    color_target_destroy(&r->ldr_pre);
    GLuint t[2] = {r->irradiance, r->specular};
    glDeleteTextures(2, t);
    r->irradiance = r->specular = 0;
}

/* The tone-mapped image before FXAA, at the output size, with FXAA only. */
static bool fxaa_target_make(Renderer *r)
{
    if (r->ldr_pre.fbo)
        color_target_destroy(&r->ldr_pre);
    if (r->settings.aa != AA_FXAA)
        return true;
    return display_target_create(&r->ldr_pre, r->settings.width, r->settings.height, "ldr.pre_fxaa");
}

/* GPU bytes per shading pixel, rounded up: G-buffer (36), HDR/LDR (20), the
 * GI images (32) and a technique's own images (at most about 90). */
enum { BYTES_PER_PIXEL = 200 };

/* The shading targets at N× the output size (w, h), the resolved radiance
 * and the final image at the output size, the pre-FXAA image with FXAA. */
static bool targets_create(Renderer *r, int w, int h)
{
    const RenderSettings *rs = &r->settings;
    int n = renderer_ssaa(rs), sw = w * n, sh = h * n;
    char what[96];
    if (n > 1)
        snprintf(what, sizeof what, "--size %dx%d with --ssaa %d", w, h, n);
    else
        snprintf(what, sizeof what, "--size %dx%d", w, h);
    if (!gpu_budget_check((uint64_t)sw * (uint64_t)sh * BYTES_PER_PIXEL, what))
        return false;
    if (!gbuffer_create(&r->gbuffer, sw, sh) || !color_target_create(&r->hdr, GL_RGBA32F, w, h, "hdr") ||
        !display_target_create(&r->ldr, w, h, "ldr"))
        return false;
    if (n > 1 && !color_target_create(&r->hdr_ss, GL_RGBA32F, sw, sh, "hdr.supersampled"))
        return false;
    if (!fxaa_target_make(r))
        return false;
    /* Forward shading's: the radiance target with the G-buffer's depth. */
    if (!fbo_make(&r->forward_fbo, &shading_target(r)->texture, 1, r->gbuffer.depth, false, "forward"))
        return false;
    if (n == 1) {
        const GLuint display[2] = {r->hdr.texture, r->ldr.texture};
        if (!fbo_make(&r->forward_display_fbo, display, 2, r->gbuffer.depth, false, "forward.display") ||
            !fbo_make(&r->forward_ldr_fbo, &r->ldr.texture, 1, r->gbuffer.depth, false, "forward.display_only"))
            return false;
        /* display only: nothing at location 0, the final image at 1 */
        const GLenum bufs[2] = {GL_NONE, GL_COLOR_ATTACHMENT0};
        glNamedFramebufferDrawBuffers(r->forward_ldr_fbo, 2, bufs);
    }
    r->irradiance = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, sw, sh, "gi.irradiance");
    r->specular = gl_texture_make(GL_TEXTURE_2D, GL_RGBA32F, sw, sh, "gi.specular");
    return r->irradiance && r->specular;
}

/* ---- The technique -------------------------------------------------------- */

static void technique_destroy(Renderer *r)
{
    if (r->gi && r->gi->destroy && r->gi_state)
        r->gi->destroy(r->gi_state);
    r->gi_state = NULL;
    r->gi = NULL;
}

static bool technique_create(Renderer *r)
{
    const RenderSettings *rs = &r->settings;
    r->gi = gi_techniques[rs->gi];
    r->gi_failed = false;
    if (rs->set.gi.visibility.on && !(r->gi->flags & GI_VISIBILITY))
        log_warn("gi", "--gi-visibility on: %s does not test the bounce's visibility (rsm and the vpl techniques do); "
                       "ignored",
                 r->gi->name);
    if (!r->gi->create)
        return true;
    int n = renderer_ssaa(rs);
    GiCreateInfo ci = {.scene = r->scene,
                       .params = &rs->set.gi,
                       .lights = &r->lights,
                       .programs = &r->programs,
                       .width = rs->width * n,
                       .height = rs->height * n,
                       .geometry_version = r->gpu_scene.version,
                       .software = r->software};
    r->gi_state = r->gi->create(&ci);
    return r->gi_state != NULL;
}

/* The BRDF's directional albedo table (brdf_albedo_table) as a texture
 * (x = n·v, y = perceptual roughness; linear filtering between the entries,
 * as brdf_specular_albedo interpolates in C). */
static GLuint brdf_albedo_texture_make(void)
{
    GLuint t = gl_texture_make(GL_TEXTURE_2D, GL_RG32F, BRDF_ALBEDO_N, BRDF_ALBEDO_N, "brdf.albedo");
    if (!t)
        return 0;
    glTextureSubImage2D(t, 0, 0, 0, BRDF_ALBEDO_N, BRDF_ALBEDO_N, GL_RG, GL_FLOAT, brdf_albedo_table());
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    return t;
}

/* ---- Lifetime ------------------------------------------------------------- */

bool renderer_create(Renderer *r, const Scene *s, const RenderSettings *rs)
{
    memset(r, 0, sizeof *r);
    r->scene = s;
    r->settings = *rs;
    r->radiance_kept = true; /* (nothing drawn yet: hdr as created) */
    r->software = gl_renderer_is_software((const char *)glGetString(GL_RENDERER));
    gpu_timer_create(&r->timer, rs->timings, rs->timing_sync);
    program_cache_create(&r->programs);
    LightStageDesc ld = light_desc(rs);
    ProgramCache *pc = &r->programs;
    if (!gpu_scene_create(&r->gpu_scene, s) || !light_stage_create(&r->lights, s, &ld, pc) ||
        !targets_create(r, rs->width, rs->height) || !pass_gbuffer_create(&r->pass_gbuffer, pc) ||
        !pass_direct_create(&r->pass_direct, pc) || !pass_shade_create(&r->pass_shade, pc) ||
        !pass_finish_create(&r->pass_finish, pc) || !pass_fxaa_create(&r->pass_fxaa, pc))
        return false;
    r->frame_ubo = gi_ubo_make(sizeof(GpuFrame), "frame");
    r->brdf_albedo = brdf_albedo_texture_make();
    if (!r->frame_ubo || !r->brdf_albedo) /* each logs its failure */
        return false;
    pass_direct_set_shadow(&r->pass_direct, rs->shadow, &rs->set.shadow);
    pass_temporal_create(&r->pass_temporal, pc);
    return vbuffer_prepare(r) && technique_create(r);
}

void renderer_destroy(Renderer *r)
{
    technique_destroy(r);
    pass_temporal_destroy(&r->pass_temporal);
    pass_fxaa_destroy(&r->pass_fxaa);
    pass_finish_destroy(&r->pass_finish);
    pass_shade_destroy(&r->pass_shade);
    pass_direct_destroy(&r->pass_direct);
    pass_gbuffer_destroy(&r->pass_gbuffer);
    if (r->vbuffer_made)
        pass_vbuffer_destroy(&r->pass_vbuffer);
    glDeleteBuffers(1, &r->frame_ubo);
    glDeleteTextures(1, &r->brdf_albedo);
    targets_destroy(r);
    light_stage_destroy(&r->lights);
    gpu_scene_destroy(&r->gpu_scene);
    program_cache_destroy(&r->programs);
    gpu_timer_destroy(&r->timer);
    memset(r, 0, sizeof *r);
}

/* What renderer_apply does; redo: the last apply failed part-way, so the
 * targets and the technique are made again whatever changed (the light
 * products know themselves whether they were made; a technique made again
 * is made at the new size, so it needs no resize). */
static bool apply(Renderer *r, const RenderSettings *rs, bool redo)
{
    RenderSettings old = r->settings;
    r->settings = *rs;
    bool resized =
        redo || rs->width != old.width || rs->height != old.height || renderer_ssaa(rs) != renderer_ssaa(&old);
    bool shading_resized = rs->width * renderer_ssaa(rs) != old.width * renderer_ssaa(&old) ||
                           rs->height * renderer_ssaa(rs) != old.height * renderer_ssaa(&old);
    /* The frame family (indirect scale, temporal accumulation) is the
     * renderer's, not the technique's: the families before it are. */
    bool technique =
        redo || rs->gi != old.gi || memcmp(&rs->set.gi, &old.set.gi, offsetof(GiParams, frame)) != 0;
    LightStageDesc ld = light_desc(rs);
    bool lights = !r->lights.made || memcmp(&ld, &r->lights.desc, sizeof ld) != 0;
    bool timer = rs->timings != old.timings || rs->timing_sync != old.timing_sync;
    if (technique || lights || resized || timer || rs->aa != old.aa)
        r->remakes++;
    if (technique || lights) {
        technique_destroy(r); /* it may hold sizes of the old light products */
        gpu_timer_forget_once(&r->timer); /* its one-time passes (vct_voxelize) */
    }
    if (technique || lights || resized || rs->set.gi.frame.temporal != old.set.gi.frame.temporal ||
        rs->set.gi.frame.temporal_clamp != old.set.gi.frame.temporal_clamp)
        pass_temporal_reset(&r->pass_temporal); /* its history is of other frames */
    if (timer) {
        gpu_timer_destroy(&r->timer);
        gpu_timer_create(&r->timer, rs->timings, rs->timing_sync);
    }
    if (lights && !light_stage_configure(&r->lights, &ld))
        return false;
    if (redo || rs->shadow != old.shadow || memcmp(&rs->set.shadow, &old.set.shadow, sizeof rs->set.shadow))
        pass_direct_set_shadow(&r->pass_direct, rs->shadow, &rs->set.shadow);
    if (resized) {
        targets_destroy(r);
        if (!targets_create(r, rs->width, rs->height))
            return false;
        int n = renderer_ssaa(rs);
        if (shading_resized && r->gi_state && r->gi->resize &&
            !r->gi->resize(r->gi_state, rs->width * n, rs->height * n))
            return false;
    } else if (rs->aa != old.aa && !fxaa_target_make(r)) {
        return false;
    }
    if (!vbuffer_prepare(r))
        return false;
    if (!r->gi)
        return technique_create(r);
    return true;
}

bool renderer_apply(Renderer *r, const RenderSettings *rs)
{
    r->apply_failed = !apply(r, rs, r->apply_failed);
    return !r->apply_failed;
}

/* ---- The frame ------------------------------------------------------------ */

static void upload_frame(Renderer *r, const Camera *cam)
{
    GpuFrame f;
    memset(&f, 0, sizeof f);
    glm_vec3_copy((float *)cam->position, f.camera);
    f.width = r->settings.width * renderer_ssaa(&r->settings); /* the shading size */
    f.height = r->settings.height * renderer_ssaa(&r->settings);
    f.indirect_scale = r->settings.set.gi.frame.indirect_scale;
    f.exposure = r->settings.exposure;
    glNamedBufferSubData(r->frame_ubo, 0, sizeof f, &f);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_FRAME, r->frame_ubo);
}

void renderer_warm_up(Renderer *r, const Camera *cam, int frames)
{
    for (int f = 0; f < frames; f++)
        renderer_frame(r, cam);
    if (!r->timer.exact)
        return;
    /* Counted from here: the first frame compiles the programs, seconds of
     * CPU work with the GPU idle. */
    glFinish();
    double t0 = util_seconds();
    for (int f = frames; f < 10000 && util_seconds() - t0 < RENDERER_WARMUP_S; f++)
        renderer_frame(r, cam);
}

void renderer_frame(Renderer *r, const Camera *cam)
{
    GpuTimer *t = &r->timer;
    ColorTarget *radiance = shading_target(r);
    int n = renderer_ssaa(&r->settings);
    upload_frame(r, cam);

    light_stage_run(&r->lights, &r->gpu_scene, t);

    bool cull = !r->settings.no_cull;
    bool fxaa = r->settings.aa == AA_FXAA;
    ColorTarget *display = fxaa ? &r->ldr_pre : &r->ldr; /* where the tone map writes */
    /* Whether the shading wrote the display image as it shaded: a forward
     * frame of one light with nothing between its shading and the final
     * image (pass_direct_forward's display), or the deferred shading's last
     * dispatch where no resolve follows. */
    bool tonemapped = false, display_only = false;
    if (renderer_forward(r)) {
        tonemapped = n == 1 && !fxaa && r->lights.light_count <= 1;
        display_only = tonemapped && r->settings.display_only;
        gpu_timer_begin(t, "depth");
        pass_gbuffer_depth_run(&r->pass_gbuffer, &r->gpu_scene, r->scene, cam, cull, &r->gbuffer);
        gpu_timer_end(t);
        gpu_timer_begin(t, "direct");
        pass_direct_forward(&r->pass_direct, &r->lights, &r->gpu_scene, cam, cull,
                            display_only ? r->forward_ldr_fbo
                            : tonemapped ? r->forward_display_fbo
                                         : r->forward_fbo,
                            tonemapped, radiance->width,
                            radiance->height);
        gpu_timer_end(t);
    } else {
        gpu_timer_begin(t, "gbuffer");
        if (r->vbuffer_made) {
            pass_vbuffer_run(&r->pass_vbuffer, &r->gpu_scene, r->scene, cam, cull, &r->gbuffer);
            r->pass_gbuffer.culled = r->pass_vbuffer.culled; /* the G-buffer's count, whichever pass drew it */
        } else
            pass_gbuffer_run(&r->pass_gbuffer, &r->gpu_scene, r->scene, cam, cull, &r->gbuffer);
        gpu_timer_end(t);
        /* The technique reads the G-buffer and the light products, never
         * the direct radiance: it runs first, so that one shading pass
         * adds the direct light and its result and tone-maps. */
        ShadeGi gi = {0};
        if (r->gi_state) {
            GiFrame f = {
                .scene = r->scene,
                .gpu_scene = &r->gpu_scene,
                .camera = cam,
                .params = &r->settings.set.gi,
                .exposure = r->settings.exposure,
                .gbuffer = &r->gbuffer,
                .lights = &r->lights,
                .timer = t,
                .irradiance = r->irradiance,
                .specular = r->specular,
                .brdf_albedo = r->brdf_albedo,
            };
            if (!r->gi->run(r->gi_state, &f))
                r->gi_failed = true;
            r->last_frame = f;
            GLuint irradiance = r->irradiance;
            if (r->settings.set.gi.frame.temporal) {
                gpu_timer_begin(t, "temporal");
                GLuint accumulated = pass_temporal_run(&r->pass_temporal, &r->gbuffer, r->irradiance, cam,
                                                         r->settings.set.gi.frame.temporal_clamp);
                gpu_timer_end(t);
                if (accumulated)
                    irradiance = accumulated;
                else
                    r->gi_failed = true; /* logged; the frame goes on without it */
            }
            gi = (ShadeGi){irradiance, (r->gi->flags & GI_HAS_SPECULAR) ? r->specular : 0, r->brdf_albedo};
        }
        tonemapped = n == 1;
        gpu_timer_begin(t, "shade");
        pass_shade_run(&r->pass_shade, &r->pass_direct, &r->lights, &r->gbuffer, &gi, radiance,
                       tonemapped ? display : NULL);
        gpu_timer_end(t);
    }

    r->radiance_kept = !display_only;
    if (!tonemapped) {
        gpu_timer_begin(t, n > 1 ? "resolve" : "tonemap");
        pass_finish_run(&r->pass_finish, radiance, n, &r->hdr, display);
        gpu_timer_end(t);
    }

    if (fxaa) {
        gpu_timer_begin(t, "fxaa");
        pass_fxaa_run(&r->pass_fxaa, &r->ldr_pre, &r->ldr);
        gpu_timer_end(t);
    }

    gpu_timer_end_frame(t);
}

void renderer_invalidate(Renderer *r) { light_stage_invalidate(&r->lights); }

bool renderer_scene_changed(Renderer *r, const SceneChange *c)
{
    if (c->what & SCENE_CHANGED_GEOMETRY)
        gpu_scene_update_vertices(&r->gpu_scene, r->scene, c->first_vertex, c->vertex_count);
    bool kinds = light_stage_kind_changed(&r->lights);
    if (!kinds && !(c->what & SCENE_CHANGED_BOUNDS))
        return true;
    /* A light's maps change kind (cube or 2D), or the grids fitted to the
     * scene's bounds must follow them: the technique (and the light
     * products) are made again, as a settings change would. */
    r->remakes++;
    technique_destroy(r);
    gpu_timer_forget_once(&r->timer);
    pass_temporal_reset(&r->pass_temporal);
    if (kinds) {
        LightStageDesc d = r->lights.desc;
        r->lights.made = false; /* light_stage_configure makes them all again */
        if (!light_stage_configure(&r->lights, &d)) {
            r->apply_failed = true;
            return false;
        }
    }
    if (!technique_create(r)) {
        r->apply_failed = true;
        return false;
    }
    return true;
}

const RenderStats *renderer_collect_stats(Renderer *r)
{
    memset(&r->stats, 0, sizeof r->stats);
    if (r->gi_state && r->gi->stats)
        r->gi->stats(r->gi_state, &r->last_frame, &r->stats);
    return &r->stats;
}

double renderer_gather_ms(const Renderer *r, const RenderStats *st, int pass, bool fastest)
{
    const GpuTimer *t = &r->timer;
    double ms = 0;
    for (int i = 0; i < st->gather_pass_count; i++) {
        if (pass >= 0 && i != pass)
            continue;
        const char *name = st->gather_passes[i].name;
        bool wall = gpu_timer_rates_use_wall(t);
        double m = fastest ? gpu_timer_min_ms(t, name, wall) : gpu_timer_mean_ms(t, name, wall);
        ms += m > 0 ? m : 0;
    }
    return ms;
}

RenderMemory renderer_gpu_memory(const Renderer *r)
{
    const GLuint tex[10] = {r->gbuffer.surface, r->gbuffer.material, r->gbuffer.depth, r->hdr.texture,
                            r->hdr_ss.texture,  r->ldr.texture,      r->ldr_pre.texture, r->irradiance,
                            r->specular,        r->brdf_albedo};
    const GLuint bufs[2] = {r->frame_ubo, r->pass_direct.shadow_ubo};
    return (RenderMemory){
        .gi = r->stats.gpu_bytes,
        .lights = light_stage_gpu_bytes(&r->lights),
        .frame = gl_textures_bytes(tex, 10) + gl_buffers_bytes(bufs, 2) + pass_temporal_bytes(&r->pass_temporal) +
                 (r->vbuffer_made ? pass_vbuffer_bytes(&r->pass_vbuffer) : 0),
        .scene = gpu_scene_bytes(&r->gpu_scene),
    };
}

uint64_t render_memory_total(const RenderMemory *m) { return m->gi + m->lights + m->frame + m->scene; }

bool renderer_frames_whole(const Renderer *r)
{
    return program_cache_failed(&r->programs) == 0 && !r->gi_failed;
}

/* Texture `tex`'s level 0 (w×h, RGBA) into `out`, rows flipped to row 0 =
 * top: its RGB, or (ao) its alpha in all three channels. Read in bands of
 * rows, so that a band's byte count fits glGetTextureSubImage's GLsizei
 * whatever the size (16 bytes a pixel pass 2^31 at 11586²) and the staging
 * buffer stays small. false after logging. */
static bool read_texture(GLuint tex, int w, int h, bool alpha, ImageF *out)
{
    if (!image_alloc(out, w, h)) /* logs */
        return false;
    int band = (int)((64u << 20) / (16u * (unsigned)w));
    band = band < 1 ? 1 : band > h ? h : band;
    float *rgba = malloc(sizeof(float) * 4 * (size_t)w * (size_t)band);
    if (!rgba) {
        log_error("render", "out of memory reading back a %dx%d image", w, h);
        image_free(out);
        return false;
    }
    for (int y0 = 0; y0 < h; y0 += band) {
        int rows = h - y0 < band ? h - y0 : band;
        glGetTextureSubImage(tex, 0, 0, y0, 0, w, rows, 1, GL_RGBA, GL_FLOAT,
                             (GLsizei)(sizeof(float) * 4 * (size_t)w * (size_t)rows), rgba);
        for (int y = 0; y < rows; y++) /* GL rows are bottom-up */
            for (int x = 0; x < w; x++) {
                const float *src = rgba + 4 * ((size_t)y * w + x);
                float *dst = image_px(out, x, h - 1 - (y0 + y));
                if (alpha)
                    dst[0] = dst[1] = dst[2] = src[3];
                else
                    memcpy(dst, src, 3 * sizeof(float));
            }
    }
    free(rgba);
    return true;
}

bool renderer_read_hdr(Renderer *r, ImageF *out)
{
    if (!r->radiance_kept) {
        log_error("render", "the last frame kept no radiance (a display-only frame): nothing to read back");
        return false;
    }
    return read_texture(r->hdr.texture, r->hdr.width, r->hdr.height, false, out);
}

bool renderer_read_gi_alpha(Renderer *r, ImageF *out)
{
    int w = 0, h = 0;
    glGetTextureLevelParameteriv(r->irradiance, 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(r->irradiance, 0, GL_TEXTURE_HEIGHT, &h);
    return read_texture(r->irradiance, w, h, true, out);
}

/* The final image as GL holds it (RGBA, rows bottom-up); caller frees.
 * NULL after logging if memory runs out. */
static uint8_t *ldr_rgba(Renderer *r)
{
    int w = r->ldr.width, h = r->ldr.height;
    uint8_t *rgba = malloc(4 * (size_t)w * h);
    if (!rgba) {
        log_error("render", "out of memory reading back a %dx%d image", w, h);
        return NULL;
    }
    glGetTextureImage(r->ldr.texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, (GLsizei)(4 * (size_t)w * h), rgba);
    return rgba;
}

bool renderer_count_nonfinite(Renderer *r, size_t *count, int *x, int *y)
{
    *x = *y = 0;
    *count = 0;
    if (!r->radiance_kept) {
        /* The forward draw wrote alpha 0 where the radiance is not finite. */
        int w = r->ldr.width, h = r->ldr.height;
        uint8_t *rgba = ldr_rgba(r);
        if (!rgba)
            return false;
        for (int row = h - 1; row >= 0; row--) /* GL rows are bottom-up: the first from the top */
            for (int col = 0; col < w; col++)
                if (rgba[4 * ((size_t)row * w + col) + 3] == 0 && (*count)++ == 0) {
                    *x = col;
                    *y = h - 1 - row;
                }
        free(rgba);
        return true;
    }
    ImageF hdr;
    if (!renderer_read_hdr(r, &hdr))
        return false;
    *count = image_count_nonfinite(&hdr, x, y);
    image_free(&hdr);
    return true;
}

uint8_t *renderer_read_ldr(Renderer *r)
{
    int w = r->ldr.width, h = r->ldr.height;
    uint8_t *rgba = ldr_rgba(r), *rgb = rgba ? malloc(3 * (size_t)w * h) : NULL;
    if (!rgb) {
        if (rgba)
            log_error("render", "out of memory reading back a %dx%d image", w, h);
        free(rgba);
        return NULL;
    }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            memcpy(rgb + 3 * ((size_t)(h - 1 - y) * w + x), rgba + 4 * ((size_t)y * w + x), 3);
    free(rgba);
    return rgb;
}
