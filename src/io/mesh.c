/* mesh.c - mesh files read with assimp (Debian's libassimp), flattened to one triangle list. */
#include "io/mesh.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/error.h"

#define MESH_MAX_TRIANGLES 200000000L

brume_status mesh_load(const char *path, double **pos_out, int *nv_out, int **idx_out, int *ntri_out)
{
    *pos_out = NULL;
    *idx_out = NULL;
    FILE *probe = fopen(path, "rb");
    if (!probe)
        return err_set(BRUME_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    /* assimp holds the whole file and more while it imports: a file larger than the memory
     * budget is refused unread; the import's share is given back once released */
    long file_size = fseek(probe, 0, SEEK_END) == 0 ? ftell(probe) : -1;
    fclose(probe);
    size_t import_bytes = file_size > 0 ? 2 * (size_t)file_size : 0;
    if (budget_take(import_bytes, path) != BRUME_OK)
        return err_status();
    const struct aiScene *sc = aiImportFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                                      aiProcess_SortByPType);
    if (!sc)
        return err_set(BRUME_ERROR_PARSE, "%s: not a readable mesh: %s", path, aiGetErrorString());
    long nv = 0, ntri = 0;
    for (unsigned m = 0; m < sc->mNumMeshes; m++) {
        const struct aiMesh *me = sc->mMeshes[m];
        nv += me->mNumVertices;
        for (unsigned f = 0; f < me->mNumFaces; f++)
            ntri += me->mFaces[f].mNumIndices == 3;
    }
    if (ntri == 0) {
        aiReleaseImport(sc);
        return err_set(BRUME_ERROR_PARSE, "%s: no triangles in the file", path);
    }
    if (ntri > MESH_MAX_TRIANGLES || nv > 3 * MESH_MAX_TRIANGLES) {
        aiReleaseImport(sc);
        budget_give(import_bytes);
        return err_set(BRUME_ERROR_RANGE, "%s: %ld triangles exceed the limit of %ld", path, ntri, MESH_MAX_TRIANGLES);
    }
    /* the triangle list here and, about as large again, the ray-tracing hierarchy built on it */
    if (budget_take(2 * (sizeof(double) * 3 * (size_t)nv + sizeof(int) * 3 * (size_t)ntri), path) != BRUME_OK) {
        aiReleaseImport(sc);
        budget_give(import_bytes);
        return err_status();
    }
    double *pos = malloc(sizeof *pos * 3 * (size_t)nv);
    int *idx = malloc(sizeof *idx * 3 * (size_t)ntri);
    if (!pos || !idx) {
        free(pos);
        free(idx);
        aiReleaseImport(sc);
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
                aiReleaseImport(sc);
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
                    aiReleaseImport(sc);
                    return err_set(BRUME_ERROR_PARSE, "%s: face %u names a missing vertex", path, f);
                }
                idx[3 * t + k] = (int)(vbase + (long)fc->mIndices[k]);
            }
            t++;
        }
        vbase += me->mNumVertices;
    }
    aiReleaseImport(sc);
    budget_give(import_bytes);
    *pos_out = pos;
    *idx_out = idx;
    *nv_out = (int)nv;
    *ntri_out = (int)ntri;
    return BRUME_OK;
}
