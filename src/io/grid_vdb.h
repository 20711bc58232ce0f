/* grid_vdb.h - OpenVDB reading (straight to a NanoVDB buffer, never through a dense array),
 * listing and writing. The work is in grid_vdb.cpp, the one C++ file, built as a module of
 * its own (libbrume-openvdb.so, beside libbrume) that grid_vdb_load.c opens on the first
 * call: OpenVDB, TBB, Boost and log4cplus cost a process some 70 ms of symbol binding at
 * start-up (docs/performance.md, "Start-up"), and most runs never read a .vdb. A program that
 * links grid_vdb.cpp in (the fuzz target) uses it as linked. Built without OpenVDB
 * (BRUME_HAVE_OPENVDB 0), or with the module missing, every call fails with a one-line error.
 * The readers run in the sandbox's child, which opens the module there: brume's own process
 * maps OpenVDB only to write.
 *
 * The readers here trust libopenvdb, which does not survive hostile files (a flipped bit can
 * make it loop for minutes or allocate gigabytes): grid_io.c calls them only inside a child
 * process under resource limits (grid_sandbox.c), never in brume's own process. */
#ifndef BRUME_IO_GRID_VDB_H
#define BRUME_IO_GRID_VDB_H

#include <stdarg.h>
#include <stddef.h>

#include "brume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One grid of a file, as `brume info` lists it. */
typedef struct gridvdb_info {
    char name[128];
    char type[32];                 /* value type: "float", "vec3s", "double", "int32", "bool", ... */
    char cls[32];                  /* grid class: "fog volume", "level set", "staggered", "unknown" */
    int bbmin[3], bbmax[3];        /* active voxels' index box, inclusive (min > max: no active voxel) */
    unsigned long long active;     /* active voxel count */
    double vmin, vmax;             /* range of the active values (vec3: of their components) */
    unsigned long long nano_bytes; /* size of the grid as NanoVDB (float and vec3s grids; else 0) */
} gridvdb_info;

/* The sink that receives a NanoVDB buffer, in pieces; returns 0 on success. */
typedef int (*gridvdb_sink)(void *user, const void *data, size_t size);

/* Lists every grid of a .vdb (from `path`, or from bytes when path is NULL); `name` names
 * the input in messages. *out is malloc'd (the caller frees), *count its length. */
brume_status gridvdb_list(const char *path, const void *bytes, size_t size, const char *name, gridvdb_info **out,
                          int *count);

/* Converts one grid of a .vdb to a NanoVDB buffer handed to sink. `grid` is a name, or
 * NULL/"" for the default: the grid named "density", else the only float grid (several
 * float grids and none named density is an error listing them). vec3 = 0 needs a float
 * grid; vec3 = 1 takes a float or a vec3 (vec3s/vec3d) grid, converted to NanoVDB Vec3f.
 * Errors name the file and the grids found. */
brume_status gridvdb_to_nano(const char *path, const void *bytes, size_t size, const char *name, const char *grid,
                             int vec3, gridvdb_sink sink, void *user);

/* .vdb file to .nvdb file keeping every float and vec3s grid (grid NULL/"") or one grid,
 * with their names and sparse trees (other value types are left out). */
brume_status gridvdb_vdb_to_nvdb(const char *in, const char *out, const char *grid);

/* Makes this process fit to fork a reader (grid_sandbox.c), once: OpenVDB's logging library
 * (log4cplus) starts a pool of idle threads when it is loaded, and a fork while one of them
 * is inside the allocator deadlocks the child where the allocator is not fork-safe
 * (AddressSanitizer's). The pool is stopped; OpenVDB does not use it (it logs nothing
 * asynchronously). Without that library loaded, or in a process forked from the one that
 * loaded it (where the pool's threads do not exist), nothing happens. */
void gridvdb_before_fork(void);

/* Writes a dense grid as one float grid "density" (fog volume) to `path`: .vdb (OpenVDB)
 * or .nvdb (NanoVDB) by `nanovdb`. Voxels equal to 0 are inactive background, except the
 * two corners of the box, kept active so that the bounding box round-trips. */
brume_status gridvdb_write_dense(const char *path, int nanovdb, const int n[3], const float *data,
                                 const double voxel_to_world[12]);

/* A sparse multi-grid writer (brume gen fire|upres, tests): grids of float or vec3 values,
 * voxels set one at a time (only the ones given become active), saved as .vdb or .nvdb.
 * Placement: the centre of voxel (i, j, k) is at world origin + voxel_size (i, j, k). */
typedef struct gridvdb_writer gridvdb_writer;
gridvdb_writer *gridvdb_writer_new(void);
/* Adds a fog-volume grid; returns its index, or -1 (err_set) on failure. */
int gridvdb_writer_add(gridvdb_writer *w, const char *grid_name, int vec3, double voxel_size, const double origin[3]);
/* Sets voxel (i, j, k) of grid g active with value v[0] (float) or v[0..2] (vec3). When an
 * allocation fails, the writer stops taking voxels and gridvdb_writer_save fails with
 * BRUME_ERROR_OUT_OF_MEMORY and one line. */
void gridvdb_writer_set(gridvdb_writer *w, int g, int i, int j, int k, const float *v);
/* Active voxels of grid g so far. */
unsigned long long gridvdb_writer_active(const gridvdb_writer *w, int g);
/* Writes every grid to path (written as is: callers go through io/atomic.h). */
brume_status gridvdb_writer_save(gridvdb_writer *w, const char *path, int nanovdb);
void gridvdb_writer_free(gridvdb_writer *w);

/* ---- the module's interface (grid_vdb.cpp <-> grid_vdb_load.c) ----------------------- */

/* Bumped whenever the table changes; a module of another version is refused. */
#define GRIDVDB_API_VERSION 1

/* The functions above, as the module provides them (the loader's functions of the same
 * names forward to these). */
typedef struct gridvdb_api {
    int version;  /* GRIDVDB_API_VERSION */
    size_t size;  /* sizeof(gridvdb_api) */
    brume_status (*list)(const char *path, const void *bytes, size_t size, const char *name, gridvdb_info **out,
                         int *count);
    brume_status (*to_nano)(const char *path, const void *bytes, size_t size, const char *name, const char *grid,
                            int vec3, gridvdb_sink sink, void *user);
    brume_status (*vdb_to_nvdb)(const char *in, const char *out, const char *grid);
    void (*before_fork)(void);
    brume_status (*write_dense)(const char *path, int nanovdb, const int n[3], const float *data,
                                const double voxel_to_world[12]);
    gridvdb_writer *(*writer_new)(void);
    int (*writer_add)(gridvdb_writer *w, const char *grid_name, int vec3, double voxel_size, const double origin[3]);
    void (*writer_set)(gridvdb_writer *w, int g, int i, int j, int k, const float *v);
    unsigned long long (*writer_active)(const gridvdb_writer *w, int g);
    brume_status (*writer_save)(gridvdb_writer *w, const char *path, int nanovdb);
    void (*writer_free)(gridvdb_writer *w);
} gridvdb_api;

/* How the module reports an error: the host's err_vset (core/error.h), so that the message
 * lands in the calling thread's last error as every other brume message does. */
typedef brume_status (*gridvdb_err_fn)(brume_status status, const char *fmt, va_list ap);

/* The module's one exported symbol: its table, given the host's error function. */
#define GRIDVDB_MODULE_SYMBOL "brume_openvdb_module"
const gridvdb_api *brume_openvdb_module(gridvdb_err_fn err);

#ifdef __cplusplus
}
#endif

#endif
