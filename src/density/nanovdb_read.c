/* nanovdb_read.c - a NanoVDB buffer made a density: its header checked (size, magic number,
 * type, root, bounding box), its placement read, its tree walked for the majorants within
 * the memory allowed, or a small box given the dense grids' cell bounds. */
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "density/density_impl.h"
#include "core/arena.h"
#include "density/nanovdb_impl.h"

/* Index boxes of at most this many voxels get the dense grids' cell bounds instead of the
 * tree's nested walk: at most 2^23 / 64 cells (1 MiB of bounds), built in about 3.4 reads
 * per voxel of the box (docs/grids.md, "Majorants of sparse grids"). */
#define NANO_CELL_GRID_VOXELS ((uint64_t)1 << 23)
static _Atomic uint64_t nano_cell_grid_voxels = NANO_CELL_GRID_VOXELS;

static atomic_uint_fast64_t nano_next_id = 1;

uint64_t nanovdb_set_cell_grid_limit(uint64_t voxels) { return atomic_exchange(&nano_cell_grid_voxels, voxels); }

static size_t hash_bytes(const cell_hash *h) { return h->cap * 4 * sizeof(int32_t); }

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

/* edge_zero: the index box [lo, hi] (ext voxels an axis) one voxel larger on every side, whose
 * voxels the tree gives its background; false with err_set at the edge of the index range. */
static bool nano_grow_box(pnanovdb_coord_t *lo, pnanovdb_coord_t hi, int64_t ext[3], const char *name)
{
    if (lo->x == INT32_MIN || lo->y == INT32_MIN || lo->z == INT32_MIN || hi.x == INT32_MAX || hi.y == INT32_MAX ||
        hi.z == INT32_MAX) {
        err_set(BRUME_ERROR_PARSE, "%s: index bounding box at the edge of the index range", name);
        return false;
    }
    lo->x -= 1, lo->y -= 1, lo->z -= 1;
    for (int a = 0; a < 3; a++)
        ext[a] += 2;
    return true;
}

/* Checks the grid in shared (its size, magic number, type, root, tiles and bounding box)
 * and reads its placement, composed with `extra` when not NULL; false with err_set. */
static bool nano_read_header(const nano_buffer *shared, int component, const affine3 *extra, bool edge_zero,
                             const char *name, nano_header *h)
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
    if (edge_zero && !nano_grow_box(&lo, hi, ext, name))
        return false;
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
    bool ok = nano_hash_init(&w.raw, 64) ? nano_value_ok(&w, bg, h->lo.x, h->lo.y, h->lo.z) && nano_walk_tree(&w, h->tiles, bg)
                                    : nano_oom(&w);
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
    ok = ok && (*small || nano_build_majorants(&w, d->filter == GRID_TRILINEAR, bg));
    d->rho_min = w.vmin * s->scale;
    d->rho_max = w.vmax * s->scale;
    nano_hash_free(&w.raw);
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
                          size_t max_memory, bool any_sign, bool edge_zero, const char *name)
{
    if (!(scale > 0.0) || !isfinite(scale)) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: density scale %g must be finite and > 0", name, scale);
        return NULL;
    }
    nano_header h;
    edge_zero = edge_zero && filter == GRID_TRILINEAR; /* a nearest lookup never reads beyond the box */
    if (!nano_read_header(shared, component, extra, edge_zero, name, &h))
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
    if (edge_zero) { /* cut to NanoVDB's world box, index [min, max + 1]: voxel space [3/2, n - 1/2] */
        const double lo[3] = {1.5, 1.5, 1.5}, hi[3] = {d->n[0] - 0.5, d->n[1] - 0.5, d->n[2] - 0.5};
        density_crop(d, lo, hi);
    }
    d->nano->shared = shared; /* ownership (a reference) passes only on success */
    shared->refs++;
    return d;
}

density *density_new_nanovdb(void *buf, size_t size, grid_filter filter, const affine3 *extra, double scale,
                             size_t max_memory, const char *name)
{
    density *out[1];
    return density_new_nanovdb_fields(buf, size, 1, filter, extra, scale, max_memory, false, false, name, out) ? out[0]
                                                                                                                : NULL;
}

bool density_new_nanovdb_fields(void *buf, size_t size, int count, grid_filter filter, const affine3 *extra,
                                double scale, size_t max_memory, bool any_sign, bool edge_zero, const char *name,
                                density **out)
{
    nano_buffer *shared = calloc(1, sizeof *shared);
    if (!shared) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        return false;
    }
    shared->mem = buf;
    shared->size = size;
    for (int c = 0; c < count; c++) {
        out[c] = nano_make(shared, count == 1 ? -1 : c, filter, extra, scale, max_memory, any_sign, edge_zero, name);
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
