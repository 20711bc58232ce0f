/* mesh.c - mesh files read with assimp (Debian's libassimp), flattened to one triangle list.
 *
 * assimp is not hardened against hostile files (a 21-byte PLY spins forever, a
 * misspelled PLY property type aborts in an assertion, a 1 KB glTF of nested instances
 * builds 5.8 GB, one OBJ polygon of 100k vertices is triangulated in quadratic time), so it
 * runs only in a child process, as OpenVDB does (io/sandbox.h): CPU time 5 s + 2 s per MiB
 * of file, wall clock twice that plus 5 s, address space 512 MiB (libraries) + what
 * render.max_memory_mb leaves (everything assimp builds, instances flattened included, must
 * fit there), no core file. Its answer comes back on a pipe:
 *   'E' status (int32) length (uint32) message    an error, reported as is
 *   'M' nv (int64) ntri (int64) pos (3 nv doubles) idx (3 ntri int32)
 * and the parent checks the counts against its own limits and every index before using
 * them. Before forking, the file is checked for what is cheap to see: a PLY header that
 * ends, with known property types, and whose binary body is there; OBJ polygons of at most
 * MESH_MAX_POLYGON vertices.
 *
 * libassimp is opened by its SONAME (BRUME_ASSIMP_SONAME, read from the library CMake found)
 * when the first mesh is read, not linked: with its draco and minizip it made the dynamic
 * loader bind some 44,000 symbols at every brume process's start, for the few scenes with
 * mesh files (docs/performance.md, "Start-up"). The functions keep the header's types. */
#include "io/mesh.h"

#include <assimp/cimport.h>
#include <stdint.h>
#include <unistd.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/error.h"
#include "core/lazylib.h"
#include "core/number.h"
#include "io/json.h"
#include "core/regular_file.h"
#include "io/sandbox.h"

#define MESH_MAX_TRIANGLES 200000000L
#define MESH_MAX_POLYGON 4096 /* vertices of one face: assimp's ear clipping is quadratic */

#ifndef BRUME_ASSIMP_SONAME
#define BRUME_ASSIMP_SONAME "libassimp.so.5"
#endif

#define ASSIMP_FUNCTIONS(X) X(aiImportFile) X(aiGetErrorString) X(aiReleaseImport)

static struct {
    ASSIMP_FUNCTIONS(LAZYLIB_POINTER)
} ai;
static const char *const ai_names[] = {ASSIMP_FUNCTIONS(LAZYLIB_NAME) NULL};
static const char *const ai_sonames[] = {BRUME_ASSIMP_SONAME, NULL};
static lazylib ai_lib = LAZYLIB("assimp", ai_sonames, ai_names, &ai, sizeof ai);

static int ply_type_size(const char *t)
{
    static const struct {
        const char *name;
        int size;
    } types[] = {{"char", 1},   {"uchar", 1},  {"int8", 1},   {"uint8", 1},   {"short", 2},  {"ushort", 2},
                 {"int16", 2},  {"uint16", 2}, {"int", 4},    {"uint", 4},    {"int32", 4},  {"uint32", 4},
                 {"float", 4},  {"float32", 4}, {"double", 8}, {"float64", 8}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(t, types[i].name) == 0)
            return types[i].size;
    return 0;
}

/* The elements of a PLY header: each one's count and which of its properties are lists. */
#define PLY_MAX_ELEMENTS 16
#define PLY_MAX_PROPERTIES 64
typedef struct ply_layout {
    int n;
    double count[PLY_MAX_ELEMENTS];
    int props[PLY_MAX_ELEMENTS];
    bool list[PLY_MAX_ELEMENTS][PLY_MAX_PROPERTIES];
} ply_layout;

/* An ASCII PLY body must hold every value its header announces, each a number, and each list
 * as many values as its count says (assimp takes a short last face, or a count of 255 with
 * three indices, and reads what is not there). */
