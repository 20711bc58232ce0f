/* bvh.c - building the bounding-volume hierarchy (core/bvh.h). */
#include "core/bvh.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"

typedef struct bvh_build_ctx {
    const box3 *boxes;
    const vec3 *c; /* centroids */
    int *tmp;      /* the sort's scratch, nitems ints */
    bvh *b;
} bvh_build_ctx;

/* Sorts item[0, n) by centroid along axis, stably (items with equal centroids keep their
 * order, so the hierarchy is a function of the items' order alone), through tmp (n ints):
 * a bottom-up merge sort, with no state outside its arguments. */
static void sort_stable(int *item, int *tmp, const vec3 *c, int axis, int n)
{
    int *src = item, *dst = tmp;
    for (size_t w = 1; w < (size_t)n; w *= 2) {
        for (size_t lo = 0; lo < (size_t)n; lo += 2 * w) {
            size_t mid = lo + w < (size_t)n ? lo + w : (size_t)n;
            size_t hi = lo + 2 * w < (size_t)n ? lo + 2 * w : (size_t)n;
            size_t i = lo, j = mid, k = lo;
            while (i < mid && j < hi)
                dst[k++] = v3_get(c[src[j]], axis) < v3_get(c[src[i]], axis) ? src[j++] : src[i++];
            while (i < mid)
                dst[k++] = src[i++];
            while (j < hi)
                dst[k++] = src[j++];
        }
        int *t = src;
        src = dst;
        dst = t;
    }
    if (src != item)
        memcpy(item, src, sizeof *item * (size_t)n);
}

static int build_node(bvh_build_ctx *x, int start, int count)
{
    bvh *b = x->b;
    int id = b->nnodes++;
    box3 box = box3_empty(), cb = box3_empty();
    for (int i = start; i < start + count; i++) {
        int it = b->item[i];
        box = box3_union(box, x->boxes[it]);
        cb.lo = v3_min(cb.lo, x->c[it]);
        cb.hi = v3_max(cb.hi, x->c[it]);
    }
    b->nodes[id].box = box;
    vec3 ext = v3_sub(cb.hi, cb.lo);
    if (count <= BVH_LEAF_SIZE || (ext.x <= 0.0 && ext.y <= 0.0 && ext.z <= 0.0)) {
        b->nodes[id].start = start;
        b->nodes[id].count = count;
        return id;
    }
    int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    int half = count / 2;
    sort_stable(b->item + start, x->tmp, x->c, axis, count);
    build_node(x, start, half);
    int right = build_node(x, start + half, count - half);
    b->nodes[id].start = right;
    b->nodes[id].count = 0;
    return id;
}

brume_status bvh_build(bvh *b, const box3 *boxes, const vec3 *centroids, int n)
{
    *b = (bvh){0};
    if (n < 1)
        return BRUME_OK;
    b->nodes = malloc(sizeof *b->nodes * (size_t)(2 * (size_t)n));
    b->item = malloc(sizeof *b->item * (size_t)n);
    int *tmp = malloc(sizeof *tmp * (size_t)n);
    vec3 *c = centroids ? NULL : malloc(sizeof *c * (size_t)n);
    if (!b->nodes || !b->item || !tmp || (!centroids && !c)) {
        free(tmp);
        free(c);
        bvh_free(b);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "bvh: out of memory for the hierarchy of %d objects", n);
    }
    for (int i = 0; i < n; i++) {
        b->item[i] = i;
        if (c)
            c[i] = v3_scale(v3_add(boxes[i].lo, boxes[i].hi), 0.5);
    }
    b->nitems = n;
    bvh_build_ctx x = {boxes, centroids ? centroids : c, tmp, b};
    build_node(&x, 0, n);
    free(tmp);
    free(c);
    return BRUME_OK;
}

void bvh_free(bvh *b)
{
    free(b->nodes);
    free(b->item);
    *b = (bvh){0};
}
