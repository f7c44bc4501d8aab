/* gl_resources.h — GL objects the volume techniques need (light propagation
 * volumes, voxel cone tracing): 3D textures with mip chains bound as images,
 * framebuffers without attachments, and a live-object census for tests.
 *
 * Names are plain GLuints like the rest of rtgi; each make has its destroy,
 * every object is labelled for debuggers, and a make that fails logs one
 * line and returns 0. All need a current GL 4.5 context. */
#ifndef RTGI_GL_RESOURCES_H
#define RTGI_GL_RESOURCES_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>

/* --- 3D textures -------------------------------------------------------- */

typedef enum TexFilter {
    TEX_FILTER_NEAREST, /* NEAREST, NEAREST_MIPMAP_NEAREST */
    TEX_FILTER_LINEAR,  /* LINEAR, LINEAR_MIPMAP_LINEAR (trilinear across mips) */
} TexFilter;

/* Levels of a full mip chain for a w×h×d texture: 1 + floor(log2(max)). */
int gl_mip_levels(int width, int height, int depth);

/* An immutable 3D texture of `levels` mips (0: the full chain) in sized
 * `format` (e.g. GL_RGBA16F), clamped to a transparent black border on all
 * three axes, so samples outside the volume read 0. Contents undefined.
 * Returns 0 after logging if the size, levels or format are not supported.
 * Caller frees with gl_texture3d_destroy. */
GLuint gl_texture3d_make(GLenum format, int width, int height, int depth, int levels, TexFilter filter,
                         const char *label);
/* Deletes the texture and zeroes *tex (0 is fine). */
void gl_texture3d_destroy(GLuint *tex);
/* Width, height, depth of mip `level` of any texture (0 for a 2D one's depth). */
void gl_texture_level_size(GLuint tex, int level, int size[3]);

/* Binds mip `level` of 3D texture `tex` to image unit `unit` as a layered
 * image (all slices: layered = GL_TRUE), for image3D load/store/atomics.
 * `access` is GL_READ_ONLY, GL_WRITE_ONLY or GL_READ_WRITE; `format` must
 * match the shader's layout qualifier, e.g. GL_RGBA16F for rgba16f, or
 * GL_R32UI to run atomics on an RGBA8 texture's texels. */
void gl_texture3d_bind_image(GLuint unit, GLuint tex, int level, GLenum access, GLenum format);

/* Rebuilds levels 1.. of `tex` from level 0 with the driver's box filter
 * (glGenerateTextureMipmap). Issues the memory barrier that makes earlier
 * shader image stores to level 0 visible first.
 *
 * Manual mips through compute, for filters the driver does not offer
 * (anisotropic VCT mips, opacity-weighted averages, integer formats, which
 * glGenerateMipmap does not filter): see gl_texture3d_build_mips. */
void gl_texture_generate_mips(GLuint tex);

/* Builds levels 1.. of 3D texture `tex` one at a time with compute program
 * `program`: for each level L it binds level L-1 to image unit 0
 * (GL_READ_ONLY) and level L to image unit 1 (GL_WRITE_ONLY), both as
 * `format`, dispatches ceil(size(L) / local_size) groups per axis and puts
 * an image-access barrier before the next level. The shader declares
 *     layout(local_size_x = N, local_size_y = N, local_size_z = N) in;
 *     layout(binding = 0, rgba16f) readonly uniform image3D src;
 *     layout(binding = 1, rgba16f) writeonly uniform image3D dst;
 * with N = local_size, and must skip invocations outside imageSize(dst)
 * (and clamp its reads to imageSize(src) for odd sizes). Ends with a
 * texture-fetch barrier so the mips can be sampled next. Leaves the
 * program current and the two image units bound. */
void gl_texture3d_build_mips(GLuint tex, GLuint program, GLenum format, int local_size);

/* --- Framebuffers ------------------------------------------------------- */

/* A framebuffer with no attachments, for passes whose fragment shaders only
 * write images or buffers (voxelisation, LPV injection, counting): the
 * rasterizer uses its default width × height, `layers` (0: not layered;
 * N: a geometry shader may select gl_Layer 0..N-1) and `samples` (0: none).
 * Returns 0 after logging if the sizes exceed the driver's limits or it is
 * not complete. Caller frees with gl_fbo_destroy. */
GLuint gl_fbo_empty_make(int width, int height, int layers, int samples, const char *label);
/* Deletes the framebuffer and zeroes *fbo (0 is fine). */
void gl_fbo_destroy(GLuint *fbo);

/* --- Fault injection (tests) -------------------------------------------- */

/* Every make of this file and targets.h (textures, buffers, framebuffers)
 * asks this first. After gl_make_fail_at(k), the k-th make from then on
 * fails as an allocation the driver refuses would: it logs one line naming
 * what and returns 0. The environment's RTGI_FAIL_GL_MAKE=k arms it at the
 * first make of the process. Tests sweep k over every make of a frame to
 * see that each failure is reported and frees what was made. */
bool gl_make_refused(const char *what, const char *label);
/* Arms the k-th make from now to fail (0: none). Returns whether the
 * previous arming fired. */
bool gl_make_fail_at(long k);

/* --- Buffers ------------------------------------------------------------ */

/* An immutable buffer of `bytes` (at least 1) with glNamedBufferStorage's
 * `data` (NULL: undefined contents) and `flags`, labelled. Returns 0 after
 * logging one line if the size does not fit a GLsizeiptr or the driver
 * gives no store of that size (out of memory): GL raises an error then and
 * leaves the buffer without one, which rendering from it would read as
 * zeros. Caller deletes it (glDeleteBuffers). */
GLuint gl_buffer_make(uint64_t bytes, const void *data, GLbitfield flags, const char *label);

/* --- GPU memory --------------------------------------------------------- */

/* Bytes a texture's levels hold, from what GL reports of it: every level's
 * width × height × depth (a 2D array's layers; a cube's six faces) times
 * its texel's bits (the components', depth, stencil and shared exponent)
 * over 8. What the driver pads or keeps beside it is not seen. 0 for 0. */
uint64_t gl_texture_bytes(GLuint tex);
/* Bytes of a buffer's data store (0 for 0). */
uint64_t gl_buffer_bytes(GLuint buf);
/* Sums over n names (zeros skipped). */
uint64_t gl_textures_bytes(const GLuint *tex, int n);
uint64_t gl_buffers_bytes(const GLuint *buf, int n);

/* --- Live-object census (tests) ------------------------------------------ */

/* Objects for which glIs* returns true among names 1..max_name. An object
 * that is deleted but still in use (a program that is current, a shader
 * attached to a live program) still counts. */
typedef struct GlObjectCounts {
    int textures;
    int buffers;
    int framebuffers;
    int renderbuffers;
    int programs;
    int shaders;
    int vertex_arrays;
    int queries;
    int samplers;
} GlObjectCounts;

/* Counts live objects of the current context with names up to `max_name`
 * (9 glIs* calls per name: fine for a few thousand in a test, not per frame).
 * A test counts before and after a make/destroy pair and expects equality. */
GlObjectCounts gl_count_live_objects(GLuint max_name);
/* Sum of all the counts. */
int gl_object_counts_total(const GlObjectCounts *c);

#endif