static brume_status ply_check_text(FILE *f, const char *path, const ply_layout *L)
{
    char tok[128];
    for (int e = 0; e < L->n; e++)
        for (double i = 0; i < L->count[e]; i++)
            for (int p = 0; p < L->props[e]; p++) {
                double v = 0.0;
                char *end;
                if (fscanf(f, "%127s", tok) != 1 || ((v = num_strtod(tok, &end)), *end != '\0') || !isfinite(v))
                    return err_set(BRUME_ERROR_PARSE, "%s: the PLY text ends before element %d's item %.0f, or holds "
                                   "'%s' where a number belongs", path, e, i, feof(f) ? "" : tok);
                if (!L->list[e][p])
                    continue;
                if (!(v >= 0.0 && v <= 1e6 && v == floor(v)))
                    return err_set(BRUME_ERROR_PARSE, "%s: a PLY list of %s values", path, tok);
                for (double k = 0; k < v; k++)
                    if (fscanf(f, "%127s", tok) != 1 || ((void)num_strtod(tok, &end), *end != '\0'))
                        return err_set(BRUME_ERROR_PARSE, "%s: a PLY list shorter than its count of %.0f", path, v);
            }
    return BRUME_OK;
}

/* One header line of an element or a property into L: BRUME_OK, or an error at line no. */
static brume_status ply_header_line(const char *line, const char *path, int no, ply_layout *L, double *need,
                                    double *elem)
{
    char a[64], b[64], c[64];
    double v = 0.0;
    if (sscanf(line, "element %63s %lf", a, &v) == 2) {
        *need += L->n > 0 ? L->count[L->n - 1] * *elem : 0.0;
        if (L->n == PLY_MAX_ELEMENTS || !(v >= 0.0 && v <= 1e12))
            return err_set(BRUME_ERROR_PARSE, "%s: PLY header line %d: more than %d elements, or a count of %.0f",
                           path, no, PLY_MAX_ELEMENTS, v);
        L->count[L->n] = v;
        L->props[L->n++] = 0;
        *elem = 0.0;
        return BRUME_OK;
    }
    bool list = sscanf(line, "property list %63s %63s %63s", a, b, c) == 3;
    if (!list && sscanf(line, "property %63s %63s", a, b) != 2)
        return BRUME_OK; /* comment, obj_info */
    if (!ply_type_size(a) || (list && !ply_type_size(b)))
        return err_set(BRUME_ERROR_PARSE, "%s: PLY header line %d: unknown property type '%s'", path, no,
                       ply_type_size(a) ? b : a);
    if (L->n == 0 || L->props[L->n - 1] == PLY_MAX_PROPERTIES)
        return err_set(BRUME_ERROR_PARSE, "%s: PLY header line %d: a property outside an element, or more than %d",
                       path, no, PLY_MAX_PROPERTIES);
    L->list[L->n - 1][L->props[L->n - 1]++] = list;
    *elem += ply_type_size(a); /* a list: at least its length */
    return BRUME_OK;
}

/* A binary PLY file must hold at least the bytes its header announces (assimp reads past
 * the end of a truncated one), a text one every value it announces; BRUME_OK for anything
 * else, which assimp checks itself. */
static brume_status ply_check(FILE *f, const char *path, long file_size)
{
    char line[512];
    rewind(f);
    if (!fgets(line, sizeof line, f) || strncmp(line, "ply", 3) != 0)
        return BRUME_OK;
    bool binary = false;
    double need = 0.0, elem = 0.0;
    ply_layout L = {0};
    brume_status st;
    for (int n = 0; n < 10000 && fgets(line, sizeof line, f); n++) {
        char a[64], b[64], c[64];
        if (sscanf(line, "format %63s %63s", a, b) >= 1) {
            binary = strncmp(a, "binary", 6) == 0;
            bool known = strcmp(a, "ascii") == 0 || strcmp(a, "binary_little_endian") == 0 ||
                         strcmp(a, "binary_big_endian") == 0;
            if (!known || sscanf(line, "format %*s %63s %63s", b, c) != 1 || strcmp(b, "1.0") != 0)
                return err_set(BRUME_ERROR_PARSE, "%s: PLY header line %d: expected format ascii, "
                               "binary_little_endian or binary_big_endian, version 1.0", path, n + 2);
        } else if (strncmp(line, "end_header", 10) == 0) {
            need += L.n > 0 ? L.count[L.n - 1] * elem : 0.0;
            long body = file_size - ftell(f), at = ftell(f);
            if (binary && !(need <= (double)body))
                return err_set(BRUME_ERROR_PARSE, "%s: truncated: the PLY header announces at least %.0f bytes, the "
                               "file holds %ld", path, need, body);
            for (int ch; !binary && (ch = fgetc(f)) != EOF;)
                if (ch == '\0') /* assimp skips them: a text body holds none */
                    return err_set(BRUME_ERROR_PARSE, "%s: a NUL byte in the text of a PLY file", path);
            return binary || fseek(f, at, SEEK_SET) != 0 ? BRUME_OK : ply_check_text(f, path, &L);
        } else if ((st = ply_header_line(line, path, n + 2, &L, &need, &elem)) != BRUME_OK) {
            return st;
        }
    }
    /* assimp's PLY reader spins on a header that never ends ("ply\nformat ascii 1.0\n") */
    return err_set(BRUME_ERROR_PARSE, "%s: a PLY header without end_header", path);
}

