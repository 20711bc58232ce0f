/* json.h - typed, checked reads from cJSON objects with messages naming file and key.
 *
 * Every reader takes the file name and the key path of the object ("media[0].phase") and
 * on failure calls err_set() with "FILE: PATH.KEY: what is wrong" and returns its status.
 * Optional keys that are absent leave *out unchanged and return BRUME_OK. */
#ifndef BRUME_IO_JSON_H
#define BRUME_IO_JSON_H

#include <cjson/cJSON.h>
#include <stddef.h>
#include <stdint.h>

#include "brume.h"
#include "core/color.h"
#include "core/vec.h"
#include "core/xform.h"

typedef struct jloc {
    const char *file;
    const char *path; /* key path of the object being read; "" at top level */
} jloc;

/* "path.key" (or "key" at top level) into buf. */
const char *json_key_path(char *buf, size_t n, const char *path, const char *key);

/* j must be an object whose keys are all in allowed (NULL-terminated); "comment" is
 * always allowed. */
brume_status json_check_object(const cJSON *j, jloc at, const char *const *allowed);
/* Parses text; on a syntax error names the file, line and column. Caller cJSON_Delete()s. */
brume_status json_parse(const char *text, const char *file, cJSON **out);
/* The first number of a text cJSON has parsed, outside strings, that JSON's grammar refuses and
 * cJSON takes ("01", "1.", "1.e5": -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?); NULL when
 * there is none. */
const char *json_bad_number(const char *text);

/* j must be an object with a string "type" (a light, a density, a phase function, ...),
 * copied into type[n]. */
brume_status json_object_type(const cJSON *j, jloc at, char *type, size_t n);

brume_status json_number(const cJSON *obj, jloc at, const char *key, int required, double lo, double hi, double *out);
brume_status json_int(const cJSON *obj, jloc at, const char *key, int required, long lo, long hi, int *out);
brume_status json_u64(const cJSON *obj, jloc at, const char *key, int required, uint64_t *out);
brume_status json_bool(const cJSON *obj, jloc at, const char *key, int required, bool *out);
brume_status json_string(const cJSON *obj, jloc at, const char *key, int required, char *buf, size_t n);
/* A 3-array of finite numbers. */
brume_status json_vec3(const cJSON *obj, jloc at, const char *key, int required, vec3 *out);
/* A number (gray) or a 3-array of RGB, each finite and in [lo, hi]. */
brume_status json_color(const cJSON *obj, jloc at, const char *key, int required, double lo, double hi, color *out);

/* A transform object {"translate": [x, y, z], "rotate": {"axis": [..], "angle": degrees},
 * "scale": s | [sx, sy, sz]}, applied as translate(rotate(scale(p))); j NULL = identity.
 * Scale factors > 0, or with mirror also < 0 (a grid's placement may mirror: a lookup
 * inverts any affine map; a surface's may not, its winding would turn). */
brume_status json_transform(const cJSON *j, jloc at, bool mirror, affine3 *out);
/* The same object read into its parts (for keyframes, which interpolate each part). */
typedef struct json_transform_parts {
    vec3 translate;
    vec3 axis;    /* rotation axis, not zero (default +z) */
    double angle; /* degrees (default 0) */
    vec3 scale;   /* factors > 0 (or != 0 with mirror) */
} json_transform_parts;
brume_status json_transform_split(const cJSON *j, jloc at, bool mirror, json_transform_parts *out);

/* A file named in a scene, relative to the scene file's folder unless absolute. */
void json_resolve_path(const char *scene_file, const char *name, char *out, size_t n);

#endif
