/* arena.c - a scene's data laid out for the GPU's address space (core/arena.h). */
#include "core/arena.h"

#include <stdlib.h>
#include <string.h>

void arena_init(dev_arena *a, size_t limit)
{
    memset(a, 0, sizeof *a);
    a->limit = limit;
}

void arena_free(dev_arena *a)
{
    free(a->buf);
    free(a->relocs);
    memset(a, 0, sizeof *a);
}

size_t arena_alloc(dev_arena *a, size_t n)
{
    if (a->failed)
        return ARENA_NULL;
    size_t off = (a->size + 15) & ~(size_t)15;
    if (n > SIZE_MAX / 2 - off || (a->limit && off + n > a->limit)) {
        a->failed = true;
        return ARENA_NULL;
    }
    if (off + n > a->cap) {
        size_t cap = a->cap ? a->cap : 4096;
        while (cap < off + n)
            cap *= 2;
        unsigned char *b = realloc(a->buf, cap);
        if (!b) {
            a->failed = true;
            return ARENA_NULL;
        }
        a->buf = b;
        a->cap = cap;
    }
    memset(a->buf + a->size, 0, off + n - a->size);
    a->size = off + n;
    return off;
}

size_t arena_put(dev_arena *a, const void *p, size_t n)
{
    if (!p)
        return ARENA_NULL;
    size_t off = arena_alloc(a, n);
    if (off != ARENA_NULL && n)
        memcpy(a->buf + off, p, n);
    return off;
}

void *arena_at(dev_arena *a, size_t off) { return a->buf + off; }

void arena_ptr(dev_arena *a, size_t field, size_t target)
{
    if (a->failed || field == ARENA_NULL)
        return;
    if (a->nrelocs == a->relocs_cap) {
        size_t cap = a->relocs_cap ? 2 * a->relocs_cap : 64;
        size_t *r = realloc(a->relocs, cap * sizeof *r);
        if (!r) {
            a->failed = true;
            return;
        }
        a->relocs = r;
        a->relocs_cap = cap;
    }
    a->relocs[a->nrelocs++] = field;
    memcpy(a->buf + field, &target, sizeof target);
}

void arena_relocate(dev_arena *a, uint64_t base)
{
    for (size_t i = 0; i < a->nrelocs; i++) {
        size_t target;
        memcpy(&target, a->buf + a->relocs[i], sizeof target);
        uint64_t v = target == ARENA_NULL ? 0 : base + (uint64_t)target;
        memcpy(a->buf + a->relocs[i], &v, sizeof v);
    }
}
