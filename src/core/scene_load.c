/* scene_load.c — scene files (JSON, cJSON) and meshes (assimp).
 * A scene file names a built-in scene or a mesh file (relative to the scene
 * file), optional inline quads, lights, camera, exposure and technique
 * parameters. See the files under scenes/ and docs/guide.md ("Scene files") for the format. */
#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cjson/cJSON.h>
#include <limits.h>
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stb/stb_image.h>

#include "core/animation.h"
#include "base/json_util.h"
#include "base/log.h"
#include "core/scene.h"
#include "core/settings.h"
#include "base/util.h"

/* ------------------------------------------------------------------ mesh */

/* Limits on what a mesh file may bring (docs/guide.md, "Scene files"). */
#define MESH_MAX_VERTICES ((uint32_t)1 << 27) /* 4 GiB of Vertex */
#define MESH_MAX_INDICES ((uint32_t)1 << 28)  /* 1 GiB of indices */
#define TEXTURE_MAX_SIZE 16384                /* texels per side (GL_MAX_TEXTURE_SIZE of common GPUs) */
#define MESH_MAX_BYTES ((size_t)1 << 31)      /* mesh or texture file size */
#define SCENE_MAX_POWER 1e30f

/* Loads (or finds) texture `name`: colour (sRGB) or, when `linear`, data. */
static int load_texture(Scene *s, const struct aiScene *ai, const char *dir, const char *name, bool linear)
{
    for (int i = 0; i < s->texture_count; i++)
        if (strcmp(s->textures[i].name, name) == 0 && s->textures[i].linear == linear)
            return i;
    int w = 0, h = 0, n;
    unsigned char *px = NULL;
    char path[1024];
    const struct aiTexture *emb = NULL; /* "*N" names the N-th embedded texture */
    if (name[0] == '*' && (unsigned)atoi(name + 1) < ai->mNumTextures)
        emb = ai->mTextures[atoi(name + 1)];
    if (emb && emb->mHeight == 0) {
        snprintf(path, sizeof path, "%s (embedded)", name);
        if (emb->mWidth > INT32_MAX) {
            log_error("scene", "%s: embedded texture too large", path);
            return -2;
        }
        if (stbi_info_from_memory((const unsigned char *)emb->pcData, (int)emb->mWidth, &w, &h, &n) &&
            (w > TEXTURE_MAX_SIZE || h > TEXTURE_MAX_SIZE)) {
            log_error("scene", "%s: texture is %dx%d, more than the limit of %d per side", path, w, h,
                      TEXTURE_MAX_SIZE);
            return -2;
        }
        px = stbi_load_from_memory((const unsigned char *)emb->pcData, (int)emb->mWidth, &w, &h, &n, 4);
    } else {
        util_join_path(dir, name, path, sizeof path);
        size_t size = 0;
        char *data = util_read_input("scene", "texture", path, MESH_MAX_BYTES, &size);
        if (!data)
            return -2;
        if (size > INT32_MAX) {
            log_error("scene", "%s: texture file too large", path);
            free(data);
            return -2;
        }
        if (stbi_info_from_memory((const unsigned char *)data, (int)size, &w, &h, &n) &&
            (w > TEXTURE_MAX_SIZE || h > TEXTURE_MAX_SIZE)) {
            log_error("scene", "%s: texture is %dx%d, more than the limit of %d per side", path, w, h,
                      TEXTURE_MAX_SIZE);
            free(data);
            return -2;
        }
        px = stbi_load_from_memory((const unsigned char *)data, (int)size, &w, &h, &n, 4);
        free(data);
    }
    if (!px) {
        log_error("scene", "%s: cannot load texture (%s)", path, stbi_failure_reason());
        return -2;
    }
    Texture *t;
    if (!util_realloc("scene", "texture list", (void **)&s->textures, (size_t)s->texture_count + 1,
                      sizeof(Texture)) ||
        !((t = &s->textures[s->texture_count])->rgba =
              util_malloc("scene", "a texture", (size_t)w * (size_t)h, 4))) {
        stbi_image_free(px);
        return -2;
    }
    t->width = w;
    t->height = h;
    t->linear = linear;
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

/* One material; glTF files (`gltf`) bring metallic-roughness parameters
 * and a dielectric F0 of 0.04, other formats are Lambertian. */
/* A mesh file's material values, as the scene file's "materials" checks
 * its own: n numbers, each finite and in [0, hi]; false after logging
 * which file, material and key. */
static bool material_in_range(const char *path, const char *material, const char *key, const float *v, int n,
                              float hi)
{
    for (int i = 0; i < n; i++)
        if (!(v[i] >= 0.f && v[i] <= hi)) { /* NaN fails too */
            if (n > 1)
                log_error("scene", "%s: material '%s': %s component %d is %g, not in [0, %g]", path, material, key, i,
                          (double)v[i], (double)hi);
            else
                log_error("scene", "%s: material '%s': %s is %g, not in [0, %g]", path, material, key, (double)v[i],
                          (double)hi);
            return false;
        }
    return true;
}

static bool load_material(Scene *s, const struct aiScene *ai, const struct aiMaterial *am, const char *path,
                          const char *dir, bool gltf, int *out)
{
    struct aiString name = {0};
    aiGetMaterialString(am, AI_MATKEY_NAME, &name);
    struct aiColor4D c = {1, 1, 1, 1};
    if (aiGetMaterialColor(am, "$clr.base", 0, 0, &c) != aiReturn_SUCCESS &&
        aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) != aiReturn_SUCCESS)
        c = (struct aiColor4D){0.8f, 0.8f, 0.8f, 1};
    const char *base_key = gltf ? "baseColorFactor" : "diffuse colour (Kd)";
    if (!material_in_range(path, name.data, base_key, &c.r, 3, 1.f))
        return false;
    int m = scene_add_material(s, name.data, (vec3){c.r, c.g, c.b});
    if (m < 0)
        return false;
    Material *mat = &s->materials[m];
    struct aiString tex;
    if (aiGetMaterialTexture(am, aiTextureType_DIFFUSE, 0, &tex, NULL, NULL, NULL, NULL, NULL, NULL) ==
        aiReturn_SUCCESS) {
        int t = load_texture(s, ai, dir, tex.data, false);
        if (t == -2)
            return false;
        s->materials[m].albedo_tex = t;
    }
    mat = &s->materials[m];
    if (gltf) {
        /* glTF 2.0 defaults: metallic 1, roughness 1 (assimp fills them in). */
        float f = 1.f;
        unsigned int one = 1;
        mat->specular = 1.f;
        if (aiGetMaterialFloatArray(am, AI_MATKEY_METALLIC_FACTOR, &f, &one) != aiReturn_SUCCESS)
            f = 1.f;
        if (!material_in_range(path, name.data, "metallicFactor", &f, 1, 1.f))
            return false;
        mat->metallic = f;
        one = 1;
        if (aiGetMaterialFloatArray(am, AI_MATKEY_ROUGHNESS_FACTOR, &f, &one) != aiReturn_SUCCESS)
            f = 1.f;
        if (!material_in_range(path, name.data, "roughnessFactor", &f, 1, 1.f))
            return false;
        mat->roughness = f;
        /* assimp 5.2 files the metallicRoughness texture as UNKNOWN. */
        if (aiGetMaterialTexture(am, aiTextureType_UNKNOWN, 0, &tex, NULL, NULL, NULL, NULL, NULL, NULL) ==
            aiReturn_SUCCESS) {
            int t = load_texture(s, ai, dir, tex.data, true);
            if (t == -2)
                return false;
            mat = &s->materials[m];
            mat->mr_tex = t;
        }
        struct aiColor4D e = {0, 0, 0, 1};
        if (aiGetMaterialColor(am, AI_MATKEY_COLOR_EMISSIVE, &e) == aiReturn_SUCCESS) {
            if (!material_in_range(path, name.data, "emissiveFactor", &e.r, 3, SCENE_MAX_POWER))
                return false;
            glm_vec3_copy((vec3){e.r, e.g, e.b}, mat->emission);
        }
    }
    struct aiString mode;
    if (aiGetMaterialString(am, "$mat.gltf.alphaMode", 0, 0, &mode) == aiReturn_SUCCESS &&
        strcmp(mode.data, "MASK") == 0) {
        mat->alpha_mask = true;
        float cutoff = 0.5f;
        unsigned int one = 1;
        if (aiGetMaterialFloatArray(am, "$mat.gltf.alphaCutoff", 0, 0, &cutoff, &one) == aiReturn_SUCCESS) {
            if (!material_in_range(path, name.data, "alphaCutoff", &cutoff, 1, 1.f))
                return false;
            mat->alpha_cutoff = cutoff;
        }
    }
    if (aiGetMaterialTexture(am, aiTextureType_OPACITY, 0, &tex, NULL, NULL, NULL, NULL, NULL, NULL) ==
            aiReturn_SUCCESS && mat->albedo_tex >= 0) {
        int t = load_texture(s, ai, dir, tex.data, false);
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

/* Byte size of a PLY scalar type name, 0 if unknown. */
static int ply_type_size(const char *t)
{
    static const struct { const char *name; int size; } types[] = {
        {"char", 1},  {"uchar", 1},  {"int8", 1},    {"uint8", 1},   {"short", 2},   {"ushort", 2},
        {"int16", 2}, {"uint16", 2}, {"int", 4},     {"uint", 4},    {"int32", 4},   {"uint32", 4},
        {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8},
    };
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(t, types[i].name) == 0)
            return types[i].size;
    return 0;
}

/* assimp 5.2's PLY reader crashes on malformed headers and on binary data
 * shorter than its header promises (found by fuzz_mesh): check the header
 * strictly, and that a binary file holds at least the bytes its elements
 * need (list properties count their length field only). */
static bool mesh_check_ply(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        log_error("scene", "%s: cannot open mesh file", path);
        return false;
    }
    static char head[65537];
    size_t n = fread(head, 1, sizeof head - 1, f);
    fseek(f, 0, SEEK_END);
    long file_size = ftell(f);
    fclose(f);
    head[n] = 0;
    if (strncmp(head, "ply", 3) != 0 && !util_ends_with(path, ".ply"))
        return true; /* not PLY: assimp picks another reader */
    const char *why = NULL;
    bool binary = false, in_element = false, done = false;
    /* Bytes the data needs at least: binary, each property's size (a
     * list's length field only); ASCII, two bytes ("0 ") per property. */
    double need = 0, need_ascii = 0, element_bytes = 0, element_props = 0, element_count = 0;
    int line_no = 0;
    size_t pos = 0;
    while (!done && !why) {
        const char *nl = memchr(head + pos, '\n', n - pos);
        if (!nl) {
            why = "no end_header in the first 64 KiB";
            break;
        }
        char line[512];
        size_t len = (size_t)(nl - (head + pos));
        if (len >= sizeof line) {
            why = "header line too long";
            break;
        }
        memcpy(line, head + pos, len);
        line[len] = 0;
        if (len && line[len - 1] == '\r')
            line[len - 1] = 0;
        pos += len + 1;
        line_no++;
        char a[64] = "", b[64] = "", c[64] = "", d[64] = "", e[64] = "";
        int k = sscanf(line, "%63s %63s %63s %63s %63s", a, b, c, d, e);
        if (line_no == 1) {
            if (strcmp(line, "ply") != 0)
                why = "first line is not \"ply\"";
        } else if (line_no == 2) {
            if (k != 3 || strcmp(a, "format") != 0 || strcmp(c, "1.0") != 0)
                why = "second line is not \"format <type> 1.0\"";
            else if (strcmp(b, "binary_little_endian") == 0 || strcmp(b, "binary_big_endian") == 0)
                binary = true;
            else if (strcmp(b, "ascii") != 0)
                why = "unknown format";
        } else if (k <= 0 || strcmp(a, "comment") == 0 || strcmp(a, "obj_info") == 0) {
            continue;
        } else if (strcmp(a, "element") == 0) {
            char *end = NULL;
            double cnt = k == 3 ? strtod(c, &end) : -1;
            if (k != 3 || !end || *end || !(cnt >= 0 && cnt <= 4294967295.0) || cnt != floor(cnt))
                why = "bad element line";
            need += element_bytes * element_count;
            need_ascii += 2 * element_props * element_count;
            element_bytes = element_props = 0;
            element_count = cnt;
            in_element = true;
        } else if (strcmp(a, "property") == 0) {
            if (!in_element)
                why = "property before any element";
            else if (strcmp(b, "list") == 0 && k == 5 && ply_type_size(c) && ply_type_size(d))
                element_bytes += ply_type_size(c), element_props++;
            else if (k == 3 && ply_type_size(b))
                element_bytes += ply_type_size(b), element_props++;
            else
                why = "bad property line";
        } else if (strcmp(a, "end_header") == 0 && k == 1) {
            done = true;
        } else {
            why = "unknown header line";
        }
    }
    need += element_bytes * element_count;
    need_ascii += 2 * element_props * element_count;
    if (!why && (double)file_size - (double)pos < (binary ? need : need_ascii - 1))
        why = "data shorter than the header's element counts need";
    if (why) {
        log_error("scene", "%s: malformed PLY file: %s (line %d)", path, why, line_no);
        return false;
    }
    return true;
}

