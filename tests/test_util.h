/* test_util.h — helpers shared by the tests: rendering a scene to a float
 * image in-process, running the CLI binary, and image statistics. */
#ifndef RTGI_TEST_UTIL_H
#define RTGI_TEST_UTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "gl/gl_context.h"
#include "io/image.h"
#include "reference/pathtracer.h"
#include "frame/renderer.h"
#include "core/scene.h"

/* cmocka group setup/teardown that create and destroy a GL context. */
int test_gl_setup(void **state);
int test_gl_teardown(void **state);

/* Render settings for a test: w×h, shadow mode, default shadow params of s. */
RenderSettings test_settings(const Scene *s, int w, int h, ShadowMode mode);
/* Renders one frame of `s` from its camera into `out` (radiance). Needs a
 * current context. Fails the test on error. */
void test_render(const Scene *s, const RenderSettings *rs, ImageF *out);

/* Renders `s` with GI technique `gi` (hard shadows; `gp` NULL: the scene's
 * GI settings) into `out`; returns the frame's GI counters. */
RenderStats test_render_gi(const Scene *s, int w, int h, GiMode gi, const GiParams *gp, ImageF *out);
/* Path-traced reference of `s` from its camera at pixel centres (as the
 * rasterizer shades), 2 threads. Fails the test on error. */
void test_reference(const Scene *s, int w, int h, PtMode mode, int spp, ImageF *out);
/* The same with samples spread over each pixel (`jitter`: a box filter,
 * what supersampling approximates) or at its centre. */
void test_reference_ex(const Scene *s, int w, int h, PtMode mode, int spp, bool jitter, ImageF *out);
/* The same with the variance of each pixel's mean into `var` (NULL: none). */
void test_reference_var(const Scene *s, int w, int h, PtMode mode, int spp, bool jitter, ImageF *out, ImageF *var);
/* The point of the plane y = 0 that the ray through the centre of pixel
 * (x, y) of a w×h image of `s`'s camera meets, into p; false (p then
 * behind the camera or at infinity) where the ray does not go down to it. */
bool test_pixel_plane_point(const Scene *s, int w, int h, int x, int y, vec3 p);
/* Pixel (x, y) of a w×h image of `s`'s camera sees the plane y = 0, lit by
 * the point-like light `l`, with albedo `albedo`: writes the analytic
 * radiance albedo/π · I cosθ / d² into `want` and returns the light's height
 * above that point (cosθ·d, for horizon checks). */
float test_plane_radiance(const Scene *s, int w, int h, int x, int y, const Light *l, float albedo, vec3 want);
/* Mean luminance of an image. */
double test_image_mean(const ImageF *img);

/* ---- Where the light lands: regions and indirect ratios ---------------
 * The "indirect ratio" of a technique over a region is the light it adds
 * over the rasterizer's --gi none image, over the light one bounce adds in
 * the reference: Σ(tech − none) / Σ(ref − ref_direct), luminance. 1 is
 * right, 0 is no GI at all. */

/* Pixels of s's camera w×h view (row 0 = top) that see material `material`
 * (by name) on face `face` (PT_FACE_*; −1: any face) through their centre,
 * and whose 8 neighbours see the same surface: mask[i] = 1 there, else 0.
 * Returns the count. Fails the test if no material has that name. */
int test_surface_mask(const Scene *s, int w, int h, const char *material, int face, uint8_t *mask);
/* Σ over the pixels with mask[i] != 0 (NULL: all) of luminance(tech − none),
 * over the same of luminance(ref − direct). */
double test_indirect_ratio(const ImageF *tech, const ImageF *none, const ImageF *ref, const ImageF *direct,
                           const uint8_t *mask);
/* The image cut into bx × by blocks; of the blocks whose reference
 * indirect light (ref − direct) is above the median block's, the lowest and
 * highest indirect ratio into lo and hi (for "no region beyond 3× or below
 * ⅓" checks on a mesh scene, where surfaces have no names worth keeping). */
void test_block_ratio_range(const ImageF *tech, const ImageF *none, const ImageF *ref, const ImageF *direct, int bx,
                            int by, double *lo, double *hi);
/* Technique `gi` (the scene's own settings) on scene `s` at w×h against
 * the path tracer's one-bounce and direct light (64 spp): the whole image's
 * indirect ratio and the range over the 16×9 blocks above the median
 * (test_block_ratio_range); prints them under `label`. At 16 spp a block's
 * reference still moved by ±10% between seeds (Sponza at 320×180: the
 * lowest block 0.314 .. 0.392 over seeds 1–4, where 64 spp reads 0.337 ..
 * 0.348 and 256 spp 0.343): more than the margin of a bound such as ⅓. */
void test_one_bounce_regions(const Scene *s, GiMode gi, int w, int h, const char *label, double *whole, double *lo,
                             double *hi);

/* Writes `content` to RTGI_TEST_TMP/name; returns the path (static buffer,
 * valid until the next call). */
const char *test_tmp_file(const char *name, const char *content);
/* Loads the shipped scene file scenes/NAME into s (the test fails if it
 * does not load). */
void test_load_scene_file(Scene *s, const char *name);

