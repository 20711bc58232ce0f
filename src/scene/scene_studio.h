/* scene_studio.h - a studio scene around a grid file (brume render smoke.vdb): written as
 * scene-file JSON (docs/scene-format.md) and read by the one scene reader, never built on a
 * second path. docs/production.md describes the choices. */
#ifndef BRUME_SCENE_SCENE_STUDIO_H
#define BRUME_SCENE_SCENE_STUDIO_H

#include "brume.h"

/* A three-quarter view direction for up vector `up` (not zero): look_at = 0 and position
 * = the unit vector towards the eye, 35 degrees round from the front (+z for a y-up world,
 * -y for a z-up one) and 20 degrees above the horizon. */
void scene_studio_direction(const double up[3], double position[3], double look_at[3]);

/* Whether `path` names a grid file that the scene loader turns into a studio scene (.vdb,
 * .nvdb, by extension). */
bool scene_studio_is_grid(const char *path);

/* The studio scene for the grid file `path` as JSON text (malloc'd, the caller frees), with
 * file names absolute so that the text reads the same from any folder. On failure *json is
 * NULL and err_message() names the file. */
brume_status scene_studio_json(const char *path, const brume_studio_options *opts, char **json);

#endif
