#include "passes/pass_rsm.h"
#include "passes/pass_shadow.h"

#include <math.h>

#include "shader.h"
#include "targets.h"

bool pass_rsm_create(PassRsm *p)
{
    p->program = shader_program_make("rsm", "scene.vert", "rsm.frag", NULL);
    if (!p->program)
        return false;
    glCreateBuffers(1, &p->light_ubo);
    glNamedBufferStorage(p->light_ubo, sizeof(GpuLight), NULL, GL_DYNAMIC_STORAGE_BIT);
    return true;
}

void pass_rsm_destroy(PassRsm *p)
{
    glDeleteProgram(p->program);
    glDeleteBuffers(1, &p->light_ubo);
    *p = (PassRsm){0};
}

bool rsm_map_create(RsmMap *m, bool cube, int size)
{
    GLenum target = cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D;
    m->size = size;
    m->cube = cube;
    m->position = gl_texture_make(target, GL_RGBA32F, size, size, "rsm.position");
    m->normal = gl_texture_make(target, GL_RGBA16F, size, size, "rsm.normal");
    m->flux = gl_texture_make(target, GL_RGBA32F, size, size, "rsm.flux");
    m->depth = gl_texture_make(target, GL_DEPTH_COMPONENT32F, size, size, "rsm.depth");
    const GLuint src[3] = {m->position, m->normal, m->flux};
    const GLenum fmt[3] = {GL_RGBA32F, GL_RGBA16F, GL_RGBA32F};
    glGenTextures(3, m->view); /* views need names that were never bound */
    for (int i = 0; i < 3; i++) {
        glTextureView(m->view[i], GL_TEXTURE_2D_ARRAY, src[i], fmt[i], 0, 1, 0, cube ? 6 : 1);
        glTextureParameteri(m->view[i], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(m->view[i], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    glCreateFramebuffers(1, &m->fbo);
    const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glNamedFramebufferDrawBuffers(m->fbo, 3, bufs);
    for (int i = 0; i < 3; i++)
        fbo_attach(m->fbo, bufs[i], src[i], cube, 0);
    fbo_attach(m->fbo, GL_DEPTH_ATTACHMENT, m->depth, cube, 0);
    return fbo_check(m->fbo, "rsm");
}

void rsm_map_destroy(RsmMap *m)
{
    GLuint t[4] = {m->position, m->normal, m->flux, m->depth};
    glDeleteTextures(4, t);
    glDeleteTextures(3, m->view);
    glDeleteFramebuffers(1, &m->fbo);
    *m = (RsmMap){0};
}

void pass_rsm_run(PassRsm *p, RsmMap *m, const GpuScene *gs, const Scene *s, const Light *l)
{
    light_frame_bind(l, s, m->size, p->light_ubo, &m->frame, &m->gpu);
    /* Texel area on the projection plane: ortho (2r/res)², perspective at
     * distance 1: (k)² with k = 2·tan(fov/2)/res. */
    float a = m->frame.texel_k * m->frame.texel_k;
    glProgramUniform1f(p->program, 11, a);
    glUseProgram(p->program);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glViewport(0, 0, m->size, m->size);
    glBindFramebuffer(GL_FRAMEBUFFER, m->fbo);
    const GLuint src[3] = {m->position, m->normal, m->flux};
    const float zero[4] = {0, 0, 0, 0}, one = 1.f;
    for (int face = 0; face < m->frame.face_count; face++) {
        if (m->cube) {
            for (int i = 0; i < 3; i++)
                fbo_attach(m->fbo, GL_COLOR_ATTACHMENT0 + (GLenum)i, src[i], true, face);
            fbo_attach(m->fbo, GL_DEPTH_ATTACHMENT, m->depth, true, face);
        }
        for (int i = 0; i < 3; i++)
            glClearNamedFramebufferfv(m->fbo, GL_COLOR, i, zero);
        glClearNamedFramebufferfv(m->fbo, GL_DEPTH, 0, &one);
        /* The face (or spot) axis is the view's −z row. */
        const float *v = (const float *)m->frame.view[face];
        vec3 axis = {-v[2], -v[6], -v[10]};
        glProgramUniform3fv(p->program, 10, 1, axis);
        glProgramUniformMatrix4fv(p->program, LOC_VIEW_PROJ, 1, GL_FALSE, (const float *)m->frame.view_proj[face]);
        gpu_scene_draw(gs, s, p->program, DRAW_SKIP_EMITTERS);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void rsm_map_bind(const RsmMap *m, GLuint light_ubo)
{
    glNamedBufferSubData(light_ubo, 0, sizeof(GpuLight), &m->gpu);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_LIGHT, light_ubo);
    glBindTextureUnit(TEX_RSM_POSITION, m->position);
    glBindTextureUnit(TEX_RSM_NORMAL, m->normal);
    glBindTextureUnit(TEX_RSM_FLUX, m->flux);
}

void rsm_map_bind_views(const RsmMap *m)
{
    glBindTextureUnit(TEX_RSM_POSITION, m->view[0]);
    glBindTextureUnit(TEX_RSM_NORMAL, m->view[1]);
    glBindTextureUnit(TEX_RSM_FLUX, m->view[2]);
}