/* Writes two 8×8 PNGs to RTGI_TEST_TMP for an alpha-masked material: a
 * white albedo, and a mask (map_d) opaque on texel columns 0-3 and
 * transparent on 4-7. */
void test_mask_textures(const char *albedo_name, const char *alpha_name);
/* Writes NAME.obj, NAME.mtl and the mask textures (test_mask_textures) to
 * RTGI_TEST_TMP: an alpha-masked 2 m leaf (Kd 0.3 0.6 0.3, transparent on
 * its x > 0 half) at y = 0.5 over a 6 m ground (Kd 0.8) at y = 0, both
 * facing +y. Returns the OBJ's path (test_tmp_file's buffer). */
const char *test_masked_leaf_obj(const char *name);
/* Fails the test if GL has recorded an error since the last call (the
 * tests' context is not a debug one: glGetError is what reports there);
 * `where` names the step in the failure. */
void test_expect_no_gl_error(const char *where);
/* Test programs run with RTGI_PROGRESS_S=1e9 (no progress lines, whatever
 * the machine's speed); a test that sets it restores it with this. */
void test_progress_off(void);
/* Runs build/rtgi with the given arguments (NULL-terminated); returns its
 * exit status and, if `err` is not NULL, what it wrote on stderr (caller
 * frees). */
int test_run_cli(char **err, const char *arg0, ...);
/* The same with the arguments after arg0 in `ap` (for variadic helpers). */
int test_run_cli_va(char **err, const char *arg0, va_list ap);
/* Same, also returning what it wrote on stdout in `out` (caller frees). */
int test_run_cli_out(char **out, char **err, const char *arg0, ...);
/* Same, for any executable (argv[0] = exe). */
int test_run_exe(char **err, const char *exe, const char *arg0, ...);

/* A virtual X server for the window tests: started once per test process
 * (Xvfb -displayfd, so the server itself picks a free display: concurrent
 * test processes cannot race for one, as `xvfb-run -a` can), DISPLAY set
 * for this process and its children, stopped at exit. Fails the test if
 * Xvfb cannot start. */
void test_x_display(void);

/* Fails unless the CLI exited with `want` and its stderr (freed here) is a
 * single line holding n1 and n2 (either may be NULL). */
void test_expect_cli_error(int rc, char *err, int want, const char *n1, const char *n2);

/* Pixel (x, y) of a G-buffer (shaders/common/gbuffer.glsl), decoded. */
typedef struct TestGbPixel {
    bool valid;          /* a surface was drawn */
    vec3 position, normal;
    vec3 base;           /* base colour */
    float metallic, roughness, specular;
    vec3 emission;
    vec3 diffuse, f0;    /* brdf_surface of the above */
} TestGbPixel;
void test_gbuffer_pixel(const GBuffer *g, int x, int y, TestGbPixel *out);

/* mask[i] = 0 on pixels that see an emitter (ids from pt_surface_map:
 * material · 6 + face, −1 none) and their 8 neighbours, else 1. */
void test_emitter_mask(const Scene *s, int w, int h, const int32_t *ids, uint8_t *mask);

/* For direct-light images (a shadowed pixel is exactly black): mask[i] = 1
 * except within one pixel of where a and b disagree about being in shadow,
 * the shadow-map resolution error a radiometry check does not measure;
 * `excluded` counts the 0s. */
void test_shadow_boundary_mask(const ImageF *a, const ImageF *b, uint8_t *mask, int *excluded);

/* Mean of channel c (0..2, or 3 = luminance) over a (2r+1)² window. */
double test_mean(const ImageF *img, int cx, int cy, int r, int c);
/* Pixel of a world point in the scene camera's w×h image; fails if behind. */
void test_project(const Scene *s, int w, int h, const vec3 p, int *x, int *y);
/* Adds a flat square (normal +y) of side `a` centred on c, at height c[1]. */
void test_add_square(Scene *s, int material, const vec3 c, float a);
/* Points camera c straight down (-y) from `position`, image up along -z. */
void test_camera_down(Camera *c, const vec3 position);
/* Crytek Sponza (not part of the repository): the path of
 * scenes/sponza_nave.json (the view down the nave the measurements use)
 * where its asset is present under RTGI_SHARED_DIR, else NULL (the caller
 * skips). Static buffer. */
const char *test_sponza_file(void);
/* Sponza's glTF under ../shared/assets, or NULL when it is not there. */
const char *test_sponza_gltf(void);
/* Skips the calling test (cmocka skip(), saying why) when Sponza's asset
 * is absent. */
void test_skip_without_sponza(void);
/* Loads test_sponza_file() (it must exist) with its glTF materials made
 * Lambertian (specular 0, metallic 0) and its sun a parallel one (size 0):
 * the path tracer's bounce then has no glossy paths a diffuse gather
 * cannot have, and its direct light is the rasterizer's apart from
 * shadow-map resolution. */
void test_sponza_lambert(Scene *s);
/* Runs the group's tests, or with argument "K/N" (1 <= K <= N) every Nth
 * of them from the Kth: ctest runs a long program as N entries
 * (rtgi_split_test in tests/CMakeLists.txt) that the cores share. */
int test_run_group_part(const char *name, const struct CMUnitTest *tests, size_t count, int argc, char **argv);

#endif
