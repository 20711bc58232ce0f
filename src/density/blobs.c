/* blobs.c - gaussian blob fields (Stam 1994, Eq. 3): a BVH over the truncation spheres for
 * ray and point queries, voxelization of the mean or of one realization, and the blob kind
 * of density (DENSITY_BLOBS) with its coarse majorant grid so that every integrator that
 * tracks through majorants renders blob fields directly. */
#include "density/blobs.h"

#include <stdlib.h>
#include <string.h>

#include "core/arena.h"
#include "core/budget.h"
#include "core/error.h"
#include "core/stats.h"
#include "density/density_impl.h"

/* (2 pi)^(3/2) */
#define TWO_PI_3_2 15.749609945722419

/* ---- building ---------------------------------------------------------------------------- */

static box3 sphere_box(vec3 c, double r)
{
    return (box3){v3(c.x - r, c.y - r, c.z - r), v3(c.x + r, c.y + r, c.z + r)};
}

/* The hierarchy over the truncation spheres (core/bvh.h, split by the centres), and the
 * blobs and their derived arrays put in its leaf order, so that a leaf's blobs are
 * f->b[start, start + count). */
static brume_status build_bvh(blob_field *f)
{
    double cutoff = blob_field_cutoff(f);
    box3 *boxes = malloc((size_t)f->n * sizeof *boxes);
    vec3 *centres = malloc((size_t)f->n * sizeof *centres);
    blob *sorted = malloc((size_t)f->n * sizeof *sorted);
    bvh h = {0};
    brume_status st = boxes && centres && sorted ? BRUME_OK : BRUME_ERROR_OUT_OF_MEMORY;
    if (st == BRUME_OK) {
        for (int i = 0; i < f->n; i++) {
            boxes[i] = sphere_box(f->b[i].x, cutoff * f->b[i].h);
            centres[i] = f->b[i].x;
        }
        st = bvh_build(&h, boxes, centres, f->n);
    }
    free(boxes);
    free(centres);
    if (st != BRUME_OK) {
        free(sorted);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "blobs: out of memory for the hierarchy of %d blobs", f->n);
    }
    for (int i = 0; i < f->n; i++)
        sorted[i] = f->b[h.item[i]];
    free(h.item);
    free(f->b);
    f->b = sorted;
    free(f->nodes);
    f->nodes = h.nodes;
    f->nnodes = h.nnodes;
    for (int i = 0; i < f->n; i++) {
        blob b = f->b[i];
        f->peak[i] = f->kernel ? b.m * f->kernel->w0 / (b.h * b.h * b.h) : b.m / (TWO_PI_3_2 * b.h * b.h * b.h);
        f->inv2h2[i] = 1.0 / (2.0 * b.h * b.h);
        f->R2[i] = cutoff * cutoff * b.h * b.h;
    }
    f->bounds = f->nodes[0].box;
    return BRUME_OK;
}

blob_field *blob_field_new(const blob *b, int n, double cutoff, const char *who)
{
    if (n < 1 || !(cutoff > 0.0 && isfinite(cutoff))) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: need at least one blob and a cutoff > 0", who);
        return NULL;
    }
    for (int i = 0; i < n; i++)
        if (!v3_isfinite(b[i].x) || !(b[i].m >= 0.0 && isfinite(b[i].m)) || !(b[i].h > 0.0 && isfinite(b[i].h))) {
            err_set(BRUME_ERROR_RANGE, "%s: blob %d: need a finite centre, mass >= 0 and radius h > 0 (got m %g, h %g)",
                    who, i, b[i].m, b[i].h);
            return NULL;
        }
    blob_field *f = calloc(1, sizeof *f);
    if (f) {
        f->b = malloc((size_t)n * sizeof *f->b);
        f->peak = malloc((size_t)n * sizeof(double));
        f->inv2h2 = malloc((size_t)n * sizeof(double));
        f->R2 = malloc((size_t)n * sizeof(double));
    }
    if (!f || !f->b || !f->peak || !f->inv2h2 || !f->R2) {
        blob_field_release(f);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for %d blobs", who, n);
        return NULL;
    }
    memcpy(f->b, b, (size_t)n * sizeof *b);
    f->n = n;
    f->cutoff = cutoff;
    f->use_bvh = true;
    if (build_bvh(f) != BRUME_OK) {
        blob_field_release(f);
        return NULL;
    }
    return f;
}

void blob_field_release(blob_field *f)
{
    if (!f)
        return;
    free(f->b);
    free(f->peak);
    free(f->inv2h2);
    free(f->R2);
    free(f->nodes);
    blob_kernel_release(f->kernel);
    free(f);
}

