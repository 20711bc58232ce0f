/* blasi.c - Blasi, Le Saec and Schlick's two-pass Monte-Carlo renderer (1993, Section 4).
 *
 * First pass. Light ray k of light l starts with power W (watts, RGB) chosen so that the
 * rays of a light carry, in expectation, the power that light sends towards the media
 * (docs/blasi.md, "Normalization"). Between two scattering points the ray's weight is
 * multiplied per channel by exp(-(sigma_a + sigma_s - sigma_bar) rho delta) (Eq. 7 in
 * the grey case, where this is exp(-alpha rho delta)), and it is intercepted where the
 * optical depth of sigma_bar = mean over channels of sigma_s (Eq. 10) since the last
 * scattering point reaches -ln(1 - u) (Eq. 9-11, docs/errata.md, erratum 4); at an interception
 * the weight is multiplied by sigma_s / sigma_bar per channel (the RGB weights of a
 * chromatic medium; 1 when grey). The fraction r is stored in the voxel, 1 - r goes on
 * along a direction drawn from the directional lobe (Eq. 22-23). Rays below `threshold`
 * of their initial weight stop; in the paper variant, a ray that leaves the media stores
 * what it carries in the last non-empty voxel it crossed (docs/errata.md, erratum 5).
 *
 * Stored power P_V becomes the isotropic source S_V = P_V / (4 pi |V|): radiance per unit
 * length, the sigma_s phi / 4 pi of the single-scattering integral (docs/errata.md, erratum 6).
 *
 * Second pass. Along a view ray each voxel crossed over length delta adds
 * A S_V (1 - exp(-kappa delta)) / kappa (the exact integral over the voxel; S_V delta for
 * thin voxels) and scales A by exp(-kappa delta), kappa = sigma_a rho (paper) or
 * (sigma_a + sigma_s) rho (physical). Below `threshold` the ray stops; otherwise the
 * background, a light or a lit surface is added, attenuated by A.
 *
 * Determinism: light rays are numbered and draw from their own counter-based stream; the
 * rays are cut into batches that threads take as they come (a slower core gets fewer), and
 * each thread adds its deposits into its own sums in fixed point (integers: the order of the
 * terms does not change their sum), added together at the end. So the sums are the same
 * bits for any thread count. */
#include "render/blasi.h"

#include <errno.h>
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/fixsum.h"
#include "core/pool.h"
#include "core/progress.h"
#include "core/sampling.h"
#include "density/blobs.h"
#include "density/randfield.h"
#include "core/cancel.h"
#include "io/atomic.h"
#include "render/stam.h"
#include "surface/surfaces.h"

static const blasi_options *blasi_opts(const brume_scene *s) { return scene_options(s, METHOD_OPTIONS_BLASI); }

#define BLASI_BATCH 1024           /* light rays per task */
#define BLASI_MAX_VOXELS (1u << 24)   /* over all media */
/* Limits that keep every walk finite (docs/scene-format.md#limits): uniform steps across
 * the media, and interceptions of one light ray. */
#define BLASI_MAX_STEPS 1e7
#define BLASI_MAX_INTERCEPTS 100000
#define BLASI_BLOCK 4              /* voxels per side of an occupancy block (empty-space skipping) */
#define BLASI_SKIP_CELLS 192       /* skip empty blocks when nx + ny + nz exceeds this: a ray through a
                                      smaller grid crosses too few voxels for the restarts to pay */
#define BLASI_R_DEFAULT 0.1        /* "a small proportion (r ~ 0.1) of isotropic scattering" (4.2) */
#define BLASI_SLABS 6               /* diagonal slabs around the non-empty voxels (walk_begin_one) */
#define BLASI_FILE_MAGIC "BRUMEBL1"
#define BLASI_FILE_VERSION 1u

typedef struct blasi_medium {
    const medium *md;
    density *vox;        /* owned: a blob field voxelized at blasi.voxels, or NULL (md->rho is a grid) */
    int n[3];
    size_t nvox, offset; /* its voxels are [offset, offset + nvox) of the state's arrays */
    affine3 w2v;         /* world -> voxel space */
    affine3 v2w;         /* voxel -> world space */
    double volume;       /* world volume of one voxel */
    double chord;        /* mean chord of one voxel, 4 volume / surface area (blasi.gather = printed) */
    double sigma_bar;    /* Eq. 10: mean over channels of sigma_s, per unit density */
    color sigma_t;       /* sigma_a + sigma_s */
    color kappa;         /* view attenuation per unit density: sigma_a or sigma_t */
    color emit;          /* sigma_a Le: emitted radiance per unit length per unit density */
    bool emits;          /* emit is not black */
    bool view_grey;      /* kappa and sigma_t each the same in every channel */
    double r;            /* fraction stored isotropically at an interception */
    const phase *dir;    /* the directional lobe (the medium's, or dir_owned) */
    phase *dir_owned;
    bool skip;           /* walk occupancy blocks first (BLASI_SKIP_CELLS) */
    int occ_lo[3], occ_hi[3]; /* the box of the voxels with rho > 0, [lo, hi) (all 0 if none) */
    double slab_lo[BLASI_SLABS], slab_hi[BLASI_SLABS]; /* the voxels with rho > 0 between the planes
                                                          n . x = lo and hi, n = blasi_slab_n (voxel space) */
    vec3 occ_c, occ_e;   /* a world box holding that box (centre, half-extents slightly enlarged;
                            e < 0 when it is empty), for line_misses_box */
    int bn[3];           /* occupancy blocks per axis: ceil(n / BLASI_BLOCK) */
    unsigned char *occ;  /* per block: 1 if any of its voxels has rho > 0 */
} blasi_medium;

struct blasi_state {
    int nm;
    blasi_medium m[SCENE_MAX_MEDIA];
    size_t nvox;      /* over all media */
    float *rho;       /* nvox densities, constant per voxel */
    float *S;         /* 3 nvox: isotropic source, radiance per unit length (RGB) */
    box3 bounds;      /* union of the media's world boxes */
    box3 light_box;   /* union of the world boxes of the media's non-empty voxels: the light
                         rays aim at it (empty when every voxel is empty) */
    vec3 centre;      /* bounding sphere of `light_box` */
    double radius;
    double step;      /* first pass: 0 = voxel walk */
    double threshold;
    blasi_exit exit;
    blasi_view_atten view;
    bool gather_printed; /* blasi.gather = printed: A L_V per voxel visited (view_voxel) */
    bool area_lights; /* some light is a sphere or a disk: view rays may end on it */
    bool sun_disks;   /* some distant light has a disk: view rays may see it */
    blasi_stats stats;
};

/* ---- walking the voxels of all media at once ------------------------------------------ */

/* One stretch [t0, t1) of a ray inside constant voxels: n media, their global voxels v. */
typedef struct piece {
    double t0, t1;
    int n;
    int m[SCENE_MAX_MEDIA];
    size_t v[SCENE_MAX_MEDIA];
} piece;

/* The exact voxel walks of every medium (density/dda.h), merged in t. With one medium
 * (the usual case) the walk skips empty space: a coarse walk over occupancy blocks, and a
 * voxel walk over each run of occupied blocks only. Empty voxels hold no density and no
 * source (nothing is ever deposited in them), so skipping them changes no sum. */
typedef struct walk {
    int nm;
    grid_dda dda[SCENE_MAX_MEDIA];
    grid_dda_step cur[SCENE_MAX_MEDIA];
    bool live[SCENE_MAX_MEDIA];
    double t;
    grid_dda blocks; /* one medium: the walk over occupancy blocks */
    bool blocks_live;
} walk;

static inline size_t voxel_index(const blasi_medium *bm, int i, int j, int k)
{
    return bm->offset + (size_t)i + (size_t)bm->n[0] * ((size_t)j + (size_t)bm->n[1] * (size_t)k);
}

/* True when the line o + t d (any t) misses the world box of centre c and half-extents e:
 * the separating-axis test of a line against a box, whose only candidate axes are the
 * cross products of d with the box's axes (a line's extent along any other axis that d
 * has a component on is unbounded). No division and one branch, where a walk's set-up
 * maps the ray to voxel space and divides by each component of d. tol covers the rounding
 * of the cross products (a few ulps of |w| |d|); a ray that passes may still miss. */
static inline bool line_misses_box(vec3 c, vec3 e, vec3 o, vec3 d)
{
    const vec3 w = v3_sub(o, c);
    const double ax = fabs(d.x), ay = fabs(d.y), az = fabs(d.z);
    const double tol = 1e-12 * (fabs(w.x) + fabs(w.y) + fabs(w.z)) * (ax + ay + az);
    return (fabs(w.y * d.z - w.z * d.y) > e.y * az + e.z * ay + tol) |
           (fabs(w.z * d.x - w.x * d.z) > e.x * az + e.z * ax + tol) |
           (fabs(w.x * d.y - w.y * d.x) > e.x * ay + e.y * ax + tol);
}

/* The normals of the diagonal slabs, voxel space: with the box of the non-empty voxels
 * they bound them by an 18-sided polyhedron, much closer to a cloud than its box. */
