/* lazylib.h - an optional library opened at its first use, not linked.
 *
 * Embree, assimp, cairo, libmicrohttpd, the MPI library, the NVIDIA driver and brume's own
 * OpenVDB module are opened with dlopen when a run first needs them: linked, their loading,
 * relocation and constructors cost every brume process's start several milliseconds for the
 * few runs that use them (docs/performance.md, "Start-up"), and a machine without them still
 * runs everything else. ctest arch.lazy_libraries checks that none of them is linked.
 *
 * A caller lists the functions it calls once, as an X-macro, and from it makes a struct of
 * pointers (each keeping the header's type) and the list of their names:
 *
 *     #define ZLIB_FUNCTIONS(X) X(deflate) X(inflate)
 *     static struct { ZLIB_FUNCTIONS(LAZYLIB_POINTER) } z;
 *     static const char *const z_names[] = {ZLIB_FUNCTIONS(LAZYLIB_NAME) NULL};
 *     static const char *const z_sonames[] = {"libz.so.1", NULL};
 *     static lazylib z_lib = LAZYLIB("zlib", z_sonames, z_names, &z, sizeof z);
 *     ...
 *     if (!lazylib_open(&z_lib))
 *         return err_set(BRUME_ERROR_UNSUPPORTED, "%s", z_lib.error);
 *
 * lazylib_open tries the SONAMEs (or paths) in order, then resolves every name into the
 * struct, in order; it does so once, whichever thread calls first, and every later call
 * returns the same answer. On failure `error` is one line naming the library, and the
 * missing symbol when that was the cause; the struct's pointers are then not to be used. */
#ifndef BRUME_CORE_LAZYLIB_H
#define BRUME_CORE_LAZYLIB_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>

/* An X-macro's entry as a struct member (the function's own type) and as its name. */
#define LAZYLIB_POINTER(f) __typeof__(f) *f;
#define LAZYLIB_NAME(f) #f,

typedef struct lazylib {
    const char *what;             /* the library in messages ("Embree") */
    const char *const *sonames;   /* tried in order, NULL-terminated: SONAMEs or paths */
    const char *const *names;     /* the symbols, NULL-terminated, in the table's order */
    void *table;                  /* a struct of as many pointers as names */
    size_t table_size;            /* its size in bytes (checked against the names) */
    bool global;                  /* RTLD_GLOBAL: the library's own plug-ins resolve its symbols */
    /* set by lazylib_open */
    pthread_mutex_t lock;
    int state;                    /* 0 not tried, 1 open, -1 failed (read atomically) */
    void *handle;                 /* the opened library; NULL when none of sonames opened */
    const char *opened;           /* which of sonames it is */
    const char *missing;          /* the symbol that was missing, or NULL */
    char error[512];              /* why it failed, one line */
} lazylib;

#define LAZYLIB(what, sonames, names, table, size) \
    {(what), (sonames), (names), (table), (size), false, PTHREAD_MUTEX_INITIALIZER, 0, NULL, NULL, NULL, {0}}
#define LAZYLIB_GLOBAL(what, sonames, names, table, size) \
    {(what), (sonames), (names), (table), (size), true, PTHREAD_MUTEX_INITIALIZER, 0, NULL, NULL, NULL, {0}}

/* Opens the library and fills its table, once (thread-safe). true when every name resolved. */
bool lazylib_open(lazylib *l);
/* Whether it has been opened, without trying. */
bool lazylib_is_open(lazylib *l);
/* A further symbol of an opened library (a data object, a handle): its address, or NULL
 * with l->error naming the library and the symbol. */
void *lazylib_symbol(lazylib *l, const char *name);

#endif
