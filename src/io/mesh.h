/* mesh.h - triangle meshes from files (OBJ, PLY, glTF, ...) through assimp's C API. */
#ifndef BRUME_IO_MESH_H
#define BRUME_IO_MESH_H

#include "brume.h"

/* Every mesh of the file, triangulated, node transforms applied: nv vertices (x, y, z as
 * doubles) and ntri triangles of three indices, in new malloc'd arrays the caller frees.
 * On failure nothing is allocated and err_set names the file and the reason. */
brume_status mesh_load(const char *path, double **pos, int *nv, int **idx, int *ntri);
/* The same, and *uv: the file's texture coordinates (u, v) per vertex (2 nv, malloc'd), or NULL
 * when some mesh of the file has none. */
brume_status mesh_load_uv(const char *path, double **pos, int *nv, int **idx, int *ntri, double **uv);

#endif