/* Binary glTF (magic "glTF", whatever the file's name): the header's total
 * length and every chunk's length must fit in the file. assimp 5.2 takes
 * them on trust and allocates what they say before it reads (found by
 * fuzz_mesh: a 512-byte GLB whose JSON chunk claimed 4 GiB held 4.2 GB of
 * memory for 12 s before the import failed). Version 1's header carries
 * one content length instead of chunks. */
static bool mesh_check_glb(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        log_error("scene", "%s: cannot open mesh file", path);
        return false;
    }
    uint8_t h[20];
    size_t n = fread(h, 1, sizeof h, f);
    fseek(f, 0, SEEK_END);
    double file_size = (double)ftell(f);
    const char *why = NULL;
    if (n < 4 || memcmp(h, "glTF", 4) != 0) {
        fclose(f);
        return true; /* not binary glTF */
    }
#define U32(b) ((uint32_t)(b)[0] | (uint32_t)(b)[1] << 8 | (uint32_t)(b)[2] << 16 | (uint32_t)(b)[3] << 24)
    uint32_t version = n >= 12 ? U32(h + 4) : 0, length = n >= 12 ? U32(h + 8) : 0;
    if (n < 12)
        why = "shorter than its 12-byte header";
    else if (version != 1 && version != 2)
        why = "unknown version (not 1 or 2)";
    else if ((double)length > file_size)
        why = "its header's length is more than the file holds";
    else if (version == 1 && (n < 20 || 20.0 + U32(h + 12) > file_size))
        why = "its content length is more than the file holds";
    for (double at = 12; !why && version == 2 && at + 8 <= (double)length; ) {
        uint8_t c[8];
        if (fseek(f, (long)at, SEEK_SET) != 0 || fread(c, 1, sizeof c, f) != sizeof c) {
            why = "cannot read a chunk header";
            break;
        }
        double chunk = U32(c);
        if (at + 8 + chunk > (double)length)
            why = "a chunk's length is more than the file holds";
        at += 8 + chunk;
    }
#undef U32
    fclose(f);
    if (why) {
        log_error("scene", "%s: malformed binary glTF: %s", path, why);
        return false;
    }
    return true;
}

/* Checks an imported, unprocessed scene for what ValidateDataStructure
 * lets through and the post-processing steps assert on: faces without
 * indices, indices out of range, and primitive-type flags that disagree
 * with the faces (recomputed here from the faces). */
