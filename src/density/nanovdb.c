/* nanovdb.c - sparse float grids in a NanoVDB buffer, traversed in C through PNanoVDB
 * (the portable C/HLSL/GLSL header of NanoVDB, Museth 2021, Debian's libnanovdb-dev).
 *
 * The buffer stays as it was written: a root table, 32^3 upper and 16^3 lower internal
 * nodes, 8^3 leaves; lookups go through a PNanoVDB read accessor, which caches the path
 * to the last leaf. Every buffer read is bounds-checked (PNANOVDB_BUF_BOUNDS_CHECK: a read
 * outside the buffer returns 0), so a hostile buffer can give wrong values but never read
 * outside its memory; and at construction every value reachable from inside the grid's
 * bounding box is visited once (one 8^3 block at a time, the unit the tree resolves to a
 * single leaf or tile) and checked finite and >= 0. That visit also builds the majorant
 * grid: one cell per 8^3 block, the max of its leaf (or its tile value). */
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
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

struct nanovdb_state {
    void *mem; /* the buffer, owned */
    pnanovdb_buf_t buf;
    pnanovdb_grid_type_t type;
    pnanovdb_root_handle_t root;
    int bbmin[3]; /* index of voxel (0, 0, 0) */
    double scale; /* multiplies every stored value */
};

static inline double nano_fetch(const nanovdb_state *s, pnanovdb_readaccessor_t *acc, int i, int j, int k)
{
    pnanovdb_coord_t ijk = {i + s->bbmin[0], j + s->bbmin[1], k + s->bbmin[2]};
    pnanovdb_address_t a = pnanovdb_readaccessor_get_value_address(s->type, s->buf, acc, &ijk);
    return (double)pnanovdb_read_float(s->buf, a) * s->scale;
}

double nanovdb_voxel(const density *d, int i, int j, int k)
{
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(&acc, d->nano->root);
    return nano_fetch(d->nano, &acc, i, j, k);
}

/* u in voxel space, inside [0, n); same filters as the dense grid (grid.c). */
double nanovdb_eval_voxel(const density *d, vec3 u)
{
    const nanovdb_state *s = d->nano;
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(&acc, s->root);
    if (d->filter == GRID_NEAREST)
        return nano_fetch(s, &acc, (int)u.x, (int)u.y, (int)u.z);
    int ijk[3][2];
    double a[3], c[8];
    trilinear_corners(u, d->n, ijk, a);
    for (int q = 0; q < 8; q++)
        c[q] = nano_fetch(s, &acc, ijk[0][q & 1], ijk[1][(q >> 1) & 1], ijk[2][q >> 2]);
    return trilinear_blend(c, a);
}

void nanovdb_free(density *d)
{
    if (d->nano) {
        free(d->nano->mem);
        free(d->nano);
    }
}

static int floor8(int v) { return (int)((unsigned)v & ~7u); } /* two's complement: floor to a multiple of 8 */

/* Visits every 8^3 block of the bounding box: checks its values, records its max, counts
 * min and max. Returns false (err_set) on a bad value. */
static bool nano_scan(density *d, const char *name)
{
    nanovdb_state *s = d->nano;
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(&acc, s->root);
    double vmin = INFINITY, vmax = 0.0;
    for (int ck = 0; ck < d->mn[2]; ck++)
        for (int cj = 0; cj < d->mn[1]; cj++)
            for (int ci = 0; ci < d->mn[0]; ci++) {
                pnanovdb_coord_t org = {floor8(s->bbmin[0]) + 8 * ci, floor8(s->bbmin[1]) + 8 * cj,
                                        floor8(s->bbmin[2]) + 8 * ck};
                pnanovdb_uint32_t level = 0;
                pnanovdb_address_t a = pnanovdb_readaccessor_get_value_address_and_level(s->type, s->buf, &acc, &org, &level);
                int count = level == 0 ? 512 : 1; /* a leaf's table, or one tile/background value */
                float m = 0.0f;
                for (int n = 0; n < count; n++) {
                    float v = pnanovdb_read_float(s->buf, pnanovdb_address_offset(a, 4u * (pnanovdb_uint32_t)n));
                    if (!isfinite(v) || v < 0.0f) {
                        /* leaf table order is x-major: n = (x & 7) << 6 | (y & 7) << 3 | (z & 7) */
                        int x = org.x + (count > 1 ? n >> 6 : 0), y = org.y + (count > 1 ? (n >> 3) & 7 : 0),
                            z = org.z + (count > 1 ? n & 7 : 0);
                        err_set(BRUME_ERROR_RANGE, "%s: voxel (%d, %d, %d) has density %g: need finite and >= 0", name,
                                x, y, z, (double)v);
                        return false;
                    }
                    m = v > m ? v : m;
                    vmin = fmin(vmin, (double)v);
                }
                vmax = fmax(vmax, (double)m);
                d->maj[(size_t)ci + (size_t)d->mn[0] * ((size_t)cj + (size_t)d->mn[1] * (size_t)ck)] =
                    (float)((double)m * s->scale);
            }
    d->rho_min = vmin * s->scale;
    d->rho_max = vmax * s->scale;
    return true;
}

/* Trilinear lookups read one voxel beyond their own, possibly in the next block: widen
 * each cell's majorant to the max of its 3^3 neighbourhood (separably, axis by axis). */
