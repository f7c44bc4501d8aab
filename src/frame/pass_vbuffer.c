#include "frame/pass_vbuffer.h"

#include <stdlib.h>
#include <string.h>

#include "base/log.h"
#include "base/util.h"
#include "gl/gl_resources.h"
#include "shared/gpu_types.h"

_Static_assert(sizeof(Vertex) == 8 * sizeof(float), "frame/vbuffer.glsl reads a Vertex as two vec4");
_Static_assert(GPU_CLUSTER_TRIANGLES == 1 << VBUFFER_TRIANGLE_BITS, "a visibility texel's triangle bits hold a cluster");

enum { BIN_UINTS = 6 }; /* per material: indirect dispatch (3), count, start, cursor (frame/vbuffer.glsl) */

static bool material_textured(const Material *m) { return m->albedo_tex >= 0 || m->mr_tex >= 0 || m->alpha_mask; }

bool pass_vbuffer_create(PassVbuffer *p, ProgramCache *pc, const GpuScene *gs, const Scene *s)
{
    memset(p, 0, sizeof *p);
    p->raster_opaque = program_cache_get(
        pc, &(ShaderProgramDesc){.label = "vbuffer", .vert = "frame/scene.vert", .frag = "frame/vbuffer.frag"});
    p->raster_masked =
        program_cache_get(pc, &(ShaderProgramDesc){.label = "vbuffer_masked", .vert = "frame/scene.vert",
                                                   .frag = "frame/vbuffer.frag", .defines = "#define MASKED\n"});
    p->classify = program_cache_get(pc, &(ShaderProgramDesc){.label = "vbuffer_classify", .comp = "frame/vbuffer_classify.comp"});
    p->scatter = program_cache_get(pc, &(ShaderProgramDesc){.label = "vbuffer_scatter", .comp = "frame/vbuffer_classify.comp",
                                                            .defines = "#define SCATTER\n"});
    p->bins_program = program_cache_get(pc, &(ShaderProgramDesc){.label = "vbuffer_bins", .comp = "frame/vbuffer_bins.comp"});
    p->resolve = program_cache_get(pc, &(ShaderProgramDesc){.label = "vbuffer_resolve", .comp = "frame/vbuffer_resolve.comp"});
    if (!p->raster_opaque || !p->raster_masked || !p->classify || !p->scatter || !p->bins_program || !p->resolve)
        return false; /* the cache logged it */

    int nm = s->material_count > 0 ? s->material_count : 1; /* an empty table is still a buffer */
    uint32_t *clusters = util_calloc("vbuffer", "cluster table", (size_t)gs->cluster_count + 1, 2 * sizeof(uint32_t));
    p->rows = util_calloc("vbuffer", "material table", (size_t)nm, sizeof(GpuMaterial));
    p->textured = util_calloc("vbuffer", "textured materials", (size_t)nm, sizeof(int));
    if (!clusters || !p->rows || !p->textured) {
        free(clusters);
        return false;
    }
    for (int i = 0; i < gs->cluster_count; i++) {
        clusters[2 * i] = gs->clusters[i].first_index / 3u;
        const Submesh *sm = &s->submeshes[gs->clusters[i].submesh];
        clusters[2 * i + 1] = (uint32_t)sm->material | (material_textured(&s->materials[sm->material]) ? 1u << 31 : 0u);
    }
    p->material_count = s->material_count;
    for (int m = 0; m < s->material_count; m++)
        if (material_textured(&s->materials[m]))
            p->textured[p->textured_count++] = m;
    p->clusters = gl_buffer_make(sizeof(uint32_t) * 2 * ((uint64_t)gs->cluster_count + 1), clusters, 0, "vbuffer.clusters");
    free(clusters);
    p->materials = gl_buffer_make(sizeof(GpuMaterial) * (uint64_t)nm, NULL, GL_DYNAMIC_STORAGE_BIT, "vbuffer.materials");
    p->bins = gl_buffer_make(sizeof(uint32_t) * BIN_UINTS * (uint64_t)nm, NULL, GL_DYNAMIC_STORAGE_BIT, "vbuffer.bins");
    return p->clusters && p->materials && p->bins; /* gl_buffer_make logs */
}

static void targets_free(PassVbuffer *p)
{
    glDeleteTextures(1, &p->ids);
    glDeleteFramebuffers(1, &p->fbo);
    glDeleteBuffers(1, &p->pixels);
    p->ids = p->fbo = p->pixels = p->depth = 0;
    p->width = p->height = 0;
}

void pass_vbuffer_destroy(PassVbuffer *p)
{
    targets_free(p);
    const GLuint bufs[3] = {p->clusters, p->materials, p->bins};
    glDeleteBuffers(3, bufs);
    free(p->rows);
    free(p->textured);
    memset(p, 0, sizeof *p);
}

bool pass_vbuffer_resize(PassVbuffer *p, const GBuffer *gb)
{
    if (p->fbo && p->depth == gb->depth && p->width == gb->width && p->height == gb->height)
        return true;
    targets_free(p);
    p->ids = gl_texture_make(GL_TEXTURE_2D, GL_R32UI, gb->width, gb->height, "vbuffer.ids");
    if (!p->ids || !fbo_make(&p->fbo, &p->ids, 1, gb->depth, false, "vbuffer"))
        return false;
    p->pixels = gl_buffer_make(sizeof(uint32_t) * (uint64_t)gb->width * (uint64_t)gb->height, NULL, 0, "vbuffer.pixels");
    if (!p->pixels)
        return false;
    p->depth = gb->depth;
    p->width = gb->width;
    p->height = gb->height;
    return true;
}

