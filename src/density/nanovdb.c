/* nanovdb.c - sparse grids in a NanoVDB buffer, traversed in C through PNanoVDB (the
 * portable C/HLSL/GLSL header of NanoVDB, Museth 2021, Debian's libnanovdb-dev), with
 * majorants built from the tree itself.
 *
 * The buffer stays as it was written: a root table, 32^3 upper and 16^3 lower internal
 * nodes, 8^3 leaves; lookups go through a PNanoVDB read accessor, which caches the path to
 * the last leaf. Float grids give their value; Vec3f grids give one component (a medium's
 * albedo is three such fields sharing one buffer). Every buffer read is bounds-checked
 * (PNANOVDB_BUF_BOUNDS_CHECK: a read outside the buffer returns 0), so a hostile buffer can
 * give wrong values but never read outside its memory.
 *
 * Construction walks the tree as lookups do (root tiles, then child pointers), with the
 * number of nodes visited bounded by what the buffer can hold, so that the work is linear
 * in the buffer's size whatever the pointers say. Every value a lookup can reach (background,
 * tiles, all 512 values of each leaf) is checked finite and >= 0 on the way.
 *
 * Majorants (docs/grids.md, "Majorants of sparse grids"): the walk records, for each lower
 * node (a "block" of 128^3 voxels), the max of each of its 16^3 leaf cells (a leaf's max or a
 * tile value); tiles above the lower level give uniform blocks. For the trilinear filter
 * it also records each leaf's 27 slab maxima (per axis its layer at 0, all of it, or its
 * layer at 7), and every cell's bound is widened by exactly what a lookup in it can read of
 * its 26 neighbours (one voxel beyond the cell: a face, an edge line or a corner of each),
 * which adds the blocks next to occupied ones. Blocks
 * live in a hash table keyed by block coordinate; a block whose 16^3 bounds are all equal
 * keeps one number. A second table marks the 4096^3 "regions" holding any block. Along a ray
 * three nested DDAs walk regions, blocks and leaf cells: space outside the tables is the
 * background's bound and costs one step per region, so nothing is dense over the bounding box. */
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "density/density_impl.h"
#include "core/arena.h"

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
/* Index boxes of at most this many voxels get the dense grids' cell bounds instead of the
 * tree's nested walk: at most 2^23 / 64 cells (1 MiB of bounds), built in about 3.4 reads
 * per voxel of the box (docs/grids.md, "Majorants of sparse grids"). */
#define NANO_CELL_GRID_VOXELS ((uint64_t)1 << 23)
static _Atomic uint64_t nano_cell_grid_voxels = NANO_CELL_GRID_VOXELS;

uint64_t nanovdb_set_cell_grid_limit(uint64_t voxels) { return atomic_exchange(&nano_cell_grid_voxels, voxels); }

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

/* ---- hash ------------------------------------------------------------------------------- */

static size_t hash3(const int32_t k[3], size_t cap)
{
    uint64_t h = (uint64_t)(uint32_t)k[0] * 0x9E3779B97F4A7C15ull ^ (uint64_t)(uint32_t)k[1] * 0xC2B2AE3D27D4EB4Full ^
                 (uint64_t)(uint32_t)k[2] * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    return (size_t)h & (cap - 1);
}

static bool hash_init(cell_hash *h, size_t expect)
{
    h->cap = 16;
    while (h->cap < 2 * expect + 2)
        h->cap *= 2;
    h->count = 0;
    h->keys = malloc(h->cap * 3 * sizeof *h->keys);
    h->val = malloc(h->cap * sizeof *h->val);
    if (!h->keys || !h->val)
        return false;
    for (size_t i = 0; i < h->cap; i++)
        h->val[i] = -1;
    return true;
}