static bool mesh_check_raw(const char *path, struct aiScene *ai)
{
    for (unsigned mi = 0; mi < ai->mNumMeshes; mi++) {
        struct aiMesh *m = ai->mMeshes[mi];
        if (!m || (m->mNumVertices && !m->mVertices) || (m->mNumFaces && !m->mFaces)) {
            log_error("scene", "%s: mesh %u has no vertex or face data", path, mi);
            return false;
        }
        unsigned types = 0;
        for (unsigned f = 0; f < m->mNumFaces; f++) {
            const struct aiFace *face = &m->mFaces[f];
            if (face->mNumIndices == 0 || !face->mIndices) {
                log_error("scene", "%s: face %u of mesh %u has no indices", path, f, mi);
                return false;
            }
            for (unsigned k = 0; k < face->mNumIndices; k++)
                if (face->mIndices[k] >= m->mNumVertices) {
                    log_error("scene", "%s: face %u of mesh %u uses vertex %u of %u", path, f, mi,
                              face->mIndices[k], m->mNumVertices);
                    return false;
                }
            types |= face->mNumIndices == 1   ? aiPrimitiveType_POINT
                     : face->mNumIndices == 2 ? aiPrimitiveType_LINE
                     : face->mNumIndices == 3 ? aiPrimitiveType_TRIANGLE
                                              : aiPrimitiveType_POLYGON;
        }
        m->mPrimitiveTypes = types;
    }
    return true;
}

/* assimp's file system for a mesh and every file it names (OBJ's mtllib,
 * glTF's buffers and images): plain stdio, except that a path which is no
 * regular file is not opened (a FIFO would block the import for ever, a
 * directory reads as garbage) and is remembered, so that the load fails
 * naming it rather than go on without it. */
typedef struct MeshIo {
    struct aiFileIO io;
    char refused[1024]; /* the first path refused, and what it is */
    const char *refused_kind;
} MeshIo;

static size_t mesh_io_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    return fread(buf, size, count, (FILE *)f->UserData);
}

static size_t mesh_io_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0; /* opened read-only */
}

static size_t mesh_io_tell(struct aiFile *f)
{
    long p = ftell((FILE *)f->UserData);
    return p < 0 ? 0 : (size_t)p;
}

static size_t mesh_io_size(struct aiFile *f)
{
    struct stat st; /* a regular file (mesh_io_open) */
    return fstat(fileno((FILE *)f->UserData), &st) == 0 ? (size_t)st.st_size : 0;
}

static enum aiReturn mesh_io_seek(struct aiFile *f, size_t offset, enum aiOrigin origin)
{
    int whence = origin == aiOrigin_CUR ? SEEK_CUR : origin == aiOrigin_END ? SEEK_END : SEEK_SET;
    if (offset > (size_t)LONG_MAX)
        return aiReturn_FAILURE;
    return fseek((FILE *)f->UserData, (long)offset, whence) == 0 ? aiReturn_SUCCESS : aiReturn_FAILURE;
}

static void mesh_io_flush(struct aiFile *f) { (void)f; }

static struct aiFile *mesh_io_open(struct aiFileIO *io, const char *path, const char *mode)
{
    MeshIo *m = (MeshIo *)io->UserData;
    if (strpbrk(mode, "wa+"))
        return NULL;
    const char *kind;
    FILE *fp = util_fopen_regular(path, &kind);
    if (!fp) {
        if (kind && !m->refused_kind) {
            snprintf(m->refused, sizeof m->refused, "%s", path);
            m->refused_kind = kind;
        }
        return NULL;
    }
    struct aiFile *f = calloc(1, sizeof *f);
    if (!f) {
        fclose(fp);
        return NULL;
    }
    f->ReadProc = mesh_io_read;
    f->WriteProc = mesh_io_write;
    f->TellProc = mesh_io_tell;
    f->FileSizeProc = mesh_io_size;
    f->SeekProc = mesh_io_seek;
    f->FlushProc = mesh_io_flush;
    f->UserData = (aiUserData)fp;
    return f;
}

static void mesh_io_close(struct aiFileIO *io, struct aiFile *f)
{
    (void)io;
    if (!f)
        return;
    fclose((FILE *)f->UserData);
    free(f);
}

/* The import's outcome against what its file system refused: false after
 * logging when a file the mesh names is no regular file. */
static bool mesh_io_check(const MeshIo *m, const char *path)
{
    if (!m->refused_kind)
        return true;
    log_error("scene", "%s: the file it names, %s, is %s, not a regular file", path, m->refused, m->refused_kind);
    return false;
}

/* assimp's import error in a user's words where its own would puzzle. */
static void log_import_error(const char *path)
{
    const char *e = aiGetErrorString();
    if (!e || !*e)
        e = "the importer gave no reason";
    if (strstr(e, "No suitable reader found"))
        log_error("scene", "%s: cannot import mesh: no importer recognises its contents (damaged, or not a format "
                  "assimp reads: .obj, .gltf, .glb, .ply, .fbx, ...)", path);
    else if (strstr(e, "Normal buffer size does not match"))
        log_error("scene", "%s: cannot import mesh: a facet's normal has no vertices (the file is cut short or "
                  "damaged)", path);
    else
        log_error("scene", "%s: cannot import mesh (%s)", path, e);
}

/* A mesh over this many vertices is large: its import and each
 * post-processing step are announced and timed (the environment's
 * RTGI_MESH_LARGE_VERTICES sets it; the tests make a small mesh large). */
#define MESH_LARGE_VERTICES 1000000u

static unsigned mesh_large_vertices(void)
{
    const char *v = getenv("RTGI_MESH_LARGE_VERTICES");
    char *end = NULL;
    unsigned long n = v && *v ? strtoul(v, &end, 10) : 0;
    return end && !*end ? (unsigned)n : MESH_LARGE_VERTICES;
}

static unsigned mesh_vertex_count(const struct aiScene *ai)
{
    unsigned n = 0;
    for (unsigned i = 0; i < ai->mNumMeshes; i++)
        n += ai->mMeshes[i]->mNumVertices;
    return n;
}

/* assimp's post-processing, a step at a time so that a large mesh says
 * which step runs and how long it took (an 8M-triangle OBJ had sat five
 * minutes in JoinIdenticalVertices without a word). Steps a file does not
 * need are skipped: smooth normals where every mesh has normals, joining
 * identical vertices where the meshes already share them (indexed glTF:
 * at most 1.5 vertices per triangle, where a mesh is about 0.5 to 1 and an
 * OBJ's unshared corners 2 (quads) or 3); an OBJ's corners are joined,
 * which keeps its vertex buffer a third of the size. The order is assimp's own. Releases `ai` and returns
 * NULL after logging on failure. */
static const struct aiScene *mesh_post_process(const struct aiScene *ai, const char *path)
{
    bool normals = true;
    for (unsigned i = 0; i < ai->mNumMeshes; i++)
        normals = normals && ai->mMeshes[i]->mNormals;
    unsigned verts = mesh_vertex_count(ai);
    bool large = verts > mesh_large_vertices();
    static const struct {
        unsigned flag;
        const char *name;
    } steps[] = {
        {aiProcess_Triangulate, "triangulating"},
        {aiProcess_GenSmoothNormals, "smooth normals"},
        {aiProcess_PreTransformVertices, "applying node transforms"},
        {aiProcess_JoinIdenticalVertices, "joining identical vertices"},
        {aiProcess_SortByPType, "sorting primitives"},
        {aiProcess_FlipUVs, "flipping texture coordinates"},
    };
    for (size_t k = 0; k < sizeof steps / sizeof steps[0] && ai; k++) {
        unsigned flag = steps[k].flag;
        if (flag == aiProcess_GenSmoothNormals && normals)
            continue;
        if (flag == aiProcess_JoinIdenticalVertices) {
            bool shared = true;
            for (unsigned i = 0; i < ai->mNumMeshes && shared; i++)
                shared = 2 * (unsigned long)ai->mMeshes[i]->mNumVertices <= 3 * (unsigned long)ai->mMeshes[i]->mNumFaces;
            if (shared)
                continue;
        }
        double t0 = util_seconds();
        if (large)
            log_progress("scene: %s: %s (%u vertices)...", path, steps[k].name, mesh_vertex_count(ai));
        ai = aiApplyPostProcessing(ai, flag); /* releases the scene on failure */
        if (large)
            log_progress("scene: %s: %s took %.1f s", path, steps[k].name, util_seconds() - t0);
    }
    if (!ai || !ai->mRootNode) {
        log_import_error(path);
        if (ai)
            aiReleaseImport(ai);
        return NULL;
    }
    return ai;
}

