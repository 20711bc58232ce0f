/* scene_paths.c - the folder a scene file may write into (scene_paths.h). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "scene/scene_paths.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"

#ifndef PATH_MAX
#define PATH_MAX 4096
#endif

brume_status scene_output_path(const char *scene_file, const char *key, const char *name, char *out, size_t n)
{
    if (!name[0])
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: empty path", scene_file, key);
    if (name[0] == '/')
        return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                       "%s: %s: '%s' is absolute; a scene file writes only inside its own folder (give the path on "
                       "the command line instead)",
                       scene_file, key, name);
    for (const char *c = name; *c;) { /* every component: no ".." */
        size_t len = strcspn(c, "/");
        if (len == 2 && c[0] == '.' && c[1] == '.')
            return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                           "%s: %s: '%s' leaves the scene's folder ('..'); a scene file writes only inside it",
                           scene_file, key, name);
        c += len;
        while (*c == '/')
            c++;
    }
    /* the scene's folder: "." for a scene without a file (JSON text through the API) */
    char dir[PATH_MAX];
    const char *slash = strrchr(scene_file, '/');
    if (!slash || scene_file[0] == '<')
        snprintf(dir, sizeof dir, ".");
    else if (slash == scene_file)
        snprintf(dir, sizeof dir, "/");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - scene_file), scene_file);
    if ((size_t)snprintf(out, n, "%s/%s", dir, name) >= n)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: path too long", scene_file, key);
    /* symbolic links: the folder the file lands in must resolve inside the scene's folder */
    char real_dir[PATH_MAX], parent[PATH_MAX], real_parent[PATH_MAX];
    if (!realpath(dir, real_dir))
        return err_set(BRUME_ERROR_IO, "%s: %s: cannot resolve the scene's folder: %s", scene_file, key,
                       strerror(errno));
    snprintf(parent, sizeof parent, "%s", out);
    char *last = strrchr(parent, '/');
    *last = '\0';
    if (!realpath(parent, real_parent))
        return err_set(BRUME_ERROR_IO, "%s: %s: '%s': its folder cannot be resolved: %s", scene_file, key, name,
                       strerror(errno));
    size_t dl = strlen(real_dir);
    bool inside = strcmp(real_dir, "/") == 0 ||
                  (strncmp(real_parent, real_dir, dl) == 0 && (real_parent[dl] == '\0' || real_parent[dl] == '/'));
    if (!inside)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                       "%s: %s: '%s' resolves through a symbolic link to '%s', outside the scene's folder", scene_file,
                       key, name, real_parent);
    return BRUME_OK;
}