static void hash_free(cell_hash *h)
{
    free(h->keys);
    free(h->val);
    h->keys = NULL;
    h->val = NULL;
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

/* Inserts k with value v unless present; returns the value stored; -2 when out of memory. */
static int32_t hash_insert(cell_hash *h, const int32_t k[3], int32_t v)
{
    if (2 * (h->count + 1) > h->cap) {
        cell_hash g;
        if (!hash_init(&g, h->count + 1))
            return -2;
        for (size_t i = 0; i < h->cap; i++)
            if (h->val[i] >= 0)
                hash_insert(&g, h->keys + 3 * i, h->val[i]);
        hash_free(h);
        *h = g;
    }
    for (size_t i = hash3(k, h->cap);; i = (i + 1) & (h->cap - 1)) {
        if (h->val[i] < 0) {
            memcpy(h->keys + 3 * i, k, 3 * sizeof *k);
            h->val[i] = v;
            h->count++;
            return v;
        }
        const int32_t *q = h->keys + 3 * i;
        if (q[0] == k[0] && q[1] == k[1] && q[2] == k[2])
            return h->val[i];
    }
}

/* ---- lookups ----------------------------------------------------------------------------- */

/* Each thread keeps a read accessor per grid (NanoVDB's ReadAccessor: the path to the last
 * leaf, lower and upper node), so that successive lookups along a ray, which mostly fall in
 * the leaf of the previous one, skip the descent from the root. Slots are keyed by the
 * grid's id, which is never reused, so a slot left by a released grid can never be taken for
 * a live one; a collision between live grids only costs a descent. */
#define NANO_ACC_SLOTS 8 /* power of two */
typedef struct nano_acc_slot {
    uint64_t id; /* 0: empty */
    pnanovdb_readaccessor_t acc;
} nano_acc_slot;
#if !defined(__CUDA_ARCH__)
static _Thread_local nano_acc_slot nano_acc_cache[NANO_ACC_SLOTS];
#endif
static atomic_uint_fast64_t nano_next_id = 1;

/* NANO_ACCESSOR(acc, s) declares pnanovdb_readaccessor_t *acc for a lookup in s: this
 * thread's cached accessor, or on the GPU (gpu/kernel.cu, no thread-local storage) a fresh
 * one in the device thread's local memory. */
#if defined(__CUDA_ARCH__)
#define NANO_ACCESSOR(acc, s)                                                                                          \
    pnanovdb_readaccessor_t acc##_local;                                                                               \
    pnanovdb_readaccessor_init(&acc##_local, (s)->root);                                                               \
    pnanovdb_readaccessor_t *acc = &acc##_local
#else
#define NANO_ACCESSOR(acc, s) pnanovdb_readaccessor_t *acc = nano_accessor(s)
static inline pnanovdb_readaccessor_t *nano_accessor(const nanovdb_state *s)
{
    nano_acc_slot *slot = &nano_acc_cache[s->id & (NANO_ACC_SLOTS - 1)];
    if (slot->id != s->id) {
        slot->id = s->id;
        pnanovdb_readaccessor_init(&slot->acc, s->root);
    }
    return &slot->acc;
}
#endif

static inline double nano_read(const nanovdb_state *s, pnanovdb_address_t a)
{
    return (double)pnanovdb_read_float(s->buf, pnanovdb_address_offset(a, s->comp_off)) * s->scale;
}

static inline double nano_fetch(const nanovdb_state *s, pnanovdb_readaccessor_t *acc, int i, int j, int k)
{
    pnanovdb_coord_t ijk = {i + s->bbmin[0], j + s->bbmin[1], k + s->bbmin[2]};
    return nano_read(s, pnanovdb_readaccessor_get_value_address(s->type, s->buf, acc, &ijk));
}

double nanovdb_voxel(const density *d, int i, int j, int k)
{
    NANO_ACCESSOR(acc, d->nano);
    return nano_fetch(d->nano, acc, i, j, k);
}

/* u in voxel space, inside [0, n); same filters as the dense grid (grid.c). */
double nanovdb_eval_voxel(const density *d, vec3 u)
{
    const nanovdb_state *s = d->nano;
    NANO_ACCESSOR(acc, s);
    if (d->filter == GRID_NEAREST)
        return nano_fetch(s, acc, (int)u.x, (int)u.y, (int)u.z);
    int ijk[3][2];
    double a[3], c[8];
    trilinear_corners(u, d->n, ijk, a);
    pnanovdb_coord_t p0 = {ijk[0][0] + s->bbmin[0], ijk[1][0] + s->bbmin[1], ijk[2][0] + s->bbmin[2]};
    if (ijk[0][1] == ijk[0][0] + 1 && ijk[1][1] == ijk[1][0] + 1 && ijk[2][1] == ijk[2][0] + 1 && (p0.x & 7) != 7 &&
        (p0.y & 7) != 7 && (p0.z & 7) != 7) {
        /* the 2 x 2 x 2 corners lie in one 8^3 leaf cell (two times in three): one descent,
         * then the leaf's table (x slowest: offsets 64, 8, 1 values), or one tile value */
        pnanovdb_uint32_t level;
        pnanovdb_address_t a0 = pnanovdb_readaccessor_get_value_address_and_level(s->type, s->buf, acc, &p0, &level);
        if (level != 0)
            return nano_read(s, a0);
        uint32_t v = PNANOVDB_GRID_TYPE_GET(s->type, value_stride_bits) >> 3;
        for (int q = 0; q < 8; q++)
            c[q] = nano_read(s, pnanovdb_address_offset(a0, v * (64u * (q & 1) + 8u * ((q >> 1) & 1) + (uint32_t)(q >> 2))));
        return trilinear_blend(c, a);
    }
    for (int q = 0; q < 8; q++)
        c[q] = nano_fetch(s, acc, ijk[0][q & 1], ijk[1][(q >> 1) & 1], ijk[2][q >> 2]);
    return trilinear_blend(c, a);
}

static void nano_free_majorants(nanovdb_state *s)
{
    hash_free(&s->blocks);
    hash_free(&s->regions);
    free(s->entries);
    free(s->tables);
    s->entries = NULL;
    s->tables = NULL;
}

void nanovdb_free(density *d)
{
    nanovdb_state *s = d->nano;
    if (!s)
        return;
    nano_free_majorants(s);
    if (s->shared && --s->shared->refs == 0) {
        free(s->shared->mem);
        free(s->shared);
    }
    free(s);
}

/* ---- the tree walk ------------------------------------------------------------------------- */

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

static bool value_ok(walk *w, float v, int x, int y, int z)
{
    if (!isfinite(v) || (v < 0.0f && !w->any_sign)) {
        err_set(BRUME_ERROR_RANGE, "%s: voxel (%d, %d, %d) has %s %g: need finite%s", w->name, x, y, z,
                w->any_sign ? "value" : "density", (double)v, w->any_sign ? "" : " and >= 0");
        return false;
    }
    w->vmin = fmin(w->vmin, (double)v);
    w->vmax = fmax(w->vmax, (double)v);
    return true;
}

static inline float read_value(const nanovdb_state *s, pnanovdb_address_t a)
{
    return pnanovdb_read_float(s->buf, pnanovdb_address_offset(a, s->comp_off));
}

/* A leaf cell's layers, for the trilinear filter: per axis 0 = its layer at 0, 1 = all of
 * it, 2 = its layer at 7 (one voxel thick). Slab (1, 1, 1) is the whole leaf; a neighbour
 * offset by d from a cell can be read, by a lookup in that cell, only in its slab
 * (d > 0 ? 0 : d < 0 ? 2 : 1) per axis. */
#define SLABS 27
static inline int slab_index(int sx, int sy, int sz) { return sx + 3 * (sy + 3 * sz); }

/* Raises every slab of leaf slot `slot` to at least v. */
static void slabs_raise(walk *w, int32_t slot, float v)
{
    float *sl = w->slabs + (size_t)slot * SLABS;
    for (int q = 0; q < SLABS; q++)
        sl[q] = v > sl[q] ? v : sl[q];
}

/* The slabs of a leaf cell whose slot is *slot (a new one, each slab at `init`, if -1);
 * NULL when out of memory. */
static float *leaf_slabs(walk *w, int32_t *slot, float init)
{
    if (*slot < 0) {
        if (w->nleaf == w->capleaf) {
            size_t cap = w->capleaf ? 2 * w->capleaf : 256;
            float *t = realloc(w->slabs, cap * SLABS * sizeof *t);
            if (!t)
                return NULL;
            w->slabs = t;
            w->capleaf = cap;
        }
        *slot = (int32_t)w->nleaf++;
        for (int q = 0; q < SLABS; q++)
            w->slabs[(size_t)*slot * SLABS + (size_t)q] = init;
    }
    return w->slabs + (size_t)*slot * SLABS;
}

/* The raw block at key, created uniform-0 if absent, with a table if `table`. Index or -1. */
static int32_t raw_block(walk *w, const int32_t key[3], bool table)
{
    if (w->nraw == w->capraw) {
        size_t cap = w->capraw ? 2 * w->capraw : 64;
        float *m = realloc(w->rawmaj, cap * sizeof *m);
        if (m)
            w->rawmaj = m;
        int32_t *a = realloc(w->rawat, cap * sizeof *a);
        if (a)
            w->rawat = a;
        if (!m || !a)
            return -1;
        w->capraw = cap;
    }
    int32_t idx = hash_insert(&w->raw, key, (int32_t)w->nraw);
    if (idx < 0)
        return -1;
    if ((size_t)idx == w->nraw) {
        w->rawmaj[idx] = 0.0f;
        w->rawat[idx] = -1;
        w->nraw++;
    }
    if (table && w->rawat[idx] < 0) {
        if (w->ntab == w->captab) {
            size_t cap = w->captab ? 2 * w->captab : 16;
            float *t = realloc(w->rawtab, cap * BLOCK_CELLS * sizeof *t);
            if (t)
                w->rawtab = t;
            int32_t *l = realloc(w->rawleaf, cap * BLOCK_CELLS * sizeof *l);
            if (l)
                w->rawleaf = l;
            if (!t || !l)
                return -1;
            w->captab = cap;
        }
        float *t = w->rawtab + w->ntab * BLOCK_CELLS;
        int32_t *l = w->rawleaf + w->ntab * BLOCK_CELLS;
        for (int c = 0; c < BLOCK_CELLS; c++) {
            t[c] = w->rawmaj[idx];
            l[c] = -1;
        }
        w->rawat[idx] = (int32_t)w->ntab++;
    }
    return idx;
}

static bool oom(walk *w)
{
    err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for the majorants", w->name);
    return false;
}

static bool walk_lower(walk *w, pnanovdb_lower_handle_t lower, const int org[3])
{
    nanovdb_state *s = w->s;
    int32_t key[3] = {org[0] >> 7, org[1] >> 7, org[2] >> 7};
    int32_t b = raw_block(w, key, true);
    if (b < 0)
        return oom(w);
    float *tab = w->rawtab + (size_t)w->rawat[b] * BLOCK_CELLS;
    int32_t *lslot = w->rawleaf + (size_t)w->rawat[b] * BLOCK_CELLS;
    float bmax = w->rawmaj[b];
    for (uint32_t n = 0; n < BLOCK_CELLS; n++) {
        int lx = (int)(n >> 8), ly = (int)((n >> 4) & 15), lz = (int)(n & 15);
        int x = org[0] + 8 * lx, y = org[1] + 8 * ly, z = org[2] + 8 * lz;
        float m;
        size_t c = (size_t)lx + 16 * ((size_t)ly + 16 * (size_t)lz);
        if (pnanovdb_lower_get_child_mask(s->buf, lower, n)) {
            if (w->budget[2]-- == 0) {
                err_set(BRUME_ERROR_PARSE, "%s: the tree reaches more leaves than the buffer holds", w->name);
                return false;
            }
            pnanovdb_leaf_handle_t leaf = pnanovdb_lower_get_child(s->type, s->buf, lower, n);
            float *sl = w->trilinear ? leaf_slabs(w, &lslot[c], tab[c]) : NULL;
            if (w->trilinear && !sl)
                return oom(w);
            m = 0.0f;
            for (uint32_t v = 0; v < 512; v++) {
                float f = read_value(s, pnanovdb_leaf_get_table_address(s->type, s->buf, leaf, v));
                const int vx = (int)(v >> 6), vy = (int)((v >> 3) & 7), vz = (int)(v & 7);
                if (!value_ok(w, f, x + vx, y + vy, z + vz))
                    return false;
                m = f > m ? f : m;
                if (sl) { /* every layer holding the voxel: per axis "all", and its own end if at one */
                    const int ex = vx == 0 ? 0 : (vx == 7 ? 2 : 1), ey = vy == 0 ? 0 : (vy == 7 ? 2 : 1),
                              ez = vz == 0 ? 0 : (vz == 7 ? 2 : 1);
                    for (int q = 0; q < 8; q++) {
                        const int sx = q & 1 ? ex : 1, sy = q & 2 ? ey : 1, sz = q & 4 ? ez : 1;
                        float *t = &sl[slab_index(sx, sy, sz)];
                        *t = f > *t ? f : *t;
                    }
                }
            }
        } else {
            m = read_value(s, pnanovdb_lower_get_table_address(s->type, s->buf, lower, n));
            if (!value_ok(w, m, x, y, z))
                return false;
            if (lslot[c] >= 0) /* a malformed tree: raise the cell's slabs too */
                slabs_raise(w, lslot[c], m);
        }
        tab[c] = m > tab[c] ? m : tab[c];
        bmax = m > bmax ? m : bmax;
    }
    w->rawmaj[b] = bmax;
    return true;
}

/* A uniform bound v over the block at key (a tile above the lower level). */
static bool walk_tile_block(walk *w, const int32_t key[3], float v)
{
    int32_t b = raw_block(w, key, false);
    if (b < 0)
        return oom(w);
    if (w->rawat[b] >= 0) {
        float *t = w->rawtab + (size_t)w->rawat[b] * BLOCK_CELLS;
        const int32_t *l = w->rawleaf + (size_t)w->rawat[b] * BLOCK_CELLS;
        for (int c = 0; c < BLOCK_CELLS; c++) {
            t[c] = v > t[c] ? v : t[c];
            if (l[c] >= 0)
                slabs_raise(w, l[c], v);
        }
    }
    w->rawmaj[b] = v > w->rawmaj[b] ? v : w->rawmaj[b];
    return true;
}

static bool walk_upper(walk *w, pnanovdb_upper_handle_t upper, const int org[3])
{
    nanovdb_state *s = w->s;
    for (uint32_t n = 0; n < 32768; n++) {
        int o[3] = {org[0] + 128 * (int)(n >> 10), org[1] + 128 * (int)((n >> 5) & 31), org[2] + 128 * (int)(n & 31)};
        if (pnanovdb_upper_get_child_mask(s->buf, upper, n)) {
            if (w->budget[1]-- == 0) {
                err_set(BRUME_ERROR_PARSE, "%s: the tree reaches more lower nodes than the buffer holds", w->name);
                return false;
            }
            if (!walk_lower(w, pnanovdb_upper_get_child(s->type, s->buf, upper, n), o))
                return false;
        } else {
            float v = read_value(s, pnanovdb_upper_get_table_address(s->type, s->buf, upper, n));
            if (!value_ok(w, v, o[0], o[1], o[2]))
                return false;
            if (v > w->bg) {
                int32_t key[3] = {o[0] >> 7, o[1] >> 7, o[2] >> 7};
                if (!walk_tile_block(w, key, v))
                    return false;
            }
        }
    }
    return true;
}

static bool walk_tree(walk *w, uint64_t tiles, float background)
{
    nanovdb_state *s = w->s;
    pnanovdb_buf_t b = s->buf;
    for (uint64_t t = 0; t < tiles; t++) {
        pnanovdb_root_tile_handle_t tile = pnanovdb_root_get_tile(s->type, s->root, (pnanovdb_uint32_t)t);
        uint64_t key = pnanovdb_root_tile_get_key(b, tile);
        int org[3] = {(int)((uint32_t)((key >> 42) & 0xFFFFF) << 12), (int)((uint32_t)((key >> 21) & 0xFFFFF) << 12),
                      (int)((uint32_t)(key & 0xFFFFF) << 12)};
        if (pnanovdb_int64_is_zero(pnanovdb_root_tile_get_child(b, tile))) {
            float v = read_value(s, pnanovdb_address_offset(tile.address, PNANOVDB_GRID_TYPE_GET(s->type, root_tile_off_value)));
            if (!value_ok(w, v, org[0], org[1], org[2]))
                return false;
            if (v > background) { /* a 4096^3 tile: its blocks inside the bounding box */
                int32_t klo[3], khi[3];
                for (int a = 0; a < 3; a++) {
                    int64_t blo = (int64_t)s->bbmin[a] >> 7, bhi = ((int64_t)s->bbmin[a] + w->n[a] - 1) >> 7;
                    int64_t tlo = org[a] >> 7, thi = tlo + 31;
                    klo[a] = (int32_t)(blo > tlo ? blo : tlo);
                    khi[a] = (int32_t)(bhi < thi ? bhi : thi);
                }
                for (int32_t z = klo[2]; z <= khi[2]; z++)
                    for (int32_t y = klo[1]; y <= khi[1]; y++)
                        for (int32_t x = klo[0]; x <= khi[0]; x++) {
                            int32_t k[3] = {x, y, z};
                            if (!walk_tile_block(w, k, v))
                                return false;
                        }
            }
            continue;
        }
        if (w->budget[0]-- == 0) {
            err_set(BRUME_ERROR_PARSE, "%s: the tree reaches more upper nodes than the buffer holds", w->name);
            return false;
        }
        if (!walk_upper(w, pnanovdb_root_get_child(s->type, b, s->root, tile), org))
            return false;
    }
    return true;
}

/* Final bounds of one block: its raw leaf-cell bounds (nearest), or for the trilinear filter
 * each cell's bound widened by exactly what a lookup inside it can read of its 26
 * neighbours: the one-voxel layer of each that touches it (a face, an edge line, a corner
 * voxel), from the leaves' slabs (a uniform cell's layers are its value). Times the scale
 * comes later. Into out[BLOCK_CELLS]. */
static void block_bounds(const walk *w, const int32_t key[3], bool dilate, float bg, float *out)
{
    if (!dilate) {
        int32_t b = hash_find(&w->raw, key);
        for (int c = 0; c < BLOCK_CELLS; c++)
            out[c] = b < 0 ? bg : (w->rawat[b] < 0 ? w->rawmaj[b] : w->rawtab[(size_t)w->rawat[b] * BLOCK_CELLS + (size_t)c]);
        return;
    }
    /* the block and one cell of each neighbour, padded to 18^3: each cell's value (uniform)
     * or its leaf's slabs */
    static _Thread_local float pad[18 * 18 * 18];
    static _Thread_local const float *padsl[18 * 18 * 18];
    const float *nb_tab[27];
    const int32_t *nb_leaf[27];
    float nb_uni[27];
    for (int q = 0; q < 27; q++) {
        int32_t k[3] = {key[0] + q % 3 - 1, key[1] + (q / 3) % 3 - 1, key[2] + q / 9 - 1};
        int32_t b = hash_find(&w->raw, k);
        bool tab = b >= 0 && w->rawat[b] >= 0;
        nb_tab[q] = tab ? w->rawtab + (size_t)w->rawat[b] * BLOCK_CELLS : NULL;
        nb_leaf[q] = tab ? w->rawleaf + (size_t)w->rawat[b] * BLOCK_CELLS : NULL;
        nb_uni[q] = b < 0 ? bg : w->rawmaj[b];
    }
    for (int z = -1; z <= 16; z++)
        for (int y = -1; y <= 16; y++)
            for (int x = -1; x <= 16; x++) {
                int qx = x < 0 ? 0 : (x > 15 ? 2 : 1), qy = y < 0 ? 0 : (y > 15 ? 2 : 1), qz = z < 0 ? 0 : (z > 15 ? 2 : 1);
                int q = qx + 3 * qy + 9 * qz;
                size_t lc = (size_t)((x + 16) & 15) + 16 * ((size_t)((y + 16) & 15) + 16 * (size_t)((z + 16) & 15));
                size_t pc = (size_t)(x + 1) + 18 * ((size_t)(y + 1) + 18 * (size_t)(z + 1));
                pad[pc] = nb_tab[q] ? nb_tab[q][lc] : nb_uni[q];
                padsl[pc] = nb_leaf[q] && nb_leaf[q][lc] >= 0 ? w->slabs + (size_t)nb_leaf[q][lc] * SLABS : NULL;
            }
    /* per neighbour offset (dx, dy, dz): the pad step and the neighbour's slab that touches
     * the cell (per axis: offset +1, its layer at 0; -1, its layer at 7; 0, all of it) */
    int step[26], slab[26], nd = 0;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                if (!dx && !dy && !dz)
                    continue;
                step[nd] = dx + 18 * (dy + 18 * dz);
                slab[nd] = slab_index(1 - dx, 1 - dy, 1 - dz);
                nd++;
            }
    for (int z = 0; z < 16; z++)
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 16; x++) {
                int pc = (x + 1) + 18 * ((y + 1) + 18 * (z + 1));
                float m = pad[pc];
                for (int k = 0; k < 26; k++) {
                    const float *sl = padsl[pc + step[k]];
                    float f = sl ? sl[slab[k]] : pad[pc + step[k]];
                    m = f > m ? f : m;
                }
                out[x + 16 * (y + 16 * z)] = m;
            }
}

