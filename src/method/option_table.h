/* option_table.h - the rows of a method's table of options (method_option) and the table
 * itself (method_options_def): what each method's file (path_options.c, blasi_options.c,
 * stam_params.c) fills in and method_options.c reads (the mechanism: method/method_options.h). */
#ifndef BRUME_METHOD_OPTION_TABLE_H
#define BRUME_METHOD_OPTION_TABLE_H

#include <stdbool.h>
#include <stddef.h>

#include "brume.h"
#include "core/color.h"

/* What an option's text is. The status of a bad value: BRUME_ERROR_PARSE for the closed
 * sets (enum, bool), BRUME_ERROR_RANGE for the others. */
typedef enum method_option_kind {
    OPTION_NUMBER,  /* a finite number in [lo, hi] ([lo, hi) with OPTION_HI_OPEN) */
    OPTION_INTEGER, /* a whole number in [lo, hi] (or 0 with OPTION_ZERO_OR) */
    OPTION_ENUM,    /* one of names: its index is stored */
    OPTION_BOOL,    /* true, false, 1 or 0 */
    OPTION_COLOR,   /* "v" (gray) or "r,g,b", each a number in [lo, hi] */
    OPTION_PATH     /* a file name, shorter than its char array field */
} method_option_kind;

/* How the field at `offset` stores the value (set by OPTION_FIELD from the member's type). */
typedef enum method_option_store {
    OPTION_STORE_NONE, /* no field: the option acts through `effect` only */
    OPTION_STORE_DOUBLE,
    OPTION_STORE_INT,
    OPTION_STORE_UINT, /* an enum type (gcc and clang make one with no negative value unsigned) */
    OPTION_STORE_U64,
    OPTION_STORE_BOOL,
    OPTION_STORE_COLOR,
    OPTION_STORE_CHARS /* char[size] */
} method_option_store;

enum {
    OPTION_HI_OPEN = 1u << 0, /* hi itself is refused */
    OPTION_ZERO_OR = 1u << 1, /* 0 is accepted besides [lo, hi] (0 = automatic, off) */
    OPTION_WRITES = 1u << 2   /* a path brume writes (a scene file's may only lie in its folder) */
};

typedef struct method_option {
    const char *key;         /* "METHOD.KEY", e.g. "blasi.light_rays" */
    method_option_kind kind;
    unsigned flags;          /* OPTION_HI_OPEN, OPTION_ZERO_OR, OPTION_WRITES */
    double lo, hi;           /* OPTION_NUMBER, OPTION_INTEGER, OPTION_COLOR's range */
    const char *const *names; /* OPTION_ENUM: NULL-terminated; a value stores its index */
    /* what a value is, as messages, help and docs say it: "'X' is not a number in [0, 1]" */
    const char *what;
    size_t offset, size;     /* the field in the method's options struct (OPTION_FIELD) */
    method_option_store store;
    /* the default as text, parsed as a value (without the effect) into a zeroed struct;
     * NULL: none, or computed by the method's `defaults` (then def_doc says what it is) */
    const char *def;
    const char *def_doc;     /* the default as docs show it when def is NULL */
    /* Called after a value is stored, with the index of an enum's name (0 otherwise): a
     * key that acts on others (blasi.variant) or records that it was given. */
    void (*effect)(void *opts, int choice);
    const char *doc;         /* meaning and units: one line */
} method_option;

/* The field of a row: offset, size and storage from the member's own type, so that a row
 * cannot name a field with the wrong type. */
#define OPTION_FIELD(type, member)                                                                                 \
    .offset = offsetof(type, member), .size = sizeof(((type *)0)->member),                                       \
    .store = _Generic(((type *)0)->member,                                                                       \
        double: OPTION_STORE_DOUBLE,                                                                             \
        int: OPTION_STORE_INT,                                                                                   \
        unsigned: OPTION_STORE_UINT,                                                                             \
        unsigned long: OPTION_STORE_U64,                                                                         \
        unsigned long long: OPTION_STORE_U64,                                                                    \
        bool: OPTION_STORE_BOOL,                                                                                 \
        color: OPTION_STORE_COLOR,                                                                               \
        char *: OPTION_STORE_CHARS)
/* An enum's names and its `what`, from the same literals. */
#define OPTION_NAMES2(a, b) .names = (const char *const[]){a, b, NULL}, .what = "one of " a ", " b
#define OPTION_NAMES3(a, b, c) .names = (const char *const[]){a, b, c, NULL}, .what = "one of " a ", " b ", " c
/* A macro's value as a string literal (a bound in `what`). */
#define OPTION_STR(x) OPTION_STR_(x)
#define OPTION_STR_(x) #x
/* A huge bound: "a number >= 0" is [0, OPTION_BIG]. */
#define OPTION_BIG 1e30

typedef struct method_options_def {
    const char *method;                 /* "blasi": its keys are "blasi.KEY" */
    size_t size;                        /* sizeof its options struct */
    const method_option *options;       /* its table */
    int count;
    /* defaults the table cannot give (NULL: none): run after the table's */
    void (*defaults)(void *opts);
} method_options_def;

#endif
