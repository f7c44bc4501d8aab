/* pass_temporal.h — temporal accumulation of the technique's indirect
 * irradiance (`--temporal on`, SPEC §10): each pixel's surface reprojected
 * into the last frame with the G-buffer's world position and the last
 * frame's camera (the motion vector), the history kept where the last
 * frame's G-buffer held the same surface (disocclusion rejection by plane
 * distance and normal), clamped to this frame's neighbourhood (variance
 * clipping, so a moving light's bounce does not lag) and blended
 * (shaders/temporal/accumulate.comp). Moving objects: their pixels find no
 * matching surface in the last frame and start again (no smear).
 * Inputs: the G-buffer, the technique's irradiance, the camera.
 * Output: its own accumulated irradiance image (what the composite reads).
 * Owns: the two history images and the last frame's G-buffer surface,
 * made at the shading size on first use (none while it is off); its
 * program is the program cache's, built on first use. */
#ifndef RTGI_PASS_TEMPORAL_H
#define RTGI_PASS_TEMPORAL_H

#include <stdbool.h>

#include "core/scene.h"
#include "gl/shader.h"
#include "gpu/targets.h"

/* The least weight of a new frame: the history averages about 1/α frames
 * (noise variance × α/(2 − α)) once it has built up. */
#define TEMPORAL_ALPHA 0.1f
/* Disocclusion: the last frame's surface must lie within this fraction of
 * the distance to the camera from this pixel's tangent plane. */
#define TEMPORAL_PLANE_TOLERANCE 0.01f
/* Neighbourhood clamp: mean ± γσ of this frame's 3×3 pixels. */
#define TEMPORAL_CLAMP_GAMMA 1.5f

typedef struct PassTemporal {
    ProgramCache *programs; /* borrowed: its program is built on first use */
    GLuint program;
    GLuint history[2];      /* RGBA32F ping-pong: accumulated irradiance, a = frames held */
    GLuint prev_surface;    /* RGBA32UI: the last frame's G-buffer surface */
    int width, height;      /* of the images (the shading size) */
    int current;            /* history[current] holds the last frame's result */
    mat4 prev_view_proj;    /* the last frame's camera */
    bool have_history;      /* false after a reset: the next frame starts afresh */
} PassTemporal;

void pass_temporal_create(PassTemporal *p, ProgramCache *pc);
/* Frees its images (the program is the cache's). */
void pass_temporal_destroy(PassTemporal *p);
/* Forgets the history: the next frame starts afresh (a new technique,
 * settings, size or a cut). */
void pass_temporal_reset(PassTemporal *p);
/* Accumulates `irradiance` (RGBA32F at the G-buffer's size) of the frame
 * seen from `cam`, the history clamped to the neighbourhood unless `clamp`
 * is false (GiParams.frame.temporal_clamp, for measuring); returns the texture that holds the result (valid until
 * the next run), or 0 after logging where its images or program could not
 * be made. */
GLuint pass_temporal_run(PassTemporal *p, const GBuffer *gb, GLuint irradiance, const Camera *cam, bool clamp);
/* GPU bytes of its images. */
uint64_t pass_temporal_bytes(const PassTemporal *p);

#endif