/* OBJ faces of at most MESH_MAX_POLYGON vertices (assimp triangulates a polygon in time
 * quadratic in its vertices); BRUME_OK for files that are not OBJ. One pass over the file. */
static brume_status obj_check(FILE *f, const char *path)
{
    size_t n = strlen(path);
    if (n < 4 || (strcmp(path + n - 4, ".obj") != 0 && strcmp(path + n - 4, ".OBJ") != 0))
        return BRUME_OK;
    rewind(f);
    long line = 1, tokens = 0;
    int c, prev = '\n';
    bool face = false, in_token = false;
    while ((c = getc(f)) != EOF) {
        if (c == '\n') {
            if (face && tokens - 1 > MESH_MAX_POLYGON)
                return err_set(BRUME_ERROR_RANGE, "%s: line %ld: a face of %ld vertices, over the %d brume triangulates",
                               path, line, tokens - 1, MESH_MAX_POLYGON);
            line++;
            face = in_token = false;
            tokens = 0;
        } else if (c == ' ' || c == '\t' || c == '\r') {
            in_token = false;
        } else {
            if (prev == '\n')
                face = c == 'f';
            if (!in_token)
                tokens++;
            in_token = true;
            if (prev == '\n' && c == 'f') {
                int d = getc(f); /* "f " starts a face; "fo..." is another statement */
                face = d == ' ' || d == '\t';
                if (d == EOF)
                    break;
                ungetc(d, f);
            }
        }
        prev = c;
    }
    if (face && tokens - 1 > MESH_MAX_POLYGON)
        return err_set(BRUME_ERROR_RANGE, "%s: line %ld: a face of %ld vertices, over the %d brume triangulates", path,
                       line, tokens - 1, MESH_MAX_POLYGON);
    return BRUME_OK;
}

/* Vertices one instance of glTF node n stands for, itself and its subtree: its mesh's
 * POSITION counts, its children's again for each child (a node named by several parents is
 * counted once per parent, as assimp's flattening copies it). -1 on a cycle or a bad index. */
static double gltf_node_vertices(const cJSON *nodes, const cJSON *meshes, const cJSON *accessors, int n, double *memo,
                                 int depth)
{
    int count = cJSON_GetArraySize(nodes);
    if (n < 0 || n >= count || depth > 64)
        return -1.0;
    if (memo[n] >= 0.0)
        return memo[n];
    const cJSON *node = cJSON_GetArrayItem(nodes, n);
    double v = 0.0;
    const cJSON *mi = cJSON_GetObjectItemCaseSensitive(node, "mesh");
    const cJSON *mesh = cJSON_IsNumber(mi) ? cJSON_GetArrayItem(meshes, mi->valueint) : NULL;
    const cJSON *prims = mesh ? cJSON_GetObjectItemCaseSensitive(mesh, "primitives") : NULL;
    const cJSON *p;
    cJSON_ArrayForEach(p, prims)
    {
        const cJSON *attr = cJSON_GetObjectItemCaseSensitive(p, "attributes");
        const cJSON *pos = attr ? cJSON_GetObjectItemCaseSensitive(attr, "POSITION") : NULL;
        const cJSON *acc = cJSON_IsNumber(pos) ? cJSON_GetArrayItem(accessors, pos->valueint) : NULL;
        const cJSON *c = acc ? cJSON_GetObjectItemCaseSensitive(acc, "count") : NULL;
        if (cJSON_IsNumber(c) && c->valuedouble > 0)
            v += c->valuedouble;
    }
    const cJSON *ch;
    cJSON_ArrayForEach(ch, cJSON_GetObjectItemCaseSensitive(node, "children"))
    {
        double w = cJSON_IsNumber(ch) ? gltf_node_vertices(nodes, meshes, accessors, ch->valueint, memo, depth + 1) : -1;
        if (w < 0.0)
            return -1.0;
        v += w;
    }
    return memo[n] = v;
}