/* v scale as a float no smaller than the double product lookups compute. */
static float scale_up(float v, double scale)
{
    double p = (double)v * scale;
    float f = (float)p;
    return (double)f < p ? nextafterf(f, INFINITY) : f;
}

/* From the raw tables of the walk to the final blocks and regions of s. */
static bool build_majorants(walk *w, bool dilate, float bg)
{
    nanovdb_state *s = w->s;
    /* the keys: raw blocks, and with dilation their neighbours */
    cell_hash keys;
    if (!hash_init(&keys, w->nraw * (dilate ? 4 : 1)))
        return oom(w);
    for (size_t i = 0; i < w->raw.cap; i++) {
        if (w->raw.val[i] < 0)
            continue;
        const int32_t *k = w->raw.keys + 3 * i;
        for (int q = 0; q < (dilate ? 27 : 1); q++) {
            int32_t n[3] = {k[0] + (dilate ? q % 3 - 1 : 0), k[1] + (dilate ? (q / 3) % 3 - 1 : 0),
                            k[2] + (dilate ? q / 9 - 1 : 0)};
            if (hash_insert(&keys, n, (int32_t)keys.count) == -2) {
                hash_free(&keys);
                return oom(w);
            }
        }
    }
    s->entries = malloc((keys.count + 1) * sizeof *s->entries);
    float *block = malloc(BLOCK_CELLS * sizeof *block);
    if (!s->entries || !block || !hash_init(&s->blocks, keys.count) || !hash_init(&s->regions, keys.count / 8 + 1)) {
        free(block);
        hash_free(&keys);
        return oom(w);
    }
    size_t ntab = 0, captab = 0;
    int32_t ne = 0;
    for (size_t i = 0; i < keys.cap; i++) {
        if (keys.val[i] < 0)
            continue;
        const int32_t *k = keys.keys + 3 * i;
        block_bounds(w, k, dilate, bg, block);
        float mx = 0.0f, mn = INFINITY;
        for (int c = 0; c < BLOCK_CELLS; c++) {
            block[c] = scale_up(block[c], s->scale);
            mx = block[c] > mx ? block[c] : mx;
            mn = block[c] < mn ? block[c] : mn;
        }
        block_entry e = {mx, -1};
        if (mn != mx) {
            if (ntab == captab) {
                size_t cap = captab ? 2 * captab : 16;
                float *t = realloc(s->tables, cap * BLOCK_CELLS * sizeof *t);
                if (!t) {
                    free(block);
                    hash_free(&keys);
                    return oom(w);
                }
                s->tables = t;
                captab = cap;
            }
            memcpy(s->tables + ntab * BLOCK_CELLS, block, BLOCK_CELLS * sizeof *block);
            e.at = (int32_t)ntab++;
        }
        s->entries[ne] = e;
        int32_t r[3] = {k[0] >> 5, k[1] >> 5, k[2] >> 5};
        if (hash_insert(&s->blocks, k, ne) == -2 || hash_insert(&s->regions, r, 0) == -2) {
            free(block);
            hash_free(&keys);
            return oom(w);
        }
        ne++;
    }
    free(block);
    hash_free(&keys);
    if (ntab > 0 && ntab < captab) { /* give back the unused tail */
        float *t = realloc(s->tables, ntab * BLOCK_CELLS * sizeof *t);
        if (t)
            s->tables = t;
    }
    s->bg_maj = scale_up(bg, s->scale);
    return true;
}

