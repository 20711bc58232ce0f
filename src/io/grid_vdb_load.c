/* grid_vdb_load.c - the functions of io/grid_vdb.h, forwarded to the OpenVDB module
 * (libbrume-openvdb.so, built from grid_vdb.cpp), which is opened on the first call.
 *
 * Why a module: libopenvdb and what it brings (TBB, Boost, Blosc, log4cplus) make the dynamic
 * loader bind some 70,000 symbols, about 70 ms of every brume process's start on the
 * project's machine, for the few runs that read or write a .vdb (docs/performance.md,
 * "Start-up"). Opened with RTLD_LOCAL, its libraries stay out of the process's global scope.
 *
 * Where the module is looked for: io/vdb_path.h. A program linking grid_vdb.cpp itself (the
 * fuzz target) defines brume_openvdb_module, and that is used. A module of another API
 * version is refused. Nothing is ever unloaded. */
#include "io/grid_vdb.h"

#include <limits.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error.h"
#include "core/lazylib.h"
#include "io/vdb_path.h"

#define MODULE_FILE "libbrume-openvdb.so"

/* Defined when grid_vdb.cpp is linked into the program; null otherwise. */
#pragma weak brume_openvdb_module

static const gridvdb_api *api;
#if BRUME_HAVE_OPENVDB
/* the module, once found (load()), opened as every optional library (core/lazylib.h) */
static char module_path[PATH_MAX + 64];
static const char *const module_sonames[] = {module_path, NULL};
static const char *const module_names[] = {GRIDVDB_MODULE_SYMBOL, NULL};
static struct {
    const gridvdb_api *(*get_api)(gridvdb_err_fn); /* GRIDVDB_MODULE_SYMBOL */
} entry;
static lazylib module = LAZYLIB("the OpenVDB module", module_sonames, module_names, &entry, sizeof entry);
#endif
static char load_error[PATH_MAX * 4 + 256];
static pthread_once_t load_once = PTHREAD_ONCE_INIT;

#if BRUME_HAVE_OPENVDB
/* The module's table if its version is this build's; else null, with load_error set. */
static const gridvdb_api *check(const gridvdb_api *a, const char *where)
{
    if (a && a->version == GRIDVDB_API_VERSION && a->size == sizeof *a)
        return a;
    snprintf(load_error, sizeof load_error, "%s is from another build of brume (interface %d, this one %d)", where,
             a ? a->version : -1, GRIDVDB_API_VERSION);
    return NULL;
}

static void load(void)
{
    if (brume_openvdb_module) {
        api = check(brume_openvdb_module(err_vset), "the linked-in OpenVDB code");
        return;
    }
    char looked[PATH_MAX * 2];
    if (!vdb_path_find(MODULE_FILE, module_path, sizeof module_path, looked, sizeof looked)) {
        snprintf(load_error, sizeof load_error,
                 "the OpenVDB module " MODULE_FILE " is missing (BRUME_MODULE_PATH=DIR names its folder; looked in %s)",
                 looked);
        return;
    }
    if (!lazylib_open(&module)) {
        snprintf(load_error, sizeof load_error, "%s", module.error);
        return;
    }
    api = check(entry.get_api(err_vset), module_path);
}

#else
static void load(void) { snprintf(load_error, sizeof load_error, "brume was built without OpenVDB"); }
#endif

static const gridvdb_api *get(void)
{
    pthread_once(&load_once, load);
    return api;
}

brume_status gridvdb_list(const char *path, const void *bytes, size_t size, const char *name, gridvdb_info **out,
                          int *count)
{
    if (!get())
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: .vdb needs OpenVDB: %.2000s", name, load_error);
    return api->list(path, bytes, size, name, out, count);
}

brume_status gridvdb_to_nano(const char *path, const void *bytes, size_t size, const char *name, const char *grid,
                             int vec3, gridvdb_sink sink, void *user)
{
    if (!get())
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: .vdb needs OpenVDB: %.2000s", name, load_error);
    return api->to_nano(path, bytes, size, name, grid, vec3, sink, user);
}

brume_status gridvdb_vdb_to_nvdb(const char *in, const char *out, const char *grid)
{
    if (!get())
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: .vdb needs OpenVDB: %.2000s", in, load_error);
    return api->vdb_to_nvdb(in, out, grid);
}

/* Only a loaded module has anything to stop before a fork; this never loads it. */
void gridvdb_before_fork(void)
{
    if (api)
        api->before_fork();
}

brume_status gridvdb_write_dense(const char *path, int nanovdb, const int n[3], const float *data,
                                 const double voxel_to_world[12])
{
    if (!get())
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: writing .vdb/.nvdb needs OpenVDB: %.2000s", path, load_error);
    return api->write_dense(path, nanovdb, n, data, voxel_to_world);
}

gridvdb_writer *gridvdb_writer_new(void)
{
    if (!get()) {
        err_set(BRUME_ERROR_UNSUPPORTED, "writing .vdb/.nvdb needs OpenVDB: %.2000s", load_error);
        return NULL;
    }
    return api->writer_new();
}

/* A writer exists only once the module is loaded; without one these do nothing. */
int gridvdb_writer_add(gridvdb_writer *w, const char *grid_name, int vec3, double voxel_size, const double origin[3])
{
    if (!w || !api) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: no grid writer", grid_name ? grid_name : "grid");
        return -1;
    }
    return api->writer_add(w, grid_name, vec3, voxel_size, origin);
}

void gridvdb_writer_set(gridvdb_writer *w, int g, int i, int j, int k, const float *v)
{
    if (w && api)
        api->writer_set(w, g, i, j, k, v);
}

unsigned long long gridvdb_writer_active(const gridvdb_writer *w, int g)
{
    return w && api ? api->writer_active(w, g) : 0;
}

brume_status gridvdb_writer_save(gridvdb_writer *w, const char *path, int nanovdb)
{
    if (!w || !api)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: no grid writer", path);
    return api->writer_save(w, path, nanovdb);
}

void gridvdb_writer_free(gridvdb_writer *w)
{
    if (w && api)
        api->writer_free(w);
}
