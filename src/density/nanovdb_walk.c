/* nanovdb_walk.c - the walk over a NanoVDB tree (root tiles, upper and lower nodes,
 * leaves) that checks every value a lookup can reach and records the bounds from which the
 * majorants are built (docs/grids.md, "Majorants of sparse grids"). */
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "density/density_impl.h"
#include "core/arena.h"
#include "density/nanovdb_impl.h"

bool nano_value_ok(walk *w, float v, int x, int y, int z)
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

/* A leaf cell's layers, for the trilinear filter: per axis 0 = its layer at 0, 1 = all of
 * it, 2 = its layer at 7 (one voxel thick). Slab (1, 1, 1) is the whole leaf; a neighbour
 * offset by d from a cell can be read, by a lookup in that cell, only in its slab
 * (d > 0 ? 0 : d < 0 ? 2 : 1) per axis. */
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
    int32_t idx = nano_hash_insert(&w->raw, key, (int32_t)w->nraw);
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

bool nano_oom(walk *w)
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
        return nano_oom(w);
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
                return nano_oom(w);
            m = 0.0f;
            for (uint32_t v = 0; v < 512; v++) {
                float f = read_value(s, pnanovdb_leaf_get_table_address(s->type, s->buf, leaf, v));
                const int vx = (int)(v >> 6), vy = (int)((v >> 3) & 7), vz = (int)(v & 7);
                if (!nano_value_ok(w, f, x + vx, y + vy, z + vz))
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
            if (!nano_value_ok(w, m, x, y, z))
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
        return nano_oom(w);
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
            if (!nano_value_ok(w, v, o[0], o[1], o[2]))
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

bool nano_walk_tree(walk *w, uint64_t tiles, float background)
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
            if (!nano_value_ok(w, v, org[0], org[1], org[2]))
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
bool nano_build_majorants(walk *w, bool dilate, float bg)
{
    nanovdb_state *s = w->s;
    /* the keys: raw blocks, and with dilation their neighbours */
    cell_hash keys;
    if (!nano_hash_init(&keys, w->nraw * (dilate ? 4 : 1)))
        return nano_oom(w);
    for (size_t i = 0; i < w->raw.cap; i++) {
        if (w->raw.val[i] < 0)
            continue;
        const int32_t *k = w->raw.keys + 3 * i;
        for (int q = 0; q < (dilate ? 27 : 1); q++) {
            int32_t n[3] = {k[0] + (dilate ? q % 3 - 1 : 0), k[1] + (dilate ? (q / 3) % 3 - 1 : 0),
                            k[2] + (dilate ? q / 9 - 1 : 0)};
            if (nano_hash_insert(&keys, n, (int32_t)keys.count) == -2) {
                nano_hash_free(&keys);
                return nano_oom(w);
            }
        }
    }
    s->entries = malloc((keys.count + 1) * sizeof *s->entries);
    float *block = malloc(BLOCK_CELLS * sizeof *block);
    if (!s->entries || !block || !nano_hash_init(&s->blocks, keys.count) || !nano_hash_init(&s->regions, keys.count / 8 + 1)) {
        free(block);
        nano_hash_free(&keys);
        return nano_oom(w);
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
                    nano_hash_free(&keys);
                    return nano_oom(w);
                }
                s->tables = t;
                captab = cap;
            }
            memcpy(s->tables + ntab * BLOCK_CELLS, block, BLOCK_CELLS * sizeof *block);
            e.at = (int32_t)ntab++;
        }
        s->entries[ne] = e;
        int32_t r[3] = {k[0] >> 5, k[1] >> 5, k[2] >> 5};
        if (nano_hash_insert(&s->blocks, k, ne) == -2 || nano_hash_insert(&s->regions, r, 0) == -2) {
            free(block);
            nano_hash_free(&keys);
            return nano_oom(w);
        }
        ne++;
    }
    free(block);
    nano_hash_free(&keys);
    if (ntab > 0 && ntab < captab) { /* give back the unused tail */
        float *t = realloc(s->tables, ntab * BLOCK_CELLS * sizeof *t);
        if (t)
            s->tables = t;
    }
    s->bg_maj = scale_up(bg, s->scale);
    return true;
}