static bool nano_dilate(density *d)
{
    size_t count = (size_t)d->mn[0] * (size_t)d->mn[1] * (size_t)d->mn[2];
    float *tmp = malloc(count * sizeof *tmp);
    if (!tmp)
        return false;
    size_t stride[3] = {1, (size_t)d->mn[0], (size_t)d->mn[0] * (size_t)d->mn[1]};
    for (int a = 0; a < 3; a++) {
        memcpy(tmp, d->maj, count * sizeof *tmp);
        for (size_t c = 0; c < count; c++) {
            size_t coord = c / stride[a] % (size_t)d->mn[a];
            float m = tmp[c];
            if (coord > 0)
                m = fmaxf(m, tmp[c - stride[a]]);
            if (coord + 1 < (size_t)d->mn[a])
                m = fmaxf(m, tmp[c + stride[a]]);
            d->maj[c] = m;
        }
    }
    free(tmp);
    return true;
}

density *density_new_nanovdb(void *buf, size_t size, grid_filter filter, const affine3 *extra, double scale,
                             size_t max_memory, const char *name)
{
    if (!(scale > 0.0) || !isfinite(scale)) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: density scale %g must be finite and > 0", name, scale);
        return NULL;
    }
    if (size < PNANOVDB_GRID_SIZE + PNANOVDB_TREE_SIZE || ((uintptr_t)buf & 7u) != 0) {
        err_set(BRUME_ERROR_PARSE, "%s: NanoVDB grid of %zu bytes is too small or misaligned", name, size);
        return NULL;
    }
    pnanovdb_buf_t b = pnanovdb_make_buf((uint32_t *)buf, size / 4);
    pnanovdb_grid_handle_t grid = {pnanovdb_address_null()};
    if (pnanovdb_grid_get_magic(b, grid) != PNANOVDB_MAGIC_NUMBER) {
        err_set(BRUME_ERROR_PARSE, "%s: not a NanoVDB grid (wrong magic number)", name);
        return NULL;
    }
    pnanovdb_uint32_t type = pnanovdb_grid_get_grid_type(b, grid);
    if (type != PNANOVDB_GRID_TYPE_FLOAT) {
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: NanoVDB grid type %u is not float (type 1)", name, (unsigned)type);
        return NULL;
    }
    uint64_t gsize = pnanovdb_grid_get_grid_size(b, grid);
    if (gsize > size) {
        err_set(BRUME_ERROR_PARSE, "%s: truncated: grid says %llu bytes, buffer has %zu", name,
                (unsigned long long)gsize, size);
        return NULL;
    }
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(b, grid);
    pnanovdb_root_handle_t root = pnanovdb_tree_get_root(b, tree);
    if (root.address.byte_offset > size || size - root.address.byte_offset < PNANOVDB_GRID_TYPE_GET(type, root_size)) {
        err_set(BRUME_ERROR_PARSE, "%s: root node offset %llu outside the grid", name,
                (unsigned long long)root.address.byte_offset);
        return NULL;
    }
    uint64_t tiles = pnanovdb_root_get_tile_count(b, root);
    if (tiles > (size - root.address.byte_offset) / PNANOVDB_GRID_TYPE_GET(type, root_tile_size)) {
        err_set(BRUME_ERROR_PARSE, "%s: root claims %llu tiles, more than the grid holds", name, (unsigned long long)tiles);
        return NULL;
    }
    pnanovdb_coord_t lo = pnanovdb_root_get_bbox_min(b, root), hi = pnanovdb_root_get_bbox_max(b, root);
    int64_t ext[3] = {(int64_t)hi.x - lo.x + 1, (int64_t)hi.y - lo.y + 1, (int64_t)hi.z - lo.z + 1};
    for (int a = 0; a < 3; a++)
        if (ext[a] < 1 || ext[a] > (1 << 30)) {
            err_set(BRUME_ERROR_PARSE, "%s: empty or oversized index bounding box (%d, %d, %d)..(%d, %d, %d)", name,
                    lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
            return NULL;
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
    affine3 v2w = affine3_compose(&i2w, &v2i);
    if (extra)
        v2w = affine3_compose(extra, &v2w);

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
    s->buf = b;
    s->type = type;
    s->root = root;
    s->scale = scale;
    s->bbmin[0] = lo.x;
    s->bbmin[1] = lo.y;
    s->bbmin[2] = lo.z;
    size_t cells = 1;
    d->mcell = 8;
    for (int a = 0; a < 3; a++) {
        d->n[a] = (int)ext[a];
        d->moff[a] = s->bbmin[a] - floor8(s->bbmin[a]);
        d->mn[a] = (d->moff[a] + d->n[a] + 7) / 8;
        cells *= (size_t)d->mn[a];
    }
    if (max_memory && cells > max_memory / (2 * sizeof(float))) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: majorant grid of %zu cells exceeds the memory limit of %zu bytes", name,
                cells, max_memory);
        goto fail;
    }
    d->maj = malloc(cells * sizeof *d->maj);
    if (!d->maj) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for the majorant grid (%zu cells)", name, cells);
        goto fail;
    }
    if (!density_set_placement(d, &v2w, name) || !nano_scan(d, name))
        goto fail;
    if (filter == GRID_TRILINEAR && !nano_dilate(d)) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        goto fail;
    }
    d->active = pnanovdb_tree_get_voxel_count(b, tree);
    d->memory = size + cells * sizeof(float);
    s->mem = buf; /* ownership passes only on success */
    return d;
fail:
    free(d->maj);
    free(s);
    free(d);
    return NULL;
}