static const int blasi_slab_n[BLASI_SLABS][3] = {{1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {1, 0, -1}, {0, 1, 1}, {0, 1, -1}};

/* [*t0, *t1] of the ray o + t d (voxel space) cut to the medium's diagonal slabs; false
 * when nothing is left. */
static inline __attribute__((always_inline)) bool slabs_clip(const blasi_medium *bm, vec3 o, vec3 d, double *t0,
                                                             double *t1)
{
    double a0 = *t0, a1 = *t1, b[BLASI_SLABS], inv[BLASI_SLABS];
    /* the six reciprocals from one division: inv_q = (product of the other b) / (product
     * of all), the products from both ends (rounding of a few ulps: the slabs' margin is
     * far wider); one at a time when a product is not a normal number (b = 0: parallel) */
    double pre[BLASI_SLABS + 1], suf[BLASI_SLABS + 1];
    pre[0] = suf[BLASI_SLABS] = 1.0;
#pragma GCC unroll 6
    for (int q = 0; q < BLASI_SLABS; q++) {
        const int *n = blasi_slab_n[q];
        b[q] = n[0] * d.x + n[1] * d.y + n[2] * d.z;
        pre[q + 1] = pre[q] * b[q];
    }
#pragma GCC unroll 6
    for (int q = BLASI_SLABS - 1; q >= 0; q--)
        suf[q] = suf[q + 1] * b[q];
    const double all = pre[BLASI_SLABS];
    if (fabs(all) >= DBL_MIN && fabs(all) <= DBL_MAX) {
        const double inv_all = 1.0 / all;
#pragma GCC unroll 6
        for (int q = 0; q < BLASI_SLABS; q++)
            inv[q] = pre[q] * suf[q + 1] * inv_all;
    } else {
#pragma GCC unroll 6
        for (int q = 0; q < BLASI_SLABS; q++)
            inv[q] = 1.0 / b[q];
    }
#pragma GCC unroll 6
    for (int q = 0; q < BLASI_SLABS; q++) {
        const int *n = blasi_slab_n[q];
        const double a = n[0] * o.x + n[1] * o.y + n[2] * o.z;
        if (b[q] == 0.0) { /* parallel to the slab: inside or not at all */
            if (!(a >= bm->slab_lo[q] && a <= bm->slab_hi[q]))
                return false;
            continue;
        }
        /* ordered by selects, as grid_dda_begin_box does (not fmin, fmax: library calls) */
        const double ta = (bm->slab_lo[q] - a) * inv[q], tb = (bm->slab_hi[q] - a) * inv[q];
        const double t_near = dda_min(tb, ta), t_far = dda_max(ta, tb);
        a0 = t_near > a0 ? t_near : a0;
        a1 = t_far < a1 ? t_far : a1;
    }
    *t0 = a0;
    *t1 = a1;
    return a0 < a1;
}

/* One medium and a small grid (!bm->skip): the walk over every voxel of the box of its
 * non-empty voxels (that lies between their diagonal slabs, with slabs), empty ones cost a
 * step. False when the ray misses them. The slabs pay for the view rays (on picture 1,
 * 376 k walks of 6.5 M voxel steps instead of 503 k of 8.1 M, for six divisions a ray),
 * not for the light rays, whose flights mostly start inside the cloud. */
static inline __attribute__((always_inline)) bool walk_begin_one(const blasi_medium *bm, ray r, double tmax, grid_dda *g,
                                                                 bool slabs)
{
    vec3 o = affine3_apply(&bm->w2v, r.o), d = affine3_apply_dir(&bm->w2v, r.d);
    double t0 = 0.0, t1 = tmax;
    return bm->occ_hi[0] > 0 && (!slabs || slabs_clip(bm, o, d, &t0, &t1)) &&
           grid_dda_begin_box(g, bm->n, bm->occ_lo, bm->occ_hi, o, d, t0, t1);
}

/* walk_begin_one without slabs for a ray whose direction's set-up is made (sun: the voxel
 * space direction of a sun's rays, shared by all of them). */
static inline __attribute__((always_inline)) bool walk_begin_one_dir(const blasi_medium *bm, ray r, double tmax,
                                                                     grid_dda *g, const grid_dda_dir *sun)
{
    return bm->occ_hi[0] > 0 && grid_dda_begin_box_dir(g, bm->n, bm->occ_lo, bm->occ_hi,
                                                       affine3_apply(&bm->w2v, r.o), sun, 0.0, tmax);
}

static void walk_begin(walk *w, const blasi_state *st, ray r, double tmax)
{
    w->nm = st->nm;
    w->t = INFINITY;
    if (w->nm == 1) {
        /* the voxel walk is begun once over the whole ray; each run of occupied blocks
         * restarts it (grid_dda_restart: no clipping, no division) */
        const blasi_medium *bm = &st->m[0];
        if (!bm->skip) {
            w->live[0] = walk_begin_one(bm, r, tmax, &w->dda[0], true);
            w->blocks_live = false;
            return;
        }
        vec3 o = affine3_apply(&bm->w2v, r.o), d = affine3_apply_dir(&bm->w2v, r.d);
        double s = 1.0 / BLASI_BLOCK;
        w->live[0] = false;
        w->blocks_live = grid_dda_begin(&w->blocks, bm->bn, v3_scale(o, s), v3_scale(d, s), 0.0, tmax) &&
                         grid_dda_begin(&w->dda[0], bm->n, o, d, 0.0, tmax);
        return;
    }
    for (int m = 0; m < st->nm; m++) {
        const blasi_medium *bm = &st->m[m];
        vec3 o = affine3_apply(&bm->w2v, r.o), d = affine3_apply_dir(&bm->w2v, r.d);
        w->live[m] = grid_dda_begin(&w->dda[m], bm->n, o, d, 0.0, tmax) && grid_dda_next(&w->dda[m], &w->cur[m]);
        if (w->live[m])
            w->t = fmin(w->t, w->cur[m].t0);
    }
}

/* One small grid (no block skipping): the next non-empty voxel. Empty voxels hold nothing
 * (no density, no source: nothing is ever deposited in them), so they are stepped over
 * here, in a tight loop that the callers inline. */
static inline bool walk_next_small(walk *w, const blasi_medium *bm, const float *rho, piece *p)
{
    grid_dda_step c;
    size_t v;
    do {
        if (!w->live[0] || !(w->live[0] = grid_dda_next(&w->dda[0], &c)))
            return false;
        v = (size_t)c.i + (size_t)bm->n[0] * ((size_t)c.j + (size_t)bm->n[1] * (size_t)c.k);
    } while (rho[v] == 0.0f);
    p->t0 = c.t0;
    p->t1 = c.t1;
    p->n = 1;
    p->m[0] = 0;
    p->v[0] = bm->offset + v;
    return true;
}

static bool walk_next_any(walk *w, const blasi_state *st, piece *p);

static inline bool walk_next(walk *w, const blasi_state *st, piece *p)
{
    if (w->nm == 1 && !st->m[0].skip)
        return walk_next_small(w, &st->m[0], st->rho + st->m[0].offset, p);
    return walk_next_any(w, st, p);
}

static bool walk_next_any(walk *w, const blasi_state *st, piece *p)
{
    if (w->nm == 1) { /* the usual case: one grid, its own walk, empty blocks skipped */
        const blasi_medium *bm = &st->m[0];
        while (!w->live[0]) { /* the next run of occupied blocks */
            grid_dda_step b;
            do {
                if (!w->blocks_live || !(w->blocks_live = grid_dda_next(&w->blocks, &b)))
                    return false;
            } while (!bm->occ[(size_t)b.i + (size_t)bm->bn[0] * ((size_t)b.j + (size_t)bm->bn[1] * (size_t)b.k)]);
            double t0 = b.t0, t1 = b.t1;
            while ((w->blocks_live = grid_dda_next(&w->blocks, &b)) &&
                   bm->occ[(size_t)b.i + (size_t)bm->bn[0] * ((size_t)b.j + (size_t)bm->bn[1] * (size_t)b.k)])
                t1 = b.t1;
            w->live[0] = grid_dda_restart(&w->dda[0], t0, t1) && grid_dda_next(&w->dda[0], &w->cur[0]);
        }
        const grid_dda_step *c = &w->cur[0];
        p->t0 = c->t0;
        p->t1 = c->t1;
        p->n = 1;
        p->m[0] = 0;
        p->v[0] = voxel_index(bm, c->i, c->j, c->k);
        w->live[0] = grid_dda_next(&w->dda[0], &w->cur[0]);
        return true;
    }
    for (;;) {
        double t = w->t, t1 = INFINITY;
        bool any = false;
        for (int m = 0; m < w->nm; m++) {
            while (w->live[m] && w->cur[m].t1 <= t)
                w->live[m] = grid_dda_next(&w->dda[m], &w->cur[m]);
            if (!w->live[m])
                continue;
            any = true;
            t1 = fmin(t1, w->cur[m].t0 > t ? w->cur[m].t0 : w->cur[m].t1);
        }
        if (!any)
            return false;
        p->n = 0;
        for (int m = 0; m < w->nm; m++)
            if (w->live[m] && w->cur[m].t0 <= t) {
                p->m[p->n] = m;
                p->v[p->n] = voxel_index(&st->m[m], w->cur[m].i, w->cur[m].j, w->cur[m].k);
                p->n++;
            }
        p->t0 = t;
        p->t1 = t1;
        w->t = t1;
        if (p->n > 0)
            return true;
    }
}

/* The voxels holding point p (uniform-step marching). */
static void piece_at(const blasi_state *st, vec3 p, piece *pc)
{
    pc->n = 0;
    for (int m = 0; m < st->nm; m++) {
        const blasi_medium *bm = &st->m[m];
        vec3 u = affine3_apply(&bm->w2v, p);
        double f[3] = {floor(u.x), floor(u.y), floor(u.z)};
        if (f[0] < 0.0 || f[1] < 0.0 || f[2] < 0.0 || f[0] >= bm->n[0] || f[1] >= bm->n[1] || f[2] >= bm->n[2])
            continue;
        pc->m[pc->n] = m;
        pc->v[pc->n] = voxel_index(bm, (int)f[0], (int)f[1], (int)f[2]);
        pc->n++;
    }
}

/* ---- first pass -------------------------------------------------------------------------- */

/* Projected area of box b seen along unit d, and a uniform point on it (the faces that d
 * enters through, each chosen in proportion to area |n . d|). */
static double box_projected_area(box3 b, vec3 d)
{
    vec3 e = v3_sub(b.hi, b.lo);
    return e.y * e.z * fabs(d.x) + e.x * e.z * fabs(d.y) + e.x * e.y * fabs(d.z);
}

static vec3 box_entry_point(box3 b, vec3 d, double u0, double u1, double u2)
{
    vec3 e = v3_sub(b.hi, b.lo);
    double a[3] = {e.y * e.z * fabs(d.x), e.x * e.z * fabs(d.y), e.x * e.y * fabs(d.z)};
    double x = u0 * (a[0] + a[1] + a[2]);
    if (x < a[0])
        return v3(d.x > 0.0 ? b.lo.x : b.hi.x, b.lo.y + u1 * e.y, b.lo.z + u2 * e.z);
    if (x < a[0] + a[1])
        return v3(b.lo.x + u1 * e.x, d.y > 0.0 ? b.lo.y : b.hi.y, b.lo.z + u2 * e.z);
    return v3(b.lo.x + u1 * e.x, b.lo.y + u2 * e.y, d.z > 0.0 ? b.lo.z : b.hi.z);
}

/* A direction from y uniform in the cone that holds the media's bounding sphere (the whole
 * sphere of directions when y is inside it); *omega is the cone's solid angle. */
static vec3 towards_media(const blasi_state *st, vec3 y, double u1, double u2, double *omega)
{
    vec3 c = v3_sub(st->centre, y);
    double dist = v3_length(c), cos_max = -1.0;
    if (dist > st->radius * (1.0 + 1e-9))
        cos_max = sqrt(fmax(0.0, 1.0 - st->radius * st->radius / (dist * dist)));
    *omega = 1.0 / sample_cone_pdf(cos_max);
    if (cos_max <= -1.0)
        return sample_sphere(u1, u2);
    frame f = frame_from_n(v3_scale(c, 1.0 / dist));
    return frame_to_world(&f, sample_cone(u1, u2, cos_max));
}

/* Light ray j of the n rays of light l (Section 4.2: each light's surface divided into
 * `sources` elementary sources, rays sent stochastically into the solid angle that holds
 * the media, following the light's goniometric distribution). *W is its power; false
 * when it carries none. */
static bool light_ray(const brume_scene *s, const blasi_state *st, const light *l, uint64_t j, uint64_t n, rng *g,
                      ray *r, color *W)
{
    double u0 = rng_next(g), u1 = rng_next(g), u2 = rng_next(g), u3 = 0.0, u4 = 0.0;
    if (l->kind == LIGHT_DISTANT && !(l->angular_radius > 0.0))
        g->counter += 2; /* a delta sun needs no u3, u4: skipped, so what follows draws the same numbers */
    else
        u3 = rng_next(g), u4 = rng_next(g);
    double inv_n = 1.0 / (double)n, omega;
    r->time = 0.0;
    switch (l->kind) {
    case LIGHT_DISTANT: {
        vec3 d = l->direction;
        color L = l->L; /* irradiance of a delta sun */
        if (l->angular_radius > 0.0) { /* a sun disk: a direction in its cone, radiance L */
            d = v3_neg(frame_to_world(&l->f, sample_cone(u3, u4, l->cos_max)));
            double sn = sin(l->angular_radius);
            L = col_scale(l->L, 1.0 / (PI * sn * sn) / sample_cone_pdf(l->cos_max));
        }
        double area = box_projected_area(st->light_box, d);
        vec3 p = box_entry_point(st->light_box, d, u0, u1, u2);
        *r = (ray){v3_madd(p, d, -1e-6 * st->radius), d, s->time};
        if (s->surf && surfaces_occluded(s->surf, r->o, v3_neg(d), 0.0, INFINITY, s->time))
            return false;
        *W = col_scale(L, area * inv_n);
        return true;
    }
    case LIGHT_POINT:
    case LIGHT_SPOT: {
        vec3 d = towards_media(st, l->position, u0, u1, &omega);
        light_sample ls; /* the intensity towards d: irradiance at distance 1 */
        if (!light_sample_at(l, v3_add(l->position, d), 0.5, 0.5, &ls))
            return false;
        *r = (ray){l->position, d, 0.0};
        *W = col_scale(ls.Li, omega * inv_n);
        return true;
    }
    case LIGHT_SPHERE:
    case LIGHT_DISK: {
        /* elementary source j mod M: a stratum of a k x k grid over the surface's
         * parameter square (both maps preserve area) */
        int k = (int)ceil(sqrt((double)blasi_opts(s)->sources));
        uint64_t cell = j % (uint64_t)(k * k);
        double a = ((double)(cell % (uint64_t)k) + u2) / k, b = ((double)(cell / (uint64_t)k) + u3) / k;
        vec3 y, nrm;
        double area;
        if (l->kind == LIGHT_SPHERE) {
            nrm = sample_sphere(a, b);
            y = v3_madd(l->position, nrm, l->radius);
            area = 4.0 * PI * l->radius * l->radius;
        } else {
            nrm = l->direction;
            y = v3_add(l->position, frame_to_world(&l->f, v3_scale(sample_disk(a, b), l->radius)));
            area = PI * l->radius * l->radius;
        }
        vec3 d = towards_media(st, y, u0, u1, &omega);
        double cos_y = v3_dot(d, nrm);
        if (cos_y <= 0.0)
            return false;
        *r = (ray){v3_madd(y, nrm, 1e-9 * (1.0 + l->radius)), d, 0.0};
        *W = col_scale(l->L, cos_y * area * omega * inv_n);
        return true;
    }
    }
    return false;
}

/* ---- the light pass's sums -----------------------------------------------------------------
 *
 * Deposited power is summed in fixed point (core/fixsum.h): integer sums do not depend on
 * the order of their terms, so each thread adds its deposits into sums of its own as it
 * makes them, and those added at the end give the same bits for any thread count and any
 * order in which the batches ran, with no record of the deposits, no ordered merge and no
 * barrier between batches. The unit is 2^-40 of a reference power per ray (ray_power_ref,
 * within a few powers of two of what rays start with): a deposit is truncated to a whole
 * unit, about 1e-12 of a ray's power (S is a float, 6e-8 of a voxel's sum), and a sum
 * would wrap only past 2^128 units, 2^88 rays' powers in one voxel: beyond any light-ray
 * count (at most 1e12 ~ 2^40) times any weight a ray reaches (a chromatic medium's weights
 * may exceed the initial power; their mean cannot). */

/* What the rays of one batch make: deposits into the sums of the thread that traces it,
 * counts for the batch's own record. */
typedef struct light_sums {
    fixsum *P;            /* 3 nocc: the thread's stored power per non-empty voxel and channel, in units */
    const uint32_t *slot; /* nvox: a non-empty voxel's place in P (deposits land in no other) */
    double per_unit;      /* units per watt */
    uint64_t intercepts, deposits;
    double emitted;  /* power the batch's rays started with, summed over channels */
} light_sums;

typedef struct pass1_job {
    const brume_scene *s;
    const blasi_state *st;
    uint64_t nrays, nbatch; /* rays traced, over all lights */
    const uint64_t *first;  /* nlights + 1: light l traces rays [first[l], first[l + 1]) */
    fixsum *P;              /* per thread: 3 nocc sums */
    const uint32_t *slot;
    size_t nocc;            /* non-empty voxels */
    double per_unit;
    light_sums *batch;      /* nbatch: each batch's counts (P unused) */
    progress prog;
    cancel_poll cancel;     /* the render's progress callback, asked between rays (issue 36) */
} pass1_job;

static inline void deposit(light_sums *out, size_t v, color w, double f)
{
    fixsum *p = out->P + 3 * (size_t)out->slot[v];
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++)
        fixsum_add(&p[c], w.c[c] * f * out->per_unit);
    out->deposits++;
}

