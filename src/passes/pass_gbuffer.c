#include "passes/pass_gbuffer.h"

#include "camera.h"
#include "shared/gpu_types.h"
#include "shader.h"

bool pass_gbuffer_create(PassGbuffer *p, ProgramCache *pc)
{
    p->program = program_cache_get(pc, &(ShaderProgramDesc){.label = "gbuffer", .vert = "frame/scene.vert", .frag = "frame/gbuffer.frag"});
    return p->program != 0;
}

void pass_gbuffer_destroy(PassGbuffer *p)
{
    p->program = 0;
}

void pass_gbuffer_run(PassGbuffer *p, const GpuScene *gs, const Scene *s, const Camera *cam, GBuffer *out)
{
    mat4 vp;
    camera_view_proj(cam, (float)out->width / (float)out->height, vp);
    glProgramUniformMatrix4fv(p->program, LOC_VIEW_PROJ, 1, GL_FALSE, (const float *)vp);
    glProgramUniform3fv(p->program, LOC_EYE, 1, cam->position);
    const float zero[4] = {0, 0, 0, 0}, one = 1.f;
    for (int i = 0; i < 5; i++)
        glClearNamedFramebufferfv(out->fbo, GL_COLOR, i, zero);
    glClearNamedFramebufferfv(out->fbo, GL_DEPTH, 0, &one);
    glBindFramebuffer(GL_FRAMEBUFFER, out->fbo);
    glViewport(0, 0, out->width, out->height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glUseProgram(p->program);
    gpu_scene_draw(gs, s, p->program, DRAW_ALL);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}
