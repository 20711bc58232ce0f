/* scene_paths.h - where a scene file may make brume write: inside its own folder only.
 *
 * Only the command line and the API's caller choose output paths freely. A path that a
 * scene file names for writing (blasi.save_light) must be relative, must not contain a
 * ".." component, and must resolve, symbolic links followed, to a place inside the scene
 * file's folder (docs/scene-format.md, "Paths"). Paths read stay relative to the scene
 * file as before. */
#ifndef BRUME_SCENE_SCENE_PATHS_H
#define BRUME_SCENE_SCENE_PATHS_H

#include <stddef.h>

#include "brume.h"

/* Checks `name`, given by `key` in scene_file, and writes the path to use into out[n];
 * a one-line error (err_set) naming the file and the key otherwise. */
brume_status scene_output_path(const char *scene_file, const char *key, const char *name, char *out, size_t n);

#endif
