/* scene_load.c — scene files (JSON, cJSON) and meshes (assimp).
 * A scene file names a built-in scene or a mesh file (relative to the scene
 * file), optional inline quads, lights, camera, exposure and technique
 * parameters. See the files under scenes/ and README.md for the format. */
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image.h>

#include "log.h"
#include "scene.h"
#include "settings.h"
#include "util.h"

/* ------------------------------------------------------------------ mesh */

static int load_texture(Scene *s, const struct aiScene *ai, const char *dir, const char *name)
{
    for (int i = 0; i < s->texture_count; i++)
        if (strcmp(s->textures[i].name, name) == 0)
            return i;
    int w, h, n;
    unsigned char *px = NULL;
    char path[1024];
    const struct aiTexture *emb = NULL; /* "*N" names the N-th embedded texture */
    if (name[0] == '*' && (unsigned)atoi(name + 1) < ai->mNumTextures)
        emb = ai->mTextures[atoi(name + 1)];
    if (emb && emb->mHeight == 0) {
        px = stbi_load_from_memory((const unsigned char *)emb->pcData, (int)emb->mWidth, &w, &h, &n, 4);
        snprintf(path, sizeof path, "%s (embedded)", name);
    } else {
        util_join_path(dir, name, path, sizeof path);
        px = stbi_load(path, &w, &h, &n, 4);
    }
    if (!px) {
        log_error("scene", "%s: cannot load texture (%s)", path, stbi_failure_reason());
        return -2;
    }
    s->textures = realloc(s->textures, sizeof(Texture) * (size_t)(s->texture_count + 1));
    Texture *t = &s->textures[s->texture_count];
    t->width = w;
    t->height = h;
    t->rgba = malloc((size_t)w * h * 4);
    memcpy(t->rgba, px, (size_t)w * h * 4);
    stbi_image_free(px);
    snprintf(t->name, sizeof t->name, "%s", name);
    return s->texture_count++;
}

/* Copies the opacity texture's first channel into the albedo texture's alpha. */
static bool merge_opacity(Scene *s, int albedo_tex, int opacity_tex)
{
    Texture *a = &s->textures[albedo_tex];
    const Texture *o = &s->textures[opacity_tex];
    if (a->width != o->width || a->height != o->height)
        return false;
    for (long i = 0; i < (long)a->width * a->height; i++)
        a->rgba[4 * i + 3] = o->rgba[4 * i];
    return true;
}

static bool load_material(Scene *s, const struct aiScene *ai, const struct aiMaterial *am,
                          const char *dir, int *out)
{
    struct aiString name = {0};
    aiGetMaterialString(am, AI_MATKEY_NAME, &name);
    struct aiColor4D c = {1, 1, 1, 1};
    if (aiGetMaterialColor(am, "$clr.base", 0, 0, &c) != aiReturn_SUCCESS &&
        aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) != aiReturn_SUCCESS)
        c = (struct aiColor4D){0.8f, 0.8f, 0.8f, 1};
    int m = scene_add_material(s, name.data, (vec3){c.r, c.g, c.b});
    Material *mat = &s->materials[m];
    struct aiString tex;
    if (aiGetMaterialTexture(am, aiTextureType_DIFFUSE, 0, &tex, NULL, NULL, NULL, NULL, NULL, NULL) ==
        aiReturn_SUCCESS) {
        int t = load_texture(s, ai, dir, tex.data);
        if (t == -2)
            return false;
        s->materials[m].albedo_tex = t;
    }
    mat = &s->materials[m];
    struct aiString mode;
    if (aiGetMaterialString(am, "$mat.gltf.alphaMode", 0, 0, &mode) == aiReturn_SUCCESS &&
        strcmp(mode.data, "MASK") == 0) {
        mat->alpha_mask = true;
        float cutoff = 0.5f;
        unsigned int one = 1;
        if (aiGetMaterialFloatArray(am, "$mat.gltf.alphaCutoff", 0, 0, &cutoff, &one) == aiReturn_SUCCESS)
            mat->alpha_cutoff = cutoff;
    }
    if (aiGetMaterialTexture(am, aiTextureType_OPACITY, 0, &tex, NULL, NULL, NULL, NULL, NULL, NULL) ==
            aiReturn_SUCCESS && mat->albedo_tex >= 0) {
        int t = load_texture(s, ai, dir, tex.data);
        if (t == -2)
            return false;
        mat = &s->materials[m];
        if (merge_opacity(s, mat->albedo_tex, t))
            mat->alpha_mask = true;
        else
            log_warn("scene", "%s: opacity map size differs from the diffuse map; ignored", tex.data);
    }
    *out = m;
    return true;
}