static size_t hash_bytes(const cell_hash *h) { return h->cap * 4 * sizeof(int32_t); }

/* ---- construction ---------------------------------------------------------------------------- */

/* What nano_make reads from a grid's header before it builds anything. */
typedef struct nano_header {
    pnanovdb_buf_t b;
    pnanovdb_uint32_t type;     /* PNANOVDB_GRID_TYPE_FLOAT or _VEC3F */
    pnanovdb_tree_handle_t tree;
    pnanovdb_root_handle_t root;
    uint64_t tiles;             /* the root's */
    pnanovdb_coord_t lo;        /* the index bounding box's min */
    int64_t ext[3];             /* its voxels per axis, in [1, 2^30] */
    affine3 v2w;                /* voxel space (as for dense grids) -> world */
} nano_header;

/* Checks the grid in shared (its size, magic number, type, root, tiles and bounding box)
 * and reads its placement, composed with `extra` when not NULL; false with err_set. */
static bool nano_read_header(const nano_buffer *shared, int component, const affine3 *extra, const char *name,
                             nano_header *h)
{
    void *buf = shared->mem;
    size_t size = shared->size;
    if (size < PNANOVDB_GRID_SIZE + PNANOVDB_TREE_SIZE || ((uintptr_t)buf & 7u) != 0) {
        err_set(BRUME_ERROR_PARSE, "%s: NanoVDB grid of %zu bytes is too small or misaligned", name, size);
        return false;
    }
    pnanovdb_buf_t b = pnanovdb_make_buf((uint32_t *)buf, size / 4);
    pnanovdb_grid_handle_t grid = {pnanovdb_address_null()};
    if (pnanovdb_grid_get_magic(b, grid) != PNANOVDB_MAGIC_NUMBER) {
        err_set(BRUME_ERROR_PARSE, "%s: not a NanoVDB grid (wrong magic number)", name);
        return false;
    }
    pnanovdb_uint32_t type = pnanovdb_grid_get_grid_type(b, grid);
    if (type != PNANOVDB_GRID_TYPE_FLOAT && type != PNANOVDB_GRID_TYPE_VEC3F) {
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: NanoVDB grid type %u is neither float (1) nor vec3f (6)", name,
                (unsigned)type);
        return false;
    }
    if (type == PNANOVDB_GRID_TYPE_VEC3F && component < 0) {
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: a vec3 grid where a float grid is needed", name);
        return false;
    }
    uint64_t gsize = pnanovdb_grid_get_grid_size(b, grid);
    if (gsize > size) {
        err_set(BRUME_ERROR_PARSE, "%s: truncated: grid says %llu bytes, buffer has %zu", name,
                (unsigned long long)gsize, size);
        return false;
    }
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(b, grid);
    pnanovdb_root_handle_t root = pnanovdb_tree_get_root(b, tree);
    if (root.address.byte_offset > size || size - root.address.byte_offset < PNANOVDB_GRID_TYPE_GET(type, root_size)) {
        err_set(BRUME_ERROR_PARSE, "%s: root node offset %llu outside the grid", name,
                (unsigned long long)root.address.byte_offset);
        return false;
    }
    uint64_t tiles = pnanovdb_root_get_tile_count(b, root);
    if (tiles > (size - root.address.byte_offset) / PNANOVDB_GRID_TYPE_GET(type, root_tile_size)) {
        err_set(BRUME_ERROR_PARSE, "%s: root claims %llu tiles, more than the grid holds", name, (unsigned long long)tiles);
        return false;
    }
    pnanovdb_coord_t lo = pnanovdb_root_get_bbox_min(b, root), hi = pnanovdb_root_get_bbox_max(b, root);
    int64_t ext[3] = {(int64_t)hi.x - lo.x + 1, (int64_t)hi.y - lo.y + 1, (int64_t)hi.z - lo.z + 1};
    for (int a = 0; a < 3; a++)
        if (ext[a] < 1 || ext[a] > (1 << 30)) {
            err_set(BRUME_ERROR_PARSE, "%s: empty or oversized index bounding box (%d, %d, %d)..(%d, %d, %d)", name,
                    lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
            return false;
        }
    /* index -> world: world = M idx + v (NanoVDB Map, row-major double matrix). */
    pnanovdb_map_handle_t map = pnanovdb_grid_get_map(b, grid);
    affine3 i2w;
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++)
            i2w.m[4 * r + c] = pnanovdb_map_get_matd(b, map, (pnanovdb_uint32_t)(3 * r + c));
        i2w.m[4 * r + 3] = pnanovdb_map_get_vecd(b, map, (pnanovdb_uint32_t)r);
    }
    /* voxel space u = idx - bbmin + 1/2 (voxel centres at half-integers, as for dense) */
    affine3 v2i = {{1, 0, 0, lo.x - 0.5, 0, 1, 0, lo.y - 0.5, 0, 0, 1, lo.z - 0.5}};
    h->v2w = affine3_compose(&i2w, &v2i);
    if (extra)
        h->v2w = affine3_compose(extra, &h->v2w);
    h->b = b;
    h->type = type;
    h->tree = tree;
    h->root = root;
    h->tiles = tiles;
    h->lo = lo;
    for (int a = 0; a < 3; a++)
        h->ext[a] = ext[a];
    return true;
}