/* The JSON of a glTF file, malloc'd and NUL-terminated: the whole of a .gltf, the first
 * chunk of a .glb (binary glTF 2.0: "glTF", version, length, then the JSON chunk's length
 * and type "JSON"); NULL for other files, or one too large to parse here (the child's limits
 * hold). */
static char *gltf_json(FILE *f, const char *path, long file_size)
{
    size_t n = strlen(path);
    bool text = n >= 5 && strcmp(path + n - 5, ".gltf") == 0, binary = n >= 4 && strcmp(path + n - 4, ".glb") == 0;
    if ((!text && !binary) || file_size <= 0 || (size_t)file_size > budget_left())
        return NULL;
    size_t offset = 0, len = (size_t)file_size;
    rewind(f);
    if (binary) {
        uint32_t h[5];
        if (fread(h, sizeof h, 1, f) != 1 || memcmp(h, "glTF", 4) != 0 || memcmp(h + 4, "JSON", 4) != 0 ||
            h[3] > (uint64_t)file_size - sizeof h)
            return NULL; /* assimp says what is wrong (the header is little-endian, as this machine) */
        offset = sizeof h;
        len = h[3];
    }
    char *json = malloc(len + 1);
    if (!json || fseek(f, (long)offset, SEEK_SET) != 0 || fread(json, 1, len, f) != len) {
        free(json);
        return NULL;
    }
    json[len] = '\0';
    return json;
}

/* A glTF file (.gltf or .glb): the vertices its scenes make once assimp has copied every
 * instance (aiProcess_PreTransformVertices) must fit in the memory budget, at about 100
 * bytes each in assimp (positions, normals, the copies) -- refused before assimp builds them
 * (a 1 KB file of 4 levels x 50 children would build 5.8 GB). BRUME_OK for other files:
 * formats without instancing (PLY, OBJ, STL) build what their size says, and the others are
 * bounded by the child's address space and CPU time. */
static brume_status gltf_check(FILE *f, const char *path, long file_size)
{
    char *text = gltf_json(f, path, file_size);
    if (!text)
        return BRUME_OK;
    cJSON *doc = cJSON_Parse(text);
    free(text);
    if (!doc)
        return BRUME_OK; /* assimp says what is wrong */
    const cJSON *nodes = cJSON_GetObjectItemCaseSensitive(doc, "nodes");
    int count = cJSON_GetArraySize(nodes);
    double *memo = count > 0 ? malloc((size_t)count * sizeof *memo) : NULL;
    double total = 0.0;
    for (int i = 0; i < count && memo; i++)
        memo[i] = -1.0;
    const cJSON *sc;
    cJSON_ArrayForEach(sc, cJSON_GetObjectItemCaseSensitive(doc, "scenes"))
    {
        const cJSON *r;
        cJSON_ArrayForEach(r, cJSON_GetObjectItemCaseSensitive(sc, "nodes"))
        {
            double v = memo && cJSON_IsNumber(r)
                           ? gltf_node_vertices(nodes, cJSON_GetObjectItemCaseSensitive(doc, "meshes"),
                                                cJSON_GetObjectItemCaseSensitive(doc, "accessors"), r->valueint, memo, 0)
                           : -1.0;
            total += v > 0.0 ? v : 0.0;
        }
    }
    free(memo);
    cJSON_Delete(doc);
    double bytes = 100.0 * total;
    if (bytes > (double)budget_left())
        return err_set(BRUME_ERROR_OUT_OF_MEMORY,
                       "%s: its instances flattened make %.3g vertices, about %.3g bytes in assimp, over the %zu bytes "
                       "render.max_memory_mb leaves",
                       path, total, bytes, budget_left());
    return BRUME_OK;
}