bool scene_load_mesh(Scene *s, const char *path, const mat4 transform)
{
    FILE *probe = fopen(path, "rb");
    if (!probe) {
        log_error("scene", "%s: mesh file does not exist or cannot be read", path);
        return false;
    }
    fclose(probe);
    unsigned flags = aiProcess_Triangulate | aiProcess_GenSmoothNormals | aiProcess_PreTransformVertices |
                     aiProcess_JoinIdenticalVertices | aiProcess_SortByPType | aiProcess_FlipUVs;
    const struct aiScene *ai = aiImportFile(path, flags);
    if (!ai || !ai->mRootNode) {
        log_error("scene", "%s: cannot import mesh (%s)", path, aiGetErrorString());
        return false;
    }
    char dir[1024];
    util_dirname(path, dir, sizeof dir);
    int *mat_map = malloc(sizeof(int) * (ai->mNumMaterials + 1));
    bool ok = true;
    for (unsigned i = 0; i < ai->mNumMaterials && ok; i++)
        ok = load_material(s, ai, ai->mMaterials[i], dir, &mat_map[i]);
    mat3 nrm_m;
    glm_mat4_pick3((vec4 *)transform, nrm_m);
    glm_mat3_inv(nrm_m, nrm_m);
    glm_mat3_transpose(nrm_m);
    unsigned tris = 0;
    for (unsigned mi = 0; mi < ai->mNumMeshes && ok; mi++) {
        const struct aiMesh *am = ai->mMeshes[mi];
        if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
            continue;
        uint32_t base = s->vertex_count;
        s->vertices = realloc(s->vertices, sizeof(Vertex) * (s->vertex_count + am->mNumVertices));
        for (unsigned v = 0; v < am->mNumVertices; v++) {
            Vertex *vx = &s->vertices[s->vertex_count++];
            vec4 p = {am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z, 1};
            glm_mat4_mulv((vec4 *)transform, p, p);
            memcpy(vx->position, p, sizeof vx->position);
            vec3 n = {0, 1, 0};
            if (am->mNormals) {
                glm_vec3_copy((vec3){am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z}, n);
                glm_mat3_mulv(nrm_m, n, n);
                glm_vec3_normalize(n);
            }
            memcpy(vx->normal, n, sizeof vx->normal);
            vx->uv[0] = am->mTextureCoords[0] ? am->mTextureCoords[0][v].x : 0.f;
            vx->uv[1] = am->mTextureCoords[0] ? am->mTextureCoords[0][v].y : 0.f;
        }
        uint32_t *idx = malloc(sizeof(uint32_t) * 3 * am->mNumFaces);
        uint32_t n = 0;
        for (unsigned f = 0; f < am->mNumFaces; f++) {
            if (am->mFaces[f].mNumIndices != 3)
                continue;
            for (int k = 0; k < 3; k++)
                idx[n++] = base + am->mFaces[f].mIndices[k];
        }
        /* Append this mesh's triangles as one submesh of its material. */
        s->indices = realloc(s->indices, sizeof(uint32_t) * (s->index_count + n));
        memcpy(s->indices + s->index_count, idx, sizeof(uint32_t) * n);
        s->submeshes = realloc(s->submeshes, sizeof(Submesh) * (size_t)(s->submesh_count + 1));
        s->submeshes[s->submesh_count++] = (Submesh){s->index_count, n, mat_map[am->mMaterialIndex]};
        s->index_count += n;
        tris += n / 3;
        free(idx);
    }
    free(mat_map);
    aiReleaseImport(ai);
    if (ok && tris == 0) {
        log_error("scene", "%s: mesh file has no triangles", path);
        ok = false;
    }
    if (ok)
        log_debug("scene", "%s: %u triangles, %d materials, %d textures", path, tris, s->material_count,
                  s->texture_count);
    return ok;
}

