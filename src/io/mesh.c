/* mesh.c - mesh files read with assimp (Debian's libassimp), flattened to one triangle list.
 *
 * libassimp is opened by its SONAME (BRUME_ASSIMP_SONAME, read from the library CMake found)
 * when the first mesh is read, not linked: with its draco and minizip it made the dynamic
 * loader bind some 44,000 symbols at every brume process's start, for the few scenes with
 * mesh files (docs/performance.md, "Start-up"). The functions keep the header's types. */
#define _GNU_SOURCE /* dlopen flags in C11 */
#include "io/mesh.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <dlfcn.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/error.h"
#include "io/regular_file.h"

#define MESH_MAX_TRIANGLES 200000000L

#ifndef BRUME_ASSIMP_SONAME
#define BRUME_ASSIMP_SONAME "libassimp.so.5"
#endif

static struct {
    __typeof__(aiImportFile) *import_file;
    __typeof__(aiGetErrorString) *error_string;
    __typeof__(aiReleaseImport) *release;
} ai;
static char ai_error[512];
static pthread_once_t ai_once = PTHREAD_ONCE_INIT;

static void ai_open(void)
{
    void *h = dlopen(BRUME_ASSIMP_SONAME, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        snprintf(ai_error, sizeof ai_error, "%s", dlerror());
        return;
    }
    ai.import_file = (__typeof__(aiImportFile) *)dlsym(h, "aiImportFile");
    ai.error_string = (__typeof__(aiGetErrorString) *)dlsym(h, "aiGetErrorString");
    ai.release = (__typeof__(aiReleaseImport) *)dlsym(h, "aiReleaseImport");
    if (!ai.import_file || !ai.error_string || !ai.release) {
        snprintf(ai_error, sizeof ai_error, "%s lacks aiImportFile, aiGetErrorString or aiReleaseImport",
                 BRUME_ASSIMP_SONAME);
        ai.import_file = NULL;
    }
}

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

/* A binary PLY file must hold at least the bytes its header announces (assimp reads past
 * the end of a truncated one); BRUME_OK for anything else, which assimp checks itself. */
static brume_status ply_check(FILE *f, const char *path, long file_size)
{
    char line[512];
    rewind(f);
    if (!fgets(line, sizeof line, f) || strncmp(line, "ply", 3) != 0)
        return BRUME_OK;
    bool binary = false;
    double need = 0.0, count = 0.0, elem = 0.0;
    for (int n = 0; n < 10000 && fgets(line, sizeof line, f); n++) {
        char a[64], b[64], c[64];
        double v = 0.0;
        if (sscanf(line, "format %63s", a) == 1) {
            binary = strncmp(a, "binary", 6) == 0;
        } else if (sscanf(line, "element %63s %lf", a, &v) == 2) {
            need += count * elem;
            count = v;
            elem = 0.0;
        } else if (sscanf(line, "property list %63s %63s %63s", a, b, c) == 3) {
            elem += ply_type_size(a); /* at least the length of each list */
        } else if (sscanf(line, "property %63s %63s", a, b) == 2) {
            elem += ply_type_size(a);
        } else if (strncmp(line, "end_header", 10) == 0) {
            need += count * elem;
            long body = file_size - ftell(f);
            if (binary && !(need <= (double)body))
                return err_set(BRUME_ERROR_PARSE, "%s: truncated: the PLY header announces at least %.0f bytes, the "
                               "file holds %ld", path, need, body);
            return BRUME_OK;
        }
    }
    return BRUME_OK;
}

brume_status mesh_load(const char *path, double **pos_out, int *nv_out, int **idx_out, int *ntri_out)
{
    *pos_out = NULL;
    *idx_out = NULL;
    FILE *probe = NULL; /* a regular file: assimp would block on a pipe */
    if (io_open_regular(path, &probe) != BRUME_OK)
        return err_status();
    /* assimp holds the whole file and more while it imports: a file larger than the memory
     * budget is refused unread; the import's share is given back once released */
    long file_size = fseek(probe, 0, SEEK_END) == 0 ? ftell(probe) : -1;
    brume_status st = file_size > 0 ? ply_check(probe, path, file_size) : BRUME_OK;
    fclose(probe);
    if (st != BRUME_OK)
        return st;
    pthread_once(&ai_once, ai_open);
    if (!ai.import_file)
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: mesh files need assimp: %s", path, ai_error);
    size_t import_bytes = file_size > 0 ? 2 * (size_t)file_size : 0;
    if (budget_take(import_bytes, path) != BRUME_OK)
        return err_status();
    const struct aiScene *sc = ai.import_file(path, aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                                      aiProcess_SortByPType);
    if (!sc)
        return err_set(BRUME_ERROR_PARSE, "%s: not a readable mesh: %s", path, ai.error_string());
    long nv = 0, ntri = 0;
    for (unsigned m = 0; m < sc->mNumMeshes; m++) {
        const struct aiMesh *me = sc->mMeshes[m];
        nv += me->mNumVertices;
        for (unsigned f = 0; f < me->mNumFaces; f++)
            ntri += me->mFaces[f].mNumIndices == 3;
    }
    if (ntri == 0) {
        ai.release(sc);
        return err_set(BRUME_ERROR_PARSE, "%s: no triangles in the file", path);
    }
    if (ntri > MESH_MAX_TRIANGLES || nv > 3 * MESH_MAX_TRIANGLES) {
        ai.release(sc);
        budget_give(import_bytes);
        return err_set(BRUME_ERROR_RANGE, "%s: %ld triangles exceed the limit of %ld", path, ntri, MESH_MAX_TRIANGLES);
    }
    /* the triangle list here and, about as large again, the ray-tracing hierarchy built on it */
    if (budget_take(2 * (sizeof(double) * 3 * (size_t)nv + sizeof(int) * 3 * (size_t)ntri), path) != BRUME_OK) {
        ai.release(sc);
        budget_give(import_bytes);
        return err_status();
    }
    double *pos = malloc(sizeof *pos * 3 * (size_t)nv);
    int *idx = malloc(sizeof *idx * 3 * (size_t)ntri);
    if (!pos || !idx) {
        free(pos);
        free(idx);
        ai.release(sc);
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
                ai.release(sc);
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
                    ai.release(sc);
                    return err_set(BRUME_ERROR_PARSE, "%s: face %u names a missing vertex", path, f);
                }
                idx[3 * t + k] = (int)(vbase + (long)fc->mIndices[k]);
            }
            t++;
        }
        vbase += me->mNumVertices;
    }
    ai.release(sc);
    budget_give(import_bytes);
    *pos_out = pos;
    *idx_out = idx;
    *nv_out = (int)nv;
    *ntri_out = (int)ntri;
    return BRUME_OK;
}
