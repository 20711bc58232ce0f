/* arena.h - a scene's data laid out for another address space (the GPU's), with its
 * pointers relocated.
 *
 * Rendering on a GPU needs the scene's whole object graph (media, densities, phase
 * functions, lights, tables) in device memory, with every pointer a device address. Each
 * module that owns a pointer-holding struct copies it here with its `*_device_put`
 * function: arena_put copies bytes and returns their offset in the arena, arena_ptr records
 * that the pointer field at one offset must point to another offset. arena_relocate then
 * turns every recorded field into base + target once the base address is known (the
 * device allocation, or the arena's own host buffer: tests/test_gpu.c renders from such a
 * host copy on the CPU and checks it gives the original's image bit for bit, which proves
 * every pointer was carried over without a GPU).
 *
 * Offsets are bytes from the arena's start; each block starts 16-byte aligned. Ownership:
 * the arena owns its buffer (arena_free). Failure: arena_put returns ARENA_NULL and sets
 * a->failed when out of memory or over a->limit (bytes; 0 = none); later calls do nothing,
 * so callers check a->failed once at the end. */
#ifndef BRUME_CORE_ARENA_H
#define BRUME_CORE_ARENA_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define ARENA_NULL ((size_t)-1) /* the offset of nothing: a pointer field set to it stays NULL */

typedef struct dev_arena {
    unsigned char *buf; /* the copy, `size` bytes used of `cap` */
    size_t size, cap;
    size_t *relocs;     /* offsets of pointer fields; each holds its target offset until relocation */
    size_t nrelocs, relocs_cap;
    size_t limit;       /* bytes the arena may hold (the device's memory budget); 0 = no limit */
    bool failed;
} dev_arena;

void arena_init(dev_arena *a, size_t limit);
void arena_free(dev_arena *a);
/* Copies n bytes of p (16-byte aligned); returns their offset, or ARENA_NULL when p is NULL
 * or on failure. */
size_t arena_put(dev_arena *a, const void *p, size_t n);
/* Reserves n zeroed bytes; returns their offset (ARENA_NULL on failure). */
size_t arena_alloc(dev_arena *a, size_t n);
/* The arena's bytes at offset off (valid until the next put). */
void *arena_at(dev_arena *a, size_t off);
/* The pointer field at offset `field` will point to offset `target` (ARENA_NULL: NULL). */
void arena_ptr(dev_arena *a, size_t field, size_t target);
/* Writes base + target into every recorded pointer field: the arena's bytes are then the
 * object graph as seen at address `base`. Call once. */
void arena_relocate(dev_arena *a, uint64_t base);

/* The usual step: the pointer member `member` of the struct copied at `at` (a type
 * named `type`) points to the copy of n bytes of p. */
#define ARENA_PUT_MEMBER(a, at, type, member, p, n) arena_ptr((a), (at) + offsetof(type, member), arena_put((a), (p), (n)))

#endif
