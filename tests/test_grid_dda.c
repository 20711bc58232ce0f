/* test_grid_dda.c - the grid's DDA (density/dda.h) against brute force: random rays, walks
 * restarted on a part, long rays within the stated tolerance, grazing and axis-parallel
 * rays, and the grid's placement in the world. */
#include "test.h"

#include <stdint.h>

#include "core/rng.h"
#include "density/density.h"

typedef struct hit {
    int i, j, k;
    double t0, t1;
} hit;

/* Every cell whose half-open box overlaps the ray on a positive length, with the same
 * crossing formula as the DDA, sorted by entry. */
static int brute_force(const int n[3], vec3 o, vec3 d, double tmin, double tmax, hit *out, int cap)
{
    const double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    int count = 0;
    for (int k = 0; k < n[2]; k++)
        for (int j = 0; j < n[1]; j++)
            for (int i = 0; i < n[0]; i++) {
                const int c[3] = {i, j, k};
                double t0 = tmin, t1 = tmax;
                /* the grid's own box clips too (the DDA's first step) */
                for (int a = 0; a < 3 && t0 < t1; a++) {
                    if (dd[a] == 0.0) {
                        if (!(oo[a] >= c[a] && oo[a] < c[a] + 1))
                            t1 = -INFINITY;
                        continue;
                    }
                    double inv = 1.0 / dd[a];
                    double ta = ((double)c[a] - oo[a]) * inv, tb = ((double)(c[a] + 1) - oo[a]) * inv;
                    double ga = (0.0 - oo[a]) * inv, gb = ((double)n[a] - oo[a]) * inv;
                    t0 = fmax(t0, fmax(fmin(ta, tb), fmin(ga, gb)));
                    t1 = fmin(t1, fmin(fmax(ta, tb), fmax(ga, gb)));
                }
                if (t1 > t0) {
                    if (count == cap)
                        TEST_FAIL("brute force: more than %d cells", cap);
                    out[count++] = (hit){i, j, k, t0, t1};
                }
            }
    for (int a = 1; a < count; a++) /* insertion sort by t0 */
        for (int b = a; b > 0 && out[b].t0 < out[b - 1].t0; b--) {
            hit s = out[b];
            out[b] = out[b - 1];
            out[b - 1] = s;
        }
    return count;
}

/* The DDA's steps against a reference list of cells (sorted by entry): the steps are
 * contiguous and increasing, and every cell's overlap length agrees within tol (a cell the
 * DDA omits or adds may be only that short), as does the total. dda.h states the bound:
 * accumulated plane crossings, a few ulps per cell crossed; tol is 1e-9 of the ray's
 * length in the grid, a million times that. */
static void check_steps(grid_dda *g, bool live, vec3 o, vec3 d, const hit *want, int nw);

static void check_against(const int n[3], vec3 o, vec3 d, double tmin, double tmax, const hit *want, int nw)
{
    grid_dda g;
    bool live = grid_dda_begin(&g, n, o, d, tmin, tmax);
    check_steps(&g, live, o, d, want, nw);
}

