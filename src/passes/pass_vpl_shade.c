#include "passes/pass_vpl_shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_types.h"
#include "log.h"
#include "shader.h"

enum { LIST_BUDGET = 32 * 1024 * 1024 }; /* tile-list entries in all (128 MiB) */

bool pass_vpl_shade_create(PassVplShade *p, int w, int h, uint32_t vpl_capacity)
{
    memset(p, 0, sizeof *p);
    p->params_slc = shader_compute_make("vpl_params_slc", "vpl_params.comp", "#define MODE_SLC\n");
    p->params_clamped = shader_compute_make("vpl_params_clamped", "vpl_params.comp", NULL);
    p->cull = shader_compute_make("vpl_cull", "vpl_cull.comp", NULL);
    p->shade_all = shader_compute_make("vpl_shade_all", "vpl_shade.comp", "#define MODE_ALL\n");
    p->shade_tiled = shader_compute_make("vpl_shade_tiled", "vpl_shade.comp", "#define MODE_TILED\n");
    p->shade_interleaved = shader_compute_make("vpl_shade_interleaved", "vpl_shade.comp", "#define MODE_INTERLEAVED\n");
    p->signature = shader_compute_make("metalight_signature", "metalight_signature.comp", NULL);
    if (!p->params_slc || !p->params_clamped || !p->cull || !p->shade_all || !p->shade_tiled ||
        !p->shade_interleaved || !p->signature)
        return false;
    p->width = w;
    p->height = h;
    p->vpl_capacity = vpl_capacity ? vpl_capacity : 1;
    p->tiles_x = (w + VPL_TILE - 1) / VPL_TILE;
    p->tiles_y = (h + VPL_TILE - 1) / VPL_TILE;
    uint32_t ntiles = (uint32_t)(p->tiles_x * p->tiles_y);
    p->tile_capacity = LIST_BUDGET / ntiles;
    if (p->tile_capacity > p->vpl_capacity)
        p->tile_capacity = p->vpl_capacity;
    p->groups = ((w + 7) / 8) * ((h + 7) / 8);
    glCreateBuffers(1, &p->ubo);
    glNamedBufferStorage(p->ubo, sizeof(GpuVplParams), NULL, GL_DYNAMIC_STORAGE_BIT);
    glCreateBuffers(1, &p->ranges);
    glNamedBufferStorage(p->ranges, (GLsizeiptr)(sizeof(float) * 2 * p->vpl_capacity), NULL, 0);
    glCreateBuffers(1, &p->tiles);
    glNamedBufferStorage(p->tiles, (GLsizeiptr)(sizeof(uint32_t) * (ntiles + 1 + (size_t)ntiles * p->tile_capacity)),
                         NULL, GL_DYNAMIC_STORAGE_BIT);
    glCreateBuffers(1, &p->evals);
    glNamedBufferStorage(p->evals, (GLsizeiptr)(sizeof(uint32_t) * 2 * (size_t)p->groups), NULL, 0);
    glCreateBuffers(1, &p->subsets);
    size_t subset_bytes = sizeof(float) * 4 * (size_t)p->vpl_capacity + sizeof(uint32_t) * 256;
    glNamedBufferStorage(p->subsets, (GLsizeiptr)subset_bytes, NULL, GL_DYNAMIC_STORAGE_BIT);
    glObjectLabel(GL_BUFFER, p->tiles, -1, "vpl.tiles");
    return true;
}

void pass_vpl_shade_destroy(PassVplShade *p)
{
    GLuint progs[7] = {p->params_slc, p->params_clamped, p->cull, p->shade_all, p->shade_tiled, p->shade_interleaved,
                       p->signature};
    for (int i = 0; i < 7; i++)
        glDeleteProgram(progs[i]);
    GLuint bufs[5] = {p->ubo, p->ranges, p->tiles, p->evals, p->subsets};
    glDeleteBuffers(5, bufs);
    memset(p, 0, sizeof *p);
}