/* The mesh file imported: rtgi's checks of the file, assimp's import with
 * its validation, the checks of what that misses, then post-processing
 * (triangulated, smooth normals, node transforms applied). NULL after
 * logging; release it with aiReleaseImport. */
static const struct aiScene *mesh_import(const char *path, bool keep_nodes)
{
    /* assimp would block on a FIFO and read a directory as garbage. */
    if (!util_check_input("scene", "mesh file", path, MESH_MAX_BYTES, NULL))
        return NULL;
    if (!mesh_check_ply(path) || !mesh_check_glb(path))
        return NULL;
    /* Import and validate first, check what assimp's own checks miss, then
     * post-process: its steps assert (abort) on inconsistent meshes. */
    MeshIo io = {.io = {.OpenProc = mesh_io_open, .CloseProc = mesh_io_close}};
    io.io.UserData = (aiUserData)&io;
    struct stat st;
    bool big = stat(path, &st) == 0 && st.st_size > (off_t)64 * 1024 * 1024;
    double t0 = util_seconds();
    if (big)
        log_progress("scene: %s: importing %.0f MB through assimp...", path, (double)st.st_size / (1024.0 * 1024.0));
    /* Nodes named by a scene file's objects: node transforms applied
     * without joining the meshes of one material (they stay the nodes'). */
    struct aiPropertyStore *props = keep_nodes ? aiCreatePropertyStore() : NULL;
    if (props)
        aiSetImportPropertyInteger(props, AI_CONFIG_PP_PTV_KEEP_HIERARCHY, 1);
    const struct aiScene *ai = aiImportFileExWithProperties(path, aiProcess_ValidateDataStructure, &io.io, props);
    if (props)
        aiReleasePropertyStore(props);
    if (big && ai)
        log_progress("scene: %s: imported in %.1f s", path, util_seconds() - t0);
    if (!mesh_io_check(&io, path) || !ai || !ai->mRootNode) {
        if (!io.refused_kind)
            log_import_error(path);
        if (ai)
            aiReleaseImport(ai);
        return NULL;
    }
    if (!mesh_check_raw(path, (struct aiScene *)ai)) {
        aiReleaseImport(ai);
        return NULL;
    }
    return mesh_post_process(ai, path);
}

/* Where a mesh file's meshes go and what they added so far. */
typedef struct MeshAppend {
    Scene *s;
    const char *path;  /* the mesh file, for messages */
    vec4 *transform;   /* borrowed: positions' mesh_scale/translate */
    mat3 normal_m;     /* normals': its 3×3's inverse transpose */
    const int *mat_map;/* assimp's material index → the scene's */
    int *mesh_submesh; /* assimp's mesh index → the submesh it became, -1: none (may be NULL) */
    unsigned tris;     /* triangles appended */
    bool area;         /* one of them has an area */
} MeshAppend;

/* Appends mesh `mi`'s vertices, transformed, with unit normals (0,1,0
 * where there are none or one is degenerate) and finite UVs; false after
 * logging a position out of range or a failed allocation. */
static bool append_vertices(MeshAppend *m, const struct aiMesh *am, unsigned mi)
{
    Scene *s = m->s;
    if (!util_realloc("scene", "mesh vertices", (void **)&s->vertices, (size_t)s->vertex_count + am->mNumVertices,
                      sizeof(Vertex)))
        return false;
    for (unsigned v = 0; v < am->mNumVertices; v++) {
        Vertex *vx = &s->vertices[s->vertex_count];
        vec4 p = {am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z, 1};
        glm_mat4_mulv(m->transform, p, p);
        for (int k = 0; k < 3; k++)
            if (!(fabsf(p[k]) <= 1e6f)) { /* SCENE_MAX_COORD, NaN and Inf too */
                log_error("scene", "%s: vertex %u of mesh %u is at %g (after mesh_scale/translate): "
                          "not finite or beyond the limit of 1e6 m", m->path, v, mi, (double)p[k]);
                return false;
            }
        memcpy(vx->position, p, sizeof vx->position);
        vec3 n = {0, 1, 0};
        if (am->mNormals) {
            glm_vec3_copy((vec3){am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z}, n);
            glm_mat3_mulv(m->normal_m, n, n);
            if (isfinite(n[0]) && isfinite(n[1]) && isfinite(n[2]) && glm_vec3_norm(n) > 1e-20f)
                glm_vec3_normalize(n);
            else
                glm_vec3_copy((vec3){0, 1, 0}, n); /* a degenerate normal: any unit vector */
        }
        memcpy(vx->normal, n, sizeof vx->normal);
        float u = am->mTextureCoords[0] ? am->mTextureCoords[0][v].x : 0.f;
        float w = am->mTextureCoords[0] ? am->mTextureCoords[0][v].y : 0.f;
        vx->uv[0] = isfinite(u) ? u : 0.f;
        vx->uv[1] = isfinite(w) ? w : 0.f;
        s->vertex_count++;
    }
    return true;
}

/* Mesh `mi`'s triangles as indices into the scene's vertices (its own
 * plus `base`) into idx, *n of them; false after logging an index out of
 * range. */
static bool triangle_indices(const MeshAppend *m, const struct aiMesh *am, unsigned mi, uint32_t base,
                             uint32_t *idx, uint32_t *n)
{
    *n = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        if (am->mFaces[f].mNumIndices != 3)
            continue;
        for (int k = 0; k < 3; k++) {
            unsigned i = am->mFaces[f].mIndices[k];
            if (i >= am->mNumVertices) { /* ValidateDataStructure should have caught it */
                log_error("scene", "%s: face %u of mesh %u uses vertex %u of %u", m->path, f, mi, i,
                          am->mNumVertices);
                return false;
            }
            idx[(*n)++] = base + i;
        }
    }
    return true;
}

/* Whether one of the n/3 triangles in idx has an area. */
static bool any_area(const Scene *s, const uint32_t *idx, uint32_t n)
{
    for (uint32_t t = 0; t < n; t += 3) {
        const float *a = s->vertices[idx[t]].position, *b = s->vertices[idx[t + 1]].position,
                    *c = s->vertices[idx[t + 2]].position;
        vec3 e1 = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2 = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, x;
        glm_vec3_cross(e1, e2, x);
        if (glm_vec3_norm2(x) > 0.f)
            return true;
    }
    return false;
}

/* Appends mesh `mi`'s triangles (its vertices start at `base`) as one
 * submesh of its material; false after logging. */
static bool append_triangles(MeshAppend *m, const struct aiMesh *am, unsigned mi, uint32_t base)
{
    Scene *s = m->s;
    uint32_t *idx = util_malloc("scene", "mesh indices", 3 * (size_t)am->mNumFaces + 1, sizeof(uint32_t));
    if (!idx)
        return false;
    uint32_t n;
    bool ok = triangle_indices(m, am, mi, base, idx, &n) &&
              util_realloc("scene", "mesh indices", (void **)&s->indices, (size_t)s->index_count + n,
                           sizeof(uint32_t)) &&
              util_realloc("scene", "submeshes", (void **)&s->submeshes, (size_t)s->submesh_count + 1,
                           sizeof(Submesh));
    if (ok) {
        if (m->mesh_submesh)
            m->mesh_submesh[mi] = s->submesh_count;
        memcpy(s->indices + s->index_count, idx, sizeof(uint32_t) * n);
        m->area = m->area || any_area(s, idx, n);
        s->submeshes[s->submesh_count++] = (Submesh){s->index_count, n, m->mat_map[am->mMaterialIndex]};
        s->index_count += n;
        m->tris += n / 3;
    }
    free(idx);
    return ok;
}