/* The steps of a begun (or restarted) walk g against the reference. */
static void check_steps(grid_dda *gp, bool live, vec3 o, vec3 d, const hit *want, int nw)
{
    static hit got[1 << 16];
    grid_dda_step s;
    int ng = 0;
    if (live)
        while (grid_dda_next(gp, &s)) {
            if (ng == (int)(sizeof got / sizeof got[0]))
                TEST_FAIL("DDA: more than %d cells", ng);
            if (ng > 0 && s.t0 != got[ng - 1].t1)
                TEST_FAIL("DDA steps not contiguous: %.17g after %.17g", s.t0, got[ng - 1].t1);
            if (!(s.t1 > s.t0))
                TEST_FAIL("DDA step of length %g", s.t1 - s.t0);
            got[ng++] = (hit){s.i, s.j, s.k, s.t0, s.t1};
        }
    double len = nw > 0 ? want[nw - 1].t1 - want[0].t0 : 0.0;
    if (isinf(len)) /* a ray along a face with tmax infinite: compare the cells only */
        len = 1.0;
    double tol = 1e-9 * (len > 0.0 ? len : 1.0), sum_w = 0.0, sum_g = 0.0;
    for (int a = 0; a < nw; a++)
        sum_w += isinf(want[a].t1) ? 0.0 : want[a].t1 - want[a].t0;
    for (int a = 0; a < ng; a++)
        sum_g += isinf(got[a].t1) ? 0.0 : got[a].t1 - got[a].t0;
    if (!(fabs(sum_w - sum_g) <= tol))
        TEST_FAIL("ray o=(%.17g %.17g %.17g) d=(%.17g %.17g %.17g): total length DDA %.17g, reference %.17g", o.x, o.y,
                  o.z, d.x, d.y, d.z, sum_g, sum_w);
    /* both lists are in t order: walk them together, matching cells */
    int a = 0, b = 0;
    while (a < nw || b < ng) {
        if (a < nw && b < ng && want[a].i == got[b].i && want[a].j == got[b].j && want[a].k == got[b].k) {
            double lw = want[a].t1 - want[a].t0, lg = got[b].t1 - got[b].t0;
            bool inf_ok = isinf(want[a].t1) && isinf(got[b].t1);
            if (!inf_ok && !(fabs(want[a].t0 - got[b].t0) <= tol && fabs(lw - lg) <= tol))
                TEST_FAIL("ray o=(%.17g %.17g %.17g) d=(%.17g %.17g %.17g) cell (%d %d %d): DDA [%.17g, %.17g], "
                          "reference [%.17g, %.17g] (tolerance %g)",
                          o.x, o.y, o.z, d.x, d.y, d.z, got[b].i, got[b].j, got[b].k, got[b].t0, got[b].t1, want[a].t0,
                          want[a].t1, tol);
            a++, b++;
        } else if (a < nw && want[a].t1 - want[a].t0 <= tol) {
            a++; /* a sliver the DDA may miss */
        } else if (b < ng && got[b].t1 - got[b].t0 <= tol) {
            b++; /* a sliver the reference may not have */
        } else {
            TEST_FAIL("ray o=(%.17g %.17g %.17g) d=(%.17g %.17g %.17g): DDA cell %d (%d %d %d) [%.17g, %.17g], "
                      "reference cell %d (%d %d %d) [%.17g, %.17g]",
                      o.x, o.y, o.z, d.x, d.y, d.z, b, b < ng ? got[b].i : -1, b < ng ? got[b].j : -1,
                      b < ng ? got[b].k : -1, b < ng ? got[b].t0 : NAN, b < ng ? got[b].t1 : NAN, a,
                      a < nw ? want[a].i : -1, a < nw ? want[a].j : -1, a < nw ? want[a].k : -1,
                      a < nw ? want[a].t0 : NAN, a < nw ? want[a].t1 : NAN);
        }
    }
}

static void check_dda(const int n[3], vec3 o, vec3 d, double tmin, double tmax)
{
    static hit want[4096];
    int nw = brute_force(n, o, d, tmin, tmax, want, 4096);
    check_against(n, o, d, tmin, tmax, want, nw);
}

/* Reference for grids too big to test every cell: every plane crossing inside the clipped
 * interval, each as (plane - o) / d from its integer plane, sorted; the cell of each
 * interval between two crossings is the one holding its midpoint. */
