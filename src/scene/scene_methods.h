/* scene_methods.h - the scene file's method objects ("blasi", "stam", ...; docs/scene-format.md):
 * each key of such an object is one brume_scene_set_option("METHOD.KEY", text) call. */
#ifndef BRUME_SCENE_SCENE_METHODS_H
#define BRUME_SCENE_SCENE_METHODS_H

#include "io/json.h"

/* For every method that owns options (method/method_options.h), reads root's object of that
 * name, if any: numbers, strings, true/false and arrays of numbers ("a,b,c") become the
 * option's text, nested objects dotted keys ("stam.voxelize.resolution"); a method's path
 * options are resolved against the scene file's folder. */
brume_status scene_parse_method_options(const cJSON *root, jloc top, brume_scene *s);

#endif
