#include "gl/gpu_budget.h"

#include <stdlib.h>

#include "base/log.h"

uint64_t gpu_budget_bytes(void)
{
    const char *env = getenv("RTGI_GPU_BUDGET_MIB");
    char *end = NULL;
    unsigned long long mib = env ? strtoull(env, &end, 10) : 0;
    if (!env || !*env || *end || mib == 0)
        mib = 4096;
    return (uint64_t)mib << 20;
}

bool gpu_budget_check(uint64_t bytes, const char *what)
{
    uint64_t budget = gpu_budget_bytes();
    if (bytes <= budget)
        return true;
    log_error("gpu", "%s needs %llu MiB of GPU memory, over the budget of %llu MiB (set RTGI_GPU_BUDGET_MIB to raise it)",
              what, (unsigned long long)(bytes >> 20), (unsigned long long)(budget >> 20));
    return false;
}