/* ------------------------------------------------------------------ JSON */

typedef struct {
    const char *file; /* scene file path, for messages */
    bool ok;
} Ctx;

static bool get_vec3(Ctx *c, const cJSON *obj, const char *key, vec3 out, bool required)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!a) {
        if (required) {
            log_error("scene", "%s: missing \"%s\"", c->file, key);
            c->ok = false;
        }
        return false;
    }
    if (cJSON_IsNumber(a)) { /* a scalar means grey */
        glm_vec3_fill(out, (float)a->valuedouble);
        return true;
    }
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 3) {
        log_error("scene", "%s: \"%s\" must be an array of 3 numbers", c->file, key);
        c->ok = false;
        return false;
    }
    for (int i = 0; i < 3; i++) {
        const cJSON *e = cJSON_GetArrayItem(a, i);
        if (!cJSON_IsNumber(e)) {
            log_error("scene", "%s: \"%s\"[%d] is not a number", c->file, key, i);
            c->ok = false;
            return false;
        }
        out[i] = (float)e->valuedouble;
    }
    return true;
}

static bool get_num(Ctx *c, const cJSON *obj, const char *key, float *out)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!a)
        return false;
    if (!cJSON_IsNumber(a)) {
        log_error("scene", "%s: \"%s\" must be a number", c->file, key);
        c->ok = false;
        return false;
    }
    *out = (float)a->valuedouble;
    return true;
}

static void parse_light(Ctx *c, Scene *s, const cJSON *j, int index)
{
    Light l = {0};
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(j, "type");
    const char *t = cJSON_IsString(type) ? type->valuestring : "";
    float deg;
    if (strcmp(t, "directional") == 0) {
        l.type = LIGHT_DIRECTIONAL;
        get_vec3(c, j, "direction", l.direction, true);
        get_vec3(c, j, "irradiance", l.color, true);
        if (get_num(c, j, "angular_diameter_deg", &deg))
            l.size = glm_rad(deg);
    } else if (strcmp(t, "spot") == 0 || strcmp(t, "point") == 0) {
        l.type = t[0] == 's' ? LIGHT_SPOT : LIGHT_POINT;
        get_vec3(c, j, "position", l.position, true);
        get_vec3(c, j, "intensity", l.color, true);
        get_num(c, j, "diameter", &l.size);
        glm_vec3_copy((vec3){0, -1, 0}, l.direction);
        if (l.type == LIGHT_SPOT) {
            get_vec3(c, j, "direction", l.direction, true);
            float inner = 30, outer = 35;
            get_num(c, j, "inner_deg", &inner);
            get_num(c, j, "outer_deg", &outer);
            if (!(inner >= 0 && outer > inner && outer < 90)) {
                log_error("scene", "%s: lights[%d]: need 0 <= inner_deg < outer_deg < 90", c->file, index);
                c->ok = false;
            }
            l.spot_inner = glm_rad(inner);
            l.spot_outer = glm_rad(outer);
        }
    } else if (strcmp(t, "quad") == 0) {
        l.type = LIGHT_QUAD;
        get_vec3(c, j, "position", l.position, true);
        get_vec3(c, j, "direction", l.direction, true);
        get_vec3(c, j, "radiance", l.color, true);
        get_vec3(c, j, "u", l.quad_u, true);
        get_vec3(c, j, "v", l.quad_v, true);
        l.size = 1.0f;
        get_num(c, j, "size", &l.size);
    } else {
        log_error("scene", "%s: lights[%d]: unknown light type \"%s\" (directional, spot, point, quad)",
                  c->file, index, t);
        c->ok = false;
        return;
    }
    if (glm_vec3_norm(l.direction) < 1e-6f) {
        log_error("scene", "%s: lights[%d]: direction is zero", c->file, index);
        c->ok = false;
    }
    if (l.size < 0) {
        log_error("scene", "%s: lights[%d]: size must be >= 0", c->file, index);
        c->ok = false;
    }
    if (c->ok)
        scene_add_light(s, &l);
}

