/* pt_scene.h — the Scene as an Embree 3 ray-tracing scene for the
 * reference path tracer: the very same triangles, materials, albedo
 * textures and alpha masks the rasterizer draws (no copy of the scene, only
 * Embree's BVH over its vertex array).
 * Geometry 0 holds opaque triangles; geometry 1 the alpha-masked ones, with
 * a filter function that rejects hits on transparent texels. */
#ifndef RTGI_PT_SCENE_H
#define RTGI_PT_SCENE_H

#include <embree3/rtcore.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/brdf.h"
#include "core/scene.h"

/* What a hit needs of its triangle, in one 128-byte record (two cache
 * lines) in Embree's primitive order: a hit reads this and nothing of the
 * Scene's index and vertex arrays. The values are the Scene's, copied. */
typedef struct PtTri {
    float p0[3];      /* vertex 0's position */
    float e1[3], e2[3]; /* edges to vertices 1 and 2 (the very differences a hit used to compute) */
    float ng[3];      /* unit geometric normal e1 × e2 (the winding's front) */
    float n[3][3];    /* vertex normals */
    float uv[3][2];   /* vertex texture coordinates */
    uint32_t material;
    uint32_t flat;    /* 1: the three vertex normals are equal (n[0] is then unit: the shading normal everywhere) */
    uint32_t pad_[3];
} PtTri;
_Static_assert(sizeof(PtTri) == 128, "PtTri is two cache lines");

/* A primitive of the quad scene (PtScene.quads): two triangles of the
 * Scene that share an edge, as Embree's quad (v0, v1, v2, v3), which it
 * tests as the triangles (v0, v1, v3) and (v2, v3, v1), or a lone triangle
 * (v3 = v2). Their records are the triangle scene's. */
typedef struct PtQuad {
    uint32_t rec;      /* the record of the first triangle; the second's is rec + 1 */
    uint8_t rot[2];    /* per triangle: Embree's vertex k is its record's vertex (k + rot) mod 3 */
    uint8_t lone;      /* one triangle */
    uint8_t pad_;
} PtQuad;

/* A scene of at most PT_TINY_MAX triangles without alpha masks (the
 * Cornell box's 32), as structure-of-arrays (lane i: record i of
 * PtScene.tris; padded with degenerate triangles to a multiple of 8),
 * against which the paths' bounce and shadow rays (pt_trace, pt_occluded)
 * test every triangle, eight at a time (Möller & Trumbore; an AVX2 clone
 * where the CPU has it): on a scene this small Embree's call and traversal
 * cost more (Cornell 256², 64 spp: 0.90× the CPU seconds of Embree's
 * quads). Camera rays and pt_intersect stay on Embree's triangles, as
 * with the quads: a triangle's edges are not watertight here either.
 * test_reference_exact quads_hit_as_triangles checks it against Embree
 * ray by ray. */
enum { PT_TINY_MAX = 64 };
typedef struct PtTiny {
    uint32_t n;
    float p0[3][PT_TINY_MAX], e1[3][PT_TINY_MAX], e2[3][PT_TINY_MAX];
} PtTiny;

typedef struct PtScene {
    const Scene *scene;     /* borrowed */
    RTCDevice device;       /* owned */
    RTCScene rtc;           /* owned: the triangles */
    PtTri *tris;            /* per primitive of `rtc`, geometry 0's then geometry 1's (owned, 128-byte aligned) */
    uint32_t tri_base[2];   /* per geometry: index in `tris` of its primitive 0 */
    /* On a scene that fits the caches (not memory_bound), the same
     * triangles paired into quads for the paths' bounce and shadow rays
     * (pt_trace, pt_occluded): Embree tests a leaf's 8 triangles in one go,
     * and the Cornell box's rays take 35-50% less of its time. A quad's
     * diagonal is tested twice, once per triangle, with rounding of its
     * own (not watertight there, where the triangles' shared first vertex
     * is), so the camera rays, which a camera without jitter can aim
     * exactly along a diagonal pixel after pixel, and pt_intersect stay on
     * the triangles; a bounce or shadow ray meets a diagonal within an ulp
     * with probability ~0. NULL on a large scene (no gain measured on
     * Sponza) and on a small one (PtTiny serves its rays). */
    RTCScene quads;         /* owned; NULL: none */
    PtQuad *quad;           /* per primitive of `quads`, geometry 0's then geometry 1's (owned) */
    uint32_t quad_base[2];  /* per geometry: index in `quad` of its primitive 0 */
    PtTiny *tiny;           /* owned; NULL: a larger scene, or one with alpha masks */
    float diag;             /* scene bounds diagonal (m), > 0 */
    bool memory_bound;      /* the triangle records and textures hold more than PT_CACHE_BYTES */
} PtScene;