brume_status blob_field_set_kernel(blob_field *f, blob_kernel *k)
{
    blob_kernel_release(f->kernel);
    f->kernel = blob_kernel_retain(k);
    return build_bvh(f);
}

brume_status blob_field_at_time(blob_field *f, vec3 velocity, double t)
{
    vec3 shift = v3_sub(v3_scale(velocity, t), v3_scale(f->velocity, f->time));
    for (int i = 0; i < f->n; i++)
        f->b[i].x = v3_add(f->b[i].x, shift);
    f->velocity = velocity;
    f->time = t;
    return build_bvh(f);
}

/* ---- queries ----------------------------------------------------------------------------- */

double blob_field_mean(const blob_field *f, vec3 p)
{
    double sum = 0.0;
    if (!f->use_bvh) {
        if (stats_tls)
            stats_tls->blob_queries++;
        for (int i = 0; i < f->n; i++)
            sum += blob_mean_at(f, i, p);
        return sum;
    }
    int stack[BVH_STACK], sp = 0, node = 0;
    for (;;) {
        const bvh_node *nd = &f->nodes[node];
        if (box3_contains(nd->box, p)) {
            if (nd->count > 0) {
                for (int i = nd->start; i < nd->start + nd->count; i++)
                    sum += blob_mean_at(f, i, p);
            } else {
                stack[sp++] = nd->start;
                node = node + 1;
                continue;
            }
        }
        if (sp == 0)
            break;
        node = stack[--sp];
    }
    return sum;
}

/* Slab test of a box against o + t d with precomputed 1/d, over [tmin, tmax]. */
#define MIN(a, b) ((a) < (b) ? (a) : (b))
#define MAX(a, b) ((a) > (b) ? (a) : (b))
static inline bool hit_box(const box3 *b, vec3 o, vec3 inv, double tmin, double tmax)
{
    double tx0 = (b->lo.x - o.x) * inv.x, tx1 = (b->hi.x - o.x) * inv.x;
    double ty0 = (b->lo.y - o.y) * inv.y, ty1 = (b->hi.y - o.y) * inv.y;
    double tz0 = (b->lo.z - o.z) * inv.z, tz1 = (b->hi.z - o.z) * inv.z;
    /* NaN (0 * inf) arises only for a ray lying exactly in a slab plane, a set of rays of
     * measure zero; the comparisons then drop that bound */
    double t0 = MAX(MAX(MIN(tx0, tx1), MIN(ty0, ty1)), MAX(MIN(tz0, tz1), tmin));
    double t1 = MIN(MIN(MAX(tx0, tx1), MAX(ty0, ty1)), MIN(MAX(tz0, tz1), tmax));
    return t0 <= t1;
}

static inline void visit_blob(const blob_field *f, int i, vec3 o, vec3 d, double tmin, double tmax,
                              blob_visit_fn fn, void *user)
{
    vec3 dx = v3_sub(f->b[i].x, o);
    double u = v3_dot(dx, d);
    vec3 perp = v3_madd(dx, d, -u); /* not |dx|^2 - u^2, which cancels near the centre */
    double d2 = v3_dot(perp, perp);
    if (d2 >= f->R2[i])
        return;
    /* the segment meets the sphere iff its closest point to the centre is inside */
    double uc = u < tmin ? tmin : (u > tmax ? tmax : u);
    double e = uc - u;
    if (d2 + e * e >= f->R2[i])
        return;
    if (stats_tls)
        stats_tls->blob_visits++;
    fn(i, u, d2, user);
}