/* The density and its nanovdb_state for the grid of h, placed, without majorants yet;
 * NULL with err_set. */
static density *nano_density_new(const nano_header *h, int component, grid_filter filter, double scale,
                                 const char *name)
{
    density *d = calloc(1, sizeof *d);
    nanovdb_state *s = calloc(1, sizeof *s);
    if (!d || !s) {
        free(d);
        free(s);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        return NULL;
    }
    d->kind = DENSITY_NANOVDB;
    d->filter = filter;
    d->nano = s;
    s->id = atomic_fetch_add(&nano_next_id, 1);
    s->buf = h->b;
    s->type = h->type;
    s->root = h->root;
    s->scale = scale;
    s->comp_off = h->type == PNANOVDB_GRID_TYPE_VEC3F ? 4u * (uint32_t)component : 0u;
    s->bbmin[0] = h->lo.x;
    s->bbmin[1] = h->lo.y;
    s->bbmin[2] = h->lo.z;
    for (int a = 0; a < 3; a++)
        d->n[a] = (int)h->ext[a];
    d->mcell = 8;
    if (!density_set_placement(d, &h->v2w, name)) {
        density_release(d);
        return NULL;
    }
    return d;
}

/* Walks the tree of d's grid (size bytes) for its values' range (d->rho_min, rho_max) and,
 * unless *small (a box small enough for a dense copy and a grid of cells,
 * nano_cell_grid_voxels), its blocks' majorants; the walk's tables must fit max_memory.
 * false with err_set. */
