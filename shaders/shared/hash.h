/* hash.h — the one 32-bit integer hash of the C code and the shaders
 * (Wellons' "lowbias32"): the VPLs' ξ (common/vpl_record.glsl), RSM
 * pattern shifts, the path tracer's per-request seeds
 * (src/reference/sampler.h) and the tests that recompute them. C includes
 * it as "shared/hash.h"; GLSL through common/math.glsl. */
#ifndef RTGI_SHARED_HASH_H
#define RTGI_SHARED_HASH_H

#ifdef GL_core_profile /* GLSL */
#define RTGI_HASH_U32 uint
#define RTGI_HASH_INLINE
#else /* C */
#include <stdint.h>
#define RTGI_HASH_U32 uint32_t
#define RTGI_HASH_INLINE static inline
#endif

RTGI_HASH_INLINE RTGI_HASH_U32 hash_u32(RTGI_HASH_U32 x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

#undef RTGI_HASH_U32
#undef RTGI_HASH_INLINE
#endif
