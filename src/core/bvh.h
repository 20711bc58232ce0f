/* bvh.h - a bounding-volume hierarchy over boxes, built on the host and traversed by the
 * same code on the CPU and the GPU (the solid objects' queries, surface/surface_query.c,
 * when Embree is not there: on the device, and in the device copy's tests).
 *
 * Build: the items' boxes are split at the median of their centroids along the centroids'
 * longest axis (a stable sort: the hierarchy depends on the items' order alone, and the
 * builder has no state outside its arguments, so threads may build at once), until a node
 * holds at most BVH_LEAF_SIZE items (or its centroids coincide). The solid objects and the
 * blob fields (density/blobs.c) are built with it. Nodes are stored depth first: an inner node's left child follows it, its right
 * child is at `start`; a leaf holds items item[start .. start + count). The depth is at most
 * log2(n) + 1, so BVH_STACK entries suffice for any int count of items.
 *
 * Ownership: bvh_build allocates nodes and item (bvh_free releases them); on failure it
 * returns BRUME_ERROR_OUT_OF_MEMORY with err_set and leaves b empty. */
#ifndef BRUME_CORE_BVH_H
#define BRUME_CORE_BVH_H

#include <stdbool.h>

#include "brume.h"
#include "core/vec.h"

#define BVH_LEAF_SIZE 4
#define BVH_STACK 64

typedef struct bvh_node {
    box3 box;         /* world units */
    int start, count; /* leaf: count > 0 items from start; inner: count 0, right child start */
} bvh_node;

typedef struct bvh {
    bvh_node *nodes;  /* root at 0 */
    int *item;        /* item indices in leaf order */
    int nnodes, nitems;
} bvh;

/* The hierarchy of n >= 1 boxes (box i is item i), split by the items' centroids: centroids
 * (n points, e.g. a sphere's centre) or, when NULL, the boxes' centres. */
brume_status bvh_build(bvh *b, const box3 *boxes, const vec3 *centroids, int n);
void bvh_free(bvh *b);

/* Whether o + t d, t in [tmin, tmax], meets box bx (inv = 1 / d componentwise); *t_in is
 * where it enters. A ray lying in a slab plane (0 * inf = NaN) keeps that slab's bounds,
 * a set of rays of measure zero. */
static inline bool bvh_box_hit(const box3 *bx, vec3 o, vec3 inv, double tmin, double tmax, double *t_in)
{
    double tx0 = (bx->lo.x - o.x) * inv.x, tx1 = (bx->hi.x - o.x) * inv.x;
    double ty0 = (bx->lo.y - o.y) * inv.y, ty1 = (bx->hi.y - o.y) * inv.y;
    double tz0 = (bx->lo.z - o.z) * inv.z, tz1 = (bx->hi.z - o.z) * inv.z;
    double a = tx0 < tx1 ? tx0 : tx1, b = tx0 < tx1 ? tx1 : tx0;
    double c = ty0 < ty1 ? ty0 : ty1, d = ty0 < ty1 ? ty1 : ty0;
    double e = tz0 < tz1 ? tz0 : tz1, f = tz0 < tz1 ? tz1 : tz0;
    double t0 = a > c ? a : c, t1 = b < d ? b : d;
    t0 = t0 > e ? t0 : e;
    t1 = t1 < f ? t1 : f;
    t0 = t0 > tmin ? t0 : tmin;
    t1 = t1 < tmax ? t1 : tmax;
    *t_in = t0;
    return t0 <= t1;
}

/* Visits the items of every leaf that o + t d, t in [tmin, *tmax], meets, nearer child
 * first: leaf(user, item, tmax) tests one item, may lower *tmax (a closest hit) and returns
 * true to stop at once (any hit). Returns whether a leaf stopped the walk. */
static inline bool bvh_traverse(const bvh *b, vec3 o, vec3 d, double tmin, double *tmax,
                                bool (*leaf)(void *user, int item, double *tmax), void *user)
{
    if (!b->nnodes)
        return false;
    vec3 inv = v3(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
    int stack[BVH_STACK], sp = 0, node = 0;
    double t_in;
    if (!bvh_box_hit(&b->nodes[0].box, o, inv, tmin, *tmax, &t_in))
        return false;
    for (;;) {
        const bvh_node *nd = &b->nodes[node];
        if (nd->count > 0) {
            for (int i = nd->start; i < nd->start + nd->count; i++)
                if (leaf(user, b->item[i], tmax))
                    return true;
        } else {
            int l = node + 1, r = nd->start;
            double tl, tr;
            bool hl = bvh_box_hit(&b->nodes[l].box, o, inv, tmin, *tmax, &tl);
            bool hr = bvh_box_hit(&b->nodes[r].box, o, inv, tmin, *tmax, &tr);
            if (hl && hr) {
                bool left_first = tl <= tr;
                stack[sp++] = left_first ? r : l;
                node = left_first ? l : r;
                continue;
            }
            if (hl || hr) {
                node = hl ? l : r;
                continue;
            }
        }
        if (sp == 0)
            return false;
        node = stack[--sp];
    }
}

#endif