static void parse_camera(Ctx *c, Scene *s, const cJSON *j)
{
    Camera *cam = &s->camera;
    get_vec3(c, j, "position", cam->position, true);
    vec3 target;
    if (get_vec3(c, j, "target", target, false))
        glm_vec3_sub(target, cam->position, cam->forward);
    else
        get_vec3(c, j, "forward", cam->forward, true);
    vec3 up = {0, 1, 0}, right;
    get_vec3(c, j, "up", up, false);
    if (glm_vec3_norm(cam->forward) < 1e-6f) {
        log_error("scene", "%s: camera: forward/target gives a zero direction", c->file);
        c->ok = false;
        return;
    }
    glm_vec3_normalize(cam->forward);
    glm_vec3_cross(cam->forward, up, right);
    if (glm_vec3_norm(right) < 1e-6f) {
        log_error("scene", "%s: camera: up is parallel to the view direction", c->file);
        c->ok = false;
        return;
    }
    glm_vec3_normalize(right);
    glm_vec3_cross(right, cam->forward, cam->up);
    float fov = glm_deg(cam->fov_y);
    get_num(c, j, "fov_y_deg", &fov);
    if (!(fov > 1 && fov < 179)) {
        log_error("scene", "%s: camera: fov_y_deg must be in (1, 179)", c->file);
        c->ok = false;
    }
    cam->fov_y = glm_rad(fov);
    get_num(c, j, "near", &cam->znear);
    get_num(c, j, "far", &cam->zfar);
}

static void parse_quads(Ctx *c, Scene *s, const cJSON *arr)
{
    int i = 0;
    const cJSON *q;
    cJSON_ArrayForEach(q, arr)
    {
        vec3 albedo = {0.8f, 0.8f, 0.8f};
        get_vec3(c, q, "albedo", albedo, false);
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(q, "vertices");
        if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 4) {
            log_error("scene", "%s: quads[%d]: \"vertices\" must hold 4 points", c->file, i);
            c->ok = false;
            return;
        }
        vec3 p[4];
        for (int k = 0; k < 4; k++) {
            const cJSON *e = cJSON_GetArrayItem(v, k);
            for (int d = 0; d < 3; d++) {
                const cJSON *x = cJSON_GetArrayItem(e, d);
                if (!cJSON_IsNumber(x)) {
                    log_error("scene", "%s: quads[%d]: vertex %d is not 3 numbers", c->file, i, k);
                    c->ok = false;
                    return;
                }
                p[k][d] = (float)x->valuedouble;
            }
        }
        char name[32];
        snprintf(name, sizeof name, "quad%d", i);
        int m = scene_add_material(s, name, albedo);
        scene_add_quad(s, m, p[0], p[1], p[2], p[3]);
        i++;
    }
}

/* The "shadow" and "gi" objects: the settings table's one parser. */
static void parse_settings(Ctx *c, Scene *s, const cJSON *j, const char *group)
{
    Settings set = {s->shadow, s->gi};
    if (!settings_parse_json(j, group, c->file, &set)) {
        c->ok = false;
        return;
    }
    s->shadow = set.shadow;
    s->gi = set.gi;
}

