/* nanovdb_impl.h - what the files of the NanoVDB density share: PNanoVDB itself, the grid's
 * state, the hash of block coordinates and the tree walk's bounds. nanovdb.c queries a grid
 * (lookups, majorant traversal; the GPU kernel includes it), nanovdb_walk.c walks and checks
 * the tree and builds the majorants, nanovdb_read.c reads a buffer's header and makes the
 * density. */
#ifndef BRUME_DENSITY_NANOVDB_IMPL_H
#define BRUME_DENSITY_NANOVDB_IMPL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "density/density_impl.h"

#define PNANOVDB_C
#define PNANOVDB_BUF_BOUNDS_CHECK
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wshadow"
#endif
#include <nanovdb/PNanoVDB.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#define BLOCK_CELLS 4096 /* leaf cells (8^3 voxels) per block: 16^3 */
/* The buffer, shared by the fields made from it (components of a vec3 grid). */
typedef struct nano_buffer {
    void *mem;
    size_t size;
    int refs;
} nano_buffer;

/* Open-addressing hash of integer cell coordinates to an entry index. */
typedef struct cell_hash {
    int32_t *keys; /* 3 per slot */
    int32_t *val;  /* -1 = empty */
    size_t cap;    /* power of two */
    size_t count;
} cell_hash;

typedef struct block_entry {
    float maj;  /* uniform bound, or the max of the table */
    int32_t at; /* offset / BLOCK_CELLS into the table pool, -1 when uniform */
} block_entry;

struct nanovdb_state {
    uint64_t id;          /* unique for the process's lifetime: keys the per-thread accessors */
    nano_buffer *shared;
    pnanovdb_buf_t buf;
    pnanovdb_grid_type_t type;
    pnanovdb_root_handle_t root;
    uint32_t comp_off; /* byte offset of the component within a value */
    int bbmin[3];      /* index of voxel (0, 0, 0) */
    double scale;      /* multiplies every stored value */
    /* majorants */
    cell_hash blocks;     /* block coordinate (index >> 7) -> entry */
    block_entry *entries;
    float *tables;        /* BLOCK_CELLS floats per non-uniform block, leaf cell x fastest */
    cell_hash regions;    /* region coordinate (index >> 12) -> 0 */
    float bg_maj;         /* bound outside every block */
};
/* Raw bounds while walking: one table of 16^3 leaf-cell maxima per block. */
typedef struct walk {
    const char *name;
    nanovdb_state *s;
    cell_hash raw;     /* block -> index into rawmaj / rawtab */
    float *rawmaj;     /* per raw block: its max */
    float *rawtab;     /* per raw block: BLOCK_CELLS maxima, or none (uniform) */
    int32_t *rawleaf;  /* per table: per cell, its leaf's slot in slabs, or -1 (uniform cell) */
    float *slabs;      /* per leaf: SLABS maxima over its one-voxel layers (see slab_index) */
    size_t nleaf, capleaf;
    int32_t *rawat;    /* per raw block: table index or -1 */
    size_t nraw, capraw, ntab, captab;
    double vmin, vmax;
    float bg;          /* the background value */
    int n[3];          /* the bounding box's voxels per axis */
    bool trilinear;    /* record the leaves' slabs (trilinear majorants) */
    bool any_sign;     /* values may be negative (a velocity component): only finiteness is checked */
    size_t budget[3];  /* upper, lower, leaf nodes the buffer can hold */
} walk;

#define SLABS 27

static inline size_t hash3(const int32_t k[3], size_t cap)
{
    uint64_t h = (uint64_t)(uint32_t)k[0] * 0x9E3779B97F4A7C15ull ^ (uint64_t)(uint32_t)k[1] * 0xC2B2AE3D27D4EB4Full ^
                 (uint64_t)(uint32_t)k[2] * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    return (size_t)h & (cap - 1);
}

static inline int32_t hash_find(const cell_hash *h, const int32_t k[3])
{
    for (size_t i = hash3(k, h->cap);; i = (i + 1) & (h->cap - 1)) {
        if (h->val[i] < 0)
            return -1;
        const int32_t *q = h->keys + 3 * i;
        if (q[0] == k[0] && q[1] == k[1] && q[2] == k[2])
            return h->val[i];
    }
}

static inline float read_value(const nanovdb_state *s, pnanovdb_address_t a)
{
    return pnanovdb_read_float(s->buf, pnanovdb_address_offset(a, s->comp_off));
}

/* nanovdb.c */
bool nano_hash_init(cell_hash *h, size_t expect);
void nano_hash_free(cell_hash *h);
int32_t nano_hash_insert(cell_hash *h, const int32_t k[3], int32_t v);

/* nanovdb_walk.c */
bool nano_value_ok(walk *w, float v, int x, int y, int z);
bool nano_oom(walk *w);
bool nano_walk_tree(walk *w, uint64_t tiles, float background);
bool nano_build_majorants(walk *w, bool dilate, float bg);

#endif
