/* gpu_budget.h — how much GPU memory the renderer may ask for, checked
 * before it allocates, so that a size the device cannot serve is a clear
 * error naming the option instead of a failed allocation (a black image
 * or a crash in the driver). The budget is RTGI_GPU_BUDGET_MIB (MiB) when
 * set, else 4096 MiB; llvmpipe takes it from system memory. */
#ifndef RTGI_GPU_BUDGET_H
#define RTGI_GPU_BUDGET_H

#include <stdbool.h>
#include <stdint.h>

uint64_t gpu_budget_bytes(void);
/* true if `bytes` fit the budget; else logs "<what> needs N MiB of GPU
 * memory, over the budget of M MiB (set RTGI_GPU_BUDGET_MIB to raise it)"
 * and returns false. */
bool gpu_budget_check(uint64_t bytes, const char *what);

#endif