static bool nano_walk_majorants(density *d, const nano_header *h, size_t size, size_t max_memory, bool any_sign,
                                const char *name, bool *small)
{
    nanovdb_state *s = d->nano;
    const pnanovdb_uint32_t type = h->type;
    walk w;
    memset(&w, 0, sizeof w);
    w.name = name;
    w.s = s;
    w.vmin = INFINITY;
    w.vmax = any_sign ? -(double)INFINITY : 0.0; /* the background's value is always seen */
    w.budget[0] = size / PNANOVDB_GRID_TYPE_GET(type, upper_size) + 1;
    w.budget[1] = size / PNANOVDB_GRID_TYPE_GET(type, lower_size) + 1;
    w.budget[2] = size / PNANOVDB_GRID_TYPE_GET(type, leaf_size) + 1;
    const float bg =
        read_value(s, pnanovdb_address_offset(h->root.address, PNANOVDB_GRID_TYPE_GET(type, root_off_background)));
    w.bg = bg;
    w.trilinear = d->filter == GRID_TRILINEAR;
    w.any_sign = any_sign;
    memcpy(w.n, d->n, sizeof w.n);
    bool ok = hash_init(&w.raw, 64) ? value_ok(&w, bg, h->lo.x, h->lo.y, h->lo.z) && walk_tree(&w, h->tiles, bg)
                                    : oom(&w);
    /* the tables of the walk and the final ones must fit the memory limit */
    if (ok && max_memory &&
        (w.ntab * 3 + 16) * BLOCK_CELLS * sizeof(float) + w.nleaf * SLABS * sizeof(float) > max_memory) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: majorants of %zu blocks exceed the memory limit of %zu bytes", name,
                w.ntab, max_memory);
        ok = false;
    }
    /* a small box gets a dense copy and a grid of cells below: the tree's majorants are
     * built only for the others */
    *small = (uint64_t)h->ext[0] * (uint64_t)h->ext[1] * (uint64_t)h->ext[2] <= atomic_load(&nano_cell_grid_voxels);
    ok = ok && (*small || build_majorants(&w, d->filter == GRID_TRILINEAR, bg));
    d->rho_min = w.vmin * s->scale;
    d->rho_max = w.vmax * s->scale;
    hash_free(&w.raw);
    free(w.rawmaj);
    free(w.rawtab);
    free(w.rawleaf);
    free(w.slabs);
    free(w.rawat);
    return ok;
}

