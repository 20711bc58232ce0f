/* lazylib.c - optional libraries opened at their first use (core/lazylib.h). */
#define _GNU_SOURCE /* dlopen flags in C11 */
#include "core/lazylib.h"

#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

/* A function's address travels through dlsym's void *: POSIX has them the same size. */
_Static_assert(sizeof(void (*)(void)) == sizeof(void *), "function and data pointers differ in size");

static bool load(lazylib *l)
{
    size_t n = 0;
    while (l->names[n])
        n++;
    if (n * sizeof(void *) != l->table_size) {
        snprintf(l->error, sizeof l->error, "%s: the table holds %zu bytes for %zu names (a bug in brume)", l->what,
                 l->table_size, n);
        return false;
    }
    const char *first = l->sonames[0] ? l->sonames[0] : "";
    char why[400] = "";
    for (int i = 0; l->sonames[i] && !l->handle; i++) {
        l->handle = dlopen(l->sonames[i], RTLD_NOW | (l->global ? RTLD_GLOBAL : RTLD_LOCAL));
        if (l->handle)
            l->opened = l->sonames[i];
        else if (!why[0])
            snprintf(why, sizeof why, "%s", dlerror());
    }
    if (!l->handle) {
        snprintf(l->error, sizeof l->error, "cannot open %s: %s", l->what, why[0] ? why : first);
        return false;
    }
    for (size_t i = 0; i < n; i++) {
        void *f = dlsym(l->handle, l->names[i]);
        if (!f) {
            l->missing = l->names[i];
            snprintf(l->error, sizeof l->error, "cannot use %s: %s lacks %s", l->what, l->opened, l->names[i]);
            return false;
        }
        memcpy((char *)l->table + i * sizeof f, &f, sizeof f);
    }
    return true;
}

bool lazylib_open(lazylib *l)
{
    int s = __atomic_load_n(&l->state, __ATOMIC_ACQUIRE);
    if (s)
        return s > 0;
    pthread_mutex_lock(&l->lock);
    if (!l->state)
        __atomic_store_n(&l->state, load(l) ? 1 : -1, __ATOMIC_RELEASE);
    s = l->state;
    pthread_mutex_unlock(&l->lock);
    return s > 0;
}

bool lazylib_is_open(lazylib *l) { return __atomic_load_n(&l->state, __ATOMIC_ACQUIRE) > 0; }

void *lazylib_symbol(lazylib *l, const char *name)
{
    void *p = l->handle ? dlsym(l->handle, name) : NULL;
    if (!p) {
        pthread_mutex_lock(&l->lock);
        l->missing = name;
        snprintf(l->error, sizeof l->error, "cannot use %s: %s lacks %s", l->what, l->opened ? l->opened : "(not open)",
                 name);
        pthread_mutex_unlock(&l->lock);
    }
    return p;
}
