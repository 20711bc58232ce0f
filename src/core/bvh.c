/* bvh.c - building the bounding-volume hierarchy (core/bvh.h). */
#include "core/bvh.h"

#include <stdlib.h>

#include "core/error.h"

typedef struct bvh_build_ctx {
    const box3 *boxes;
    vec3 *c; /* centroids */
    bvh *b;
} bvh_build_ctx;

static box3 box_union(box3 a, box3 b) { return (box3){v3_min(a.lo, b.lo), v3_max(a.hi, b.hi)}; }

/* Puts the items of item[lo, hi) whose centroid along axis is below the k-th smallest
 * first (quickselect, Hoare partition): item[k] is then the k-th, those before it are not
 * larger, those after not smaller. Deterministic: no random pivot. */
static void select_kth(int *item, const vec3 *c, int axis, int lo, int hi, int k)
{
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        double pivot = v3_get(c[item[mid]], axis);
        int i = lo, j = hi - 1;
        while (i <= j) {
            while (v3_get(c[item[i]], axis) < pivot)
                i++;
            while (v3_get(c[item[j]], axis) > pivot)
                j--;
            if (i <= j) {
                int t = item[i];
                item[i] = item[j];
                item[j] = t;
                i++;
                j--;
            }
        }
        /* [lo, j] <= pivot <= [i, hi) and (j, i) == pivot */
        if (k <= j)
            hi = j + 1;
        else if (k >= i)
            lo = i;
        else
            return;
    }
}

static int build_node(bvh_build_ctx *x, int start, int count)
{
    bvh *b = x->b;
    int id = b->nnodes++;
    box3 box = box3_empty(), cb = box3_empty();
    for (int i = start; i < start + count; i++) {
        int it = b->item[i];
        box = box_union(box, x->boxes[it]);
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
    select_kth(b->item, x->c, axis, start, start + count, start + half);
    build_node(x, start, half);
    int right = build_node(x, start + half, count - half);
    b->nodes[id].start = right;
    b->nodes[id].count = 0;
    return id;
}

brume_status bvh_build(bvh *b, const box3 *boxes, int n)
{
    *b = (bvh){0};
    if (n < 1)
        return BRUME_OK;
    b->nodes = malloc(sizeof *b->nodes * (size_t)(2 * (size_t)n));
    b->item = malloc(sizeof *b->item * (size_t)n);
    vec3 *c = malloc(sizeof *c * (size_t)n);
    if (!b->nodes || !b->item || !c) {
        free(c);
        bvh_free(b);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "bvh: out of memory for the hierarchy of %d objects", n);
    }
    for (int i = 0; i < n; i++) {
        b->item[i] = i;
        c[i] = v3_scale(v3_add(boxes[i].lo, boxes[i].hi), 0.5);
    }
    b->nitems = n;
    bvh_build_ctx x = {boxes, c, b};
    build_node(&x, 0, n);
    free(c);
    return BRUME_OK;
}

void bvh_free(bvh *b)
{
    free(b->nodes);
    free(b->item);
    *b = (bvh){0};
}