/* Appends mesh `mi` of the import if it has triangles: its vertices, then
 * its triangles as a submesh; false after logging a bad material index,
 * the scene's limits exceeded or what the steps logged. */
static bool append_mesh(MeshAppend *m, const struct aiScene *ai, unsigned mi)
{
    const struct aiMesh *am = ai->mMeshes[mi];
    if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
        return true;
    if (am->mMaterialIndex >= ai->mNumMaterials) {
        log_error("scene", "%s: mesh %u names material %u of %u", m->path, mi, am->mMaterialIndex,
                  ai->mNumMaterials);
        return false;
    }
    const Scene *s = m->s;
    if ((uint64_t)s->vertex_count + am->mNumVertices > MESH_MAX_VERTICES ||
        (uint64_t)s->index_count + 3ull * am->mNumFaces > MESH_MAX_INDICES) {
        log_error("scene", "%s: more than %u vertices or %u indices (the limit)", m->path, MESH_MAX_VERTICES,
                  MESH_MAX_INDICES);
        return false;
    }
    uint32_t base = s->vertex_count;
    return append_vertices(m, am, mi) && append_triangles(m, am, mi, base);
}

/* Adds (name, submesh) of node `n`'s meshes for it and every ancestor on
 * `names` (depth entries). false after logging if memory runs out. */
static bool map_node(const struct aiNode *n, const int *mesh_submesh, const char (*names)[64], int depth,
                     SceneNodeMap *map, int *cap)
{
    char stack[32][64];
    int d = depth < 31 ? depth : 31;
    if (d > 0)
        memcpy(stack, names, sizeof stack[0] * (size_t)d);
    snprintf(stack[d], sizeof stack[d], "%.63s", n->mName.data);
    for (unsigned k = 0; k < n->mNumMeshes; k++) {
        int sm = mesh_submesh[n->mMeshes[k]];
        for (int a = 0; sm >= 0 && a <= d; a++) {
            if (map->count == *cap) {
                *cap = 2 * *cap + 16;
                if (!util_realloc("scene", "the mesh's nodes", (void **)&map->entries, (size_t)*cap,
                                  sizeof *map->entries))
                    return false;
            }
            snprintf(map->entries[map->count].name, sizeof map->entries[0].name, "%s", stack[a]);
            map->entries[map->count++].submesh = sm;
        }
    }
    for (unsigned c = 0; c < n->mNumChildren; c++)
        if (!map_node(n->mChildren[c], mesh_submesh, (const char(*)[64])stack, d + 1, map, cap))
            return false;
    return true;
}

bool scene_load_mesh(Scene *s, const char *path, const mat4 transform)
{
    return scene_load_mesh_nodes(s, path, transform, NULL);
}

bool scene_load_mesh_nodes(Scene *s, const char *path, const mat4 transform, SceneNodeMap *nodes)
{
    const struct aiScene *ai = mesh_import(path, nodes != NULL);
    if (!ai)
        return false;
    char dir[1024];
    util_dirname(path, dir, sizeof dir);
    int *mat_map = util_malloc("scene", "the material map", (size_t)ai->mNumMaterials + 1, sizeof(int));
    bool ok = mat_map != NULL;
    bool gltf = util_ends_with(path, ".gltf") || util_ends_with(path, ".glb");
    for (unsigned i = 0; ok && i < ai->mNumMaterials; i++)
        ok = load_material(s, ai, ai->mMaterials[i], path, dir, gltf, &mat_map[i]);
    MeshAppend m = {.s = s, .path = path, .transform = (vec4 *)transform, .mat_map = mat_map};
    if (ok && nodes) {
        ok = (m.mesh_submesh = util_malloc("scene", "the mesh's nodes", (size_t)ai->mNumMeshes + 1, sizeof(int))) != NULL;
        for (unsigned mi = 0; ok && mi < ai->mNumMeshes; mi++)
            m.mesh_submesh[mi] = -1;
    }
    glm_mat4_pick3((vec4 *)transform, m.normal_m);
    glm_mat3_inv(m.normal_m, m.normal_m);
    glm_mat3_transpose(m.normal_m);
    for (unsigned mi = 0; ok && mi < ai->mNumMeshes; mi++)
        ok = append_mesh(&m, ai, mi);
    int cap = 0;
    if (ok && nodes)
        ok = map_node(ai->mRootNode, m.mesh_submesh, NULL, 0, nodes, &cap);
    free(m.mesh_submesh);
    free(mat_map);
    aiReleaseImport(ai);
    if (ok && m.tris == 0) {
        log_error("scene", "%s: mesh file has no triangles", path);
        ok = false;
    } else if (ok && !m.area) {
        log_error("scene", "%s: all %u triangles have zero area (after mesh_scale/translate): nothing to draw", path,
                  m.tris);
        ok = false;
    }
    if (ok)
        log_debug("scene", "%s: %u triangles, %d materials, %d textures", path, m.tris, s->material_count,
                  s->texture_count);
    return ok;
}

/* ------------------------------------------------------------------ JSON */

/* Limits on scene-file values (docs/guide.md, "Scene files"): beyond them the
 * renderers' float arithmetic overflows or the GPU cannot hold the scene. */
#define SCENE_MAX_COORD 1e6f      /* |coordinate| of positions and vectors (m) */
#define SCENE_MAX_LIGHTS 32       /* lights per scene: each gets shadow maps and an RSM */
#define SCENE_MAX_QUADS 100000    /* inline quads per scene file */
#define SCENE_MAX_BYTES ((size_t)64 << 20) /* scene file size */

typedef struct {
    const char *file; /* scene file path, for messages */
    bool ok;          /* false after the first error; later ones are not logged */
    char where[64];   /* object being parsed: "camera", "lights[2]", "" = top level */
} Ctx;

/* Logs "<file>: <where>.<key>: <message>" for the first error only, so that
 * a bad file gives exactly one line. */
static void bad(Ctx *c, const char *key, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void bad(Ctx *c, const char *key, const char *fmt, ...)
{
    if (!c->ok)
        return;
    c->ok = false;
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    const char *sep = c->where[0] && key ? "." : "";
    log_error("scene", "%s: %s%s%s%s%s", c->file, c->where, sep, key ? key : "", c->where[0] || key ? ": " : "",
              msg);
}

static void set_where(Ctx *c, const char *fmt, int index)
{
    snprintf(c->where, sizeof c->where, fmt, index);
}

static bool check_keys(Ctx *c, const cJSON *obj, const char *const *known)
{
    if (c->ok && !json_check_keys(obj, known, c->file, c->where))
        c->ok = false;
    return c->ok;
}

/* A JSON number as a finite float (1e400 parses as infinity, 1e39
 * overflows a float). */
static bool to_float(Ctx *c, const char *key, const cJSON *e, int index, float *out)
{
    double d = e->valuedouble;
    float f = (float)d;
    if (!isfinite(d) || !isfinite(f)) {
        char k[96];
        if (index >= 0)
            snprintf(k, sizeof k, "%s[%d]", key, index);
        else
            snprintf(k, sizeof k, "%s", key);
        bad(c, k, "%g is not a finite 32-bit float (|x| < 3.4e38)", d);
        return false;
    }
    *out = f;
    return true;
}

static bool get_vec3(Ctx *c, const cJSON *obj, const char *key, vec3 out, bool required)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!a) {
        if (required)
            bad(c, key, "missing");
        return false;
    }
    if (cJSON_IsNumber(a)) { /* a scalar means grey */
        float v;
        if (!to_float(c, key, a, -1, &v))
            return false;
        glm_vec3_fill(out, v);
        return true;
    }
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 3) {
        bad(c, key, "must be an array of 3 numbers");
        return false;
    }
    for (int i = 0; i < 3; i++) {
        const cJSON *e = cJSON_GetArrayItem(a, i);
        if (!cJSON_IsNumber(e)) {
            char k[96];
            snprintf(k, sizeof k, "%s[%d]", key, i);
            bad(c, k, "is not a number");
            return false;
        }
        if (!to_float(c, key, e, i, &out[i]))
            return false;
    }
    return true;
}

