/* scene_pbrt.h - pbrt-v4 scene files (.pbrt) translated to brume's scene description (JSON,
 * docs/scene-format.md) for the one scene reader. What is read and how it maps is in
 * docs/pbrt.md; every directive or parameter brume cannot honour is
 * refused with one line naming it and FILE:LINE. */
#ifndef BRUME_SCENE_SCENE_PBRT_H
#define BRUME_SCENE_SCENE_PBRT_H

#include <stdbool.h>

#include "brume.h"

/* Whether path names a pbrt scene (.pbrt, by extension). */
bool scene_pbrt_is_pbrt(const char *path);
/* The translation of the pbrt-v4 file at path as JSON text (malloc'd; the caller frees).
 * File names in it are absolute. On failure *json is NULL and err_message() names
 * FILE:LINE and the directive. lenient: a directive or parameter brume cannot honour is
 * skipped instead and its refusal listed in the translation's "ignored" key. */
brume_status scene_pbrt_read(const char *path, bool lenient, char **json);
/* scene_pbrt_read without lenient. */
brume_status scene_pbrt_json(const char *path, char **json);

#endif
