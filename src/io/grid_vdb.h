/* grid_vdb.h - the C interface of grid_vdb.cpp, the one C++ file: OpenVDB reading and
 * writing, and NanoVDB writing (both need C++). Built only when CMake finds libopenvdb
 * (BRUME_HAVE_OPENVDB); otherwise grid_io.c reports "built without OpenVDB". */
#ifndef BRUME_IO_GRID_VDB_H
#define BRUME_IO_GRID_VDB_H

#include <stddef.h>

#include "brume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A dense copy of a VDB grid's active bounding box. */
typedef struct gridvdb_dense {
    int n[3];                  /* voxels per axis */
    float *data;               /* n0 n1 n2 floats, x fastest, malloc'd; the caller frees */
    double voxel_to_world[12]; /* row-major 3x4: voxel (i, j, k) spans [i, i+1) x ...; centre = index coord */
    unsigned long long active; /* active voxel count of the tree */
} gridvdb_dense;

/* Reads the float grid "density" (or the first float grid) of the .vdb bytes. Fails with
 * err_set("NAME: reason") on malformed input, no float grid, a non-linear transform or
 * more voxels than max_memory bytes. */
brume_status gridvdb_read(const void *bytes, size_t size, const char *name, size_t max_memory, gridvdb_dense *out);

/* Writes a dense grid as one float grid "density" (fog volume) to `path`: .vdb (OpenVDB)
 * or .nvdb (NanoVDB) by `nanovdb`. Voxels equal to 0 are inactive background, except the
 * two corners of the box, kept active so that the bounding box round-trips. */
brume_status gridvdb_write_dense(const char *path, int nanovdb, const int n[3], const float *data,
                                 const double voxel_to_world[12]);

/* .vdb file to .nvdb file, keeping the sparse tree. */
brume_status gridvdb_vdb_to_nvdb(const char *in, const char *out);

#ifdef __cplusplus
}
#endif

#endif
