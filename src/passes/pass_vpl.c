#include "passes/pass_vpl.h"

#include "shader.h"

bool vpl_buffer_create(VplBuffer *b, uint32_t capacity, uint32_t list_capacity)
{
    b->capacity = capacity;
    b->list_capacity = list_capacity;
    glCreateBuffers(1, &b->vpls);
    glNamedBufferStorage(b->vpls, (GLsizeiptr)sizeof(GpuVpl) * (capacity ? capacity : 1), NULL, 0);
    glObjectLabel(GL_BUFFER, b->vpls, -1, "vpls");
    glCreateBuffers(1, &b->counters);
    glNamedBufferStorage(b->counters, (GLsizeiptr)sizeof(uint32_t) * (2 + list_capacity), NULL,
                         GL_DYNAMIC_STORAGE_BIT);
    glObjectLabel(GL_BUFFER, b->counters, -1, "vpl.counters");
    return true;
}

void vpl_buffer_destroy(VplBuffer *b)
{
    glDeleteBuffers(1, &b->vpls);
    glDeleteBuffers(1, &b->counters);
    *b = (VplBuffer){0};
}

void vpl_buffer_reset(VplBuffer *b)
{
    const uint32_t zero[2] = {0, 0};
    glNamedBufferSubData(b->counters, 0, sizeof zero, zero);
}

void vpl_buffer_bind(const VplBuffer *b)
{
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VPL, b->vpls);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_COUNTERS, b->counters);
}

uint32_t vpl_buffer_counter(const VplBuffer *b, int i)
{
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    uint32_t v = 0;
    glGetNamedBufferSubData(b->counters, (GLintptr)(sizeof(uint32_t) * (size_t)i), sizeof v, &v);
    return v;
}

bool pass_vpl_create(PassVpl *p)
{
    p->program = shader_compute_make("vpl_extract", "vpl_extract.comp", NULL);
    return p->program != 0;
}

void pass_vpl_destroy(PassVpl *p)
{
    glDeleteProgram(p->program);
    p->program = 0;
}

void pass_vpl_run(PassVpl *p, const RsmMap *m, int stride, unsigned seed, VplBuffer *out)
{
    rsm_map_bind_views(m);
    vpl_buffer_bind(out);
    glProgramUniform1i(p->program, 0, stride);
    glProgramUniform1ui(p->program, 1, seed);
    glUseProgram(p->program);
    GLuint n = (GLuint)((m->size + stride - 1) / stride);
    glDispatchCompute((n + 7) / 8, (n + 7) / 8, m->cube ? 6 : 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}
