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
#include "density/nanovdb_impl.h"

bool nano_hash_init(cell_hash *h, size_t expect)
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

void nano_hash_free(cell_hash *h)
{
    free(h->keys);
    free(h->val);
    h->keys = NULL;
    h->val = NULL;
}

/* Inserts k with value v unless present; returns the value stored; -2 when out of memory. */
int32_t nano_hash_insert(cell_hash *h, const int32_t k[3], int32_t v)
{
    if (2 * (h->count + 1) > h->cap) {
        cell_hash g;
        if (!nano_hash_init(&g, h->count + 1))
            return -2;
        for (size_t i = 0; i < h->cap; i++)
            if (h->val[i] >= 0)
                nano_hash_insert(&g, h->keys + 3 * i, h->val[i]);
        nano_hash_free(h);
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
    nano_hash_free(&s->blocks);
    nano_hash_free(&s->regions);
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