static bool load_json(Scene *s, const char *path)
{
    char *text = util_read_file(path, NULL);
    if (!text) {
        log_error("scene", "%s: scene file does not exist or cannot be read", path);
        return false;
    }
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(text, &end, 1);
    if (!root) {
        int line = 1, col = 1;
        for (const char *p = text; end && p < end && *p; p++) {
            if (*p == '\n') {
                line++;
                col = 1;
            } else {
                col++;
            }
        }
        log_error("scene", "%s:%d:%d: malformed JSON", path, line, col);
        free(text);
        return false;
    }
    free(text);
    if (!cJSON_IsObject(root)) {
        log_error("scene", "%s: top level must be a JSON object", path);
        cJSON_Delete(root);
        return false;
    }
    Ctx c = {path, true};
    char dir[1024];
    util_dirname(path, dir, sizeof dir);

    const cJSON *builtin = cJSON_GetObjectItemCaseSensitive(root, "builtin");
    const cJSON *mesh = cJSON_GetObjectItemCaseSensitive(root, "mesh");
    if (cJSON_IsString(builtin)) {
        if (strcmp(builtin->valuestring, "cornell") != 0) {
            log_error("scene", "%s: unknown builtin scene \"%s\" (cornell)", path, builtin->valuestring);
            cJSON_Delete(root);
            return false;
        }
        scene_build_cornell(s);
    } else {
        scene_init(s);
    }
    snprintf(s->source, sizeof s->source, "%s", path);
    if (mesh) {
        if (!cJSON_IsString(mesh)) {
            log_error("scene", "%s: \"mesh\" must be a file path", path);
            cJSON_Delete(root);
            return false;
        }
        char mesh_path[1024];
        util_join_path(dir, mesh->valuestring, mesh_path, sizeof mesh_path);
        mat4 xf = GLM_MAT4_IDENTITY_INIT;
        float scale = 1.f;
        vec3 tr = {0, 0, 0};
        get_num(&c, root, "mesh_scale", &scale);
        get_vec3(&c, root, "mesh_translate", tr, false);
        glm_translate(xf, tr);
        glm_scale_uni(xf, scale);
        if (!c.ok || !scene_load_mesh(s, mesh_path, xf)) {
            cJSON_Delete(root);
            return false;
        }
    }
    const cJSON *quads = cJSON_GetObjectItemCaseSensitive(root, "quads");
    if (quads)
        parse_quads(&c, s, quads);
    if (s->vertex_count == 0 && c.ok) {
        log_error("scene", "%s: no geometry (give \"builtin\", \"mesh\" or \"quads\")", path);
        c.ok = false;
    }
    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    if (lights) {
        if (!cJSON_IsArray(lights)) {
            log_error("scene", "%s: \"lights\" must be an array", path);
            c.ok = false;
        } else {
            s->light_count = 0; /* the file's lights replace a builtin's */
            int i = 0;
            const cJSON *l;
            cJSON_ArrayForEach(l, lights) parse_light(&c, s, l, i++);
        }
    }
    get_num(&c, root, "exposure", &s->exposure);
    const cJSON *shadow = cJSON_GetObjectItemCaseSensitive(root, "shadow");
    if (shadow)
        parse_settings(&c, s, shadow, "shadow");
    const cJSON *gi = cJSON_GetObjectItemCaseSensitive(root, "gi");
    if (gi)
        parse_settings(&c, s, gi, "gi");
    const cJSON *cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    bool has_camera = cam != NULL || cJSON_IsString(builtin);
    if (cam)
        parse_camera(&c, s, cam);
    cJSON_Delete(root);
    if (!c.ok)
        return false;
    if (s->light_count == 0)
        scene_add_default_sun(s);
    scene_finalize(s);
    if (!has_camera)
        scene_default_camera(s);
    return true;
}

bool scene_load(Scene *s, const char *what)
{
    if (strcmp(what, "cornell") == 0) {
        scene_build_cornell(s);
        scene_finalize(s);
        return true;
    }
    if (util_ends_with(what, ".json")) {
        scene_init(s);
        if (load_json(s, what))
            return true;
        scene_free(s);
        return false;
    }
    scene_init(s);
    snprintf(s->source, sizeof s->source, "%s", what);
    mat4 id = GLM_MAT4_IDENTITY_INIT;
    if (!scene_load_mesh(s, what, id)) {
        scene_free(s);
        return false;
    }
    scene_add_default_sun(s);
    s->shadow.map_size = 2048; /* a sun over a whole model needs the texels */
    scene_finalize(s);
    scene_default_camera(s);
    return true;
}