void pass_vpl_shade_set_params(PassVplShade *p, const GiParams *gp, float exposure, float range)
{
    GpuVplParams u;
    memset(&u, 0, sizeof u);
    u.slc[0] = gp->slc_emax;
    u.slc[1] = exposure > 0.f ? exposure : 1.f;
    u.slc[2] = gp->vpl_near_clamp;
    u.slc[3] = range;
    u.misc[0] = gp->vpl_keep;
    u.misc[1] = (float)p->tile_capacity;
    u.misc[2] = (float)(gp->interleave_n * gp->interleave_m);
    u.misc[3] = (float)p->subset_len;
    u.tiles[0] = p->tiles_x;
    u.tiles[1] = p->tiles_y;
    u.tiles[2] = gp->interleave_n;
    u.tiles[3] = gp->interleave_m;
    u.samples[0] = 16;
    u.samples[1] = 16;
    p->params = u;
    glNamedBufferSubData(p->ubo, 0, sizeof u, &u);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_VPL, p->ubo);
}

static void bind_all(const PassVplShade *p, const VplBuffer *vb)
{
    vpl_buffer_bind(vb);
    glBindBufferBase(GL_UNIFORM_BUFFER, UBO_VPL, p->ubo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_VPL_RANGE, p->ranges);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_TILES, p->tiles);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_EVALS, p->evals);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SSBO_SUBSETS, p->subsets);
}