/* Coefficients of a piece: sigma_bar rho summed over its media (returned), and in *kx the
 * per-channel (sigma_t - sigma_bar) rho, the rate at which the weight decays between
 * interceptions (alpha rho for a grey medium, Eq. 7). */
static inline double piece_coeffs(const blasi_state *st, const piece *pc, color *kx)
{
    double sb = 0.0;
    *kx = col(0.0);
    for (int i = 0; i < pc->n; i++) {
        const blasi_medium *bm = &st->m[pc->m[i]];
        double rho = (double)st->rho[pc->v[i]];
        sb += bm->sigma_bar * rho;
        for (int c = 0; c < 3; c++)
            kx->c[c] += (bm->sigma_t.c[c] - bm->sigma_bar) * rho;
    }
    return sb;
}

/* T = exp(-tau) and f = (1 - T) / tau, the fraction of a voxel's length that its source
 * fills, for tau >= 0. Most voxels are optically thin (tau ~ 0.01 in the paper's scenes):
 * there the Taylor series of f to tau^7 (truncation below 1e-15 for tau < 1/16) gives
 * both without calling exp. */
static inline void voxel_exp(double tau, double *T, double *f)
{
    if (tau < 0.0625) {
        /* Estrin's scheme: the terms in pairs, so the series costs a few multiplications of
         * latency rather than a chain of eight */
        double x = tau, x2 = x * x, x4 = x2 * x2;
        double p01 = 1.0 - x * (1.0 / 2), p23 = 1.0 / 6 - x * (1.0 / 24), p45 = 1.0 / 120 - x * (1.0 / 720),
               p67 = 1.0 / 5040 - x * (1.0 / 40320);
        *f = (p01 + x2 * p23) + x4 * (p45 + x2 * p67);
        *T = 1.0 - x * *f;
        return;
    }
    *T = exp(-tau);
    *f = (1.0 - *T) / tau;
}

/* exp(-x) per channel, once when the channels are equal (a grey medium), and by
 * voxel_exp's series for 0 <= x < 1/16, where most of a light ray's decays are (a
 * chromatic medium's may be negative: exp). */
static inline color col_exp_neg(color x)
{
    color e;
    for (int c = 0; c < BRUME_NSAMPLES; c++) {
        double T = 0.0, f;
        if (c > 0 && x.c[c] == x.c[c - 1])
            T = e.c[c - 1];
        else if (x.c[c] >= 0.0)
            voxel_exp(x.c[c], &T, &f);
        else
            T = exp(-x.c[c]);
        e.c[c] = T;
    }
    return e;
}

/* One flight of a light ray, from the source or a scattering point to the next
 * interception. tau is the sigma_bar optical depth since it began; it scatters where tau
 * reaches the target -ln(1 - u) (Eq. 11), with u the flight's first random number, drawn
 * at the first voxel that can scatter (most light rays miss the media), and its log taken
 * only when tau passes a lower bound of the target, u (1 - 2^-20) (0 for u < 2^-30: the
 * rounding of 1 - u and of the log cannot take the target under it): a flight that leaves
 * the media before needs no log, and the one that takes it scatters where it did. The weight's
 * decay is kept as an optical depth D per channel and exponentiated once, at the
 * interception or the exit; the stop test is D > lim = log(w / w_stop) per channel, with
 * the logs taken only when D passes their lower bound lim_lo = 1 - w_stop / w
 * (log x >= 1 - 1/x), itself found at the first voxel crossed: most flights end long
 * before. */
typedef struct flight {
    double u, bound, target, tau; /* bound: the target's lower bound, then the target */
    bool have_u, have_target, lim_lo_known, lim_known;
    color D, lim, lim_lo; /* a grey flight keeps one D and its bounds in channel 0 */
} flight;

static inline void flight_begin(flight *f)
{
    f->have_u = f->have_target = f->lim_lo_known = f->lim_known = false;
    f->bound = f->target = INFINITY; /* until drawn */
    f->tau = 0.0;
    f->D = col(0.0);
}

/* Draws u, at the first voxel that can scatter. */
static inline void flight_draw(flight *f, rng *g)
{
    f->u = rng_next(g);
    f->bound = f->u >= 0x1p-30 ? f->u * (1.0 - 0x1p-20) : 0.0;
    f->have_u = true;
}

/* True when the optical depth x (>= f->bound) reaches the target, taken now if not yet. */
static inline bool flight_reaches(flight *f, double x)
{
    if (!f->have_target) {
        f->bound = f->target = sample_exponential(f->u, 1.0);
        f->have_target = true;
    }
    return x >= f->target;
}

/* True when a stretch of length dl with sigma_bar rho = sb scatters in it. */
static inline bool flight_scatters(flight *f, double sb, double dl, rng *g)
{
    if (!(sb > 0.0))
        return false;
    if (!f->have_u)
        flight_draw(f, g);
    const double x = f->tau + sb * dl;
    return x >= f->bound && flight_reaches(f, x);
}

/* The stop test after the decay reached D (the while condition: L_R > THRESHOLD): true
 * when the weight is under the threshold in every channel. grey: D's channels are equal
 * (D.c[0] is read), and D exceeds every channel's bound exactly when it exceeds the
 * largest, that of the largest weight (both bounds grow with the weight, and so do their
 * rounded values): one division, one log and one comparison, kept in channel 0. */
static inline __attribute__((always_inline)) bool flight_stops_as(flight *f, color D, const color *wp, double w_stop,
                                                                  bool grey)
{
    const int nc = grey ? 1 : BRUME_NSAMPLES;
    color w = *wp;
    if (!f->lim_lo_known) {
        if (grey)
            w.c[0] = col_max(w);
        for (int c = 0; c < nc; c++)
            f->lim_lo.c[c] = w.c[c] > 0.0 ? 1.0 - w_stop / w.c[c] : -(double)INFINITY;
        f->lim_lo_known = true;
    }
    for (int c = 0; c < nc; c++)
        if (!(D.c[c] > f->lim_lo.c[c]))
            return false;
    if (!f->lim_known) {
        if (grey)
            w.c[0] = col_max(w);
        for (int c = 0; c < nc; c++)
            f->lim.c[c] = w.c[c] > 0.0 ? log(w.c[c] / w_stop) : -(double)INFINITY;
        f->lim_known = true;
    }
    for (int c = 0; c < nc; c++)
        if (!(D.c[c] > f->lim.c[c]))
            return false;
    return true;
}

static inline bool flight_stops(flight *f, color D, color w, double w_stop)
{
    return flight_stops_as(f, D, &w, w_stop, false);
}

static inline bool col_is_grey(color a)
{
    for (int c = 1; c < BRUME_NSAMPLES; c++)
        if (a.c[c] != a.c[0])
            return false;
    return true;
}

/* A stretch of length dl with coefficients sb, kx that the flight crosses whole. True when
 * the weight falls under the threshold there. */
static inline bool flight_cross(flight *f, double sb, color kx, double dl, color w, double w_stop)
{
    f->tau += sb * dl;
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        f->D.c[c] += kx.c[c] * dl;
    return flight_stops(f, f->D, w, w_stop);
}