/* A small box: its voxels in a dense array as well, when the memory limit allows (a lookup
 * is then 8 array reads instead of a descent of the tree, as for a dense grid:
 * density_impl.h), and one grid of cells with exact bounds of those values, walked by one
 * DDA. Sets d->memory; false with err_set. */
static bool nano_small_box(density *d, size_t size, size_t max_memory, const char *name)
{
    d->nbx = (d->n[0] + 3) / 4;
    d->nby = (d->n[1] + 1) / 2;
    size_t nvox = (size_t)d->nbx * (size_t)d->nby * (size_t)((d->n[2] + 1) / 2) * DENSITY_BRICK_FLOATS;
    /* the cells' bounds (three floats a cell: density_build_cell_bounds) are counted too,
     * so that the grid with its copy stays within the limit */
    const size_t C = DENSITY_MAJORANT_CELL;
    size_t cells = 3 * (((size_t)d->n[0] + C - 1) / C) * (((size_t)d->n[1] + C - 1) / C) *
                   (((size_t)d->n[2] + C - 1) / C);
    if (!max_memory || size + (nvox + cells) * sizeof(float) <= max_memory)
        d->data = aligned_alloc(64, nvox * sizeof(float));
    if (d->data) {
        memset(d->data, 0, nvox * sizeof(float));
        for (int z = 0; z < d->n[2]; z++)
            for (int y = 0; y < d->n[1]; y++)
                for (int x = 0; x < d->n[0]; x++)
                    d->data[dense_brick_x(x) + dense_brick_y(d, y) + dense_brick_z(d, z)] =
                        (float)nanovdb_voxel(d, x, y, z);
        d->bricked = true;
    }
    if (!density_build_cell_bounds(d, density_voxel)) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for the majorant grid", name);
        return false;
    }
    d->memory = size + 3 * (size_t)d->mn[0] * (size_t)d->mn[1] * (size_t)d->mn[2] * sizeof(float) +
                (d->data ? nvox * sizeof(float) : 0);
    return true;
}

/* A field of the grid in shared (component 0..2 of a vec3 grid, or -1 for a float grid):
 * the header's checks, the density, the tree's walk, then the small box's dense copy or the
 * tree's block majorants. On failure NULL (err_set), and nothing of it is left: one release,
 * density_release, since shared is taken (a reference) only on success. */
static density *nano_make(nano_buffer *shared, int component, grid_filter filter, const affine3 *extra, double scale,
                          size_t max_memory, bool any_sign, const char *name)
{
    if (!(scale > 0.0) || !isfinite(scale)) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: density scale %g must be finite and > 0", name, scale);
        return NULL;
    }
    nano_header h;
    if (!nano_read_header(shared, component, extra, name, &h))
        return NULL;
    density *d = nano_density_new(&h, component, filter, scale, name);
    if (!d)
        return NULL;
    const size_t size = shared->size;
    bool small;
    if (!nano_walk_majorants(d, &h, size, max_memory, any_sign, name, &small)) {
        density_release(d);
        return NULL;
    }
    d->active = pnanovdb_tree_get_voxel_count(h.b, h.tree);
    if (small) {
        if (!nano_small_box(d, size, max_memory, name)) {
            density_release(d);
            return NULL;
        }
    } else {
        nanovdb_state *s = d->nano;
        d->memory = size + hash_bytes(&s->blocks) + hash_bytes(&s->regions) + s->blocks.count * sizeof(block_entry);
        for (size_t i = 0; i < s->blocks.count; i++)
            d->memory += s->entries[i].at >= 0 ? BLOCK_CELLS * sizeof(float) : 0;
        d->mn[0] = (int)s->blocks.count; /* blocks with their own bounds (density_get_info) */
    }
    d->nano->shared = shared; /* ownership (a reference) passes only on success */
    shared->refs++;
    return d;
}

density *density_new_nanovdb(void *buf, size_t size, grid_filter filter, const affine3 *extra, double scale,
                             size_t max_memory, const char *name)
{
    density *out[1];
    return density_new_nanovdb_fields(buf, size, 1, filter, extra, scale, max_memory, false, name, out) ? out[0] : NULL;
}

bool density_new_nanovdb_fields(void *buf, size_t size, int count, grid_filter filter, const affine3 *extra,
                                double scale, size_t max_memory, bool any_sign, const char *name, density **out)
{
    nano_buffer *shared = calloc(1, sizeof *shared);
    if (!shared) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        return false;
    }
    shared->mem = buf;
    shared->size = size;
    for (int c = 0; c < count; c++) {
        out[c] = nano_make(shared, count == 1 ? -1 : c, filter, extra, scale, max_memory, any_sign, name);
        if (!out[c]) {
            /* undo: the buffer stays the caller's */
            shared->refs += 1;
            for (int k = 0; k < c; k++)
                density_release(out[k]);
            free(shared);
            return false;
        }
    }
    return true;
}