static int cmp_t(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

static int crossings_reference(const int n[3], vec3 o, vec3 d, hit *out, int cap)
{
    static double t[3 * 4200];
    const double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    double t0 = 0.0, t1 = INFINITY;
    for (int a = 0; a < 3; a++) {
        double ta = (0.0 - oo[a]) / dd[a], tb = ((double)n[a] - oo[a]) / dd[a];
        t0 = fmax(t0, fmin(ta, tb));
        t1 = fmin(t1, fmax(ta, tb));
    }
    if (!(t1 > t0))
        return 0;
    int nt = 0;
    t[nt++] = t0;
    for (int a = 0; a < 3; a++)
        for (int p = 1; p < n[a]; p++) {
            double x = ((double)p - oo[a]) / dd[a];
            if (x > t0 && x < t1)
                t[nt++] = x;
        }
    t[nt++] = t1;
    qsort(t, (size_t)nt, sizeof t[0], cmp_t);
    int count = 0;
    for (int q = 0; q + 1 < nt; q++) {
        if (!(t[q + 1] > t[q]))
            continue;
        double tm = 0.5 * (t[q] + t[q + 1]);
        int c[3];
        for (int a = 0; a < 3; a++) {
            c[a] = (int)floor(oo[a] + tm * dd[a]);
            c[a] = c[a] < 0 ? 0 : (c[a] >= n[a] ? n[a] - 1 : c[a]);
        }
        if (count == cap)
            TEST_FAIL("reference: more than %d cells", cap);
        out[count++] = (hit){c[0], c[1], c[2], t[q], t[q + 1]};
    }
    return count;
}

TEST(dda_random_rays)
{
    const int n[3] = {7, 5, 9};
    rng r = rng_make(42, 0, 0);
    for (int it = 0; it < 3000; it++) {
        /* half start inside, half outside; directions of both signs, some tiny components */
        vec3 o = v3(rng_next(&r) * 13 - 3, rng_next(&r) * 11 - 3, rng_next(&r) * 15 - 3);
        if (it % 2)
            o = v3(rng_next(&r) * n[0], rng_next(&r) * n[1], rng_next(&r) * n[2]);
        vec3 d = v3(rng_next(&r) - 0.5, rng_next(&r) - 0.5, rng_next(&r) - 0.5);
        if (it % 7 == 0)
            d.y *= 1e-9;
        double tmin = it % 3 == 0 ? rng_next(&r) * 3 : 0.0;
        double tmax = it % 5 == 0 ? tmin + rng_next(&r) * 10 : (double)INFINITY;
        check_dda(n, o, d, tmin, tmax);
    }
}

/* grid_dda_restart (an empty-space skipper's jump) walks exactly the cells of the part
 * [t0, t1] it is given, within the interval the walk was begun with: two parts of one ray
 * in turn, each against brute force on it. */
TEST(dda_restart_walks_the_part)
{
    const int n[3] = {7, 5, 9};
    rng r = rng_make(43, 0, 0);
    static hit want[4096];
    int restarted = 0;
    for (int it = 0; it < 2000; it++) {
        vec3 o = v3(rng_next(&r) * 13 - 3, rng_next(&r) * 11 - 3, rng_next(&r) * 15 - 3);
        vec3 d = v3(rng_next(&r) - 0.5, rng_next(&r) - 0.5, rng_next(&r) - 0.5);
        grid_dda g;
        if (!grid_dda_begin(&g, n, o, d, 0.0, INFINITY))
            continue;
        double u[4];
        for (int k = 0; k < 4; k++) /* the parts may start before or end after the grid */
            u[k] = g.t_in - 0.2 * (g.t_out - g.t_in) + 1.4 * (g.t_out - g.t_in) * rng_next(&r);
        for (int a = 1; a < 4; a++) /* sorted: the second part after the first */
            for (int b = a; b > 0 && u[b] < u[b - 1]; b--) {
                double t = u[b];
                u[b] = u[b - 1];
                u[b - 1] = t;
            }
        const double t_in = g.t_in, t_out = g.t_out; /* the walk begun: [0, inf) clipped to the grid */
        for (int part = 0; part < 2; part++) {
            int nw = brute_force(n, o, d, fmax(u[2 * part], t_in), fmin(u[2 * part + 1], t_out), want, 4096);
            bool live = grid_dda_restart(&g, u[2 * part], u[2 * part + 1]);
            restarted += live;
            check_steps(&g, live, o, d, want, nw);
        }
    }
    ASSERT_TRUE(restarted > 1000);
}

/* Long walks through a 1000 x 700 x 1200 grid (no voxels needed: the DDA sees only n):
 * the accumulated crossings stay within the tolerance over thousands of cells. */
TEST(dda_long_rays_within_tolerance)
{
    const int n[3] = {1000, 700, 1200};
    static hit want[3 * 4200];
    rng r = rng_make(11, 0, 0);
    for (int it = 0; it < 200; it++) {
        vec3 target = v3(rng_next(&r) * n[0], rng_next(&r) * n[1], rng_next(&r) * n[2]);
        double z = 2 * rng_next(&r) - 1, phi = 2 * PI * rng_next(&r), sn = sqrt(1 - z * z);
        vec3 d = v3(sn * cos(phi), sn * sin(phi), z);
        vec3 o = v3_madd(target, d, -3000.0);
        int nw = crossings_reference(n, o, d, want, 3 * 4200);
        ASSERT_TRUE(nw > 0);
        check_against(n, o, d, 0.0, INFINITY, want, nw);
    }
}

/* Rays in voxel faces, along edges, through corners: ties between axes. */
TEST(dda_grazing_and_axis_parallel)
{
    const int n[3] = {6, 6, 6};
    rng r = rng_make(7, 0, 0);
    for (int it = 0; it < 3000; it++) {
        int kind = it % 6;
        vec3 o = v3((int)(rng_next(&r) * 8) - 1, (int)(rng_next(&r) * 8) - 1, (int)(rng_next(&r) * 8) - 1);
        vec3 d = v3((int)(rng_next(&r) * 5) - 2, (int)(rng_next(&r) * 5) - 2, (int)(rng_next(&r) * 5) - 2);
        if (kind == 1) /* axis-parallel along a face or edge line */
            d = v3(it % 4 < 2 ? 1 : -1, 0, 0);
        else if (kind == 2)
            d = v3(0, 0, it % 4 < 2 ? 1 : -1);
        else if (kind == 3) /* inside a face plane, diagonal */
            d.z = 0.0, o.x += 0.5;
        else if (kind == 4) /* half-integer origin: through corners of the lattice shifted */
            o = v3(o.x + 0.5, o.y + 0.5, o.z + 0.5);
        else if (kind == 5) /* through exact corners from inside */
            o = v3(3, 3, 3), d = v3(1, (it / 6) % 3 - 1, 1);
        if (d.x == 0 && d.y == 0 && d.z == 0)
            d.x = 1;
        check_dda(n, o, d, 0.0, INFINITY);
        check_dda(n, o, v3_neg(d), 0.0, INFINITY);
    }
    /* on the grid's upper faces: outside (half-open) */
    check_dda(n, v3(6, 1.5, 1.5), v3(0, 1, 0), -10, 10);
    check_dda(n, v3(0, 1.5, 1.5), v3(0, 1, 0), -10, 10);
}

/* The density-level voxel walk in a rotated, scaled grid covers the ray between the
 * grid's entry and exit, in contiguous steps, in the voxels that density_eval reads. */
TEST(dda_world_placement)
{
    float *v = calloc(8 * 6 * 5, sizeof *v);
    for (int i = 0; i < 8 * 6 * 5; i++)
        v[i] = (float)i;
    double c = cos(0.4), s = sin(0.4);
    affine3 v2w = {{0.1 * c, -0.2 * s, 0, 1, 0.1 * s, 0.2 * c, 0, -2, 0, 0.05, 0.3, 0.5}};
    density *d = density_new_grid_affine(8, 6, 5, v, &v2w, GRID_NEAREST);
    ASSERT_TRUE(d);
    rng r = rng_make(3, 0, 0);
    for (int it = 0; it < 500; it++) {
        box3 b = density_bounds(d);
        vec3 target = v3(b.lo.x + rng_next(&r) * (b.hi.x - b.lo.x), b.lo.y + rng_next(&r) * (b.hi.y - b.lo.y),
                         b.lo.z + rng_next(&r) * (b.hi.z - b.lo.z));
        vec3 o = v3_add(target, v3(rng_next(&r) * 4 - 2, rng_next(&r) * 4 - 2, rng_next(&r) * 4 - 2));
        ray ry = {o, v3_normalize(v3_sub(target, o)), 0};
        grid_dda g;
        grid_dda_step st;
        double prev = -1;
        if (!density_voxel_dda_begin(d, ry, 0, INFINITY, &g))
            continue;
        while (grid_dda_next(&g, &st)) {
            if (prev >= 0)
                ASSERT_EQ_INT(st.t0 == prev, 1);
            prev = st.t1;
            double tm = 0.5 * (st.t0 + st.t1);
            ASSERT_NEAR(density_eval(d, ray_at(ry, tm)), (double)(st.i + 8 * (st.j + 6 * st.k)), 0);
        }
    }
    density_release(d);
}

TEST_MAIN(dda_random_rays, dda_restart_walks_the_part, dda_long_rays_within_tolerance, dda_grazing_and_axis_parallel,
          dda_world_placement)