/* A point or extent: every |coordinate| <= SCENE_MAX_COORD. */
static bool get_point(Ctx *c, const cJSON *obj, const char *key, vec3 out, bool required)
{
    if (!get_vec3(c, obj, key, out, required))
        return false;
    for (int i = 0; i < 3; i++)
        if (fabsf(out[i]) > SCENE_MAX_COORD) {
            bad(c, key, "%g is beyond the limit of %g m", (double)out[i], (double)SCENE_MAX_COORD);
            return false;
        }
    return true;
}

/* A direction: finite, not zero. */
static bool get_dir(Ctx *c, const cJSON *obj, const char *key, vec3 out, bool required)
{
    if (!get_point(c, obj, key, out, required))
        return false;
    if (!(glm_vec3_norm(out) > 1e-6f)) {
        bad(c, key, "is zero (a direction must have a length)");
        return false;
    }
    return true;
}

/* Radiometric quantity or albedo: every component in [0, hi]. */
static bool get_color(Ctx *c, const cJSON *obj, const char *key, vec3 out, bool required, float hi)
{
    if (!get_vec3(c, obj, key, out, required))
        return false;
    for (int i = 0; i < 3; i++)
        if (!(out[i] >= 0.f && out[i] <= hi)) {
            bad(c, key, "%g is outside [0, %g]", (double)out[i], (double)hi);
            return false;
        }
    return true;
}

static bool get_num(Ctx *c, const cJSON *obj, const char *key, float *out)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!a)
        return false;
    if (!cJSON_IsNumber(a)) {
        bad(c, key, "must be a number");
        return false;
    }
    return to_float(c, key, a, -1, out);
}

/* get_num, then lo <= v <= hi (or lo < v when lo_open). */
static bool get_num_in(Ctx *c, const cJSON *obj, const char *key, float *out, float lo, bool lo_open, float hi)
{
    float v;
    if (!get_num(c, obj, key, &v))
        return false;
    if ((lo_open ? !(v > lo) : !(v >= lo)) || !(v <= hi)) {
        bad(c, key, "%g is outside %s%g, %g]", (double)v, lo_open ? "(" : "[", (double)lo, (double)hi);
        return false;
    }
    *out = v;
    return true;
}

static const char *const k_light_common[] = {"type", NULL};
static const char *const k_directional_keys[] = {"type", "direction", "irradiance", "angular_diameter_deg", NULL};
static const char *const k_point_keys[] = {"type", "position", "intensity", "diameter", NULL};
static const char *const k_spot_keys[] = {"type",      "position",  "direction", "intensity",
                                          "inner_deg", "outer_deg", "diameter",  NULL};
static const char *const k_quad_light_keys[] = {"type", "position", "direction", "radiance", "u", "v", "size", NULL};

/* The largest radiometric value a light may have: its float sums over
 * pixels and samples must stay finite. */

static void parse_light(Ctx *c, Scene *s, const cJSON *j, int index)
{
    Light l = {0};
    set_where(c, "lights[%d]", index);
    if (!cJSON_IsObject(j)) {
        bad(c, NULL, "must be an object");
        return;
    }
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(j, "type");
    if (!type) {
        bad(c, "type", "missing (directional, spot, point, quad)");
        return;
    }
    if (!cJSON_IsString(type)) {
        bad(c, "type", "must be a string (directional, spot, point, quad)");
        return;
    }
    const char *t = type->valuestring;
    float deg;
    if (strcmp(t, "directional") == 0) {
        l.type = LIGHT_DIRECTIONAL;
        if (!check_keys(c, j, k_directional_keys))
            return;
        get_dir(c, j, "direction", l.direction, true);
        get_color(c, j, "irradiance", l.color, true, SCENE_MAX_POWER);
        if (get_num_in(c, j, "angular_diameter_deg", &deg, 0.f, false, 90.f))
            l.size = glm_rad(deg);
    } else if (strcmp(t, "spot") == 0 || strcmp(t, "point") == 0) {
        l.type = t[0] == 's' ? LIGHT_SPOT : LIGHT_POINT;
        if (!check_keys(c, j, l.type == LIGHT_SPOT ? k_spot_keys : k_point_keys))
            return;
        get_point(c, j, "position", l.position, true);
        get_color(c, j, "intensity", l.color, true, SCENE_MAX_POWER);
        get_num_in(c, j, "diameter", &l.size, 0.f, false, SCENE_MAX_COORD);
        glm_vec3_copy((vec3){0, -1, 0}, l.direction);
        if (l.type == LIGHT_SPOT) {
            get_dir(c, j, "direction", l.direction, true);
            float inner = 30, outer = 35;
            get_num(c, j, "inner_deg", &inner);
            get_num(c, j, "outer_deg", &outer);
            if (!(inner >= 0 && outer > inner && outer < 90))
                bad(c, NULL, "need 0 <= inner_deg < outer_deg < 90");
            l.spot_inner = glm_rad(inner);
            l.spot_outer = glm_rad(outer);
        }
    } else if (strcmp(t, "quad") == 0) {
        l.type = LIGHT_QUAD;
        if (!check_keys(c, j, k_quad_light_keys))
            return;
        get_point(c, j, "position", l.position, true);
        get_dir(c, j, "direction", l.direction, true);
        get_color(c, j, "radiance", l.color, true, SCENE_MAX_POWER);
        get_point(c, j, "u", l.quad_u, true);
        get_point(c, j, "v", l.quad_v, true);
        l.size = 1.0f;
        get_num_in(c, j, "size", &l.size, 0.f, false, 1e3f);
        if (c->ok) {
            /* Non-degenerate, and L·A and the emitter's L/size² finite. */
            vec3 n;
            glm_vec3_cross(l.quad_u, l.quad_v, n);
            double area = glm_vec3_norm(n), lmax = fmax(fmax(l.color[0], l.color[1]), l.color[2]);
            if (!(area > 1e-12))
                bad(c, NULL, "u and v span no area (parallel or zero)");
            else if (!(area * lmax <= SCENE_MAX_POWER))
                bad(c, NULL, "radiance x area = %g W/sr exceeds the limit of %g", area * lmax,
                    (double)SCENE_MAX_POWER);
            else if (l.size > 0.f && !(lmax / ((double)l.size * l.size) <= SCENE_MAX_POWER))
                bad(c, "size", "%g makes the emitted radiance exceed %g", (double)l.size, (double)SCENE_MAX_POWER);
        }
    } else {
        (void)k_light_common;
        bad(c, "type", "unknown light type \"%s\" (directional, spot, point, quad)", t);
        return;
    }
    if (c->ok && scene_add_light(s, &l) < 0)
        c->ok = false; /* logged */
}

static const char *const k_camera_keys[] = {"position", "target", "forward", "up", "fov_y_deg", "near", "far", NULL};

static void parse_camera(Ctx *c, Scene *s, const cJSON *j)
{
    set_where(c, "camera", 0);
    if (!cJSON_IsObject(j)) {
        bad(c, NULL, "must be an object");
        return;
    }
    if (!check_keys(c, j, k_camera_keys))
        return;
    Camera *cam = &s->camera;
    get_point(c, j, "position", cam->position, true);
    vec3 target;
    if (cJSON_GetObjectItemCaseSensitive(j, "target") && cJSON_GetObjectItemCaseSensitive(j, "forward")) {
        bad(c, NULL, "give \"target\" or \"forward\", not both");
        return;
    }
    if (get_point(c, j, "target", target, false))
        glm_vec3_sub(target, cam->position, cam->forward);
    else if (c->ok)
        get_dir(c, j, "forward", cam->forward, true);
    vec3 up = {0, 1, 0}, right;
    get_dir(c, j, "up", up, false);
    if (!c->ok)
        return;
    if (!(glm_vec3_norm(cam->forward) > 1e-6f)) {
        bad(c, NULL, "forward/target gives a zero direction (position equals target)");
        return;
    }
    glm_vec3_normalize(cam->forward);
    glm_vec3_normalize(up);
    glm_vec3_cross(cam->forward, up, right);
    if (!(glm_vec3_norm(right) > 1e-4f)) {
        bad(c, "up", "is parallel to the view direction");
        return;
    }
    glm_vec3_normalize(right);
    glm_vec3_cross(right, cam->forward, cam->up);
    float fov = glm_deg(cam->fov_y);
    get_num(c, j, "fov_y_deg", &fov);
    if (c->ok && !(fov > 1 && fov < 179))
        bad(c, "fov_y_deg", "%g: must be in (1, 179)", (double)fov);
    cam->fov_y = glm_rad(fov);
    get_num_in(c, j, "near", &cam->znear, 0.f, true, SCENE_MAX_COORD);
    get_num_in(c, j, "far", &cam->zfar, 0.f, true, SCENE_MAX_COORD);
    if (c->ok && !(cam->zfar > cam->znear * 1.0001f))
        bad(c, NULL, "need 0 < near < far (near %g, far %g)", (double)cam->znear, (double)cam->zfar);
}

