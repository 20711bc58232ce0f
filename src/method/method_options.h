/* method_options.h - the one option mechanism of the rendering methods: each method owns
 * a typed options struct and the parser of its "METHOD.KEY" = text options; the scene holds
 * one struct per method, opaque to it, set through brume_scene_set_option (the scene file's
 * "METHOD" objects are read through the same call). A method adds a key in its own setter
 * only; a method with options adds one row to the table in method_options.c. */
#ifndef BRUME_METHOD_METHOD_OPTIONS_H
#define BRUME_METHOD_METHOD_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>

#include "brume.h"

typedef enum method_options_id {
    METHOD_OPTIONS_PATH, /* the path and single methods */
    METHOD_OPTIONS_BLASI,
    METHOD_OPTIONS_STAM,
    METHOD_OPTIONS_COUNT
} method_options_id;

typedef struct method_options_def {
    const char *method;                 /* "blasi": its keys are "blasi.KEY" */
    size_t size;                        /* sizeof its options struct */
    void (*defaults)(void *opts);
    /* Sets KEY (without "METHOD.") from text; on failure err_set() names "METHOD.KEY" and
     * the value, and *opts is unchanged. */
    brume_status (*set)(void *opts, const char *key, const char *value);
    const char *(*names)(void);         /* the keys, for messages */
    bool (*is_path)(const char *key);   /* keys whose value is a file name (a scene file's are
                                           resolved against its folder) */
} method_options_def;

const method_options_def *method_options_def_get(method_options_id id);
/* The method owning "METHOD.KEY"; NULL when no method has that prefix. *rest = "KEY". */
const method_options_def *method_options_find(const char *key, method_options_id *id, const char **rest);
/* "path, blasi, stam": the methods that have options. */
const char *method_options_methods(void);
/* text, all of it, as a finite number in [lo, hi] into *out; false (and *out unchanged)
 * otherwise. The one number parser of every method's setter. */
bool method_option_number(const char *text, double lo, double hi, double *out);
/* The same for an integer in [lo, hi] (a count, a resolution). */
bool method_option_integer(const char *text, double lo, double hi, double *out);

#endif