uint64_t pass_vbuffer_bytes(const PassVbuffer *p)
{
    const GLuint bufs[4] = {p->clusters, p->materials, p->bins, p->pixels};
    return gl_texture_bytes(p->ids) + gl_buffers_bytes(bufs, 4);
}

/* The material table as gpu_scene_bind_material sets the uniforms. */
static void upload_materials(PassVbuffer *p, const Scene *s)
{
    for (int i = 0; i < p->material_count; i++) {
        const Material *m = &s->materials[i];
        p->rows[i] = (GpuMaterial){
            .albedo = {m->albedo[0], m->albedo[1], m->albedo[2], m->albedo_tex >= 0 ? 1.f : 0.f},
            .emission = {m->emission[0], m->emission[1], m->emission[2], m->alpha_mask ? m->alpha_cutoff : -1.f},
            .pbr = {m->metallic, m->roughness, m->specular, m->mr_tex >= 0 ? 1.f : 0.f},
        };
    }
    if (p->material_count)
        glNamedBufferSubData(p->materials, 0, (GLsizeiptr)(sizeof(GpuMaterial) * (size_t)p->material_count), p->rows);
}

/* Depth and ids: the G-buffer pass's order and depth test (LEQUAL: of
 * surfaces at the same depth the last drawn is kept, as the G-buffer's
 * colour pass keeps it), in one pass. */
static void raster(PassVbuffer *p, const GpuScene *gs, const Scene *s, const Camera *cam, bool cull, mat4 vp)
{
    camera_view_proj(cam, (float)p->width / (float)p->height, vp);
    glProgramUniformMatrix4fv(p->raster_opaque, LOC_VIEW_PROJ, 1, GL_FALSE, (const float *)vp);
    glProgramUniformMatrix4fv(p->raster_masked, LOC_VIEW_PROJ, 1, GL_FALSE, (const float *)vp);
    const GLuint zero[4] = {0, 0, 0, 0}; /* no surface */
    glClearNamedFramebufferuiv(p->fbo, GL_COLOR, 0, zero);
    scene_raster_begin(p->fbo, p->width, p->height, GL_LEQUAL);
    /* Without culling: every cluster in scene order, as pass_gbuffer_run draws them. */
    DrawView view = {.view_proj = cull ? (const float *)vp : NULL, .eye = cull ? cam->position : NULL,
                     .culled = &p->culled, .draw_ids = true};
    p->culled = 0;
    gpu_scene_draw_view(gs, s, &(DrawPrograms){p->raster_opaque, p->raster_masked, 0}, DRAW_ALL, &view);
    glDepthFunc(GL_LESS);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void pass_vbuffer_run(PassVbuffer *p, const GpuScene *gs, const Scene *s, const Camera *cam, bool cull, GBuffer *out)
{
    mat4 vp;
    raster(p, gs, s, cam, cull, vp);
    upload_materials(p, s);
    const GLuint programs[4] = {p->classify, p->scatter, p->bins_program, p->resolve};
    for (int i = 0; i < 4; i++)
        glProgramUniformMatrix4fv(programs[i], LOC_VIEW_PROJ, 1, GL_FALSE, (const float *)vp);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_SCENE_VERTICES, gs->vbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_SCENE_INDICES, gs->ibo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VBUFFER_CLUSTERS, p->clusters);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VBUFFER_MATERIALS, p->materials);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VBUFFER_BINS, p->bins);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VBUFFER_PIXELS, p->pixels);
    glBindImageTexture(IMG_VBUFFER_ID, p->ids, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    glBindImageTexture(IMG_OUT, out->surface, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
    glBindImageTexture(IMG_OUT2, out->material, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
    if (p->textured_count)
        glClearNamedBufferData(p->bins, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, NULL);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);

    /* Every pixel: cleared, resolved (materials without textures) or counted. */
    glUseProgram(p->classify);
    fullscreen_dispatch(p->width, p->height);
    if (p->textured_count) {
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glUseProgram(p->bins_program);
        glDispatchCompute(1, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
        glUseProgram(p->scatter);
        fullscreen_dispatch(p->width, p->height);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        /* One dispatch per textured material, its textures bound. */
        glUseProgram(p->resolve);
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, p->bins);
        for (int i = 0; i < p->textured_count; i++) {
            int m = p->textured[i];
            const Material *mat = &s->materials[m];
            glProgramUniform1ui(p->resolve, LOC_VBUFFER_MATERIAL, (GLuint)m);
            if (mat->albedo_tex >= 0)
                glBindTextureUnit(TEX_ALBEDO, gs->textures[mat->albedo_tex]);
            if (mat->mr_tex >= 0)
                glBindTextureUnit(TEX_MATERIAL_MR, gs->textures[mat->mr_tex]);
            glDispatchComputeIndirect((GLintptr)(sizeof(uint32_t) * 4 * (size_t)m));
        }
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                        GL_TEXTURE_UPDATE_BARRIER_BIT);
    }
    glUseProgram(0);
}
