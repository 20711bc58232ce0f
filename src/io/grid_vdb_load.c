/* grid_vdb_load.c - the functions of io/grid_vdb.h, forwarded to the OpenVDB module
 * (libbrume-openvdb.so, built from grid_vdb.cpp), which is opened on the first call.
 *
 * Why a module: libopenvdb and what it brings (TBB, Boost, Blosc, log4cplus) make the dynamic
 * loader bind some 70,000 symbols, about 70 ms of every brume process's start on the
 * project's machine, for the few runs that read or write a .vdb (docs/performance.md,
 * "Start-up"). Opened with RTLD_LOCAL, its libraries stay out of the process's global scope.
 *
 * Where the module is looked for, in order:
 *   0. the directory the environment variable BRUME_MODULE_PATH names, when set: for a
 *      program linking the static libbrume.a from somewhere the others do not reach;
 *   1. the build tree, when the object holding this code (the program, or libbrume.so) is
 *      inside it: the tests, benches and tools of a build use that build's module;
 *   2. the directory of that object: libbrume.so's, for programs linking the shared library
 *      and the Python package;
 *   3. that directory's BIN_TO_LIB: an installed brume tool finds the library directory
 *      beside its own, also after `cmake --install --prefix` to another place;
 *   4. the library directory the build was configured to install into.
 * A program linking grid_vdb.cpp itself (the fuzz target) defines brume_openvdb_module, and
 * that is used. A module of another API version is refused. Nothing is ever unloaded. */
#define _GNU_SOURCE /* dladdr1, RTLD_DL_LINKMAP */
#include "io/grid_vdb.h"

#include <dlfcn.h>
#include <limits.h>
#include <link.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error.h"
#include "core/lazylib.h"

#define MODULE_FILE "libbrume-openvdb.so"

#ifndef BRUME_BUILD_DIR
#define BRUME_BUILD_DIR ""
#endif
#ifndef BRUME_BIN_TO_LIB
#define BRUME_BIN_TO_LIB "../lib"
#endif
#ifndef BRUME_INSTALL_LIBDIR
#define BRUME_INSTALL_LIBDIR ""
#endif

/* Defined when grid_vdb.cpp is linked into the program; null otherwise. */
#pragma weak brume_openvdb_module

static const gridvdb_api *api;
#if BRUME_HAVE_OPENVDB
/* the module, once found (load()), opened as every optional library (core/lazylib.h) */
static char module_path[PATH_MAX + sizeof MODULE_FILE + 1];
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
/* The directory of the object holding this code, into dir[n]; false when unknown. */
static bool own_dir(char *dir, size_t n)
{
    Dl_info info;
    struct link_map *self = NULL;
    char path[PATH_MAX];
    if (!dladdr1((void *)&own_dir, &info, (void **)&self, RTLD_DL_LINKMAP) || !self)
        return false;
    if (self->l_name && self->l_name[0]) { /* a shared library */
        if (!realpath(self->l_name, path))
            return false;
    } else { /* the program itself */
        ssize_t len = readlink("/proc/self/exe", path, sizeof path - 1);
        if (len <= 0)
            return false;
        path[len] = '\0';
    }
    char *slash = strrchr(path, '/');
    if (!slash || (size_t)(slash - path) >= n)
        return false;
    *slash = '\0';
    snprintf(dir, n, "%s", path[0] ? path : "/");
    return true;
}

static bool inside(const char *dir, const char *root)
{
    size_t k = strlen(root);
    return k > 0 && strncmp(dir, root, k) == 0 && (dir[k] == '/' || dir[k] == '\0');
}

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
    char dir[PATH_MAX], cand[5][PATH_MAX];
    int nc = 0;
    const char *env = getenv("BRUME_MODULE_PATH");
    if (env && env[0])
        snprintf(cand[nc++], PATH_MAX, "%.*s", PATH_MAX - 1, env);
    bool have_dir = own_dir(dir, sizeof dir);
    if (have_dir && inside(dir, BRUME_BUILD_DIR))
        snprintf(cand[nc++], PATH_MAX, "%s", BRUME_BUILD_DIR);
    if (have_dir) {
        snprintf(cand[nc++], PATH_MAX, "%s", dir);
        snprintf(cand[nc++], PATH_MAX, "%.*s/%s", PATH_MAX / 2, dir, BRUME_BIN_TO_LIB);
    }
    if (BRUME_INSTALL_LIBDIR[0])
        snprintf(cand[nc++], PATH_MAX, "%s", BRUME_INSTALL_LIBDIR);
    char looked[PATH_MAX * 2] = "";
    for (int c = 0; c < nc; c++) {
        char path[PATH_MAX + sizeof MODULE_FILE + 1];
        snprintf(path, sizeof path, "%.*s/%s", PATH_MAX - 1, cand[c], MODULE_FILE);
        bool seen = false;
        for (int e = 0; e < c; e++)
            seen = seen || strcmp(cand[e], cand[c]) == 0;
        if (seen)
            continue;
        if (access(path, F_OK) != 0) {
            size_t at = strlen(looked);
            snprintf(looked + at, sizeof looked - at, "%s%.*s", at ? ", " : "", PATH_MAX / 4, cand[c]);
            continue;
        }
        snprintf(module_path, sizeof module_path, "%s", path);
        if (!lazylib_open(&module)) {
            snprintf(load_error, sizeof load_error, "%s", module.error);
            return;
        }
        api = check(entry.get_api(err_vset), path);
        return;
    }
    snprintf(load_error, sizeof load_error,
             "the OpenVDB module " MODULE_FILE " is missing (BRUME_MODULE_PATH=DIR names its folder; looked in %s)",
             looked);
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
