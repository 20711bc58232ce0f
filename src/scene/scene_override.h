/* scene_override.h - scene overrides "KEY=VALUE" applied to a scene's JSON document before
 * the reader builds the scene (scene_override.c; brume render --set). */
#ifndef BRUME_SCENE_SCENE_OVERRIDE_H
#define BRUME_SCENE_SCENE_OVERRIDE_H

#include <cjson/cJSON.h>

#include "brume.h"

/* Sets each "KEY=VALUE" of overrides[0..n) in root, in order (a later one wins). KEY is a
 * dotted path with array indices ("media.0.sigma_s" or "media[0].sigma_s"); VALUE is JSON,
 * or a string when it does not parse as JSON. Missing objects on the path are created; the
 * scene reader validates the result. Fails (err_set naming source and the override) on a
 * malformed override, an index outside an array or a path through a number or string. */
brume_status scene_apply_overrides(cJSON *root, const char *source, const char *const *overrides, int n);

/* After the reader refused the document: when the refused key is one an override set, adds
 * "(set by override KEY=VALUE)" to this thread's error message. */
void scene_override_annotate(const char *const *overrides, int n);

#endif