/* The interception in piece pc, at ds into it (ray parameter t_hit), for a flight that
 * has reached its target there: the RGB weight (Eq. 10) and the decay, the fraction r
 * stored, and the new direction from the lobe (Eq. 23 for Schlick lobes). False when what
 * goes on is under the threshold (the ray ends). */
static bool intercept(const blasi_state *st, const piece *pc, double sb, color kx, const flight *f, double ds,
                      double t_hit, ray *r, color *w, double w_stop, rng *g, light_sums *acc, size_t *last)
{
    int pick = 0;
    if (pc->n > 1) { /* the medium that scatters, in proportion to its sigma_bar rho */
        double x = rng_next(g) * sb;
        for (pick = 0; pick < pc->n - 1; pick++) {
            double wi = st->m[pc->m[pick]].sigma_bar * (double)st->rho[pc->v[pick]];
            if (x < wi)
                break;
            x -= wi;
        }
    }
    color sig_s = col(0.0), dep; /* RGB weight sigma_s / sigma_bar (Eq. 10) */
    for (int i = 0; i < pc->n; i++)
        sig_s = col_madd(sig_s, st->m[pc->m[i]].md->sigma_s, (double)st->rho[pc->v[i]]);
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        dep.c[c] = f->D.c[c] + kx.c[c] * ds;
    color T = col_exp_neg(dep);
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        w->c[c] *= T.c[c] * sig_s.c[c] / sb;
    const blasi_medium *bm = &st->m[pc->m[pick]];
    deposit(acc, pc->v[pick], *w, bm->r);
    acc->intercepts++;
    *last = pc->v[pick];
    *w = col_scale(*w, 1.0 - bm->r);
    if (!(col_max(*w) > w_stop))
        return false;
    double pdf, ua = rng_next(g), ub = rng_next(g);
    vec3 d = phase_sample(bm->dir, r->d, ua, ub, &pdf); /* Eq. 23 for Schlick lobes */
    *r = (ray){ray_at(*r, t_hit), d, 0.0};
    return true;
}

/* What a flight ended with. */
typedef enum flight_end { FLIGHT_LEFT, FLIGHT_SCATTERED, FLIGHT_STOPPED } flight_end;

/* A flight through one small grid (one medium, no block skipping, the voxel walk: the
 * usual case): the general loop of fly() with the piece reduced to one voxel, the walk's
 * and the flight's state in locals the loop keeps in registers, and no branch on whether a
 * voxel is empty: an empty one (sb = 0, kx = 0) adds exactly 0 to tau and D, cannot
 * scatter (tau + 0 < target), is not remembered as the last voxel, and leaves the stop
 * test's answer as it was, so the flight is the same as with the branch. grey: the decay
 * rate kx is the same in every channel (sigma_t - sigma_bar grey, e.g. a grey medium), so
 * D's channels stay equal and the loop keeps one (the same sums: every channel's would be
 * this one). */
static inline __attribute__((always_inline)) flight_end fly_one_as(const blasi_state *st, flight *f, ray *r,
                                                                   double t_end, color *w, double w_stop, rng *g,
                                                                   light_sums *acc, bool *have_last, size_t *last,
                                                                   const grid_dda_dir *sun, color kx1, bool grey)
{
    const blasi_medium *bm = &st->m[0];
    grid_dda g0;
    if (!(sun ? walk_begin_one_dir(bm, *r, t_end, &g0, sun) : walk_begin_one(bm, *r, t_end, &g0, false)))
        return FLIGHT_LEFT;
    grid_dda gd = g0; /* never escapes */
    const float *rho = st->rho;
    const size_t nx = (size_t)bm->n[0], ny = (size_t)bm->n[1];
    const double sigma_bar = bm->sigma_bar;
    const int nc = grey ? 1 : BRUME_NSAMPLES; /* the channels the loop keeps */
    double tau = f->tau, bound = f->bound; /* bound: as f's, kept here */
    bool have_u = f->have_u;
    color D = f->D;
    bool was = *have_last;
    size_t lv = *last;
    flight_end e = FLIGHT_LEFT;
    grid_dda_step c;
    while (grid_dda_next(&gd, &c)) {
        const size_t v = (size_t)c.i + nx * ((size_t)c.j + ny * (size_t)c.k);
        const double rh = (double)rho[v], dl = c.t1 - c.t0, sb = sigma_bar * rh;
        color kx;
#pragma GCC unroll 3
        for (int k = 0; k < nc; k++)
            kx.c[k] = kx1.c[k] * rh;
        if (!have_u && sb > 0.0) { /* the first voxel that can scatter: draw u */
            flight_draw(f, g);
            have_u = true;
            bound = f->bound;
        }
        if (tau + sb * dl >= bound) { /* sb > 0 here: tau < bound before */
            const bool hit = flight_reaches(f, tau + sb * dl);
            bound = f->bound; /* the target, taken now */
            if (hit) {
                double ds = (f->target - tau) / sb;
                piece pc; /* only what intercept reads */
                pc.n = 1;
                pc.m[0] = 0;
                pc.v[0] = v;
                f->D = grey ? col(D.c[0]) : D;
                kx = grey ? col(kx.c[0]) : kx;
                *have_last = true;
                return intercept(st, &pc, sb, kx, f, ds, c.t0 + ds, r, w, w_stop, g, acc, last) ? FLIGHT_SCATTERED
                                                                                              : FLIGHT_STOPPED;
            }
        }
        /* !(sb <= 0 && kx == 0), with | so that no branch is mispredicted on it */
        bool counts = !(sb <= 0.0);
#pragma GCC unroll 3
        for (int k = 0; k < nc; k++)
            counts |= kx.c[k] != 0.0;
        tau += counts ? sb * dl : 0.0;
#pragma GCC unroll 3
        for (int k = 0; k < nc; k++)
            D.c[k] += counts ? kx.c[k] * dl : 0.0;
        lv = counts ? v : lv;
        was |= counts;
        if (was && flight_stops_as(f, D, w, w_stop, grey)) {
            e = FLIGHT_STOPPED;
            break;
        }
    }
    f->tau = tau;
    f->D = grey ? col(D.c[0]) : D;
    *have_last = was;
    *last = lv;
    return e;
}

static flight_end fly_one(const blasi_state *st, flight *f, ray *r, double t_end, color *w, double w_stop, rng *g,
                          light_sums *acc, bool *have_last, size_t *last, const grid_dda_dir *sun)
{
    const blasi_medium *bm = &st->m[0];
    color kx1; /* (sigma_t - sigma_bar) per unit density */
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        kx1.c[c] = bm->sigma_t.c[c] - bm->sigma_bar;
    if (col_is_grey(kx1) && col_is_grey(f->D))
        return fly_one_as(st, f, r, t_end, w, w_stop, g, acc, have_last, last, sun, kx1, true);
    return fly_one_as(st, f, r, t_end, w, w_stop, g, acc, have_last, last, sun, kx1, false);
}

/* A flight through any media: the merged voxel walks, or uniform steps (blasi.step). */
static flight_end fly(const blasi_state *st, flight *f, ray *r, double t_end, color *w, double w_stop, rng *g,
                      light_sums *acc, bool *have_last, size_t *last)
{
    walk wk;
    piece pc;
    double t_march = 0.0, t_march_end = 0.0;
    uint64_t k_march = 0; /* steps are placed by index, t_march + k step: never t += step */
    if (st->step > 0.0) {
        if (!box3_intersect(st->bounds, *r, 0.0, t_end, &t_march, &t_march_end))
            t_march = t_march_end = 0.0;
    } else {
        walk_begin(&wk, st, *r, t_end);
    }
    for (;;) {
        double dl, t_mid = 0.0;
        if (st->step > 0.0) { /* uniform steps: the voxels at the step's midpoint */
            double a = t_march + (double)k_march * st->step;
            if (!(a < t_march_end))
                return FLIGHT_LEFT;
            k_march++;
            dl = fmin(st->step, t_march_end - a);
            t_mid = a + 0.5 * dl;
            pc.t0 = a;
            piece_at(st, ray_at(*r, t_mid), &pc);
        } else {
            if (!walk_next(&wk, st, &pc))
                return FLIGHT_LEFT;
            dl = pc.t1 - pc.t0;
        }
        color kx;
        double sb = piece_coeffs(st, &pc, &kx);
        if (flight_scatters(f, sb, dl, g)) {
            /* interception: exactly inside the voxel, or at the step's midpoint */
            double ds = st->step > 0.0 ? dl : (f->target - f->tau) / sb;
            double t_hit = st->step > 0.0 ? t_mid : pc.t0 + ds;
            *have_last = true;
            return intercept(st, &pc, sb, kx, f, ds, t_hit, r, w, w_stop, g, acc, last) ? FLIGHT_SCATTERED
                                                                                     : FLIGHT_STOPPED;
        }
        if (sb <= 0.0 && kx.c[0] == 0.0 && kx.c[1] == 0.0 && kx.c[2] == 0.0)
            continue; /* empty voxel */
        *have_last = true;
        *last = pc.v[0];
        if (flight_cross(f, sb, kx, dl, *w, w_stop))
            return FLIGHT_STOPPED;
    }
}

/* Follows one light ray through the media (Algorithm of the First Pass), flight by
 * flight. */
/* True when light flights take fly_one: one small grid, the voxel walk. */
static inline bool flights_one(const blasi_state *st) { return st->nm == 1 && !st->m[0].skip && !(st->step > 0.0); }

/* The voxel-space set-up of the direction of a delta sun's rays (light_ray gives them all
 * its direction), for their first flights through one small grid; NULL for another light
 * or other media. */
static const grid_dda_dir *sun_dir(const blasi_state *st, const light *l, grid_dda_dir *out)
{
    if (!flights_one(st) || l->kind != LIGHT_DISTANT || l->angular_radius > 0.0)
        return NULL;
    grid_dda_dir_make(out, affine3_apply_dir(&st->m[0].w2v, l->direction));
    return out;
}

/* sun: sun_dir of the ray's light, or NULL. */
static void trace_light_ray(const brume_scene *s, const blasi_state *st, ray r, color w, rng *g, light_sums *acc,
                            const grid_dda_dir *sun)
{
    const bool one = flights_one(st);
    double w_stop = st->threshold * col_max(w);
    bool have_last = false; /* the last non-empty voxel crossed, for the exit deposit */
    size_t last = 0;
    for (int flights = 0;; flights++) { /* one flight from the source or a scattering point */
        if (flights > BLASI_MAX_INTERCEPTS) {
            /* A walk that neither leaves nor fades (albedo 1, r = 0, an optically huge
             * medium) ends here with a defined result: what it still carries stays in
             * the voxel it has reached, as the paper stores the energy of a ray that
             * leaves in its last voxel. */
            if (have_last)
                deposit(acc, last, w, 1.0);
            return;
        }
        double t_end = INFINITY;
        surface_hit h;
        if (s->surf && surfaces_intersect(s->surf, r, 0.0, INFINITY, &h))
            t_end = h.t;
        flight f;
        flight_begin(&f);
        flight_end e = one ? fly_one(st, &f, &r, t_end, &w, w_stop, g, acc, &have_last, &last, flights == 0 ? sun : NULL)
                           : fly(st, &f, &r, t_end, &w, w_stop, g, acc, &have_last, &last);
        if (e == FLIGHT_SCATTERED)
            continue;
        if (e == FLIGHT_STOPPED || isfinite(t_end)) /* under the threshold, or stopped by a surface */
            return;
        if (st->exit == BLASI_EXIT_PAPER && have_last) { /* "stored in the last non-empty voxel" */
            w = col_mul(w, col_exp_neg(f.D));
            deposit(acc, last, w, 1.0);
        }
        return;
    }
}

