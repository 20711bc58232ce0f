/* vdb_path.c - where the OpenVDB module and brume-openvdb-reader are found (vdb_path.h). */
#define _GNU_SOURCE /* dladdr1, RTLD_DL_LINKMAP */
#include "io/vdb_path.h"

#include <dlfcn.h>
#include <limits.h>
#include <link.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error.h"

#ifndef BRUME_BUILD_DIR
#define BRUME_BUILD_DIR ""
#endif
#ifndef BRUME_BIN_TO_LIB
#define BRUME_BIN_TO_LIB "../lib"
#endif
#ifndef BRUME_INSTALL_LIBDIR
#define BRUME_INSTALL_LIBDIR ""
#endif

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

bool vdb_path_find(const char *file, char *path, size_t n, char *looked, size_t nl)
{
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
    looked[0] = '\0';
    for (int c = 0; c < nc; c++) {
        bool seen = false;
        for (int e = 0; e < c; e++)
            seen = seen || strcmp(cand[e], cand[c]) == 0;
        if (seen)
            continue;
        snprintf(path, n, "%.*s/%s", PATH_MAX - 1, cand[c], file);
        if (access(path, F_OK) == 0)
            return true;
        size_t at = strlen(looked);
        snprintf(looked + at, nl - at, "%s%.*s", at ? ", " : "", PATH_MAX / 4, cand[c]);
    }
    return false;
}

brume_status vdb_path_reader(char *path, size_t n)
{
    char looked[PATH_MAX * 2];
    if (vdb_path_find(VDB_PATH_READER_FILE, path, n, looked, sizeof looked))
        return BRUME_OK;
    return err_set(BRUME_ERROR_UNSUPPORTED,
                   "the OpenVDB reader program " VDB_PATH_READER_FILE " is missing (it is installed beside the OpenVDB "
                   "module; BRUME_MODULE_PATH=DIR names their folder; looked in %.2000s)", looked);
}