static const char *const k_quad_keys[] = {"albedo", "vertices", NULL};

static void parse_quads(Ctx *c, Scene *s, const cJSON *arr)
{
    if (!cJSON_IsArray(arr)) {
        bad(c, "quads", "must be an array of objects");
        return;
    }
    if (cJSON_GetArraySize(arr) > SCENE_MAX_QUADS) {
        bad(c, "quads", "%d quads is more than the limit of %d", cJSON_GetArraySize(arr), SCENE_MAX_QUADS);
        return;
    }
    int i = 0;
    const cJSON *q;
    cJSON_ArrayForEach(q, arr)
    {
        set_where(c, "quads[%d]", i);
        if (!cJSON_IsObject(q)) {
            bad(c, NULL, "must be an object");
            return;
        }
        if (!check_keys(c, q, k_quad_keys))
            return;
        vec3 albedo = {0.8f, 0.8f, 0.8f};
        get_color(c, q, "albedo", albedo, false, 1.f);
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(q, "vertices");
        if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 4) {
            bad(c, "vertices", "must hold 4 points");
            return;
        }
        vec3 p[4];
        for (int k = 0; k < 4 && c->ok; k++) {
            const cJSON *e = cJSON_GetArrayItem(v, k);
            if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 3) {
                bad(c, "vertices", "vertex %d is not 3 numbers", k);
                return;
            }
            for (int d = 0; d < 3 && c->ok; d++) {
                const cJSON *x = cJSON_GetArrayItem(e, d);
                if (!cJSON_IsNumber(x)) {
                    bad(c, "vertices", "vertex %d is not 3 numbers", k);
                    return;
                }
                char key[32];
                snprintf(key, sizeof key, "vertices[%d]", k);
                if (to_float(c, key, x, d, &p[k][d]) && fabsf(p[k][d]) > SCENE_MAX_COORD)
                    bad(c, "vertices", "vertex %d: %g is beyond the limit of %g m", k, (double)p[k][d],
                        (double)SCENE_MAX_COORD);
            }
        }
        if (!c->ok)
            return;
        /* Both triangles (p0 p1 p2, p0 p2 p3) must have an area. */
        vec3 e1, e2, e3, n1, n2;
        glm_vec3_sub(p[1], p[0], e1);
        glm_vec3_sub(p[2], p[0], e2);
        glm_vec3_sub(p[3], p[0], e3);
        glm_vec3_cross(e1, e2, n1);
        glm_vec3_cross(e2, e3, n2);
        if (!(glm_vec3_norm(n1) > 1e-12f && glm_vec3_norm(n2) > 1e-12f && glm_vec3_norm(e1) > 1e-6f &&
              glm_vec3_norm(e3) > 1e-6f)) {
            bad(c, "vertices", "the quad is degenerate (no area)");
            return;
        }
        char name[32];
        snprintf(name, sizeof name, "quad%d", i);
        int m = scene_add_material(s, name, albedo);
        if (m < 0 || !scene_add_quad(s, m, p[0], p[1], p[2], p[3])) {
            c->ok = false; /* logged */
            return;
        }
        i++;
    }
    c->where[0] = 0;
}

static const char *const k_material_keys[] = {"base_color", "metallic", "roughness", "specular", "emission", NULL};

/* The "materials" object: per material name (a mesh's material, a built-in
 * surface such as the Cornell box's "tall_block", or "quad<i>"), any of
 * base_color, metallic, roughness, specular (dielectric F0 = 0.04 ×
 * specular; 0 is Lambertian) and emission, replacing what the scene had. */
static void parse_materials(Ctx *c, Scene *s, const cJSON *obj)
{
    if (!cJSON_IsObject(obj)) {
        bad(c, "materials", "must be an object of material name -> parameters");
        return;
    }
    const cJSON *e;
    cJSON_ArrayForEach(e, obj)
    {
        snprintf(c->where, sizeof c->where, "materials.%.40s", e->string);
        if (!cJSON_IsObject(e)) {
            bad(c, NULL, "must be an object");
            return;
        }
        if (!check_keys(c, e, k_material_keys))
            return;
        int found = 0;
        for (int i = 0; i < s->material_count && c->ok; i++) {
            Material *m = &s->materials[i];
            if (m->light_index >= 0 || strcmp(m->name, e->string) != 0)
                continue;
            found++;
            get_color(c, e, "base_color", m->albedo, false, 1.f);
            get_num_in(c, e, "metallic", &m->metallic, 0.f, false, 1.f);
            get_num_in(c, e, "roughness", &m->roughness, 0.f, false, 1.f);
            get_num_in(c, e, "specular", &m->specular, 0.f, false, 1.f);
            get_color(c, e, "emission", m->emission, false, SCENE_MAX_POWER);
        }
        if (c->ok && !found) {
            char names[256] = "";
            for (int i = 0; i < s->material_count && strlen(names) < 200; i++)
                snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? ", " : "",
                         s->materials[i].name);
            bad(c, NULL, "no material of that name in the scene (it has: %s)", names);
            return;
        }
    }
    c->where[0] = 0;
}

/* The settings' objects ("shadow", "rsm", ..., and the old "gi"): the
 * settings table's one parser. */
static void parse_settings(Ctx *c, Scene *s, const cJSON *root)
{
    Settings set = {s->settings.shadow, s->settings.gi};
    if (!settings_parse_scene(root, c->file, &set)) {
        c->ok = false;
        return;
    }
    s->settings.shadow = set.shadow;
    s->settings.gi = set.gi;
}

/* With the settings' objects (settings_scene_keys). */
static const char *const k_top_keys[] = {"builtin", "mesh",   "mesh_scale", "mesh_translate", "quads",     "materials",
                                         "camera",  "lights", "exposure",   "objects",        "animation", NULL};

/* What most likely broke JSON text where the parser stopped (*at, cJSON's
 * error position), the mistakes people make by hand: a comma before a
 * closing bracket, a missing comma, an unclosed string or bracket. *at
 * moves to the place to point at (the stray comma). */
static const char *json_syntax_hint(const char *text, const char **at)
{
    const char *p = *at, *prev;
    /* cJSON stops past a closing bracket or an opening single quote that
     * it could not take: the character to blame is the one before. */
    if (p > text && strchr("}]'", p[-1]) && (!*p || isspace((unsigned char)*p) || isalnum((unsigned char)*p)))
        p--;
    *at = prev = p;
    while (prev > text && strchr(" \t\r\n", prev[-1]))
        prev--;
    char before = prev > text ? prev[-1] : 0;
    if (!*p)
        return "the file ends inside a value (a '}', ']' or '\"' is missing)";
    if (before == ',' && (*p == '}' || *p == ']')) {
        *at = prev - 1;
        return *p == '}' ? "a comma before '}' (JSON allows no trailing comma)"
                         : "a comma before ']' (JSON allows no trailing comma)";
    }
    if (*p == '"' && before && strchr("\"0123456789el}]", before))
        return "a ',' is missing before this member";
    if ((*p == '{' || *p == '[' || isdigit((unsigned char)*p) || *p == '-') && before && strchr("\"0123456789el}]", before))
        return "a ',' is missing before this value";
    if (*p == '\'')
        return "strings take double quotes (\"...\"), not single ones";
    if (*p == '/' || *p == '#')
        return "JSON has no comments";
    if (isalpha((unsigned char)*p))
        return "a bare word: keys and strings take double quotes; values may be numbers, true, false or null";
    return "unexpected character here";
}