void pass_vpl_cull_run(PassVplShade *p, VplMethod method, const GBuffer *gb, const VplBuffer *vb)
{
    bind_all(p, vb);
    glUseProgram(method == VPL_SLC ? p->params_slc : p->params_clamped);
    glDispatchCompute((p->vpl_capacity + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    uint32_t zero = 0;
    uint32_t ntiles = (uint32_t)(p->tiles_x * p->tiles_y);
    glNamedBufferSubData(p->tiles, sizeof(uint32_t) * ntiles, sizeof zero, &zero); /* overflow */
    glBindTextureUnit(TEX_GB_POSITION, gb->position);
    glUseProgram(p->cull);
    glDispatchCompute((GLuint)p->tiles_x, (GLuint)p->tiles_y, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

uint32_t pass_vpl_cull_overflow(const PassVplShade *p)
{
    uint32_t v = 0;
    uint32_t ntiles = (uint32_t)(p->tiles_x * p->tiles_y);
    glGetNamedBufferSubData(p->tiles, sizeof(uint32_t) * ntiles, sizeof v, &v);
    return v;
}

/* Interleave-bit Morton code of two 16-bit coordinates. */
static uint32_t morton2(uint32_t x, uint32_t y)
{
    uint32_t r = 0;
    for (int b = 0; b < 16; b++)
        r |= ((x >> b) & 1u) << (2 * b) | ((y >> b) & 1u) << (2 * b + 1);
    return r;
}

typedef struct SortItem {
    uint64_t key;
    uint64_t tie;   /* the VPL's position bits: fixed per texel */
    uint32_t index;
} SortItem;

static int cmp_item(const void *a, const void *b)
{
    const SortItem *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    if (x->tie != y->tie)
        return x->tie < y->tie ? -1 : 1;
    return 0;
}

bool pass_vpl_grouping_current(const PassVplShade *p, VplMethod method, uint64_t key)
{
    return method == VPL_METALIGHTS && p->regroups > 0 && key == p->grouping_key;
}

void pass_vpl_subsets_run(PassVplShade *p, VplMethod method, uint64_t key, const GiParams *gp, const GBuffer *gb,
                          const VplBuffer *vb)
{
    if (pass_vpl_grouping_current(p, method, key))
        return; /* nothing changed: keep the grouping */
    uint32_t n = vpl_buffer_counter(vb, 0);
    uint32_t K = (uint32_t)(gp->interleave_n * gp->interleave_m);
    uint32_t L = (n + K - 1) / K;
    SortItem *items = malloc(sizeof(SortItem) * (n + 1));
    /* Every VPL's own ξ (fixed by its RSM texel and the seed) orders it, so
     * the subsets do not depend on the order the GPU appended VPLs in. */
    GpuVpl *vpls = malloc(sizeof(GpuVpl) * (n + 1));
    glGetNamedBufferSubData(vb->vpls, 0, (GLsizeiptr)(sizeof(GpuVpl) * n), vpls);
    uint32_t *xi_bits = malloc(sizeof(uint32_t) * (n + 1));
    for (uint32_t i = 0; i < n; i++) {
        memcpy(&xi_bits[i], &vpls[i].position_xi[3], sizeof(uint32_t));
        uint32_t pb[3];
        memcpy(pb, vpls[i].position_xi, sizeof pb);
        items[i].tie = ((uint64_t)pb[0] << 32 | pb[1]) ^ ((uint64_t)pb[2] * 0x9e3779b97f4a7c15ull);
    }
    free(vpls);
    if (method == VPL_METALIGHTS) {
        bind_all(p, vb);
        glBindTextureUnit(TEX_GB_POSITION, gb->position);
        glBindTextureUnit(TEX_GB_NORMAL, gb->normal);
        glUseProgram(p->signature);
        glDispatchCompute((n + 63) / 64, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        float(*sig)[4] = malloc(sizeof(float) * 4 * (n + 1));
        glGetNamedBufferSubData(p->subsets, 0, (GLsizeiptr)(sizeof(float) * 4 * n), sig);
        for (uint32_t i = 0; i < n; i++) {
            bool none = !(sig[i][2] > 0.f);
            uint32_t cx = (uint32_t)(fminf(fmaxf(sig[i][0], 0.f), 1.f) * 65535.f);
            uint32_t cy = (uint32_t)(fminf(fmaxf(sig[i][1], 0.f), 1.f) * 65535.f);
            /* Metalights group VPLs that light the same part of the view:
             * ordered along a Morton curve of their contribution centroid,
             * with VPLs that light nothing last. */
            items[i].key = none ? UINT64_MAX : ((uint64_t)morton2(cx, cy) << 32 | xi_bits[i]);
            items[i].index = i;
        }
        free(sig);
        qsort(items, n, sizeof *items, cmp_item);
        p->grouping_key = key;
        p->regroups++;
    } else {
        /* Random disjoint subsets: VPLs in the order of their random ξ,
         * dealt round-robin. */
        for (uint32_t i = 0; i < n; i++) {
            items[i].key = xi_bits[i];
            items[i].index = i;
        }
        qsort(items, n, sizeof *items, cmp_item);
    }
    free(xi_bits);
    uint32_t *sub = malloc(sizeof(uint32_t) * ((size_t)K * L + 1));
    memset(sub, 0xff, sizeof(uint32_t) * (size_t)K * L);
    for (uint32_t j = 0; j < n; j++) {
        uint32_t group = j / K, member = j % K;
        uint32_t k = method == VPL_METALIGHTS ? (member + group) % K : member;
        sub[(size_t)k * L + group] = items[j].index;
    }
    glNamedBufferSubData(p->subsets, 0, (GLsizeiptr)(sizeof(uint32_t) * (size_t)K * L), sub);
    free(sub);
    free(items);
    p->subset_len = L;
    p->params.misc[3] = (float)L;
    glNamedBufferSubData(p->ubo, 0, sizeof p->params, &p->params);
}

void pass_vpl_shade_run(PassVplShade *p, VplMethod method, const GBuffer *gb, const VplBuffer *vb, GLuint out)
{
    bind_all(p, vb);
    glBindTextureUnit(TEX_GB_POSITION, gb->position);
    glBindTextureUnit(TEX_GB_NORMAL, gb->normal);
    glBindImageTexture(IMG_OUT, out, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    GLuint prog = method == VPL_ALL ? p->shade_all
                  : (method == VPL_CLAMPED || method == VPL_SLC) ? p->shade_tiled
                                                                  : p->shade_interleaved;
    glUseProgram(prog);
    glDispatchCompute((GLuint)(p->width + 7) / 8, (GLuint)(p->height + 7) / 8, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

uint64_t pass_vpl_shade_evaluations(const PassVplShade *p, uint64_t *candidates)
{
    uint32_t *e = malloc(sizeof(uint32_t) * 2 * (size_t)p->groups);
    glGetNamedBufferSubData(p->evals, 0, (GLsizeiptr)(sizeof(uint32_t) * 2 * (size_t)p->groups), e);
    uint64_t sum = 0, visits = 0;
    for (int i = 0; i < p->groups; i++) {
        sum += e[i];
        visits += e[p->groups + i];
    }
    free(e);
    if (candidates)
        *candidates = visits;
    return sum;
}
