/* method_options.h - the one option mechanism of the rendering methods: each method owns a
 * typed options struct and ONE table of its options (method_option rows: key, kind, range,
 * field, default, doc), in its own file (path_options.c, blasi_options.c, stam_params.c).
 * The scene holds one struct per method, opaque to it, set through brume_scene_set_option
 * (the scene file's "METHOD" objects, and so `brume render --set`, are read through the same
 * call). Everything else is generated from the tables: the setter (method_option_set), the
 * defaults, the "known here" lists of messages, the public list (brume_option_count,
 * brume_option_get), `brume options` (and `brume help render`'s list) and
 * docs/scene-format.md's "Method options" (`brume options --markdown`, put there by
 * scripts/option-docs.sh); tests/test_options.c checks the doc and brume.h's list of keys.
 * A method adds an option by adding a row to its table; a new method with options adds its
 * id below and its table to methods[] and method_options_methods() in method_options.c. The
 * tables' types are method/option_table.h's, which the methods' files include (this file
 * includes theirs). */
#ifndef BRUME_METHOD_METHOD_OPTIONS_H
#define BRUME_METHOD_METHOD_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>

#include "brume.h"
#include "method/option_table.h"

typedef enum method_options_id {
    METHOD_OPTIONS_PATH, /* the path and single methods */
    METHOD_OPTIONS_BLASI,
    METHOD_OPTIONS_STAM,
    METHOD_OPTIONS_COUNT
} method_options_id;

const method_options_def *method_options_def_get(method_options_id id);
/* The method owning "METHOD.KEY"; NULL when no method has that prefix. */
const method_options_def *method_options_find(const char *key, method_options_id *id);
/* "path, blasi, stam": the methods that have options. */
const char *method_options_methods(void);
/* The row of "METHOD.KEY" in def's table; NULL if none. */
const method_option *method_option_find(const method_options_def *def, const char *key);
/* The defaults of method def into opts (def->size bytes): zeros, the table's `def`s, then
 * def->defaults. */
void method_options_default(const method_options_def *def, void *opts);
/* Sets "METHOD.KEY" (key, whole) from text into opts, a struct of def's. On failure
 * err_set() names the key and the value (and, for an unknown key, the keys known here),
 * and *opts is unchanged. */
brume_status method_option_set(const method_options_def *def, void *opts, const char *key, const char *text);
/* text, all of it, as a finite number in [lo, hi] into *out; false (and *out unchanged)
 * otherwise. The one number parser of every method's options. */
bool method_option_number(const char *text, double lo, double hi, double *out);
/* The same for an integer in [lo, hi] (a count, a resolution). */
bool method_option_integer(const char *text, double lo, double hi, double *out);

#endif