/* In the child: assimp's import of path flattened to one triangle list (malloc'd). */
/* The texture coordinates (u, v) of every vertex, in mesh_import's order (2 nv, malloc'd), when
 * every mesh of the file has a first set of them; else NULL. */
static double *mesh_uv(const struct aiScene *sc, long nv)
{
    for (unsigned m = 0; m < sc->mNumMeshes; m++)
        if (!sc->mMeshes[m]->mTextureCoords[0])
            return NULL;
    double *uv = malloc(sizeof *uv * 2 * (size_t)nv);
    long k = 0;
    for (unsigned m = 0; uv && m < sc->mNumMeshes; m++)
        for (unsigned v = 0; v < sc->mMeshes[m]->mNumVertices; v++, k++) {
            uv[2 * k] = (double)sc->mMeshes[m]->mTextureCoords[0][v].x;
            uv[2 * k + 1] = (double)sc->mMeshes[m]->mTextureCoords[0][v].y;
        }
    return uv;
}

static brume_status mesh_import(const char *path, long file_size, double **pos_out, long *nv_out, int **idx_out,
                                long *ntri_out, double **uv_out)
{
    if (!lazylib_open(&ai_lib))
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: mesh files need assimp: %s", path, ai_lib.error);
    size_t import_bytes = file_size > 0 ? 2 * (size_t)file_size : 0;
    if (budget_take(import_bytes, path) != BRUME_OK)
        return err_status();
    const struct aiScene *sc = ai.aiImportFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                                      aiProcess_SortByPType);
    if (!sc)
        return err_set(BRUME_ERROR_PARSE, "%s: not a readable mesh: %s", path, ai.aiGetErrorString());
    long nv = 0, ntri = 0;
    for (unsigned m = 0; m < sc->mNumMeshes; m++) {
        const struct aiMesh *me = sc->mMeshes[m];
        nv += me->mNumVertices;
        for (unsigned f = 0; f < me->mNumFaces; f++)
            ntri += me->mFaces[f].mNumIndices == 3;
    }
    if (ntri == 0) {
        ai.aiReleaseImport(sc);
        return err_set(BRUME_ERROR_PARSE, "%s: no triangles in the file", path);
    }
    if (ntri > MESH_MAX_TRIANGLES || nv > 3 * MESH_MAX_TRIANGLES) {
        ai.aiReleaseImport(sc);
        budget_give(import_bytes);
        return err_set(BRUME_ERROR_RANGE, "%s: %ld triangles exceed the limit of %ld", path, ntri, MESH_MAX_TRIANGLES);
    }
    double *pos = malloc(sizeof *pos * 3 * (size_t)nv);
    int *idx = malloc(sizeof *idx * 3 * (size_t)ntri);
    if (!pos || !idx) {
        free(pos);
        free(idx);
        ai.aiReleaseImport(sc);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for %ld triangles", path, ntri);
    }
    long vbase = 0, t = 0;
    for (unsigned m = 0; m < sc->mNumMeshes; m++) {
        const struct aiMesh *me = sc->mMeshes[m];
        for (unsigned v = 0; v < me->mNumVertices; v++) {
            const struct aiVector3D *p = &me->mVertices[v];
            double x = (double)p->x, y = (double)p->y, z = (double)p->z;
            if (!isfinite(x) || !isfinite(y) || !isfinite(z)) {
                free(pos);
                free(idx);
                ai.aiReleaseImport(sc);
                return err_set(BRUME_ERROR_RANGE, "%s: vertex %ld has a non-finite coordinate", path, vbase + v);
            }
            pos[3 * (vbase + v)] = x;
            pos[3 * (vbase + v) + 1] = y;
            pos[3 * (vbase + v) + 2] = z;
        }
        for (unsigned f = 0; f < me->mNumFaces; f++) {
            const struct aiFace *fc = &me->mFaces[f];
            if (fc->mNumIndices != 3)
                continue; /* points and lines */
            for (int k = 0; k < 3; k++) {
                if (fc->mIndices[k] >= me->mNumVertices) {
                    free(pos);
                    free(idx);
                    ai.aiReleaseImport(sc);
                    return err_set(BRUME_ERROR_PARSE, "%s: face %u names a missing vertex", path, f);
                }
                idx[3 * t + k] = (int)(vbase + (long)fc->mIndices[k]);
            }
            t++;
        }
        vbase += me->mNumVertices;
    }
    *uv_out = mesh_uv(sc, nv);
    ai.aiReleaseImport(sc);
    *pos_out = pos;
    *idx_out = idx;
    *nv_out = nv;
    *ntri_out = ntri;
    return BRUME_OK;
}

