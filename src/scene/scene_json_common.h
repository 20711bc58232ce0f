/* scene_json_common.h - what the sections of the scene file reader share: helpers
 * (scene_json_common.c) and each section's entry (scene_json.c: the top level and "render";
 * scene_json_view.c: camera, lights, background; scene_json_density.c: densities;
 * scene_json_media.c: media; scene_json_load.c: sources and brume_scene_load). The top level
 * calls the sections, which call only the helpers: the reader is built in one direction. */
#ifndef BRUME_SCENE_SCENE_JSON_COMMON_H
#define BRUME_SCENE_SCENE_JSON_COMMON_H

#include "brume.h"
#include "io/json.h"

static const double BIG = 1e30;

/* scene_json_common.c */
brume_status scene_json_vec(const cJSON *j, jloc at, const char *key, int required, double out[3]);
brume_status scene_json_color(const cJSON *j, jloc at, const char *key, int required, double hi, double out[3]);
brume_status scene_json_built(brume_status st, jloc at);
brume_status scene_parse_unit_vector(const cJSON *j, jloc at, const char *key, double out[3]);

/* scene_json_view.c */
brume_status scene_parse_camera(const cJSON *j, jloc at, brume_scene *s);
brume_status scene_parse_light(const cJSON *j, jloc at, brume_scene *s);
brume_status scene_parse_background(const cJSON *root, jloc top, brume_scene *s);

/* scene_json_density.c */
long scene_frame_number(const brume_scene *s);
brume_status scene_parse_grid_options(const cJSON *j, jloc at, const char *const *extra, long frame_no, char *path,
                                      size_t cap, brume_grid_file_options *o, bool *sequence);
brume_status scene_parse_density(const cJSON *j, jloc at, const brume_scene *s, brume_density **out);

/* scene_json_media.c */
brume_status scene_parse_medium(const cJSON *j, jloc at, brume_scene *s);

#endif
