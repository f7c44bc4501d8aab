/* sampler.c — the tables of sampler.h. */
#include "reference/sampler.h"

#include <pthread.h>

uint32_t sobol_rev_table[3][3][256];

static pthread_once_t g_once = PTHREAD_ONCE_INIT;

/* Sobol' dimensions 1, 2 and 3 (dimension 0 is van der Corput): primitive
 * polynomials x + 1, x² + x + 1 and x³ + x + 1 with Joe & Kuo's initial
 * direction numbers (new-joe-kuo-6.21201, its dimensions 2 to 4): degree s,
 * interior coefficients a, m_1…m_s. */
static const struct {
    int s;
    uint32_t a, m[3];
} g_dims[3] = {{1, 0, {1}}, {2, 1, {1, 3}}, {3, 1, {1, 3, 1}}};

static void fill_tables(void)
{
    for (int d = 0; d < 3; d++) {
        /* Direction numbers as 32-bit fractions: v_k = m_k / 2^k for k ≤ s,
         * then Bratley & Fox's recurrence. */
        int s = g_dims[d].s;
        uint32_t a = g_dims[d].a, dir[24];
        for (int k = 0; k < 24; k++) {
            if (k < s) {
                dir[k] = g_dims[d].m[k] << (31 - k);
                continue;
            }
            uint32_t v = dir[k - s] ^ (dir[k - s] >> s);
            for (int i = 1; i < s; i++)
                if (a >> (s - 1 - i) & 1u)
                    v ^= dir[k - i];
            dir[k] = v;
        }
        for (int b = 0; b < 3; b++)
            for (uint32_t x = 0; x < 256; x++) {
                uint32_t acc = 0;
                for (int k = 0; k < 8; k++)
                    if (x >> k & 1u)
                        acc ^= dir[8 * b + k];
                sobol_rev_table[d][b][x] = util_reverse_bits(acc);
            }
    }
}

void sampler_init(void)
{
    pthread_once(&g_once, fill_tables);
}