static void pass1_batch(size_t task, int thread, void *user)
{
    pass1_job *job = user;
    const brume_scene *s = job->s;
    light_sums sums = {job->P + (size_t)thread * 3 * job->nocc, job->slot, job->per_unit, 0, 0, 0.0}, *out = &sums;
    uint64_t b = task;
    uint64_t first = b * BLASI_BATCH, end = first + BLASI_BATCH < job->nrays ? first + BLASI_BATCH : job->nrays;
    /* the light of the batch's first ray, found once per batch (by bisection: first[] is
     * non-decreasing, first[0] = 0 <= first < first[nlights] = nrays) */
    size_t lo = 0, hi = (size_t)s->nlights;
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (job->first[mid] <= first)
            lo = mid;
        else
            hi = mid;
    }
    size_t l = lo;
    uint64_t l0 = job->first[l], l1 = job->first[l + 1];
    grid_dda_dir sun_mem;
    const grid_dda_dir *sun = sun_dir(job->st, &s->lights[l], &sun_mem);
    for (uint64_t i = first; i < end; i++) {
        if (cancel_poll_stop(&job->cancel))
            return; /* the pass is abandoned: its sums are never read */
        while (i >= l1) { /* the next light's share (a light may own no ray) */
            l++;
            l0 = l1;
            l1 = job->first[l + 1];
            sun = sun_dir(job->st, &s->lights[l], &sun_mem);
        }
        rng g = rng_make(s->settings.seed, i, 0xB1A5100000ULL);
        ray r;
        color W;
        if (light_ray(s, job->st, &s->lights[l], i - l0, l1 - l0, &g, &r, &W) && col_max(W) > 0.0) {
            out->emitted += W.c[0] + W.c[1] + W.c[2];
            trace_light_ray(s, job->st, r, W, &g, out, sun);
        }
    }
    job->batch[b] = (light_sums){NULL, NULL, 0.0, sums.intercepts, sums.deposits, sums.emitted};
    progress_add(&job->prog, 1);
}

/* Solid angle of the cone from y that holds the sphere (c, radius): 4 pi from inside it. */
static double cone_solid_angle(vec3 c, double radius, vec3 y)
{
    double dist = v3_length(v3_sub(c, y));
    if (!(dist > radius * (1.0 + 1e-9)))
        return 4.0 * PI;
    return 2.0 * PI * (1.0 - sqrt(fmax(0.0, 1.0 - radius * radius / (dist * dist))));
}

/* The share of light l's rays that the first pass traces: its rays aim at light_box (the
 * non-empty voxels) where the paper's aim at the media's bounds, and a ray that misses
 * light_box crosses no non-empty voxel, so deposits nothing. The traced rays keep the
 * weight the paper's rays have (power / number of rays, over the area or solid angle aimed
 * at), so the count shrinks as that area or solid angle does: by the projected areas along
 * a sun's direction, by the solid angles seen from the centre of any other light
 * (docs/blasi.md, "Rays that cannot deposit"). */
static double light_share(const blasi_state *st, const light *l)
{
    if (l->kind == LIGHT_DISTANT) {
        double a = box_projected_area(st->bounds, l->direction);
        return a > 0.0 ? box_projected_area(st->light_box, l->direction) / a : 1.0;
    }
    vec3 cb = v3_scale(v3_add(st->bounds.lo, st->bounds.hi), 0.5);
    double rb = 0.5 * v3_length(v3_sub(st->bounds.hi, st->bounds.lo));
    return cone_solid_angle(st->centre, st->radius, l->position) / cone_solid_angle(cb, rb, l->position);
}

/* The order of magnitude of the power a ray of light l starts with (light_ray's *W, largest
 * channel), n the rays it traces: the fixed-point unit's reference. An upper bound up to
 * a spot's profile (the projected area is at most half the box's surface, a sun disk's
 * radiance factor at most 2, cos_y at most 1, the solid angle at most 4 pi). */
static double ray_power_ref(const blasi_state *st, const light *l, uint64_t n)
{
    double g = 4.0 * PI; /* point and spot: the intensity over the directions */
    if (l->kind == LIGHT_DISTANT) {
        vec3 e = v3_sub(st->light_box.hi, st->light_box.lo);
        g = 2.0 * (e.x * e.y + e.y * e.z + e.x * e.z);
    } else if (l->kind == LIGHT_SPHERE) {
        g = 16.0 * PI * PI * l->radius * l->radius;
    } else if (l->kind == LIGHT_DISK) {
        g = 4.0 * PI * PI * l->radius * l->radius;
    }
    return col_max(l->L) * g / (double)n;
}

static brume_status first_pass(const brume_scene *s, blasi_state *st)
{
    uint64_t nominal = s->nlights > 0 && st->nm > 0 && st->light_box.lo.x <= st->light_box.hi.x
                           ? blasi_opts(s)->light_rays
                           : 0;
    if (nominal == 0)
        return BRUME_OK;
    /* light l's nominal rays: [l N / nl, (l + 1) N / nl) of the N; those it traces: its
     * share of them (light_share), at least one when it has any */
    uint64_t *first = malloc(((size_t)s->nlights + 1) * sizeof *first);
    if (!first)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: blasi: out of memory for the light pass", s->source);
    uint64_t nl = (uint64_t)s->nlights;
    first[0] = 0;
    for (uint64_t l = 0; l < nl; l++) {
        uint64_t n = (l + 1) * nominal / nl - l * nominal / nl;
        double k = fmin(1.0, light_share(st, &s->lights[l])) * (double)n;
        uint64_t m = n > 0 && k > 0.0 ? (uint64_t)llround(k) : 0;
        first[l + 1] = first[l] + (n > 0 && k > 0.0 && m == 0 ? 1 : m);
    }
    uint64_t nrays = first[nl];
    /* the work before it starts (render.max_work, issue 36): rays x the steps of one across the
     * media's box (a step of blasi.step, or a voxel of the finest medium) */
    double steps = 0.0;
    for (int m = 0; m < st->nm; m++)
        steps = fmax(steps, (double)st->m[m].n[0] + st->m[m].n[1] + st->m[m].n[2]);
    if (st->step > 0.0)
        steps = 2.0 * st->radius / st->step;
    double work = (double)nrays * (steps + 1.0);
    if (work > s->max_work) {
        free(first);
        return err_set(BRUME_ERROR_RANGE,
                       "%s: blasi: the light pass's %llu rays of about %.3g steps each are %.3g units of work, over "
                       "render.max_work (%.3g): raise blasi.step or lower blasi.light_rays (or raise render.max_work)",
                       s->source, (unsigned long long)nrays, steps, work, s->max_work);
    }
    pass1_job job = {.s = s, .st = st, .nrays = nrays, .nbatch = (nrays + BLASI_BATCH - 1) / BLASI_BATCH,
                     .first = first};
    /* the unit: 2^-40 of the largest reference power per ray over the lights, a power of two */
    double W_ref = 0.0;
    for (uint64_t l = 0; l < nl; l++)
        if (first[l + 1] > first[l])
            W_ref = fmax(W_ref, ray_power_ref(st, &s->lights[l], first[l + 1] - first[l]));
    int e = 0;
    (void)frexp(W_ref > 0.0 && isfinite(W_ref) ? W_ref : 1.0, &e);
    job.per_unit = ldexp(1.0, 40 - (e < -900 ? -900 : e > 900 ? 900 : e));
    /* sums for the non-empty voxels only (a sixth of picture 1's: fewer pages to touch,
     * each a page fault, and to merge), one copy per thread, as many threads as the memory
     * limit leaves room for (the result is the same with any number) */
    uint32_t *slot = malloc(st->nvox * sizeof *slot);
    if (slot)
        for (size_t v = 0; v < st->nvox; v++)
            slot[v] = st->rho[v] != 0.0f ? (uint32_t)job.nocc++ : UINT32_MAX;
    job.slot = slot;
    const size_t copy = 3 * job.nocc * sizeof(fixsum), left = s->max_memory > s->memory_used ? s->max_memory - s->memory_used : 0;
    size_t threads = (size_t)(s->settings.threads > 0 ? s->settings.threads : pool_default_threads());
    threads = threads < job.nbatch ? threads : (size_t)job.nbatch;
    if (copy > left) { /* not even one thread's sums fit under the limit */
        free(slot);
        free(first);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY,
                       "%s: blasi: the light pass needs %.1f MB for its sums, over what render.max_memory_mb leaves "
                       "(%.1f MB)",
                       s->source, (double)copy / 1048576.0, (double)left / 1048576.0);
    }
    threads = threads * copy <= left ? threads : left / copy;
    job.P = calloc(threads * 3 * job.nocc + 1, sizeof *job.P);
    job.batch = calloc((size_t)job.nbatch, sizeof *job.batch);
    if (!slot || !job.P || !job.batch) {
        free(slot);
        free(job.P);
        free(job.batch);
        free(first);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: blasi: out of memory for the light pass", s->source);
    }
    cancel_poll_init(&job.cancel, &s->settings);
    progress_begin(&job.prog, "light pass", (size_t)job.nbatch, s->settings.progress, s->settings.progress_interval);
    pool_run((int)threads, (size_t)job.nbatch, pass1_batch, &job);
    progress_end(&job.prog, !cancel_poll_cancelled(&job.cancel));
    if (cancel_poll_cancelled(&job.cancel)) {
        cancel_poll_finish(&job.cancel);
        free(slot);
        free(job.P);
        free(job.batch);
        free(first);
        return err_set(BRUME_ERROR_CANCELLED, "%s: blasi: the light pass was cancelled", s->source);
    }
    cancel_poll_finish(&job.cancel);
    for (uint64_t k = 0; k < job.nbatch; k++) { /* batch order: the emitted power's sum is the same bits too */
        st->stats.interceptions += job.batch[k].intercepts;
        st->stats.deposits += job.batch[k].deposits;
        st->stats.emitted_power += job.batch[k].emitted / 3.0;
    }
    for (size_t t = 1; t < threads; t++) /* the threads' sums into the first copy */
        for (size_t i = 0; i < 3 * job.nocc; i++)
            fixsum_merge(&job.P[i], job.P[t * 3 * job.nocc + i]);
    free(job.batch);
    free(first);
    /* power -> source per unit length, S = P / (4 pi |V|) */
    double total = 0.0;
    for (int m = 0; m < st->nm; m++) {
        const blasi_medium *bm = &st->m[m];
        double norm = 1.0 / (4.0 * PI * bm->volume);
        for (size_t v = bm->offset; v < bm->offset + bm->nvox; v++)
            for (int c = 0; slot[v] != UINT32_MAX && c < 3; c++) { /* S stays 0 in empty voxels */
                double p = fixsum_value(job.P[3 * (size_t)slot[v] + (size_t)c]) / job.per_unit;
                total += p;
                st->S[3 * v + (size_t)c] = (float)(p * norm);
            }
    }
    free(job.P);
    free(slot);
    st->stats.light_rays = nominal;
    st->stats.traced_rays = nrays;
    st->stats.stored_power = total / 3.0;
    return BRUME_OK;
}

/* ---- setting up --------------------------------------------------------------------------- */

/* Splits a medium's phase function into the paper's isotropic fraction r and directional
 * lobe (Eq. 22 with k = 0; docs/blasi.md "Phase functions"). */