void blob_field_query_ray(const blob_field *f, vec3 o, vec3 d, double tmin, double tmax, blob_visit_fn fn,
                          void *user)
{
    if (!(tmax > tmin))
        return;
    if (!f->use_bvh) {
        if (stats_tls)
            stats_tls->blob_queries++;
        for (int i = 0; i < f->n; i++)
            visit_blob(f, i, o, d, tmin, tmax, fn, user);
        return;
    }
    vec3 inv = v3(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
    int stack[BVH_STACK], sp = 0, node = 0;
    stats_counters *sc = stats_tls;
    if (sc)
        sc->blob_queries++;
    for (;;) {
        const bvh_node *nd = &f->nodes[node];
        if (sc)
            sc->blob_nodes++;
        if (hit_box(&nd->box, o, inv, tmin, tmax)) {
            if (nd->count > 0) {
                for (int i = nd->start; i < nd->start + nd->count; i++)
                    visit_blob(f, i, o, d, tmin, tmax, fn, user);
            } else {
                stack[sp++] = nd->start;
                node = node + 1;
                continue;
            }
        }
        if (sp == 0)
            break;
        node = stack[--sp];
    }
}

/* ---- voxelization ------------------------------------------------------------------------ */

void blob_field_voxelize(const blob_field *f, const int n[3], box3 bounds, const randfield *q, vec3 q_shift,
                         double eps, double eta, float *out)
{
    size_t count = (size_t)n[0] * (size_t)n[1] * (size_t)n[2];
    double *mean = calloc(count, sizeof *mean), *sig = NULL;
    if (q)
        sig = calloc(count, sizeof *sig);
    vec3 cs = v3((bounds.hi.x - bounds.lo.x) / n[0], (bounds.hi.y - bounds.lo.y) / n[1],
                 (bounds.hi.z - bounds.lo.z) / n[2]);
    if (!mean || (q && !sig)) {
        /* no memory for the accumulators: evaluate cell by cell (slow, exact) */
        for (int k = 0; k < n[2]; k++)
            for (int j = 0; j < n[1]; j++)
                for (int i = 0; i < n[0]; i++) {
                    vec3 p = v3(bounds.lo.x + (i + 0.5) * cs.x, bounds.lo.y + (j + 0.5) * cs.y,
                                bounds.lo.z + (k + 0.5) * cs.z);
                    double rho = 0.0, s = 0.0;
                    for (int b = 0; b < f->n; b++) {
                        double m = blob_mean_at(f, b, p);
                        rho += m;
                        s += sqrt(eps * stam_clamp(m, eta));
                    }
                    if (q)
                        rho += s * randfield_eval(q, v3_sub(p, q_shift));
                    out[(size_t)i + (size_t)n[0] * ((size_t)j + (size_t)n[1] * (size_t)k)] = (float)fmax(0.0, rho);
                }
        free(mean);
        free(sig);
        return;
    }
    /* blob by blob over the cells its truncation sphere covers */
    for (int b = 0; b < f->n; b++) {
        double R = sqrt(f->R2[b]);
        int lo[3], hi[3];
        for (int a = 0; a < 3; a++) {
            double c = v3_get(f->b[b].x, a), l = v3_get(bounds.lo, a), s = v3_get(cs, a);
            lo[a] = (int)fmax(0.0, floor((c - R - l) / s - 0.5));
            hi[a] = (int)fmin((double)n[a] - 1, ceil((c + R - l) / s - 0.5));
        }
        for (int k = lo[2]; k <= hi[2]; k++)
            for (int j = lo[1]; j <= hi[1]; j++)
                for (int i = lo[0]; i <= hi[0]; i++) {
                    vec3 p = v3(bounds.lo.x + (i + 0.5) * cs.x, bounds.lo.y + (j + 0.5) * cs.y,
                                bounds.lo.z + (k + 0.5) * cs.z);
                    double m = blob_mean_at(f, b, p);
                    if (m <= 0.0)
                        continue;
                    size_t idx = (size_t)i + (size_t)n[0] * ((size_t)j + (size_t)n[1] * (size_t)k);
                    mean[idx] += m;
                    if (sig)
                        sig[idx] += sqrt(eps * stam_clamp(m, eta));
                }
    }
    for (int k = 0; k < n[2]; k++)
        for (int j = 0; j < n[1]; j++)
            for (int i = 0; i < n[0]; i++) {
                size_t idx = (size_t)i + (size_t)n[0] * ((size_t)j + (size_t)n[1] * (size_t)k);
                double rho = mean[idx];
                if (sig && sig[idx] > 0.0) {
                    vec3 p = v3(bounds.lo.x + (i + 0.5) * cs.x, bounds.lo.y + (j + 0.5) * cs.y,
                                bounds.lo.z + (k + 0.5) * cs.z);
                    rho += sig[idx] * randfield_eval(q, v3_sub(p, q_shift));
                }
                out[idx] = (float)fmax(0.0, rho);
            }
    free(mean);
    free(sig);
}

/* ---- the blob kind of density -------------------------------------------------------------- */

/* Upper bound of the truncated mean over each majorant cell: sum over the blobs whose sphere
 * reaches the cell of m W at the cell's nearest point to the centre (W falls with distance:
 * a kernel table must not increase, blob_kernel.h). */
static bool blobs_build_majorant(density *d)
{
    const blob_field *f = d->blobs;
    size_t count = (size_t)d->n[0] * (size_t)d->n[1] * (size_t)d->n[2];
    d->maj = calloc(count, sizeof *d->maj);
    if (!d->maj)
        return false;
    vec3 lo = d->bounds.lo;
    vec3 cs = v3((d->bounds.hi.x - lo.x) / d->n[0], (d->bounds.hi.y - lo.y) / d->n[1], (d->bounds.hi.z - lo.z) / d->n[2]);
    double rho_max = 0.0;
    for (int b = 0; b < f->n; b++) {
        double R = sqrt(f->R2[b]);
        vec3 c = f->b[b].x;
        int ilo[3], ihi[3];
        for (int a = 0; a < 3; a++) {
            double l = v3_get(lo, a), s = v3_get(cs, a), x = v3_get(c, a);
            ilo[a] = (int)fmax(0.0, floor((x - R - l) / s));
            ihi[a] = (int)fmin((double)d->n[a] - 1, floor((x + R - l) / s));
        }
        for (int k = ilo[2]; k <= ihi[2]; k++)
            for (int j = ilo[1]; j <= ihi[1]; j++)
                for (int i = ilo[0]; i <= ihi[0]; i++) {
                    vec3 clo = v3(lo.x + i * cs.x, lo.y + j * cs.y, lo.z + k * cs.z);
                    vec3 near = v3_min(v3_max(c, clo), v3_add(clo, cs));
                    vec3 dx = v3_sub(near, c);
                    double r2 = v3_dot(dx, dx);
                    if (r2 >= f->R2[b])
                        continue;
                    size_t idx = (size_t)i + (size_t)d->n[0] * ((size_t)j + (size_t)d->n[1] * (size_t)k);
                    /* a float that rounds up: the bound must stay a bound */
                    double v = (double)d->maj[idx] + blob_density_r2(f, b, r2);
                    d->maj[idx] = nextafterf((float)v, INFINITY);
                    rho_max = fmax(rho_max, (double)d->maj[idx]);
                }
    }
    d->rho_max = rho_max;
    return true;
}

/* The cells per axis of a blob field's majorant grid over bounds (density_new_blobs). */
static void majorant_dims(box3 bounds, int majorant_cells, int n[3])
{
    vec3 ext = v3_sub(bounds.hi, bounds.lo);
    double longest = fmax(ext.x, fmax(ext.y, ext.z));
    for (int a = 0; a < 3; a++)
        n[a] = (int)fmax(1.0, fmin((double)majorant_cells, ceil(majorant_cells * v3_get(ext, a) / longest)));
}

double blob_majorant_pairs(const blob *b, int n, double cutoff, int majorant_cells)
{
    box3 bounds = box3_empty();
    for (int i = 0; i < n; i++)
        bounds = box3_union(bounds, sphere_box(b[i].x, cutoff * b[i].h));
    int mn[3];
    majorant_dims(bounds, majorant_cells, mn);
    vec3 cs = v3((bounds.hi.x - bounds.lo.x) / mn[0], (bounds.hi.y - bounds.lo.y) / mn[1],
                 (bounds.hi.z - bounds.lo.z) / mn[2]);
    double pairs = 0.0;
    for (int i = 0; i < n; i++) {
        double R = cutoff * b[i].h, cells = 1.0;
        for (int a = 0; a < 3; a++) {
            double l = v3_get(bounds.lo, a), s = v3_get(cs, a), x = v3_get(b[i].x, a);
            double lo = s > 0.0 ? fmax(0.0, floor((x - R - l) / s)) : 0.0;
            double hi = s > 0.0 ? fmin((double)mn[a] - 1, floor((x + R - l) / s)) : 0.0;
            cells *= hi >= lo ? hi - lo + 1.0 : 1.0;
        }
        pairs += cells;
    }
    return pairs;
}

density *density_new_blobs(blob_field *f, int majorant_cells)
{
    if (majorant_cells < 1 || majorant_cells > 512) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "blobs: majorant cells %d outside [1, 512]", majorant_cells);
        return NULL;
    }
    density *d = calloc(1, sizeof *d);
    if (!d) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "blobs: out of memory");
        return NULL;
    }
    d->kind = DENSITY_BLOBS;
    d->filter = GRID_TRILINEAR;
    vec3 ext = v3_sub(f->bounds.hi, f->bounds.lo);
    majorant_dims(f->bounds, majorant_cells, d->n);
    /* "voxel space" is majorant-cell space: one majorant cell per voxel */
    affine3 v2w = {{ext.x / d->n[0], 0, 0, f->bounds.lo.x, 0, ext.y / d->n[1], 0, f->bounds.lo.y, 0, 0,
                    ext.z / d->n[2], f->bounds.lo.z}};
    if (!density_set_placement(d, &v2w, "blobs")) {
        free(d);
        return NULL;
    }
    d->bounds = f->bounds;
    d->blobs = f;
    d->mcell = 1;
    for (int a = 0; a < 3; a++) {
        d->moff[a] = 0;
        d->mn[a] = d->n[a];
    }
    if (!blobs_build_majorant(d)) {
        free(d);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "blobs: out of memory for the majorant grid");
        return NULL;
    }
    density_set_active_box(d);
    d->rho_min = 0.0;
    d->active = (uint64_t)f->n;
    d->memory = (size_t)f->n * (sizeof(blob) + 3 * sizeof(double)) + (size_t)f->nnodes * sizeof(bvh_node) +
                (size_t)d->n[0] * (size_t)d->n[1] * (size_t)d->n[2] * sizeof(float);
    return d;
}

