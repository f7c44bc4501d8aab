#include "passes/pass_shadow.h"

#include "shader.h"
#include "targets.h"

bool pass_shadow_create(PassShadow *p)
{
    p->program = shader_program_make("shadow", "scene.vert", "shadow_depth.frag", NULL);
    if (!p->program)
        return false;
    glCreateBuffers(1, &p->light_ubo);
    glNamedBufferStorage(p->light_ubo, sizeof(GpuLight), NULL, GL_DYNAMIC_STORAGE_BIT);
    p->dummy_2d = gl_texture_make(GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, 1, 1, "shadow.dummy2d");
    p->dummy_cube = gl_texture_make(GL_TEXTURE_CUBE_MAP, GL_DEPTH_COMPONENT32F, 1, 1, "shadow.dummycube");
    return true;
}

void pass_shadow_destroy(PassShadow *p)
{
    glDeleteProgram(p->program);
    glDeleteBuffers(1, &p->light_ubo);
    GLuint t[2] = {p->dummy_2d, p->dummy_cube};
    glDeleteTextures(2, t);
    *p = (PassShadow){0};
}

bool shadow_map_create(ShadowMap *m, bool cube, int size)
{
    m->size = size;
    m->cube = cube;
    m->texture = gl_texture_make(cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, size, size,
                                 cube ? "shadow.cube" : "shadow.2d");
    glCreateFramebuffers(1, &m->fbo);
    glNamedFramebufferDrawBuffer(m->fbo, GL_NONE);
    glNamedFramebufferReadBuffer(m->fbo, GL_NONE);
    fbo_attach(m->fbo, GL_DEPTH_ATTACHMENT, m->texture, cube, 0);
    return fbo_check(m->fbo, "shadow map");
}

void shadow_map_destroy(ShadowMap *m)
{
    glDeleteTextures(1, &m->texture);
    glDeleteFramebuffers(1, &m->fbo);
    *m = (ShadowMap){0};
}

void light_frame_bind(const Light *l, const Scene *s, int size, GLuint ubo, ShadowFrame *frame, GpuLight *gpu)
{
    shadow_frame_compute(l, s->bounds_min, s->bounds_max, size, frame);
    shadow_frame_to_gpu(l, frame, size, gpu);
    glNamedBufferSubData(ubo, 0, sizeof(GpuLight), gpu);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_LIGHT, ubo);
}

void pass_shadow_run(PassShadow *p, ShadowMap *m, const GpuScene *gs, const Scene *s, const Light *l)
{
    light_frame_bind(l, s, m->size, p->light_ubo, &m->frame, &m->gpu);

    glUseProgram(p->program);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glViewport(0, 0, m->size, m->size);
    glBindFramebuffer(GL_FRAMEBUFFER, m->fbo);
    for (int face = 0; face < m->frame.face_count; face++) {
        if (m->cube)
            fbo_attach(m->fbo, GL_DEPTH_ATTACHMENT, m->texture, true, face);
        const float one = 1.f;
        glClearNamedFramebufferfv(m->fbo, GL_DEPTH, 0, &one);
        glProgramUniformMatrix4fv(p->program, LOC_VIEW_PROJ, 1, GL_FALSE, (const float *)m->frame.view_proj[face]);
        gpu_scene_draw(gs, s, p->program, DRAW_SKIP_EMITTERS);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void pass_shadow_bind(const PassShadow *p, const ShadowMap *m)
{
    glBindTextureUnit(TEX_SHADOW_2D, m->cube ? p->dummy_2d : m->texture);
    glBindTextureUnit(TEX_SHADOW_CUBE, m->cube ? m->texture : p->dummy_cube);
}
