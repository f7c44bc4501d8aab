// vpl_record.glsl — reading and writing one GpuVpl (shared/gpu_types.h).
// The shading loops read a VPL through vpl_position, vpl_shading_normal
// and its flux: the record's first two vec4s, two loads per VPL (on
// llvmpipe each is a per-lane load inside a loop, and a third, the
// unpacked normal, had cost vpl-slc a fifth of its pass). The unpacked
// normal and ξ (normal_xi) serve culling, ranges and injection.
#ifndef VPL_RECORD_GLSL
#define VPL_RECORD_GLSL

#include "common/math.glsl"
#include "common/packing.glsl"

vec3 vpl_position(GpuVpl v) { return uintBitsToFloat(v.surface.xyz); }

// The lit side's normal from its 16-bit octahedral code: the very value
// vpl_make stored in normal_xi.xyz when it was made from that code.
vec3 vpl_shading_normal(GpuVpl v) { return unpack_oct16(v.surface.w); }

vec3 vpl_normal(GpuVpl v) { return v.normal_xi.xyz; }

float vpl_xi(GpuVpl v) { return v.normal_xi.w; }

// ξ as light/vpl_extract.comp draws it: a hash of the record's surface words
// (position bits and normal code, which tell VPLs apart whatever order the
// GPU appended them in) and the buffer's seed (counters[1]). The SLC loop
// recomputes it, integer arithmetic for all lanes at once, rather than load
// normal_xi per candidate (vpl-slc 256², one thread: 705 -> 584 ms).
float vpl_xi_of(uvec4 surface, uint seed)
{
    uint h = hash_u32(surface.x ^ hash_u32(surface.y ^ hash_u32(surface.z ^ hash_u32(surface.w ^ seed))));
    return (float(h >> 8) + 1.0) / 16777216.0; // (0, 1]
}

// A VPL at position p with the normal of octahedral code `oct`
// (pack_oct16; an RSM texel's z word as it is), flux Φ for area A.
GpuVpl vpl_make(vec3 p, float xi, uint oct, vec3 flux, float area)
{
    return GpuVpl(uvec4(floatBitsToUint(p), oct), vec4(flux, area), vec4(unpack_oct16(oct), xi));
}

#endif
