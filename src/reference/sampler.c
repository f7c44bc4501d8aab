/* sampler.c — the tables of sampler.h. */
#include "reference/sampler.h"

#include <pthread.h>

uint32_t sobol1_rev_table[3][256];

static pthread_once_t g_once = PTHREAD_ONCE_INIT;

static void fill_tables(void)
{
    /* Direction numbers of dimension 1: v_0 = 1/2, v_k = v_{k−1} ⊕ v_{k−1}/2. */
    uint32_t dir[24], v = 1u << 31;
    for (int k = 0; k < 24; k++, v ^= v >> 1)
        dir[k] = v;
    for (int b = 0; b < 3; b++)
        for (uint32_t x = 0; x < 256; x++) {
            uint32_t acc = 0;
            for (int k = 0; k < 8; k++)
                if (x >> k & 1u)
                    acc ^= dir[8 * b + k];
            sobol1_rev_table[b][x] = util_reverse_bits(acc);
        }
}

void sampler_init(void)
{
    pthread_once(&g_once, fill_tables);
}