/* The child: limits, the import, the answer on fd; never returns. */
static void mesh_child(const char *path, long file_size, int fd, double cpu, size_t max_memory)
{
    sandbox_child_limits(cpu, ((size_t)512 << 20) + max_memory);
    double *pos = NULL, *uv = NULL;
    int *idx = NULL;
    long nv = 0, ntri = 0;
    if (mesh_import(path, file_size, &pos, &nv, &idx, &ntri, &uv) != BRUME_OK) {
        sandbox_child_error(fd);
        _exit(0);
    }
    int64_t counts[3] = {nv, ntri, uv != NULL};
    if (sandbox_write_all(fd, "M", 1) || sandbox_write_all(fd, counts, sizeof counts) ||
        sandbox_write_all(fd, pos, sizeof *pos * 3 * (size_t)nv) || sandbox_write_all(fd, idx, sizeof *idx * 3 * (size_t)ntri) ||
        (uv && sandbox_write_all(fd, uv, sizeof *uv * 2 * (size_t)nv)))
        _exit(3);
    _exit(0);
}

/* The parent: reads the child's answer into *pos, *idx (malloc'd, counted in the budget) and,
 * when the file has them, the texture coordinates into *uv (else NULL). */
static brume_status mesh_receive(const char *path, int fd, double deadline, double **pos, long *nv, int **idx,
                                 long *ntri, double **uv, int *rr)
{
    char tag = 0;
    if ((*rr = sandbox_read_all(fd, &tag, 1, deadline)) != 0)
        return BRUME_OK; /* sandbox_reap says what happened */
    if (tag == 'E')
        return (*rr = sandbox_read_error(fd, deadline)) == 0 ? err_status() : BRUME_OK;
    int64_t counts[3];
    if (tag != 'M' || (*rr = sandbox_read_all(fd, counts, sizeof counts, deadline)) != 0) {
        *rr = *rr ? *rr : -1;
        return BRUME_OK;
    }
    if (counts[0] < 3 || counts[1] < 1 || counts[1] > MESH_MAX_TRIANGLES || counts[0] > 3 * MESH_MAX_TRIANGLES)
        return err_set(BRUME_ERROR_RANGE, "%s: %lld vertices and %lld triangles, outside brume's limits (%ld triangles)",
                       path, (long long)counts[0], (long long)counts[1], MESH_MAX_TRIANGLES);
    *nv = (long)counts[0];
    *ntri = (long)counts[1];
    /* the triangle list here and, about as large again, the ray-tracing hierarchy built on it */
    if (budget_take(2 * (sizeof(double) * 3 * (size_t)*nv + sizeof(int) * 3 * (size_t)*ntri), path) != BRUME_OK)
        return err_status();
    *pos = malloc(sizeof **pos * 3 * (size_t)*nv);
    *idx = malloc(sizeof **idx * 3 * (size_t)*ntri);
    if (!*pos || !*idx)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for %ld triangles", path, *ntri);
    if ((*rr = sandbox_read_all(fd, *pos, sizeof **pos * 3 * (size_t)*nv, deadline)) != 0 ||
        (*rr = sandbox_read_all(fd, *idx, sizeof **idx * 3 * (size_t)*ntri, deadline)) != 0)
        return BRUME_OK;
    for (size_t i = 0; i < 3 * (size_t)*nv; i++) /* the child is not trusted */
        if (!isfinite((*pos)[i]))
            return err_set(BRUME_ERROR_RANGE, "%s: vertex %zu has a non-finite coordinate", path, i / 3);
    for (size_t i = 0; i < 3 * (size_t)*ntri; i++)
        if ((*idx)[i] < 0 || (*idx)[i] >= *nv)
            return err_set(BRUME_ERROR_PARSE, "%s: triangle %zu names a missing vertex", path, i / 3);
    if (!counts[2])
        return BRUME_OK;
    if (!(*uv = malloc(sizeof **uv * 2 * (size_t)*nv)))
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for %ld texture coordinates", path, *nv);
    if ((*rr = sandbox_read_all(fd, *uv, sizeof **uv * 2 * (size_t)*nv, deadline)) != 0)
        return BRUME_OK;
    for (size_t i = 0; i < 2 * (size_t)*nv; i++)
        if (!((*uv)[i] >= -1e12 && (*uv)[i] <= 1e12))
            return err_set(BRUME_ERROR_RANGE, "%s: vertex %zu's texture coordinates are not finite", path, i / 2);
    return BRUME_OK;
}