/* The file parsed, a JSON object; NULL (logged with the line and column
 * where the JSON broke, and what most likely broke it) if not. */
static cJSON *read_json(const char *path)
{
    char *text = util_read_input("scene", "scene file", path, SCENE_MAX_BYTES, NULL);
    if (!text)
        return NULL;
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(text, &end, 1);
    if (!root) {
        const char *at = end ? end : text, *why = json_syntax_hint(text, &at);
        int line = 1, col = 1;
        for (const char *p = text; p < at && *p; p++) {
            if (*p == '\n') {
                line++;
                col = 1;
            } else {
                col++;
            }
        }
        log_error("scene", "%s:%d:%d: malformed JSON: %s", path, line, col, why);
    } else if (!cJSON_IsObject(root)) {
        log_error("scene", "%s: top level must be a JSON object", path);
        cJSON_Delete(root);
        root = NULL;
    }
    free(text);
    return root;
}

/* "builtin", then "mesh" (a path relative to the file's directory dir,
 * placed by "mesh_scale" and "mesh_translate"), then "quads": at least one
 * of them. */
static void parse_geometry(Ctx *c, Scene *s, const cJSON *root, const char *dir, SceneNodeMap *nodes)
{
    const cJSON *builtin = cJSON_GetObjectItemCaseSensitive(root, "builtin");
    const cJSON *mesh = cJSON_GetObjectItemCaseSensitive(root, "mesh");
    if (builtin && !cJSON_IsString(builtin))
        bad(c, "builtin", "must be a string (cornell)");
    else if (builtin && strcmp(builtin->valuestring, "cornell") != 0)
        bad(c, "builtin", "unknown builtin scene \"%s\" (cornell)", builtin->valuestring);
    else if (builtin && !scene_build_cornell(s))
        c->ok = false; /* logged */
    if (!c->ok)
        return;
    if (mesh && !cJSON_IsString(mesh)) {
        bad(c, "mesh", "must be a file path");
    } else if (mesh) {
        char mesh_path[1024];
        util_join_path(dir, mesh->valuestring, mesh_path, sizeof mesh_path);
        mat4 xf = GLM_MAT4_IDENTITY_INIT;
        float scale = 1.f;
        vec3 tr = {0, 0, 0};
        get_num_in(c, root, "mesh_scale", &scale, 0.f, true, SCENE_MAX_COORD);
        get_point(c, root, "mesh_translate", tr, false);
        glm_translate(xf, tr);
        glm_scale_uni(xf, scale);
        if (c->ok && !scene_load_mesh_nodes(s, mesh_path, xf, animation_wants_nodes(root) ? nodes : NULL))
            c->ok = false; /* logged */
    } else if (cJSON_GetObjectItemCaseSensitive(root, "mesh_scale") ||
               cJSON_GetObjectItemCaseSensitive(root, "mesh_translate")) {
        bad(c, cJSON_GetObjectItemCaseSensitive(root, "mesh_scale") ? "mesh_scale" : "mesh_translate",
            "given without \"mesh\"");
    }
    const cJSON *quads = cJSON_GetObjectItemCaseSensitive(root, "quads");
    if (quads && c->ok)
        parse_quads(c, s, quads);
    if (s->vertex_count == 0 && c->ok)
        bad(c, NULL, "no geometry (give \"builtin\", \"mesh\" or \"quads\")");
}

/* "lights": they replace a builtin scene's. */
static void parse_lights(Ctx *c, Scene *s, const cJSON *lights)
{
    if (!cJSON_IsArray(lights)) {
        bad(c, "lights", "must be an array");
    } else if (cJSON_GetArraySize(lights) > SCENE_MAX_LIGHTS) {
        bad(c, "lights", "%d lights is more than the limit of %d", cJSON_GetArraySize(lights), SCENE_MAX_LIGHTS);
    } else {
        s->light_count = 0;
        int i = 0;
        const cJSON *l;
        cJSON_ArrayForEach(l, lights) parse_light(c, s, l, i++);
        c->where[0] = 0;
    }
}

static bool load_json(Scene *s, const char *path)
{
    cJSON *root = read_json(path);
    if (!root)
        return false;
    Ctx c = {path, true, ""};
    char dir[1024];
    util_dirname(path, dir, sizeof dir);
    SceneNodeMap nodes = {0};
    const char *top_keys[64];
    int top_count = 0;
    for (; k_top_keys[top_count]; top_count++)
        top_keys[top_count] = k_top_keys[top_count];
    settings_scene_keys(top_keys, &top_count, 64);
    if (check_keys(&c, root, top_keys))
        parse_geometry(&c, s, root, dir, &nodes);
    if (c.ok)
        snprintf(s->source, sizeof s->source, "%s", path);
    const cJSON *materials = cJSON_GetObjectItemCaseSensitive(root, "materials");
    if (materials && c.ok)
        parse_materials(&c, s, materials);
    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    if (lights && c.ok)
        parse_lights(&c, s, lights);
    if (c.ok)
        get_num_in(&c, root, "exposure", &s->exposure, SCENE_EXPOSURE_MIN, false, SCENE_EXPOSURE_MAX);
    if (c.ok)
        parse_settings(&c, s, root);
    const cJSON *cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    bool has_camera = cam != NULL || cJSON_IsString(cJSON_GetObjectItemCaseSensitive(root, "builtin"));
    if (cam && c.ok)
        parse_camera(&c, s, cam);
    bool ok = c.ok && (s->light_count > 0 || scene_add_default_sun(s)) && scene_finalize(s);
    if (ok && !has_camera)
        scene_default_camera(s);
    /* Named objects and keyframe tracks (animation.c), once the scene is
     * whole: the objects' transforms and the state at t = 0 put in place. */
    ok = ok && animation_parse(s, root, path, &nodes);
    scene_node_map_free(&nodes);
    cJSON_Delete(root);
    return ok; /* else logged; the caller frees the scene */
}

const char *scene_builtin_near(const char *what)
{
    static const char *const builtins[] = {"cornell", NULL};
    if (strchr(what, '/') || strchr(what, '.') || !strcmp(what, "cornell"))
        return NULL;
    const char *near = util_nearest(what, builtins);
    return near && access(what, F_OK) != 0 ? near : NULL;
}

static bool load_any(Scene *s, const char *what)
{
    if (strcmp(what, "cornell") == 0) {
        if (scene_build_cornell(s) && scene_finalize(s))
            return true;
        scene_free(s); /* each logged its failure */
        return false;
    }
    const char *near = scene_builtin_near(what);
    if (near) {
        log_error("scene", "%s: no such file or built-in scene; did you mean '%s'?", what, near);
        scene_init(s);
        return false;
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
    s->settings.shadow.map_size = 2048; /* a sun over a whole model needs the texels */
    s->exposure = 8.f;         /* a 4 W/m² sun, most of the view in its bounce light */
    if (!scene_add_default_sun(s) || !scene_finalize(s)) {
        scene_free(s); /* logged */
        return false;
    }
    scene_default_camera(s);
    return true;
}

bool scene_load(Scene *s, const char *what)
{
    if (!load_any(s, what))
        return false;
    if (scene_check_view(s))
        return true;
    scene_free(s);
    return false;
}

bool scene_load_scaled(Scene *s, const char *what, float light_scale)
{
    if (!scene_load(s, what))
        return false;
    if ((light_scale < 0.f || scene_rescale_lights(s, light_scale)) &&
        scene_check_lights(s, light_scale >= 0.f ? ", after --light-scale" : ""))
        return true;
    scene_free(s);
    return false;
}
