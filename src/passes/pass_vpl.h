/* pass_vpl.h — VPL generation: every RSM texel holding a surface becomes a
 * virtual point light {position, normal, flux, fixed random ξ} in a shader
 * storage buffer (SPEC §3, §4). `stride` > 1 keeps one texel in stride² per
 * axis pair, with its flux scaled by stride² (subsampling to a VPL budget).
 * Inputs: an RsmMap. Output: VplBuffer (VPLs, counters[0] = count).
 * Owns: its program. The VplBuffer (owned by the renderer) also holds the
 * pixel list and counters of the screen-space interpolation. */
#ifndef RTGI_PASS_VPL_H
#define RTGI_PASS_VPL_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>

#include "passes/pass_rsm.h"

typedef struct VplBuffer {
    GLuint vpls;         /* GpuVpl[capacity] */
    GLuint counters;     /* uint[2 + list_capacity]: VPL count, full-gather count, pixel list */
    uint32_t capacity;
    uint32_t list_capacity;
} VplBuffer;

typedef struct PassVpl {
    GLuint program;
} PassVpl;

bool vpl_buffer_create(VplBuffer *b, uint32_t capacity, uint32_t list_capacity);
void vpl_buffer_destroy(VplBuffer *b);
/* Zeroes the counters (VPL count, full-gather count). */
void vpl_buffer_reset(VplBuffer *b);
/* Binds to SSBO_VPL and SSBO_COUNTERS. */
void vpl_buffer_bind(const VplBuffer *b);
/* Reads counter i back (waits for the GPU). */
uint32_t vpl_buffer_counter(const VplBuffer *b, int i);

bool pass_vpl_create(PassVpl *p);
void pass_vpl_destroy(PassVpl *p);
/* Appends the VPLs of `m` (counters[0] grows); their ξ come from `seed`. */
void pass_vpl_run(PassVpl *p, const RsmMap *m, int stride, unsigned seed, VplBuffer *out);

#endif