/* ---- majorant traversal ------------------------------------------------------------------------ */

/* Ray in index space: o_idx + t d; a DDA over the cells of size `cell` of a region whose
 * first cell is c0, n cells per axis, over [t0, t1]. */
static bool sub_begin(grid_dda *g, const majorant_iter *it, double cell, const int32_t c0[3], int n, double t0,
                      double t1)
{
    double inv = 1.0 / cell;
    vec3 o = v3(it->o_idx.x * inv - c0[0], it->o_idx.y * inv - c0[1], it->o_idx.z * inv - c0[2]);
    const int nn[3] = {n, n, n};
    return grid_dda_begin(g, nn, o, v3_scale(it->d_idx, inv), t0, t1);
}

void nanovdb_majorant_begin(const density *d, vec3 o, vec3 dir, double t0, double t1, majorant_iter *it)
{
    const nanovdb_state *s = d->nano;
    it->nano = s;
    it->level = 0;
    it->o_idx = v3(o.x + s->bbmin[0], o.y + s->bbmin[1], o.z + s->bbmin[2]);
    it->d_idx = dir;
    /* regions of 4096^3 voxels over the box */
    int lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = s->bbmin[a] >> 12;
        hi[a] = (int)(((int64_t)s->bbmin[a] + d->n[a] - 1) >> 12);
        it->base[0][a] = lo[a];
    }
    const int nr[3] = {hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1};
    double inv = 1.0 / 4096.0;
    vec3 oc = v3(it->o_idx.x * inv - lo[0], it->o_idx.y * inv - lo[1], it->o_idx.z * inv - lo[2]);
    if (!grid_dda_begin(&it->dda, nr, oc, v3_scale(dir, inv), t0, t1))
        it->dda.done = true;
}

bool nanovdb_majorant_cell(majorant_iter *it, majorant_seg *seg)
{
    const nanovdb_state *s = it->nano;
    grid_dda_step st;
    for (;;) {
        if (it->level == 2) {
            if (grid_dda_next(&it->sub[1], &st)) {
                seg->t0 = st.t0;
                seg->t1 = st.t1;
                seg->rho_maj = (double)it->table[st.i + 16 * (st.j + 16 * st.k)];
                seg->rho_min = seg->rho_ctl = 0.0;
                return true;
            }
            it->level = 1;
        }
        if (it->level == 1) {
            if (grid_dda_next(&it->sub[0], &st)) {
                int32_t k[3] = {it->base[1][0] + st.i, it->base[1][1] + st.j, it->base[1][2] + st.k};
                int32_t e = hash_find(&s->blocks, k);
                if (e < 0 || s->entries[e].at < 0) {
                    seg->t0 = st.t0;
                    seg->t1 = st.t1;
                    seg->rho_maj = e < 0 ? (double)s->bg_maj : (double)s->entries[e].maj;
                    seg->rho_min = seg->rho_ctl = 0.0;
                    return true;
                }
                it->table = s->tables + (size_t)s->entries[e].at * BLOCK_CELLS;
                int32_t c0[3] = {k[0] * 16, k[1] * 16, k[2] * 16};
                if (sub_begin(&it->sub[1], it, 8.0, c0, 16, st.t0, st.t1))
                    it->level = 2;
                continue;
            }
            it->level = 0;
        }
        if (!grid_dda_next(&it->dda, &st))
            return false;
        int32_t r[3] = {it->base[0][0] + st.i, it->base[0][1] + st.j, it->base[0][2] + st.k};
        if (hash_find(&s->regions, r) < 0) {
            seg->t0 = st.t0;
            seg->t1 = st.t1;
            seg->rho_maj = (double)s->bg_maj;
            seg->rho_min = seg->rho_ctl = 0.0;
            return true;
        }
        int32_t c0[3] = {r[0] * 32, r[1] * 32, r[2] * 32};
        if (sub_begin(&it->sub[0], it, 128.0, c0, 32, st.t0, st.t1)) {
            memcpy(it->base[1], c0, sizeof c0);
            it->level = 1;
        }
    }
}

size_t density_shared_bytes(const density *d)
{
    return d->kind == DENSITY_NANOVDB && d->nano->shared ? d->nano->shared->size : 0;
}

/* ---- the GPU's copy (core/arena.h) ------------------------------------------------------------ */

static void hash_device_put(const cell_hash *h, dev_arena *a, size_t at)
{
    ARENA_PUT_MEMBER(a, at, cell_hash, keys, h->keys, h->cap * 3 * sizeof(int32_t));
    ARENA_PUT_MEMBER(a, at, cell_hash, val, h->val, h->cap * sizeof(int32_t));
}

size_t nanovdb_device_put(const nanovdb_state *s, dev_arena *a)
{
    size_t at = arena_put(a, s, sizeof *s);
    if (at == ARENA_NULL)
        return at;
    arena_ptr(a, at + offsetof(nanovdb_state, shared), ARENA_NULL); /* the host's reference count */
    ARENA_PUT_MEMBER(a, at, nanovdb_state, buf.data, s->buf.data, (size_t)s->buf.size_in_words * 4);
    hash_device_put(&s->blocks, a, at + offsetof(nanovdb_state, blocks));
    hash_device_put(&s->regions, a, at + offsetof(nanovdb_state, regions));
    /* an entry per block (and the one past them); the tables of the non-uniform ones */
    const size_t nentries = s->entries ? s->blocks.count + 1 : 0;
    size_t ntab = 0;
    for (size_t i = 0; i < s->blocks.count && s->entries; i++)
        if (s->entries[i].at >= 0 && (size_t)s->entries[i].at + 1 > ntab)
            ntab = (size_t)s->entries[i].at + 1;
    ARENA_PUT_MEMBER(a, at, nanovdb_state, entries, s->entries, nentries * sizeof(block_entry));
    ARENA_PUT_MEMBER(a, at, nanovdb_state, tables, s->tables, ntab * BLOCK_CELLS * sizeof(float));
    return at;
}