blob_field *density_get_blobs(const density *d) { return d->kind == DENSITY_BLOBS ? d->blobs : NULL; }

static brume_status rebuild_density(density *d);

brume_status density_blobs_at_time(density *d, vec3 velocity, double t)
{
    if (d->kind != DENSITY_BLOBS)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "not a blob field");
    brume_status st = blob_field_at_time(d->blobs, velocity, t);
    if (st != BRUME_OK)
        return st;
    return rebuild_density(d);
}

brume_status density_blobs_set_kernel(density *d, blob_kernel *k)
{
    if (d->kind != DENSITY_BLOBS)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "not a blob field");
    brume_status st = blob_field_set_kernel(d->blobs, k);
    if (st != BRUME_OK)
        return st;
    return rebuild_density(d);
}

/* The density of a changed field (bounds, majorants) at the same majorant resolution. */
static brume_status rebuild_density(density *d)
{
    int cells = d->n[0];
    for (int a = 1; a < 3; a++)
        cells = d->n[a] > cells ? d->n[a] : cells;
    density *nd = density_new_blobs(d->blobs, cells);
    if (!nd)
        return err_status();
    free(d->maj);
    *d = *nd;
    free(nd);
    return BRUME_OK;
}

density *blob_field_grid(const blob_field *f, int resolution, const randfield *q, double eps, double eta,
                         const char *who)
{
    box3 b = f->bounds;
    vec3 ext = v3_sub(b.hi, b.lo);
    double longest = fmax(ext.x, fmax(ext.y, ext.z));
    int n[3];
    for (int a = 0; a < 3; a++)
        n[a] = (int)fmax(1.0, ceil(resolution * v3_get(ext, a) / longest));
    size_t cells = (size_t)n[0] * (size_t)n[1] * (size_t)n[2];
    /* the grid stays in the memory budget; blob_field_voxelize's two accumulators are
     * given back once it is done */
    if (budget_take(cells * sizeof(float), who) != BRUME_OK || budget_take(cells * 2 * sizeof(double), who) != BRUME_OK)
        return NULL;
    float *data = malloc(cells * sizeof *data);
    if (!data) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for %d x %d x %d voxels", who, n[0], n[1], n[2]);
        return NULL;
    }
    blob_field_voxelize(f, n, b, q, v3_scale(f->velocity, f->time), eps, eta, data);
    budget_give(cells * 2 * sizeof(double));
    density *g = density_new_grid(n[0], n[1], n[2], data, b, GRID_TRILINEAR);
    if (!g) {
        free(data);
        err_prefix("%s", who);
    }
    return g;
}