static void split_phase(const phase *ph, double *r, const phase **dir)
{
    *r = BLASI_R_DEFAULT;
    *dir = ph;
    switch (phase_get_kind(ph)) {
    case PHASE_ISOTROPIC: *r = 1.0; return;
    case PHASE_SCHLICK: *r = 0.0; return;
    case PHASE_MIXTURE:
        if (phase_lobe_count(ph) == 2) {
            double w0, w1;
            const phase *a = phase_lobe(ph, 0, &w0), *b = phase_lobe(ph, 1, &w1);
            int iso = -1; /* the lobe treated as isotropic */
            if (phase_get_kind(a) == PHASE_ISOTROPIC)
                iso = 0;
            else if (phase_get_kind(b) == PHASE_ISOTROPIC)
                iso = 1;
            else if (phase_get_kind(a) == PHASE_SCHLICK && phase_get_kind(b) == PHASE_SCHLICK)
                iso = phase_schlick_k(a) <= phase_schlick_k(b) ? 0 : 1;
            if (iso >= 0) {
                *r = iso == 0 ? w0 : w1;
                *dir = iso == 0 ? b : a;
            }
        }
        return;
    default: return;
    }
}

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 0x100000001b3ULL;
    return h;
}

static uint64_t fnv_d(uint64_t h, double x) { return fnv(h, &x, sizeof x); }
static uint64_t fnv_col(uint64_t h, color c)
{
    for (int i = 0; i < 3; i++)
        h = fnv_d(h, c.c[i]);
    return h;
}

/* A hash of everything the first pass depends on except the ray count and the seed:
 * grids, coefficients, the split of the phase functions, lights, surfaces and options. */
static uint64_t scene_hash(const brume_scene *s, const blasi_state *st)
{
    uint64_t h = 0xcbf29ce484222325ULL;
    h = fnv(h, &st->nm, sizeof st->nm);
    for (int m = 0; m < st->nm; m++) {
        const blasi_medium *bm = &st->m[m];
        h = fnv(h, bm->n, sizeof bm->n);
        for (int i = 0; i < 12; i++)
            h = fnv_d(h, bm->w2v.m[i]);
        h = fnv(h, st->rho + bm->offset, bm->nvox * sizeof(float));
        h = fnv_col(fnv_col(fnv_col(h, bm->md->sigma_a), bm->md->sigma_s), bm->md->Le);
        h = fnv_d(h, bm->r);
        for (int i = 0; i <= 8; i++)
            h = fnv_d(h, phase_eval(bm->dir, -1.0 + 0.25 * i));
    }
    for (int i = 0; i < s->nlights; i++) {
        const light *l = &s->lights[i];
        int k = (int)l->kind;
        h = fnv(h, &k, sizeof k);
        h = fnv_d(fnv_d(fnv_d(h, l->direction.x), l->direction.y), l->direction.z);
        h = fnv_d(fnv_d(fnv_d(h, l->position.x), l->position.y), l->position.z);
        h = fnv_col(h, l->L);
        h = fnv_d(fnv_d(fnv_d(fnv_d(h, l->radius), l->angular_radius), l->cos_inner), l->cos_outer);
        h = fnv(h, &l->profile_n, sizeof l->profile_n);
        for (int p = 0; p < l->profile_n; p++)
            h = fnv_d(fnv_d(h, l->profile_angle[p]), l->profile_value[p]);
    }
    long ns = s->surf ? surfaces_count(s->surf) : 0, nt = s->surf ? surfaces_triangle_count(s->surf) : 0;
    h = fnv(fnv(h, &ns, sizeof ns), &nt, sizeof nt);
    int ex = (int)st->exit, src = blasi_opts(s)->sources;
    h = fnv(fnv(h, &ex, sizeof ex), &src, sizeof src);
    return fnv_d(fnv_d(h, st->step), st->threshold);
}

/* The saved first pass (docs/blasi.md, "Light files"), little-endian:
 *   8 bytes "BRUMEBL1", u32 version (1), u32 number of media, u64 scene hash,
 *   per medium: u32 nx, ny, nz, u32 0; then per medium nx ny nz x 3 float32: the source
 *   S (RGB radiance per unit length, world units), x fastest. */
static bool host_is_little_endian(void)
{
    uint32_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 1;
}

static brume_status save_light(const char *path, const brume_scene *s, const blasi_state *st)
{
    if (!host_is_little_endian())
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: blasi.save_light: light files are little-endian", path);
    atomic_file f;
    brume_status rc = atomic_open(&f, path);
    if (rc != BRUME_OK)
        return err_prefix("blasi.save_light");
    uint32_t head[2] = {BLASI_FILE_VERSION, (uint32_t)st->nm};
    uint64_t hash = scene_hash(s, st);
    bool ok = fwrite(BLASI_FILE_MAGIC, 1, 8, f.fp) == 8 && fwrite(head, sizeof head, 1, f.fp) == 1 &&
              fwrite(&hash, sizeof hash, 1, f.fp) == 1;
    for (int m = 0; ok && m < st->nm; m++) {
        uint32_t dims[4] = {(uint32_t)st->m[m].n[0], (uint32_t)st->m[m].n[1], (uint32_t)st->m[m].n[2], 0};
        ok = fwrite(dims, sizeof dims, 1, f.fp) == 1;
    }
    if (ok && st->nvox > 0)
        ok = fwrite(st->S, sizeof(float) * 3, st->nvox, f.fp) == st->nvox;
    if (!ok) {
        atomic_abort(&f);
        return err_set(BRUME_ERROR_IO, "%s: blasi.save_light: write error: %s", path, strerror(errno));
    }
    if (atomic_commit(&f) != BRUME_OK)
        return err_prefix("blasi.save_light");
    return BRUME_OK;
}

static brume_status load_light(const char *path, const brume_scene *s, blasi_state *st)
{
    if (!host_is_little_endian())
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: blasi.load_light: light files are little-endian", path);
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return err_set(BRUME_ERROR_IO, "%s: blasi.load_light: cannot open: %s", path, strerror(errno));
    char magic[8];
    uint32_t head[2];
    uint64_t hash;
    brume_status rc = BRUME_OK;
    if (fread(magic, 1, 8, fp) != 8 || memcmp(magic, BLASI_FILE_MAGIC, 8) != 0 || fread(head, sizeof head, 1, fp) != 1 ||
        fread(&hash, sizeof hash, 1, fp) != 1) {
        rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: not a brume light file", path);
    } else if (head[0] != BLASI_FILE_VERSION) {
        rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: version %u, this brume reads %u", path, head[0],
                     BLASI_FILE_VERSION);
    } else if (head[1] != (uint32_t)st->nm) {
        rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: made for %u media, the scene has %d", path, head[1],
                     st->nm);
    }
    for (int m = 0; rc == BRUME_OK && m < st->nm; m++) {
        uint32_t dims[4];
        if (fread(dims, sizeof dims, 1, fp) != 1)
            rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: truncated header", path);
        else if (dims[0] != (uint32_t)st->m[m].n[0] || dims[1] != (uint32_t)st->m[m].n[1] ||
                 dims[2] != (uint32_t)st->m[m].n[2])
            rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: medium %d is %u x %u x %u voxels, the scene's %d x %d x %d",
                         path, m, dims[0], dims[1], dims[2], st->m[m].n[0], st->m[m].n[1], st->m[m].n[2]);
    }
    uint64_t want = scene_hash(s, st);
    if (rc == BRUME_OK && hash != want)
        rc = err_set(BRUME_ERROR_PARSE,
                     "%s: blasi.load_light: made for another scene or other first-pass options (hash %016llx, this "
                     "scene %016llx)",
                     path, (unsigned long long)hash, (unsigned long long)want);
    if (rc == BRUME_OK && st->nvox > 0 && fread(st->S, sizeof(float) * 3, st->nvox, fp) != st->nvox)
        rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: truncated data", path);
    if (rc == BRUME_OK && fgetc(fp) != EOF)
        rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: trailing bytes after the data", path);
    for (size_t i = 0; rc == BRUME_OK && i < 3 * st->nvox; i++)
        if (!(isfinite(st->S[i]) && st->S[i] >= 0.0f))
            rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: value %zu is negative or not finite", path, i);
    fclose(fp);
    return rc;
}

void blasi_finish(blasi_state *st)
{
    if (!st)
        return;
    for (int m = 0; m < st->nm; m++) {
        phase_release(st->m[m].dir_owned);
        density_release(st->m[m].vox);
        free(st->m[m].occ);
    }
    free(st->rho);
    free(st->S);
    free(st);
}

