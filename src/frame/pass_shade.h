/* pass_shade.h — deferred shading as compute (shaders/frame/shade.comp):
 * every light's direct radiance from the G-buffer (the light model and the
 * per-light-type, per-filter program variants of pass_direct), the
 * surfaces' emission, the GI technique's indirect light (composite) and the
 * tone map. The last light's dispatch composites and tone-maps, so that a
 * frame of one light is one dispatch where it was three full-screen raster
 * passes (direct, composite, tone map): on GPUs whose raster pipeline is a
 * small share of the chip (an H100 runs pixel shaders on 4 of 132 SMs)
 * compute is what scales, and no pass reads the radiance back to blend it.
 * Inputs: G-buffer, the light stage (light blocks, shadow maps), shadow
 * parameters (pass_direct's uniform buffer), the GI images.
 * Outputs: radiance (RGBA32F, every pixel written: zero where no surface)
 * and, when asked, the display image (a display target's RGBA8 storage).
 * Owns: nothing (its programs are the program cache's). */
#ifndef RTGI_PASS_SHADE_H
#define RTGI_PASS_SHADE_H

#include <stdbool.h>

#include "gpu/light_stage.h"
#include "frame/pass_direct.h"
#include "gl/shader.h"
#include "gpu/targets.h"

typedef struct PassShade {
    GLuint program;    /* any light type and shadow mode (the variants' fallback; PassDirect.general) */
    GLuint program_glossy; /* the same with glossy materials' composite */
    ProgramCache *pc;  /* borrowed: builds the variants */
} PassShade;

/* The GI technique's images for the composite; irradiance 0: no GI. */
typedef struct ShadeGi {
    GLuint irradiance;  /* RGBA32F E at the shading size */
    GLuint specular;    /* RGBA32F radiance, or 0 (techniques without a specular image) */
    GLuint brdf_albedo; /* the GGX lobe's directional albedo table */
} ShadeGi;

bool pass_shade_create(PassShade *p, ProgramCache *pc);
void pass_shade_destroy(PassShade *p);
/* Shades `hdr` (the shading size) from `gb` with every light of `ls` (none:
 * emission alone), adds `gi`'s indirect light when it has an irradiance
 * image, and writes the display image into `ldr` unless it is NULL (then
 * a later pass tone-maps: supersampling). `d` holds the shadow parameters
 * and builds the variants. */
void pass_shade_run(PassShade *p, const PassDirect *d, const LightStage *ls, const GBuffer *gb, const ShadeGi *gi,
                    ColorTarget *hdr, ColorTarget *ldr);

#endif