brume_status mesh_load(const char *path, double **pos_out, int *nv_out, int **idx_out, int *ntri_out)
{
    return mesh_load_uv(path, pos_out, nv_out, idx_out, ntri_out, NULL);
}

brume_status mesh_load_uv(const char *path, double **pos_out, int *nv_out, int **idx_out, int *ntri_out,
                          double **uv_out)
{
    *pos_out = NULL;
    *idx_out = NULL;
    if (uv_out)
        *uv_out = NULL;
    FILE *probe = NULL; /* a regular file: assimp would block on a pipe */
    if (io_open_regular(path, &probe) != BRUME_OK)
        return err_status();
    long file_size = fseek(probe, 0, SEEK_END) == 0 ? ftell(probe) : -1;
    brume_status st = file_size > 0 ? ply_check(probe, path, file_size) : BRUME_OK;
    if (st == BRUME_OK)
        st = obj_check(probe, path);
    if (st == BRUME_OK)
        st = gltf_check(probe, path, file_size);
    fclose(probe);
    if (st != BRUME_OK)
        return st;
    /* assimp holds the whole file and more while it imports: a file larger than the memory
     * budget is refused unread (the child counts it again against its copy of the budget) */
    size_t import_bytes = file_size > 0 ? 2 * (size_t)file_size : 0;
    if (import_bytes > budget_left())
        return budget_take(import_bytes, path);
    double cpu = (5.0 + 2.0 * (double)(file_size > 0 ? file_size : 0) / 1048576.0) * (SANDBOX_ASAN ? 4.0 : 1.0);
    double wall = 2.0 * cpu + 5.0, deadline = sandbox_now() + wall;
    int fds[2];
    if (pipe(fds) != 0)
        return err_set(BRUME_ERROR_IO, "%s: cannot create a pipe: %s", path, strerror(errno));
    size_t max_memory = budget_left();
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: cannot start the mesh reader process: %s", path, strerror(errno));
    }
    if (pid == 0) {
        close(fds[0]);
        mesh_child(path, file_size, fds[1], cpu, max_memory);
    }
    close(fds[1]);
    double *pos = NULL, *uv = NULL;
    int *idx = NULL;
    long nv = 0, ntri = 0;
    int rr = 0;
    st = mesh_receive(path, fds[0], deadline, &pos, &nv, &idx, &ntri, &uv, &rr);
    close(fds[0]);
    brume_status reaped = sandbox_reap(pid, st == BRUME_OK ? rr : (rr == -2 || rr == -3 ? rr : 0), path, "the mesh reader",
                                       "a malformed or hostile mesh file", cpu, wall);
    if (st == BRUME_OK)
        st = reaped;
    if (st != BRUME_OK) {
        free(pos);
        free(idx);
        free(uv);
        return st;
    }
    if (uv_out)
        *uv_out = uv;
    else
        free(uv);
    *pos_out = pos;
    *idx_out = idx;
    *nv_out = (int)nv;
    *ntri_out = (int)ntri;
    return BRUME_OK;
}