brume_status blasi_prepare(const brume_scene *s, blasi_state **out)
{
    *out = NULL;
    double t0 = progress_now();
    const blasi_options *o0 = scene_options(s, METHOD_OPTIONS_BLASI);
    /* before any work: the light file must not replace the scene, one of its inputs or a device */
    if (o0->save_light[0] && io_output_check("blasi.save_light", o0->save_light,
                                             s->source[0] != '<' ? s->source : NULL, &s->inputs) != BRUME_OK)
        return err_status();
    blasi_state *st = calloc(1, sizeof *st);
    if (!st)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: blasi: out of memory", s->source);
    const blasi_options *o = scene_options(s, METHOD_OPTIONS_BLASI);
    const stam_params *sp = scene_options(s, METHOD_OPTIONS_STAM);
    st->nm = s->nmedia;
    st->step = o->step;
    st->threshold = o->threshold;
    st->exit = o->exit_deposit;
    st->view = o->view_attenuation;
    st->gather_printed = o->gather == BLASI_GATHER_PRINTED;
    for (int i = 0; i < s->nlights; i++) {
        const light *l = &s->lights[i];
        st->area_lights |= l->kind == LIGHT_SPHERE || l->kind == LIGHT_DISK;
        st->sun_disks |= l->kind == LIGHT_DISTANT && l->angular_radius > 0.0;
    }
    st->bounds = box3_empty();
    brume_status rc = BRUME_OK;
    randfield *q = NULL; /* Stam's Q, for blob fields voxelized with their perturbation */
    for (int m = 0; m < st->nm && rc == BRUME_OK; m++) {
        const medium *md = &s->media[m];
        blasi_medium *bm = &st->m[m];
        const blob_field *bf = density_get_blobs(md->rho);
        if (bf && o->voxels <= 0) {
            /* a blob field has no voxels of its own; a silent coarse grid would not be Stam's field */
            rc = err_set(BRUME_ERROR_UNSUPPORTED,
                         "%s: media[%d]%s%s: method blasi renders voxel grids and this medium is a blob field: give "
                         "blasi.voxels=N (e.g. --set blasi.voxels=128) to render one realization of it (stam.eps) "
                         "on N cells along its longest axis, or use --method stam, path or single",
                         s->source, m, md->name[0] ? " " : "", md->name);
            break;
        }
        if (bf) {
            if (!q && sp->eps > 0.0) {
                randfield_params rp;
                stam_randfield_params(sp, s->time, stam_blob_extent(s), &rp);
                if (!(q = randfield_new(&rp))) {
                    rc = err_prefix("%s: blasi.voxels", s->source);
                    break;
                }
            }
            char who[600];
            snprintf(who, sizeof who, "%s: media[%d]: blasi.voxels", s->source, m);
            if (!(bm->vox = blob_field_grid(bf, o->voxels, q, sp->eps, sp->eta, who))) {
                rc = err_status();
                break;
            }
        }
        const density *rho = bm->vox ? bm->vox : md->rho;
        density_info info;
        density_get_info(rho, &info);
        bm->md = md;
        memcpy(bm->n, info.n, sizeof bm->n);
        bm->nvox = (size_t)info.n[0] * (size_t)info.n[1] * (size_t)info.n[2];
        bm->offset = st->nvox;
        if (st->nvox + bm->nvox > BLASI_MAX_VOXELS) {
            rc = err_set(BRUME_ERROR_UNSUPPORTED,
                         "%s: media[%d] '%s': %d x %d x %d voxels; blasi keeps at most %u voxels over all media "
                         "(use a coarser grid)",
                         s->source, m, md->name, info.n[0], info.n[1], info.n[2], BLASI_MAX_VOXELS);
            break;
        }
        st->nvox += bm->nvox;
        bm->volume = fabs(affine3_det(&info.voxel_to_world));
        bm->v2w = info.voxel_to_world;
        {   /* the voxel's edges in world space, for its surface area */
            vec3 c0 = affine3_apply(&bm->v2w, v3(0, 0, 0)), e[3];
            for (int a = 0; a < 3; a++)
                e[a] = v3_sub(affine3_apply(&bm->v2w, v3(a == 0, a == 1, a == 2)), c0);
            double area = 2.0 * (v3_length(v3_cross(e[0], e[1])) + v3_length(v3_cross(e[1], e[2])) +
                                 v3_length(v3_cross(e[2], e[0])));
            bm->chord = area > 0.0 ? 4.0 * bm->volume / area : 0.0;
        }
        if (!affine3_invert(&info.voxel_to_world, &bm->w2v) || !(bm->volume > 0.0)) {
            rc = err_set(BRUME_ERROR_RANGE, "%s: media[%d] '%s': singular grid placement", s->source, m, md->name);
            break;
        }
        st->bounds = (box3){v3_min(st->bounds.lo, info.bounds.lo), v3_max(st->bounds.hi, info.bounds.hi)};
        bm->sigma_bar = col_avg(md->sigma_s);
        bm->sigma_t = col_add(md->sigma_a, md->sigma_s);
        bm->kappa = st->view == BLASI_VIEW_EXTINCTION ? bm->sigma_t : md->sigma_a;
        bm->emit = col_mul(md->sigma_a, md->Le);
        bm->emits = !col_is_black(bm->emit);
        bm->view_grey = col_is_grey(bm->kappa) && col_is_grey(bm->sigma_t);
        split_phase(md->ph, &bm->r, &bm->dir);
        if (!isnan(o->r))
            bm->r = o->r;
        if (!isnan(o->kprime)) {
            bm->dir_owned = phase_new_schlick(o->kprime);
            if (!bm->dir_owned)
                rc = err_prefix("%s: blasi.kprime", s->source);
            bm->dir = bm->dir_owned;
        }
    }
    if (rc == BRUME_OK && st->step > 0.0 &&
        !(v3_length(v3_sub(st->bounds.hi, st->bounds.lo)) / st->step <= BLASI_MAX_STEPS))
        rc = err_set(BRUME_ERROR_RANGE,
                     "%s: blasi.step: %g is more than %.0f steps across the media (%g wide); use a longer step or "
                     "0 (voxel by voxel)",
                     s->source, st->step, BLASI_MAX_STEPS, v3_length(v3_sub(st->bounds.hi, st->bounds.lo)));
    randfield_release(q);
    if (rc == BRUME_OK && st->nvox > 0) {
        st->rho = malloc(st->nvox * sizeof *st->rho);
        st->S = calloc(st->nvox * 3, sizeof *st->S);
        if (!st->rho || !st->S)
            rc = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: blasi: out of memory for %zu voxels", s->source, st->nvox);
    }
    for (int m = 0; m < st->nm && rc == BRUME_OK; m++) {
        blasi_medium *bm = &st->m[m];
        size_t nblocks = 1;
        for (int a = 0; a < 3; a++) {
            bm->bn[a] = (bm->n[a] + BLASI_BLOCK - 1) / BLASI_BLOCK;
            nblocks *= (size_t)bm->bn[a];
        }
        bm->skip = bm->n[0] + bm->n[1] + bm->n[2] > BLASI_SKIP_CELLS;
        bm->occ = calloc(nblocks, 1);
        if (!bm->occ) {
            rc = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: blasi: out of memory for %zu voxels", s->source, st->nvox);
            break;
        }
        float *dst = st->rho + bm->offset;
        bool any = false; /* occ_lo, occ_hi stay 0 (calloc) for an empty grid */
        for (int k = 0; k < bm->n[2]; k++)
            for (int j = 0; j < bm->n[1]; j++)
                for (int i = 0; i < bm->n[0]; i++) {
                    float rho = (float)density_voxel(bm->vox ? bm->vox : bm->md->rho, i, j, k);
                    *dst++ = rho;
                    if (rho != 0.0f) {
                        const int c[3] = {i, j, k};
                        for (int a = 0; a < 3; a++) {
                            bm->occ_lo[a] = !any || c[a] < bm->occ_lo[a] ? c[a] : bm->occ_lo[a];
                            bm->occ_hi[a] = !any || c[a] + 1 > bm->occ_hi[a] ? c[a] + 1 : bm->occ_hi[a];
                        }
                        for (int sl = 0; sl < BLASI_SLABS; sl++) { /* the voxel's extent along n */
                            const int *n = blasi_slab_n[sl];
                            int lo = 0, hi = 0;
                            for (int a = 0; a < 3; a++) {
                                lo += n[a] * c[a] + (n[a] < 0 ? n[a] : 0);
                                hi += n[a] * c[a] + (n[a] > 0 ? n[a] : 0);
                            }
                            bm->slab_lo[sl] = !any || lo < bm->slab_lo[sl] ? lo : bm->slab_lo[sl];
                            bm->slab_hi[sl] = !any || hi > bm->slab_hi[sl] ? hi : bm->slab_hi[sl];
                        }
                        any = true;
                    }
                    if (rho != 0.0f)
                        bm->occ[(size_t)(i / BLASI_BLOCK) +
                                (size_t)bm->bn[0] * ((size_t)(j / BLASI_BLOCK) + (size_t)bm->bn[1] * (size_t)(k / BLASI_BLOCK))] = 1;
                }
        for (int sl = 0; sl < BLASI_SLABS; sl++) { /* a millionth of a voxel wider: far more than
                                                     the rounding of a ray's clipping to them */
            bm->slab_lo[sl] -= 1e-6;
            bm->slab_hi[sl] += 1e-6;
        }
    }
    st->light_box = box3_empty();
    for (int m = 0; m < st->nm && rc == BRUME_OK; m++) { /* the world box of each medium's non-empty voxels */
        blasi_medium *bm = &st->m[m];
        bm->occ_c = v3(0.0, 0.0, 0.0);
        bm->occ_e = v3(-1.0, -1.0, -1.0); /* every line misses */
        if (bm->occ_hi[0] == 0)
            continue; /* no non-empty voxel */
        box3 b = affine3_apply_box(&bm->v2w, (box3){v3(bm->occ_lo[0], bm->occ_lo[1], bm->occ_lo[2]),
                                                    v3(bm->occ_hi[0], bm->occ_hi[1], bm->occ_hi[2])});
        st->light_box = (box3){v3_min(st->light_box.lo, b.lo), v3_max(st->light_box.hi, b.hi)};
        /* enlarged by 1e-9 of its size and place: far more than the rounding of the corners
         * and of the walk's own clipping in voxel space */
        bm->occ_c = v3_scale(v3_add(b.lo, b.hi), 0.5);
        vec3 e = v3_scale(v3_sub(b.hi, b.lo), 0.5);
        double pad = 1e-9 * (v3_length(e) + v3_length(bm->occ_c));
        bm->occ_e = v3(e.x + pad, e.y + pad, e.z + pad);
    }
    if (st->light_box.lo.x <= st->light_box.hi.x) {
        /* within the media's bounds (the corners' rounding must not take it outside) */
        st->light_box = (box3){v3_max(st->light_box.lo, st->bounds.lo), v3_min(st->light_box.hi, st->bounds.hi)};
        st->centre = v3_scale(v3_add(st->light_box.lo, st->light_box.hi), 0.5);
        st->radius = 0.5 * v3_length(v3_sub(st->light_box.hi, st->light_box.lo));
    }
    if (rc == BRUME_OK) {
        if (o->load_light[0]) {
            rc = load_light(o->load_light, s, st);
            st->stats.loaded = true;
            /* one medium: an empty voxel holds no source, as after a first pass run here (the
             * view walk passes over it): a file that says otherwise is read as if it did not */
            for (size_t v = 0; rc == BRUME_OK && st->nm == 1 && v < st->nvox; v++)
                if (st->rho[v] == 0.0f)
                    st->S[3 * v] = st->S[3 * v + 1] = st->S[3 * v + 2] = 0.0f;
        } else {
            rc = first_pass(s, st);
        }
    }
    if (rc == BRUME_OK && o->save_light[0])
        rc = save_light(o->save_light, s, st);
    if (rc != BRUME_OK) {
        blasi_finish(st);
        return rc;
    }
    st->stats.light_seconds = progress_now() - t0;
    *out = st;
    return BRUME_OK;
}

void blasi_get_stats(const blasi_state *st, blasi_stats *out) { *out = st->stats; }

/* ---- second pass ------------------------------------------------------------------------- */

/* exp(-kappa delta) per channel over [0, tmax] along r: the view attenuation of a segment. */
static color view_attenuation(const blasi_state *st, ray r, double tmax)
{
    color A = col(1.0);
    walk wk;
    piece pc;
    walk_begin(&wk, st, r, tmax);
    while (walk_next(&wk, st, &pc)) {
        double dl = pc.t1 - pc.t0;
        for (int i = 0; i < pc.n; i++) {
            double rho = (double)st->rho[pc.v[i]];
            for (int c = 0; c < 3; c++)
                A.c[c] *= exp(-st->m[pc.m[i]].kappa.c[c] * rho * dl);
        }
    }
    return A;
}

/* The extinction optical depth of the last camera ray blasi_Li walked to its end, per
 * thread: the render asks for the transmittance of the same ray right after (the pixel's
 * alpha), and gets the same sum without a second walk. */
typedef struct tau_cache {
    const blasi_state *st;
    vec3 o, d;
    color tau;
} tau_cache;
static _Thread_local tau_cache last_tau;