/* ---- the GPU's copy ------------------------------------------------------------------------ */

size_t blob_field_device_put(const blob_field *f, dev_arena *a)
{
    size_t at = arena_put(a, f, sizeof *f);
    if (at == ARENA_NULL)
        return at;
    const size_t n = (size_t)f->n;
    ARENA_PUT_MEMBER(a, at, blob_field, b, f->b, n * sizeof *f->b);
    ARENA_PUT_MEMBER(a, at, blob_field, peak, f->peak, n * sizeof(double));
    ARENA_PUT_MEMBER(a, at, blob_field, inv2h2, f->inv2h2, n * sizeof(double));
    ARENA_PUT_MEMBER(a, at, blob_field, R2, f->R2, n * sizeof(double));
    ARENA_PUT_MEMBER(a, at, blob_field, nodes, f->nodes, (size_t)f->nnodes * sizeof *f->nodes);
    if (f->kernel) { /* stam.kernel = table: the point density's table; the line table is stam's, host only */
        size_t k = arena_put(a, f->kernel, sizeof *f->kernel);
        arena_ptr(a, at + offsetof(blob_field, kernel), k);
        if (k != ARENA_NULL) {
            ARENA_PUT_MEMBER(a, k, blob_kernel, w, f->kernel->w, (size_t)(f->kernel->n + 2) * sizeof(double));
            arena_ptr(a, k + offsetof(blob_kernel, g), ARENA_NULL);
        }
    }
    return at;
}
