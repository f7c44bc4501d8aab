#include "frame/pass_gbuffer.h"

#include "core/camera.h"
#include "shared/gpu_types.h"
#include "gl/shader.h"

bool pass_gbuffer_create(PassGbuffer *p, ProgramCache *pc)
{
    p->program = program_cache_get(pc, &(ShaderProgramDesc){.label = "gbuffer", .vert = "frame/scene.vert", .frag = "frame/gbuffer.frag"});
    p->program_opaque = program_cache_get(pc, &(ShaderProgramDesc){.label = "gbuffer_opaque", .vert = "frame/scene.vert",
                                                                   .frag = "frame/gbuffer.frag", .defines = "#define OPAQUE_DRAW\n"});
    p->program_untextured = program_cache_get(
        pc, &(ShaderProgramDesc){.label = "gbuffer_untextured", .vert = "frame/scene.vert", .frag = "frame/gbuffer.frag",
                                 .defines = "#define OPAQUE_DRAW\n#define UNTEXTURED\n"});
    p->depth_opaque = program_cache_get(pc, &(ShaderProgramDesc){.label = "gbuffer_depth", .vert = "frame/scene.vert",
                                                                  .frag = "frame/depth.frag"});
    p->depth_masked = program_cache_get(pc, &(ShaderProgramDesc){.label = "gbuffer_depth_masked", .vert = "frame/scene.vert",
                                                                  .frag = "frame/depth.frag", .defines = "#define MASKED\n"});
    return p->program != 0 && p->program_opaque != 0 && p->program_untextured != 0 && p->depth_opaque != 0 &&
           p->depth_masked != 0;
}

void pass_gbuffer_destroy(PassGbuffer *p)
{
    *p = (PassGbuffer){0};
}

/* The view's matrix into the programs the run draws with (the pre-pass's,
 * and with `colors` the G-buffer's), the depth (and with `colors` the
 * colour targets) cleared, the state for the depth pre-pass. */
static void gbuffer_begin(PassGbuffer *p, const Camera *cam, const GBuffer *out, bool colors, mat4 vp)
{
    camera_view_proj(cam, (float)out->width / (float)out->height, vp);
    const GLuint programs[5] = {p->depth_opaque, p->depth_masked, p->program_opaque, p->program, p->program_untextured};
    for (int i = 0; i < (colors ? 5 : 2); i++) {
        glProgramUniformMatrix4fv(programs[i], LOC_VIEW_PROJ, 1, GL_FALSE, (const float *)vp);
        if (i >= 2) /* the pre-pass's programs have no eye (frame/depth.frag) */
            glProgramUniform3fv(programs[i], LOC_EYE, 1, cam->position);
    }
    const GLuint zero[4] = {0, 0, 0, 0}; /* no surface, no material */
    for (int i = 0; i < 2 && colors; i++)
        glClearNamedFramebufferuiv(out->fbo, GL_COLOR, i, zero);
    scene_raster_begin(out->fbo, out->width, out->height, GL_LESS);
}

/* Opaque materials with early depth, nearest clusters first so it rejects
 * what they hide; alpha-masked ones after, with their discard. Clusters
 * outside the view frustum are skipped. */
static void gbuffer_depth(PassGbuffer *p, const GpuScene *gs, const Scene *s, const DrawView *view)
{
    glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glColorMaski(1, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gpu_scene_draw_view(gs, s, &(DrawPrograms){p->depth_opaque, p->depth_masked, 0}, DRAW_ALL, view);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void pass_gbuffer_depth_run(PassGbuffer *p, const GpuScene *gs, const Scene *s, const Camera *cam, bool cull,
                            GBuffer *out)
{
    mat4 vp;
    gbuffer_begin(p, cam, out, false, vp);
    DrawView view = {.view_proj = (const float *)vp, .eye = cam->position, .culled = &p->culled};
    gbuffer_depth(p, gs, s, cull ? &view : NULL);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void pass_gbuffer_run(PassGbuffer *p, const GpuScene *gs, const Scene *s, const Camera *cam, bool cull, GBuffer *out)
{
    mat4 vp;
    gbuffer_begin(p, cam, out, true, vp);
    /* Depth first, then the G-buffer where the depth is the pre-pass's. */
    DrawView view = {.view_proj = (const float *)vp, .eye = cam->position, .culled = &p->culled};
    gbuffer_depth(p, gs, s, cull ? &view : NULL);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    gpu_scene_draw_view(gs, s, &(DrawPrograms){p->program_opaque, p->program, p->program_untextured}, DRAW_ALL,
                        cull ? &view : NULL);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}
