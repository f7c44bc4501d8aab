#include "gpu_scene.h"

#include <stddef.h>
#include <stdlib.h>

#include "shared/gpu_types.h"

bool gpu_scene_create(GpuScene *g, const Scene *s)
{
    glCreateBuffers(1, &g->vbo);
    glNamedBufferStorage(g->vbo, (GLsizeiptr)(sizeof(Vertex) * s->vertex_count), s->vertices, 0);
    glObjectLabel(GL_BUFFER, g->vbo, -1, "scene.vertices");
    glCreateBuffers(1, &g->ibo);
    glNamedBufferStorage(g->ibo, (GLsizeiptr)(sizeof(uint32_t) * s->index_count), s->indices, 0);
    glObjectLabel(GL_BUFFER, g->ibo, -1, "scene.indices");

    glCreateVertexArrays(1, &g->vao);
    glVertexArrayVertexBuffer(g->vao, 0, g->vbo, 0, sizeof(Vertex));
    glVertexArrayElementBuffer(g->vao, g->ibo);
    const GLuint offs[3] = {offsetof(Vertex, position), offsetof(Vertex, normal), offsetof(Vertex, uv)};
    const GLint comps[3] = {3, 3, 2};
    for (GLuint a = 0; a < 3; a++) {
        glEnableVertexArrayAttrib(g->vao, a);
        glVertexArrayAttribFormat(g->vao, a, comps[a], GL_FLOAT, GL_FALSE, offs[a]);
        glVertexArrayAttribBinding(g->vao, a, 0);
    }

    g->texture_count = s->texture_count;
    g->textures = calloc((size_t)s->texture_count + 1, sizeof(GLuint));
    for (int i = 0; i < s->texture_count; i++) {
        const Texture *t = &s->textures[i];
        int levels = 1;
        for (int m = t->width > t->height ? t->width : t->height; m > 1; m >>= 1)
            levels++;
        glCreateTextures(GL_TEXTURE_2D, 1, &g->textures[i]);
        glTextureStorage2D(g->textures[i], levels, t->linear ? GL_RGBA8 : GL_SRGB8_ALPHA8, t->width, t->height);
        glTextureSubImage2D(g->textures[i], 0, 0, 0, t->width, t->height, GL_RGBA, GL_UNSIGNED_BYTE, t->rgba);
        glGenerateTextureMipmap(g->textures[i]);
        glTextureParameteri(g->textures[i], GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTextureParameteri(g->textures[i], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(g->textures[i], GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTextureParameteri(g->textures[i], GL_TEXTURE_WRAP_T, GL_REPEAT);
        glObjectLabel(GL_TEXTURE, g->textures[i], -1, t->name);
    }
    return true;
}

void gpu_scene_destroy(GpuScene *g)
{
    if (g->texture_count)
        glDeleteTextures(g->texture_count, g->textures);
    free(g->textures);
    glDeleteVertexArrays(1, &g->vao);
    glDeleteBuffers(1, &g->vbo);
    glDeleteBuffers(1, &g->ibo);
    *g = (GpuScene){0};
}

void gpu_scene_draw(const GpuScene *g, const Scene *s, GLuint program, DrawFlags flags)
{
    gpu_scene_draw_split(g, s, program, program, flags);
}

void gpu_scene_draw_split(const GpuScene *g, const Scene *s, GLuint opaque, GLuint masked, DrawFlags flags)
{
    glBindVertexArray(g->vao);
    /* Opaque first (they fill depth that masked draws are then tested
     * against), masked after; one pass when both programs are the same. */
    for (int pass = 0; pass < (opaque == masked ? 1 : 2); pass++) {
        GLuint program = pass == 0 ? opaque : masked;
        glUseProgram(program);
        for (int i = 0; i < s->submesh_count; i++) {
            const Submesh *sm = &s->submeshes[i];
            const Material *m = &s->materials[sm->material];
            if ((flags & DRAW_SKIP_EMITTERS) && m->light_index >= 0)
                continue;
            if (opaque != masked && m->alpha_mask != (pass == 1))
                continue;
            glProgramUniform3fv(program, LOC_MATERIAL_ALBEDO, 1, m->albedo);
            glProgramUniform1i(program, LOC_MATERIAL_HAS_TEX, m->albedo_tex >= 0);
            glProgramUniform1f(program, LOC_MATERIAL_CUTOFF, m->alpha_mask ? m->alpha_cutoff : -1.f);
            glProgramUniform3fv(program, LOC_MATERIAL_EMISSION, 1, m->emission);
            glProgramUniform4f(program, LOC_MATERIAL_PBR, m->metallic, m->roughness, m->specular,
                               m->mr_tex >= 0 ? 1.f : 0.f);
            if (m->albedo_tex >= 0)
                glBindTextureUnit(TEX_ALBEDO, g->textures[m->albedo_tex]);
            if (m->mr_tex >= 0)
                glBindTextureUnit(TEX_MATERIAL_MR, g->textures[m->mr_tex]);
            glDrawElements(GL_TRIANGLES, (GLsizei)sm->index_count, GL_UNSIGNED_INT,
                           (const void *)(sizeof(uint32_t) * sm->first_index));
        }
    }
    glBindVertexArray(0);
}
