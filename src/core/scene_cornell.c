/* scene_cornell.c — the Cornell box from the published Cornell University
 * "Cornell Box Data" (../shared/assets/cornell/cornell_box_facts.json),
 * converted from millimetres to metres. Albedos are the linear-sRGB values
 * derived from the measured spectra; the light's radiance is the derived
 * linear-sRGB emission, taken as W/(m²·sr). The light quad is lowered 1 mm
 * below the ceiling and emits downward only.
 * Each surface has its own material, named after it (floor, ceiling,
 * back_wall, left_wall, right_wall, short_block, tall_block), so that a
 * scene file's "materials" can make one of them glossy; all are Lambertian
 * by default. */
#include <string.h>

#include "core/scene.h"

typedef struct {
    const char *material; /* "white" | "red" | "green" */
    const char *surface;  /* the material's name */
    float v[4][3];        /* millimetres */
} CornellFace;

static const CornellFace k_faces[] = {
    {"white", "floor", {{552.8f, 0, 0}, {0, 0, 0}, {0, 0, 559.2f}, {549.6f, 0, 559.2f}}},                 /* floor */
    {"white", "ceiling", {{556, 548.8f, 0}, {556, 548.8f, 559.2f}, {0, 548.8f, 559.2f}, {0, 548.8f, 0}}},   /* ceiling */
    {"white", "back_wall", {{549.6f, 0, 559.2f}, {0, 0, 559.2f}, {0, 548.8f, 559.2f}, {556, 548.8f, 559.2f}}}, /* back */
    {"green", "right_wall", {{0, 0, 559.2f}, {0, 0, 0}, {0, 548.8f, 0}, {0, 548.8f, 559.2f}}},                 /* right */
    {"red", "left_wall", {{552.8f, 0, 0}, {549.6f, 0, 559.2f}, {556, 548.8f, 559.2f}, {556, 548.8f, 0}}},     /* left */
    {"white", "short_block", {{130, 165, 65}, {82, 165, 225}, {240, 165, 272}, {290, 165, 114}}},               /* short block */
    {"white", "short_block", {{290, 0, 114}, {290, 165, 114}, {240, 165, 272}, {240, 0, 272}}},
    {"white", "short_block", {{130, 0, 65}, {130, 165, 65}, {290, 165, 114}, {290, 0, 114}}},
    {"white", "short_block", {{82, 0, 225}, {82, 165, 225}, {130, 165, 65}, {130, 0, 65}}},
    {"white", "short_block", {{240, 0, 272}, {240, 165, 272}, {82, 165, 225}, {82, 0, 225}}},
    {"white", "tall_block", {{423, 330, 247}, {265, 330, 296}, {314, 330, 456}, {472, 330, 406}}},             /* tall block */
    {"white", "tall_block", {{423, 0, 247}, {423, 330, 247}, {472, 330, 406}, {472, 0, 406}}},
    {"white", "tall_block", {{472, 0, 406}, {472, 330, 406}, {314, 330, 456}, {314, 0, 456}}},
    {"white", "tall_block", {{314, 0, 456}, {314, 330, 456}, {265, 330, 296}, {265, 0, 296}}},
    {"white", "tall_block", {{265, 0, 296}, {265, 330, 296}, {423, 330, 247}, {423, 0, 247}}},
};

bool scene_build_cornell(Scene *s)
{
    scene_init(s);
    strcpy(s->source, "cornell");
    const vec3 white = {0.7381f, 0.7361f, 0.7376f}, red = {0.4899f, 0.0504f, 0.0509f},
               green = {0.0689f, 0.3985f, 0.0864f};
    int m = -1;
    bool ok = true;
    for (size_t f = 0; ok && f < sizeof k_faces / sizeof k_faces[0]; f++) {
        const CornellFace *cf = &k_faces[f];
        if (f == 0 || strcmp(cf->surface, k_faces[f - 1].surface) != 0)
            m = scene_add_material(s, cf->surface,
                                   strcmp(cf->material, "red") == 0     ? red
                                   : strcmp(cf->material, "green") == 0 ? green
                                                                         : white);
        vec3 p[4];
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 3; k++)
                p[i][k] = cf->v[i][k] * 0.001f;
        ok = m >= 0 && scene_add_quad(s, m, p[0], p[1], p[2], p[3]); /* each logs its failure */
    }

    Light l = {0};
    l.type = LIGHT_QUAD;
    glm_vec3_copy((vec3){0.278f, 0.5488f - 0.001f, 0.2795f}, l.position);
    glm_vec3_copy((vec3){0, -1, 0}, l.direction);
    glm_vec3_copy((vec3){20.655f, 10.902f, 2.767f}, l.color);
    glm_vec3_copy((vec3){0, 0, 0.105f}, l.quad_u);
    glm_vec3_copy((vec3){-0.130f, 0, 0}, l.quad_v);
    l.size = 1.0f;
    ok = ok && scene_add_light(s, &l) >= 0;

    Camera *c = &s->camera;
    glm_vec3_copy((vec3){0.278f, 0.273f, -0.800f}, c->position);
    glm_vec3_copy((vec3){0, 0, 1}, c->forward);
    glm_vec3_copy((vec3){0, 1, 0}, c->up);
    c->fov_y = glm_rad(39.30764811610662f);
    c->znear = 0.01f;
    c->zfar = 10.0f;
    s->exposure = 3.0f;
    s->settings.shadow.map_size = 512;
    /* Sampling radius for the light's cube RSM, in face widths. With the
     * paper's ξ1² weights a larger disk lowers the image relMSE against the
     * exhaustive sum (0.030 at 0.3, 0.025 at 1, 0.020 at 2) but lets distant
     * samples dominate near the walls, where the colour bleeding is (a floor
     * point in shadow beside the green wall came out redder than one beside
     * the red wall at r_max 2); 0.5 keeps the bleeding right. The unbiased
     * weighting does best at 2 (relMSE 0.011): --rsm-weighting unbiased
     * --rsm-rmax 2. */
    s->settings.gi.rsm.r_max = 0.5f;
    return ok;
}