static inline bool v3_equal(vec3 a, vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/* Radiance leaving a surface towards -r.d: emission and direct light from every light,
 * through the media with the view attenuation (the paper has no surfaces; docs/blasi.md). */
static color shade_surface(const brume_scene *s, const blasi_state *st, ray r, const surface_hit *h, rng *g)
{
    vec3 wo = v3_neg(r.d);
    color L = surface_emission(h, wo);
    if (material_is_black(h->mat))
        return L;
    vec3 n = v3_dot(h->ng, r.d) < 0.0 ? h->ng : v3_neg(h->ng);
    vec3 p = surface_offset(h, n);
    for (int i = 0; i < s->nlights; i++) {
        light_sample ls;
        double u1 = rng_next(g), u2 = rng_next(g);
        if (!light_sample_at(&s->lights[i], p, u1, u2, &ls) || !(ls.pdf > 0.0))
            continue;
        double cosn = v3_dot(ls.wi, n);
        if (cosn <= 0.0 || surfaces_occluded(s->surf, p, ls.wi, 0.0, ls.dist * (1.0 - 1e-7), r.time))
            continue;
        color f = col_scale(material_eval(h->mat, n, wo, ls.wi), cosn / ls.pdf);
        L = col_add(L, col_mul(col_mul(ls.Li, f), view_attenuation(st, (ray){p, ls.wi, r.time}, ls.dist)));
    }
    return L;
}

/* What a view ray has gathered so far: radiance L, view attenuation A, and the extinction
 * optical depth tau_t (the transmittance behind the pixel's alpha). */
typedef struct view_sums {
    color L, A, tau_t;
} view_sums;

/* One voxel of one medium crossed over length dl (the second pass's loop body): its source,
 * attenuated by A and integrated over the voxel, and A attenuated. False when A fell under
 * the threshold ("While A > THRESHOLD"). */
static inline __attribute__((always_inline)) bool view_voxel(const blasi_state *st, const blasi_medium *bm, size_t v, double dl, view_sums *s)
{
    double rho = (double)st->rho[v];
    const float *sv = st->S + 3 * v;
    color S, kap;
#pragma GCC unroll 3
    for (int c = 0; c < BRUME_NSAMPLES; c++) {
        s->tau_t.c[c] += bm->sigma_t.c[c] * (rho * dl); /* as blasi_transmittance sums it */
        S.c[c] = (double)sv[c] + bm->emit.c[c] * rho;
        kap.c[c] = bm->kappa.c[c] * rho;
    }
    if (st->gather_printed) { /* Blasi's second pass as printed: "L_P = L_P + A L_V", then attenuate */
        s->L = col_add(s->L, col_scale(col_mul(s->A, S), bm->chord));
#pragma GCC unroll 3
        for (int c = 0; c < BRUME_NSAMPLES; c++)
            s->A.c[c] *= exp(-kap.c[c] * dl);
        return col_max(s->A) > st->threshold;
    }
    if (kap.c[0] == 0.0 && kap.c[1] == 0.0 && kap.c[2] == 0.0) {
        if (!col_is_black(S)) /* a source without attenuation (e.g. alpha = 0, paper variant) */
            s->L = col_add(s->L, col_scale(col_mul(s->A, S), dl));
        return true;
    }
    bool grey = kap.c[0] == kap.c[1] && kap.c[1] == kap.c[2];
    double T = 0.0, f = 0.0;
#pragma GCC unroll 3
    for (int c = 0; c < BRUME_NSAMPLES; c++) {
        if (c == 0 || !grey) /* the integral of exp(-kappa s) over the voxel is dl f */
            voxel_exp(kap.c[c] * dl, &T, &f);
        s->L.c[c] += s->A.c[c] * S.c[c] * dl * f;
        s->A.c[c] *= T;
    }
    return col_max(s->A) > st->threshold;
}

/* The view walk over [0, t_end) through one small grid (one medium, no block skipping:
 * the usual case). The same sums as view_walk, with the walk's state in locals the loop
 * keeps in registers; for a grey medium (kappa and sigma_t the same in every channel) A
 * and tau_t are one number each, as all their channels are equal. False when the
 * threshold stopped the ray. */
static inline __attribute__((always_inline)) bool view_walk_one_as(const blasi_state *st, ray r, double t_end,
                                                                    view_sums *out, bool grey, bool emits)
{
    const blasi_medium *bm = &st->m[0];
    grid_dda g0;
    if (!walk_begin_one(bm, r, t_end, &g0, true))
        return true;
    grid_dda g = g0; /* never escapes: the compiler keeps it in registers */
    const float *rho = st->rho;
    const size_t nx = (size_t)bm->n[0], ny = (size_t)bm->n[1];
    grid_dda_step c;
    bool on = true;
    if (!grey) {
        view_sums s = *out;
        while (grid_dda_next(&g, &c)) {
            size_t v = (size_t)c.i + nx * ((size_t)c.j + ny * (size_t)c.k);
            if (rho[v] == 0.0f) /* empty: no density, no source */
                continue;
            if (!(on = view_voxel(st, bm, v, c.t1 - c.t0, &s)))
                break;
        }
        *out = s;
        return on;
    }
    /* grey: view_voxel with A and tau_t one number each, and without its branches: an empty
     * voxel (rho = 0, S = 0: blasi_prepare keeps no source there) adds exactly 0 to L and
     * tau_t and multiplies A by exactly 1 (voxel_exp(0) gives T = f = 1), as does the
     * attenuation-free case of view_voxel with f = 1, so the sums are the same bit for bit,
     * without the mispredicted branch on each voxel's emptiness */
    const double kappa = bm->kappa.c[0], sigma_t = bm->sigma_t.c[0], threshold = st->threshold;
    const color emit = bm->emit;
    double A = out->A.c[0], tau_t = out->tau_t.c[0];
    color L = out->L;
    while (grid_dda_next(&g, &c)) {
        size_t v = (size_t)c.i + nx * ((size_t)c.j + ny * (size_t)c.k);
        const double rh = (double)rho[v], dl = c.t1 - c.t0, kap = kappa * rh;
        const float *sv = st->S + 3 * v;
        color S; /* without emission, the stored source alone (adding 0 changes no sum) */
#pragma GCC unroll 3
        for (int k = 0; k < BRUME_NSAMPLES; k++)
            S.c[k] = emits ? (double)sv[k] + emit.c[k] * rh : (double)sv[k];
        tau_t += sigma_t * (rh * dl);
        double T, f;
        voxel_exp(kap * dl, &T, &f);
#pragma GCC unroll 3
        for (int k = 0; k < BRUME_NSAMPLES; k++)
            L.c[k] += A * S.c[k] * dl * f;
        A *= T;
        if (!(A > threshold)) {
            on = false;
            break;
        }
    }
    out->L = L;
    out->A = col(A);
    out->tau_t = col(tau_t);
    return on;
}

static bool view_walk_one(const blasi_state *st, ray r, double t_end, view_sums *out)
{
    const blasi_medium *bm = &st->m[0];
    if (bm->view_grey && !st->gather_printed && col_is_grey(out->A) && col_is_grey(out->tau_t))
        return bm->emits ? view_walk_one_as(st, r, t_end, out, true, true)
                         : view_walk_one_as(st, r, t_end, out, true, false);
    return view_walk_one_as(st, r, t_end, out, false, true);
}

/* The view walk over [0, t_end) through any media: each piece's voxels summed. */
static bool view_walk(const blasi_state *st, ray r, double t_end, view_sums *out)
{
    walk wk;
    piece pc;
    walk_begin(&wk, st, r, t_end);
    while (walk_next(&wk, st, &pc)) {
        double dl = pc.t1 - pc.t0;
        if (pc.n == 1) {
            if (!view_voxel(st, &st->m[pc.m[0]], pc.v[0], dl, out))
                return false;
            continue;
        }
        color S = col(0.0), kap = col(0.0);
        for (int i = 0; i < pc.n; i++) {
            const blasi_medium *bm = &st->m[pc.m[i]];
            double rho = (double)st->rho[pc.v[i]];
            out->tau_t = col_madd(out->tau_t, bm->sigma_t, rho * dl);
            const float *sv = st->S + 3 * pc.v[i];
            for (int c = 0; c < 3; c++) {
                S.c[c] += (double)sv[c] + bm->emit.c[c] * rho;
                kap.c[c] += bm->kappa.c[c] * rho;
            }
        }
        if (kap.c[0] == 0.0 && kap.c[1] == 0.0 && kap.c[2] == 0.0) {
            if (!col_is_black(S))
                out->L = col_add(out->L, col_scale(col_mul(out->A, S), dl));
            continue;
        }
        bool grey = kap.c[0] == kap.c[1] && kap.c[1] == kap.c[2];
        double T = 0.0, f = 0.0;
        for (int c = 0; c < 3; c++) {
            if (c == 0 || !grey)
                voxel_exp(kap.c[c] * dl, &T, &f);
            out->L.c[c] += out->A.c[c] * S.c[c] * dl * f;
            out->A.c[c] *= T;
        }
        if (!(col_max(out->A) > st->threshold))
            return false;
    }
    return true;
}

color blasi_Li(const brume_scene *s, const blasi_state *st, ray r, rng *g, bool *hit_surface)
{
    last_tau.st = NULL; /* valid again only if this walk reaches the end of the ray */
    if (hit_surface)
        *hit_surface = false;
    /* what ends the walk: a surface, an area light, or nothing (the background) */
    double t_end = INFINITY;
    int hit_light = -1;
    color Le_light = col(0.0);
    for (int i = 0; st->area_lights && i < s->nlights; i++) {
        const light *l = &s->lights[i];
        double t, pdf;
        color c;
        if ((l->kind == LIGHT_SPHERE || l->kind == LIGHT_DISK) && light_hit(l, r.o, r.d, &t, &c, &pdf) && t < t_end) {
            t_end = t;
            hit_light = i;
            Le_light = c;
        }
    }
    surface_hit h;
    bool on_surface = s->surf && surfaces_intersect(s->surf, r, 0.0, t_end, &h);
    if (on_surface)
        t_end = h.t;
    if (hit_surface)
        *hit_surface = on_surface;

    color L = col(0.0), A = col(1.0), tau_t = col(0.0);
    const bool one = st->nm == 1 && !st->m[0].skip;
    /* most view rays miss the non-empty voxels of one grid: those are told here, without a
     * walk or its set-up */
    if (st->nm > 0 && !(one && line_misses_box(st->m[0].occ_c, st->m[0].occ_e, r.o, r.d))) {
        view_sums v = {L, A, tau_t};
        bool on = one ? view_walk_one(st, r, t_end, &v) : view_walk(st, r, t_end, &v);
        L = v.L;
        A = v.A;
        tau_t = v.tau_t;
        if (!on)
            return L;
    }
    if (isinf(t_end)) /* the whole ray walked: its transmittance is known */
        last_tau = (tau_cache){st, r.o, r.d, tau_t};
    if (on_surface)
        return col_add(L, col_mul(A, shade_surface(s, st, r, &h, g)));
    if (hit_light >= 0)
        return col_add(L, col_mul(A, Le_light));
    /* "add the attenuated radiance of the background", and any sun disk seen directly */
    color Lb = background_eval(&s->bg, r.d);
    for (int i = 0; st->sun_disks && i < s->nlights; i++) {
        const light *l = &s->lights[i];
        double t, pdf;
        color c;
        if (l->kind == LIGHT_DISTANT && light_hit(l, r.o, r.d, &t, &c, &pdf))
            Lb = col_add(Lb, c);
    }
    return col_add(L, col_mul(A, Lb));
}

color blasi_transmittance(const brume_scene *s, const blasi_state *st, ray r)
{
    (void)s;
    color tau = col(0.0);
    if (last_tau.st == st && v3_equal(last_tau.o, r.o) && v3_equal(last_tau.d, r.d)) {
        tau = last_tau.tau; /* the render asks right after blasi_Li walked this ray */
        goto done;
    }
    walk wk;
    piece pc;
    walk_begin(&wk, st, r, INFINITY);
    while (walk_next(&wk, st, &pc)) {
        double dl = pc.t1 - pc.t0;
        for (int i = 0; i < pc.n; i++)
            tau = col_madd(tau, st->m[pc.m[i]].sigma_t, (double)st->rho[pc.v[i]] * dl);
    }
done:
    if (tau.c[0] == tau.c[1] && tau.c[1] == tau.c[2]) /* grey; 0 for the rays that miss the media */
        return col(tau.c[0] == 0.0 ? 1.0 : exp(-tau.c[0]));
    return col_rgb(exp(-tau.c[0]), exp(-tau.c[1]), exp(-tau.c[2]));
}