/* A ray's hit, with normals oriented toward the ray's origin. */
typedef struct PtHit {
    float t;
    vec3 p;
    vec3 ng;       /* unit geometric normal facing the ray origin */
    vec3 ns;       /* unit shading normal, same side as ng */
    float uv[2];
    int material;
    bool front;    /* hit the side the triangle's winding faces (emitters emit there) */
} PtHit;

/* Above this many bytes of triangle records and texels a hit's reads are
 * mostly cache misses (a last-level cache's share per core). */
#define PT_CACHE_BYTES ((size_t)4 << 20)

bool pt_scene_create(PtScene *ps, const Scene *s);
void pt_scene_destroy(PtScene *ps);

/* Closest hit along o + t·d, t in (0, tmax); false if none. On the
 * triangles. */
bool pt_intersect(const PtScene *ps, const vec3 o, const vec3 d, float tmax, PtHit *h);
/* pt_intersect in two halves, so that a caller tracing several paths can
 * overlap their memory reads (the triangle records and texels of a large
 * scene are cache misses): pt_trace finds the hit (Embree's answer) and
 * asks for its triangle's record ahead of pt_hit, which makes the PtHit
 * from it; pt_prefetch_surface asks for the texels pt_surface will read. */
typedef struct PtRawHit {
    float t, u, v;     /* u, v: the barycentrics of the record's vertices 1 and 2 */
    uint32_t rec;      /* the hit triangle's record in PtScene.tris */
} PtRawHit;
/* pt_trace and pt_occluded: on the quads where there are. */
bool pt_trace(const PtScene *ps, const vec3 o, const vec3 d, float tmax, PtRawHit *r);
void pt_hit(const PtScene *ps, const vec3 d, const PtRawHit *r, PtHit *h);
void pt_prefetch_surface(const PtScene *ps, const PtHit *h);
/* Closest hits of up to PT_PACKET rays from one origin o along d[i],
 * i < n, t in (0, ∞), traced together as one Embree packet (coherent rays:
 * a row of camera rays): hit[i] says whether ray i hit, and h[i] is then
 * its hit, as pt_intersect would give it (test_reference_exact checks the
 * two agree). */
enum { PT_PACKET = 16 };
void pt_intersect_packet(const PtScene *ps, const vec3 o, const vec3 *d, int n, PtHit *h, bool *hit);
/* Every hit along the ray (unordered), at most `max`; returns the count. */
int pt_intersect_all(const PtScene *ps, const vec3 o, const vec3 d, float tmax, PtHit *hits, int max);
/* true if anything blocks o + t·d for t in (0, tmax). */
bool pt_occluded(const PtScene *ps, const vec3 o, const vec3 d, float tmax);
/* Linear base colour of the hit's material (texture × factor). */
void pt_albedo(const PtScene *ps, const PtHit *h, vec3 out);
/* The BRDF parameters at the hit: base colour, metallic and roughness
 * (factors × the metallicRoughness texture's B and G), as the G-buffer
 * pass computes them. */
void pt_surface(const PtScene *ps, const PtHit *h, BrdfSurface *out);
/* Moves the hit point p off its surface along the unit geometric normal n,
 * for a ray leaving on n's side: by 256 ulps of each coordinate (Wächter &
 * Binder 2019), so that the ray cannot hit that surface again, at any
 * distance from the origin. */
void pt_offset(const vec3 p, const vec3 n, vec3 out);

#endif
