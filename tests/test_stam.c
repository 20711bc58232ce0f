/* test_stam.c - Stam 1994: the random field Q, the closed-form transparency statistics
 * checked against quadrature and against Monte Carlo over explicit 3-D realizations of the
 * density (docs/errata.md, erratum 7), the blob density's majorants; the tabulated kernel
 * and the joint covariance of overlapping blobs likewise. The stochastic renderer against
 * the path tracer is in test_stam_render.c. */
#include "test.h"

#include "brume.h"
#include "core/error.h"
#include "core/rng.h"
#include "density/blobs.h"
#include "density/randfield.h"
#include "render/stam_stats.h"
#include "stam_profiles.h"

/* Composite Simpson over [a, b] with n (even) intervals of f(u) = F(mean of one blob at o + u d). */
static double quad_blob(const blob_field *f, vec3 o, vec3 d, double a, double b, double eta, int n)
{
    double hstep = (b - a) / n, sum = 0.0;
    for (int k = 0; k <= n; k++) {
        double m = stam_clamp(blob_mean_at(f, 0, v3_madd(o, d, a + k * hstep)), eta);
        sum += m * (k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0));
    }
    return sum * hstep / 3.0;
}

typedef struct one_hit {
    double u, d2;
    int count;
} one_hit;
static void take_hit(int i, double u, double d2, void *user)
{
    (void)i;
    one_hit *h = user;
    h->u = u;
    h->d2 = d2;
    h->count++;
}

/* The ray of direction (0.2, 0.1, 1) passing `offset` beside c, from 10 before it: its
 * origin *o and direction *d, and its one hit in f. */
static one_hit ray_beside(const blob_field *f, vec3 c, double offset, vec3 *o, vec3 *d)
{
    *d = v3_normalize(v3(0.2, 0.1, 1.0));
    vec3 side = v3_normalize(v3_cross(*d, v3(0, 1, 0)));
    *o = v3_sub(v3_add(c, v3_scale(side, offset)), v3_scale(*d, 10.0));
    one_hit h = {0, 0, 0};
    blob_field_query_ray(f, *o, *d, 0.0, 1e9, take_hit, &h);
    ASSERT_EQ_INT(h.count, 1);
    return h;
}

/* The integral of F_eta(mean) over [a, b]: the mean's when eta is infinite. */
static double depth_F(const blob_ray *br, double eta, double a, double b)
{
    return isinf(eta) ? blob_T_mean(br, a, b) : blob_T_clamped(br, eta, a, b);
}

/* T_mean and the clamped integral in closed form (erf) against Simpson quadrature, for rays
 * through, beside and ending inside a blob, with and without clamping. */
TEST(closed_form_mean_matches_quadrature)
{
    stam_stats_init();
    blob b = {v3(0.3, -0.2, 0.1), 2.5, 0.7};
    blob_field *f = blob_field_new(&b, 1, BLOB_DEFAULT_CUTOFF, "test");
    ASSERT_TRUE(f);
    const double offsets[] = {0.0, 0.35, 1.1, 1.9}; /* cutoff 3 h = 2.1 */
    const double ends[][2] = {{0.0, 20.0}, {0.0, 9.8}, {10.0, 10.2}, {3.0, 7.5}};
    const double etas[] = {INFINITY, 0.5, 0.05};
    for (int oi = 0; oi < 4; oi++)
        for (int ei = 0; ei < 4; ei++)
            for (int k = 0; k < 3; k++) {
                vec3 o, d;
                one_hit h = ray_beside(f, b.x, offsets[oi], &o, &d);
                ASSERT_NEAR(sqrt(h.d2), offsets[oi], 1e-12);
                ASSERT_NEAR(h.u, 10.0, 1e-12);
                blob_ray br = blob_ray_make(f, 0, h.u, h.d2);
                double a = ends[ei][0], e = ends[ei][1];
                double want = quad_blob(f, o, d, a, e, etas[k], 200000);
                double got = depth_F(&br, etas[k], a, e);
                ASSERT_NEAR(got, want, 2e-6 * (1.0 + want)); /* Simpson across the truncation jump */
            }
    /* the clamped integral is below the mean integral and equals it for a large eta */
    blob_ray br = blob_ray_make(f, 0, 5.0, 0.0);
    ASSERT_TRUE(blob_T_clamped(&br, 0.1, 0, 10) < blob_T_mean(&br, 0, 10));
    ASSERT_NEAR(blob_T_clamped(&br, 1e9, 0, 10), blob_T_mean(&br, 0, 10), 0.0);
    /* a ray through the centre of an unbounded blob: T = m / (2 pi h^2) */
    double whole = b.m / (2.0 * PI * b.h * b.h) * erf(BLOB_DEFAULT_CUTOFF / sqrt(2.0)); /* truncated at cutoff h */
    ASSERT_NEAR(blob_T_mean(&br, -100, 100), whole, 1e-6 * whole);
    blob_field_release(f);
}

/* Q over independent realizations: unit variance, covariance exp(-r^2 / 2 alpha^2) at lags
 * of 1 to 4 cells along each axis, no cross-correlation of the Re/Im pair; a frame a short
 * time later is strongly correlated with the first and has the same variance. Estimates are
 * spatial averages per realization; the tolerance is 5 standard errors across realizations. */
TEST(random_field_covariance)
{
    enum { N = 24, M = 48 };
    randfield_params p = {{N, N, N}, 0.5, 1.0, 7, 0.0, 2.0};
    size_t count = (size_t)N * N * N;
    float *re = malloc(count * sizeof *re), *im = malloc(count * sizeof *im), *later = malloc(count * sizeof *later);
    double s[7] = {0}, s2[7] = {0};
    for (int r = 0; r < M; r++) {
        p.time = 0.0;
        ASSERT_EQ_INT(randfield_synthesize(&p, (uint64_t)r, re, im), BRUME_OK);
        p.time = 0.05;
        ASSERT_EQ_INT(randfield_synthesize(&p, (uint64_t)r, later, NULL), BRUME_OK);
        double est[7] = {0};
        for (int k = 0; k < N; k++)
            for (int j = 0; j < N; j++)
                for (int i = 0; i < N; i++) {
                    size_t at = (size_t)i + N * ((size_t)j + N * (size_t)k);
                    double q = re[at];
                    est[0] += q * q;
                    for (int m = 1; m <= 4; m++) {
                        size_t bx = (size_t)((i + m) % N) + N * ((size_t)j + N * (size_t)k);
                        size_t bz = (size_t)i + N * ((size_t)j + N * (size_t)((k + m) % N));
                        est[m] += 0.5 * (q * re[bx] + q * re[bz]);
                    }
                    est[5] += q * im[at];
                    est[6] += q * later[at];
                }
        for (int m = 0; m < 7; m++) {
            est[m] /= (double)count;
            s[m] += est[m];
            s2[m] += est[m] * est[m];
        }
    }
    for (int m = 0; m < 7; m++) {
        double mean = s[m] / M, sd = sqrt(fmax(0.0, s2[m] / M - mean * mean) * M / (M - 1)), se = sd / sqrt(M);
        double lag = m <= 4 ? m * p.cell : 0.0;
        double want = m <= 4 ? exp(-lag * lag / (2.0 * p.alpha * p.alpha)) : (m == 5 ? 0.0 : mean);
        printf("Q covariance %d: %.4f +- %.4f, expected %.4f\n", m, mean, se, want);
        ASSERT_NEAR(mean, want, 5.0 * se + 1e-3);
    }
    ASSERT_TRUE(s[6] / M > 0.95); /* coherent in time */
    /* the field at a later time still has unit variance */
    p.time = 3.0;
    double v = 0.0;
    for (int r = 0; r < 8; r++) {
        ASSERT_EQ_INT(randfield_synthesize(&p, (uint64_t)r, re, NULL), BRUME_OK);
        for (size_t i = 0; i < count; i++)
            v += re[i] * re[i];
    }
    ASSERT_NEAR(v / (8.0 * (double)count), 1.0, 0.1);
    /* the trilinear lookup reproduces lattice values and is periodic */
    randfield *q = randfield_new(&p);
    ASSERT_TRUE(q);
    ASSERT_NEAR(randfield_eval(q, v3(3 * p.cell, 5 * p.cell, 7 * p.cell)), q->q[3 + N * (5 + N * 7)], 1e-6);
    ASSERT_NEAR(randfield_eval(q, v3(0.3, -0.7, 1.1)), randfield_eval(q, v3(0.3 + N * p.cell, -0.7, 1.1 - N * p.cell)),
                1e-5);
    randfield_release(q);
    free(re);
    free(im);
    free(later);
}

/* The lattice of the Monte-Carlo tests: NX x NY x MC_NZ, rays along z through (i, 8, k). */
enum { MC_NX = 16, MC_NY = 16, MC_NZ = 64 };

/* Sample sums of T = trapezoid integral of rho = mean + sig Q along each ray's lattice line
 * from k0[r] to the end, over 2 x pairs realizations of Q (Re and Im of each synthesis):
 * s1[r] += T, s2[r] += T^2; returns the number of realizations. */
static int mc_depths(const randfield_params *p, int pairs, int rays, const int *ray_i, const int *ray_k0,
                     double (*mean)[MC_NZ], double (*sig)[MC_NZ], double *s1, double *s2)
{
    size_t count = (size_t)MC_NX * MC_NY * MC_NZ;
    float *q[2] = {malloc(count * sizeof(float)), malloc(count * sizeof(float))};
    ASSERT_TRUE(q[0] && q[1]);
    int M = 0;
    for (int pr = 0; pr < pairs; pr++) {
        ASSERT_EQ_INT(randfield_synthesize(p, (uint64_t)pr, q[0], q[1]), BRUME_OK);
        for (int w = 0; w < 2; w++, M++)
            for (int r = 0; r < rays; r++) {
                double T = 0.0;
                for (int k = ray_k0[r]; k < MC_NZ; k++) {
                    double rho =
                        mean[r][k] + sig[r][k] * q[w][(size_t)(ray_i[r] % MC_NX) + MC_NX * (8 + (size_t)MC_NY * (size_t)k)];
                    T += (k == ray_k0[r] || k == MC_NZ - 1 ? 0.5 : 1.0) * rho * p->cell;
                }
                s1[r] += T;
                s2[r] += T * T;
            }
    }
    free(q[0]);
    free(q[1]);
    return M;
}

/* The Monte-Carlo test of the transparency statistics (docs/errata.md, erratum 7). Explicit 3-D
 * realizations of one random blob rho = mean + sigma Q, sigma^2 = eps F_eta(mean), with Q
 * synthesized on a 16 x 16 x 64 periodic lattice (spacing alpha / 1.5, exact unit variance at
 * the nodes), are integrated along lattice lines by the trapezoid rule (exact to e^-44 for
 * this correlation), for rays at distances 0, h/2, h, 3h/2 from the centre and one that starts
 * at the centre. The sample mean and variance of T over 2 x 500 realizations must match
 * blob_T_mean and blob_T_var within 5 standard errors of each estimator; the paper's Eq. 12
 * (and Eq. 12 with Eq. 13's second scaling by Q's variance K_Q(0)) must not. */
TEST(transparency_statistics_monte_carlo)
{
    enum { NZ = MC_NZ, PAIRS = 500, RAYS = 5 };
    const double alpha = 0.25, cell = alpha / 1.5, eps = 0.6, eta = 0.3;
    stam_stats_init();
    randfield_params p = {{MC_NX, MC_NY, MC_NZ}, cell, alpha, 2024, 0.0, 0.0};
    blob b = {v3(8 * cell, 8 * cell, 32 * cell), 4.0, 1.0}; /* peak density 0.254: clamped near the centre */
    blob_field *f = blob_field_new(&b, 1, BLOB_DEFAULT_CUTOFF, "test");
    ASSERT_TRUE(f);
    const int ray_i[RAYS] = {8, 11, 14, 17, 8}; /* Q is periodic: node 17 is node 1 */
    const int ray_k0[RAYS] = {0, 0, 0, 0, 32}; /* the last ray starts at the blob's centre plane */
    /* per ray: lattice mean and sigma along the line (the field is rho = mean + sigma Q) */
    static double mean[RAYS][NZ], sig[RAYS][NZ];
    double want_mean[RAYS], want_var[RAYS], paper12[RAYS], paper13[RAYS];
    for (int r = 0; r < RAYS; r++) {
        for (int k = 0; k < NZ; k++) {
            vec3 x = v3(ray_i[r] * cell, 8 * cell, k * cell);
            mean[r][k] = blob_mean_at(f, 0, x);
            sig[r][k] = sqrt(eps * stam_clamp(mean[r][k], eta));
        }
        vec3 o = v3(ray_i[r] * cell, 8 * cell, ray_k0[r] * cell), d = v3(0, 0, 1);
        one_hit h = {0, 0, 0};
        blob_field_query_ray(f, o, d, 0.0, (NZ - 1 - ray_k0[r]) * cell, take_hit, &h);
        ASSERT_EQ_INT(h.count, 1);
        blob_ray br = blob_ray_make(f, 0, h.u, h.d2);
        double len = (NZ - 1 - ray_k0[r]) * cell;
        want_mean[r] = blob_T_mean(&br, 0.0, len);
        want_var[r] = blob_T_var(&br, eps, eta, alpha, 0.0, len);
        paper12[r] = blob_T_var_paper(&br, eps, eta, alpha, 0.0, len);
        paper13[r] = paper12[r] / (pow(2.0 * PI, 1.5) * alpha * alpha * alpha);
    }
    double s[RAYS] = {0}, s2[RAYS] = {0};
    int M = mc_depths(&p, PAIRS, RAYS, ray_i, ray_k0, mean, sig, s, s2);
    for (int r = 0; r < RAYS; r++) {
        double m = s[r] / M, var = (s2[r] - M * m * m) / (M - 1);
        /* T is gaussian: se(mean) = sqrt(var / M), se(var) = var sqrt(2 / (M - 1)) */
        double se_m = sqrt(want_var[r] / M), se_v = want_var[r] * sqrt(2.0 / (M - 1));
        printf("ray %d: mean %.5f (closed form %.5f), variance %.6f (ours %.6f, Eq. 12 %.6f, Eq. 12+13 %.6f)\n", r,
               m, want_mean[r], var, want_var[r], paper12[r], paper13[r]);
        ASSERT_NEAR(m, want_mean[r], 5.0 * se_m + 1e-4 * want_mean[r]);
        ASSERT_NEAR(var, want_var[r], 5.0 * se_v);
        /* the paper's unrepaired normalizations are far outside the same tolerance */
        ASSERT_TRUE(fabs(var - paper12[r]) > 5.0 * se_v);
        ASSERT_TRUE(fabs(var - paper13[r]) > 5.0 * se_v);
    }
    blob_field_release(f);
}

/* Along `rays` random rays through a blob density d, at random points of each majorant
 * segment: density_eval is the sum of the blobs' truncated means and lies under the segment's
 * majorant. */
static void check_majorant(const density *d, int rays)
{
    const blob_field *f = density_get_blobs(d);
    rng g = rng_make(5, 0, 0);
    for (int r = 0; r < rays; r++) {
        vec3 o = v3(6 * rng_next(&g) - 3, 6 * rng_next(&g) - 3, 6);
        vec3 t = v3(2 * rng_next(&g) - 1, rng_next(&g) - 0.5, 2 * rng_next(&g) - 1);
        ray ry = {o, v3_normalize(v3_sub(t, o)), 0.0};
        majorant_iter it;
        majorant_seg seg;
        density_majorant_begin(d, ry, 0.0, 20.0, &it);
        while (majorant_next(&it, &seg))
            for (int k = 0; k < 8; k++) {
                vec3 x = ray_at(ry, seg.t0 + (seg.t1 - seg.t0) * rng_next(&g));
                double rho = density_eval(d, x), brute = 0.0;
                for (int i = 0; i < f->n; i++)
                    brute += blob_mean_at(f, i, x);
                ASSERT_NEAR(rho, brute, 1e-12 + 1e-9 * brute);
                ASSERT_TRUE(rho <= seg.rho_maj);
            }
    }
}

/* The blob density seen by path and single: density_eval is the truncated mean, and along
 * random rays every point lies under its majorant segment. */
TEST(blob_density_majorant_bounds)
{
    blob_list l = {0};
    blob_cloud_params p = {v3(0, 0, 0), v3(1.5, 0.7, 1.0), 300, 0.08, 0.3, 0.2, 1.0, 9};
    ASSERT_EQ_INT(blob_gen_cloud(&p, &l), BRUME_OK);
    blob_field *f = blob_field_new(l.b, l.n, BLOB_DEFAULT_CUTOFF, "test");
    density *d = density_new_blobs(f, 24);
    ASSERT_TRUE(d);
    check_majorant(d, 200);
    /* the hierarchy finds exactly the blobs a linear scan finds */
    f->use_bvh = false;
    double scan = blob_field_mean(f, v3(0.1, 0.05, -0.2));
    f->use_bvh = true;
    ASSERT_NEAR(blob_field_mean(f, v3(0.1, 0.05, -0.2)), scan, 1e-12);
    density_release(d);
    blob_list_free(&l);
}

/* ---- Stam's two optional models (docs/stam.md): the tabulated radial kernel W of Section 6.1
 * (`stam.kernel = table`, density/blob_kernel.h) against the analytic gaussian and against
 * quadrature of its own point field (its file validation is in test_stam_render.c); and
 * the joint covariance of overlapping blobs (`stam.overlap = joint`) against Monte Carlo
 * over explicit 3-D realizations. ---- */

/* The kernel of a profile written by write_profile and read back (the file then removed). */
static blob_kernel *profile_kernel(const char *name, double (*w)(double), int n, double ds)
{
    const char *path = write_profile(name, w, n, ds);
    blob_kernel *k = blob_kernel_read(path, "stam.kernel_file");
    remove(path);
    if (!k)
        TEST_FAIL("%s", err_message());
    return k;
}

/* A gaussian written as a table (s = 0 .. 8, 2049 points) renders Appendix A's field: the
 * point density within the linear interpolation's error (ds^2 / 8 max|w''| = 1.9e-6 of the
 * peak, plus the normalisation's, of the same order), the ray integrals T_mean and I_F
 * within the bilinear error of the line table, gs^2 / 8 (max|G_xx| + max|G_dd|) <=
 * 1.2e-4 (0.61 + 2.51) = 3.8e-4 of peak h (gs = 8 / 256; G_xx = w'(r) x / r, |G_dd| <= the
 * integral of |w''| along the line, sqrt(2 pi)). */
TEST(tabulated_gaussian_matches_the_analytic_kernel)
{
    stam_stats_init();
    blob_kernel *k = profile_kernel("gauss.txt", gaussian, 2048, 8.0 / 2048);
    ASSERT_NEAR(k->w0, pow(2.0 * PI, -1.5), 1e-5 * pow(2.0 * PI, -1.5));
    blob b = {v3(0.3, -0.2, 0.1), 2.5, 0.7};
    blob_field *fa = blob_field_new(&b, 1, BLOB_DEFAULT_CUTOFF, "test");
    blob_field *ft = blob_field_new(&b, 1, BLOB_DEFAULT_CUTOFF, "test");
    ASSERT_TRUE(fa && ft);
    ASSERT_EQ_INT(blob_field_set_kernel(ft, k), BRUME_OK);
    blob_kernel_release(k);
    ASSERT_NEAR(ft->R2[0], fa->R2[0], 1e-15); /* cutoff 3 < s_max 8: the same truncation */
    double peak = fa->peak[0], worst = 0.0;
    rng g = rng_make(3, 0, 0);
    for (int i = 0; i < 2000; i++) {
        vec3 p = v3_add(b.x, v3(2.2 * (2 * rng_next(&g) - 1), 2.2 * (2 * rng_next(&g) - 1), 2.2 * (2 * rng_next(&g) - 1)));
        double e = fabs(blob_mean_at(ft, 0, p) - blob_mean_at(fa, 0, p));
        worst = fmax(worst, e);
        ASSERT_NEAR(blob_mean_at(ft, 0, p), blob_mean_at(fa, 0, p), 1e-5 * peak);
    }
    printf("point density: worst difference %.2e of the peak\n", worst / peak);
    const double offsets[] = {0.0, 0.35, 1.1, 1.9};
    const double ends[][2] = {{0.0, 20.0}, {0.0, 9.8}, {10.0, 10.2}, {3.0, 7.5}};
    const double etas[] = {INFINITY, 0.5, 0.05};
    double tol = 3.8e-4 * peak * b.h, wt = 0.0;
    for (int oi = 0; oi < 4; oi++)
        for (int ei = 0; ei < 4; ei++)
            for (int e = 0; e < 3; e++) {
                vec3 o, d;
                one_hit h = ray_beside(ft, b.x, offsets[oi], &o, &d);
                blob_ray ba = blob_ray_make(fa, 0, h.u, h.d2), bt = blob_ray_make(ft, 0, h.u, h.d2);
                double a = ends[ei][0], z = ends[ei][1];
                double want = depth_F(&ba, etas[e], a, z), got = depth_F(&bt, etas[e], a, z);
                wt = fmax(wt, fabs(got - want));
                ASSERT_NEAR(got, want, tol);
            }
    printf("ray integrals: worst difference %.2e of peak h (bound 3.8e-4)\n", wt / (peak * b.h));
    blob_field_release(fa);
    blob_field_release(ft);
}

/* A kernel that is not a gaussian, the cone w = 1 - s / 2 on [0, 2]: its normalisation is
 * W(0) = 3 / (pi s_max^3) in closed form, its truncation the table's end (2 h < 3 h), and
 * its ray integrals (mean, clamped) match Simpson quadrature of its own point field within
 * the bilinear bound (w'' = 0 but for the kink at 0 and the truncation: gs^2 / 8 times
 * |G_dd|, which grows like ln(1 / d) near the axis: 1e-4 of peak h). A blob field with it
 * keeps its majorant above its density along random rays. */
TEST(tabulated_cone_kernel_is_consistent)
{
    stam_stats_init();
    blob_kernel *k = profile_kernel("cone.txt", cone, 64, 2.0 / 64);
    ASSERT_NEAR(k->w0, 3.0 / (PI * 8.0), 1e-12);
    blob b = {v3(0.0, 0.0, 0.0), 1.7, 0.5};
    blob_field *f = blob_field_new(&b, 1, BLOB_DEFAULT_CUTOFF, "test");
    ASSERT_TRUE(f);
    ASSERT_EQ_INT(blob_field_set_kernel(f, k), BRUME_OK);
    ASSERT_NEAR(f->R2[0], 1.0, 1e-15); /* (2 h)^2 */
    ASSERT_NEAR(blob_mean_at(f, 0, v3(0.25, 0, 0)), b.m * k->w0 * 0.75 / (0.125), 1e-12);
    ASSERT_NEAR(blob_mean_at(f, 0, v3(0.0, 1.01, 0)), 0.0, 0.0);
    double peak = f->peak[0], worst = 0.0;
    for (int oi = 0; oi < 5; oi++)
        for (int e = 0; e < 3; e++) {
            const double etas[] = {INFINITY, 0.6 * peak, 0.2 * peak};
            double off = 0.21 * oi;
            vec3 d = v3_normalize(v3(0.3, -0.2, 1.0));
            vec3 side = v3_normalize(v3_cross(d, v3(0, 1, 0)));
            vec3 o = v3_sub(v3_scale(side, off), v3_scale(d, 3.0));
            one_hit h = {0, 0, 0};
            blob_field_query_ray(f, o, d, 0.0, 1e9, take_hit, &h);
            ASSERT_EQ_INT(h.count, 1);
            blob_ray br = blob_ray_make(f, 0, h.u, h.d2);
            const double ends[][2] = {{0.0, 6.0}, {0.0, 3.1}, {2.7, 3.3}};
            for (int ei = 0; ei < 3; ei++) {
                double a = ends[ei][0], z = ends[ei][1];
                double want = quad_blob(f, o, d, a, z, etas[e], 200000);
                double got = depth_F(&br, etas[e], a, z);
                worst = fmax(worst, fabs(got - want));
                ASSERT_NEAR(got, want, 1e-4 * peak * b.h);
            }
        }
    printf("cone: worst ray-integral error %.2e of peak h\n", worst / (peak * b.h));
    blob_field_release(f);
    /* the majorant of a cloud with this kernel bounds its density */
    blob_list l = {0};
    blob_cloud_params p = {v3(0, 0, 0), v3(1.5, 0.7, 1.0), 200, 0.08, 0.3, 0.2, 1.0, 9};
    ASSERT_EQ_INT(blob_gen_cloud(&p, &l), BRUME_OK);
    blob_field *fc = blob_field_new(l.b, l.n, BLOB_DEFAULT_CUTOFF, "test");
    ASSERT_EQ_INT(blob_field_set_kernel(fc, k), BRUME_OK);
    blob_kernel_release(k);
    density *dn = density_new_blobs(fc, 24);
    ASSERT_TRUE(dn);
    check_majorant(dn, 100);
    density_release(dn);
    blob_list_free(&l);
}

/* ---- overlapping blobs ---------------------------------------------------------------------- */

typedef struct hits {
    int n, i[8];
    double u[8], d2[8];
} hits;
static void take_hits(int i, double u, double d2, void *user)
{
    hits *h = user;
    if (h->n < 8) {
        h->i[h->n] = i;
        h->u[h->n] = u;
        h->d2[h->n] = d2;
    }
    h->n++;
}

/* blob_T_cross, the integral of sqrt(F_i F_j) along a ray, against Simpson quadrature: for
 * two gaussian blobs in closed form (unclamped, one clamped, both clamped, the segment
 * ending inside), for a cone kernel by Gauss-Legendre per piece; and blob_T_cov(i, i) is
 * blob_T_var. */
TEST(cross_integral_matches_quadrature)
{
    stam_stats_init();
    blob_kernel *k = profile_kernel("cone2.txt", cone, 64, 2.0 / 64);
    blob bb[2] = {{v3(0.0, 0.0, 0.0), 2.0, 0.6}, {v3(0.2, 0.1, 0.7), 1.0, 0.4}};
    for (int kern = 0; kern < 2; kern++) {
        blob_field *f = blob_field_new(bb, 2, BLOB_DEFAULT_CUTOFF, "test");
        ASSERT_TRUE(f);
        if (kern)
            ASSERT_EQ_INT(blob_field_set_kernel(f, k), BRUME_OK);
        double pk = fmax(f->peak[0], f->peak[1]);
        const double etas[] = {1e30, 0.5 * pk, 0.2 * pk, 0.05 * pk};
        vec3 d = v3_normalize(v3(0.1, 0.05, 1.0)), o = v3(0.05, 0.02, -4.0);
        hits h = {0};
        blob_field_query_ray(f, o, d, 0.0, 1e9, take_hits, &h);
        ASSERT_EQ_INT(h.n, 2);
        blob_ray b0 = blob_ray_make(f, h.i[0], h.u[0], h.d2[0]), b1 = blob_ray_make(f, h.i[1], h.u[1], h.d2[1]);
        for (int e = 0; e < 4; e++)
            for (int end = 0; end < 2; end++) {
                double a = 0.0, z = end ? 4.3 : 9.0, n = 400000, hs = (z - a) / n, want = 0.0;
                for (int q = 0; q <= n; q++) {
                    vec3 x = v3_madd(o, d, a + q * hs);
                    double f0 = stam_clamp(blob_mean_at(f, h.i[0], x), etas[e]);
                    double f1 = stam_clamp(blob_mean_at(f, h.i[1], x), etas[e]);
                    want += sqrt(f0 * f1) * (q == 0 || q == n ? 1.0 : (q % 2 ? 4.0 : 2.0));
                }
                want *= hs / 3.0;
                double got = blob_T_cross(&b0, &b1, etas[e], a, z);
                printf("%s eta %.3g end %.1f: cross %.6f, quadrature %.6f\n", kern ? "cone" : "gaussian", etas[e], z, got,
                       want);
                /* Simpson across the truncation jumps: 1e-5; Gauss-Legendre on the cone's kinks: 2e-3 */
                ASSERT_NEAR(got, want, (kern ? 2e-3 : 1e-5) * want + 1e-9);
                ASSERT_NEAR(blob_T_cross(&b0, &b0, etas[e], a, z), blob_T_clamped(&b0, etas[e], a, z),
                            (kern ? 2e-3 : 1e-6) * blob_T_clamped(&b0, etas[e], a, z));
            }
        ASSERT_NEAR(blob_T_cov(&b0, &b0, 0.6, 0.3, 0.1, 0.0, 9.0), blob_T_var(&b0, 0.6, 0.3, 0.1, 0.0, 9.0),
                    1e-5 * blob_T_var(&b0, 0.6, 0.3, 0.1, 0.0, 9.0)); /* Phi's table at other arguments */
        blob_field_release(f);
    }
    blob_kernel_release(k);
}

/* The Monte-Carlo test of overlapping blobs: three blobs perturbed by the same Q (two on the
 * rays' axis h apart, one beside), explicit 3-D realizations rho = sum_i (mean_i + sigma_i Q)
 * integrated along lattice lines as in transparency_statistics_monte_carlo (same
 * lattice, alpha, eps, eta). The variance of the summed depth must match the joint variance
 * sum_ij Cov(T_i, T_j) (stam.overlap = joint) within 5 standard errors; the variance that the
 * independent samples sigma_i Q(x_ui) give, sum_ij sigma_i sigma_j K_Q(u_i - u_j), must not. */
TEST(joint_covariance_matches_monte_carlo)
{
    enum { NZ = MC_NZ, PAIRS = 500, RAYS = 4, NB = 3 };
    const double alpha = 0.25, cell = alpha / 1.5, eps = 0.6, eta = 0.3;
    stam_stats_init();
    randfield_params p = {{MC_NX, MC_NY, MC_NZ}, cell, alpha, 4048, 0.0, 0.0};
    blob bl[NB] = {{v3(8 * cell, 8 * cell, 29 * cell), 4.0, 1.0},
                   {v3(8 * cell, 8 * cell, 35 * cell), 3.0, 1.0},
                   {v3(11 * cell, 8 * cell, 32 * cell), 2.0, 0.8}};
    blob_field *f = blob_field_new(bl, NB, BLOB_DEFAULT_CUTOFF, "test");
    ASSERT_TRUE(f);
    const int ray_i[RAYS] = {8, 11, 14, 8};
    const int ray_k0[RAYS] = {0, 0, 0, 32};
    static double mean[RAYS][NZ], sig[RAYS][NZ];
    double want_mean[RAYS], want_var[RAYS], indep_var[RAYS];
    for (int r = 0; r < RAYS; r++) {
        for (int k = 0; k < NZ; k++) {
            vec3 x = v3(ray_i[r] * cell, 8 * cell, k * cell);
            mean[r][k] = sig[r][k] = 0.0;
            for (int b = 0; b < NB; b++) {
                double m = blob_mean_at(f, b, x);
                mean[r][k] += m;
                sig[r][k] += sqrt(eps * stam_clamp(m, eta));
            }
        }
        vec3 o = v3(ray_i[r] * cell, 8 * cell, ray_k0[r] * cell), d = v3(0, 0, 1);
        double len = (NZ - 1 - ray_k0[r]) * cell;
        hits h = {0};
        blob_field_query_ray(f, o, d, 0.0, len, take_hits, &h);
        ASSERT_EQ_INT(h.n, NB);
        blob_ray br[NB];
        double s[NB], uc[NB];
        want_mean[r] = want_var[r] = indep_var[r] = 0.0;
        for (int b = 0; b < NB; b++) {
            br[b] = blob_ray_make(f, h.i[b], h.u[b], h.d2[b]);
            want_mean[r] += blob_T_mean(&br[b], 0.0, len);
            s[b] = sqrt(blob_T_var(&br[b], eps, eta, alpha, 0.0, len));
            uc[b] = fmin(fmax(h.u[b], 0.0), len);
        }
        for (int b = 0; b < NB; b++)
            for (int c = 0; c < NB; c++) {
                want_var[r] += b == c ? s[b] * s[b] : blob_T_cov(&br[b], &br[c], eps, eta, alpha, 0.0, len);
                indep_var[r] += s[b] * s[c] * exp(-(uc[b] - uc[c]) * (uc[b] - uc[c]) / (2 * alpha * alpha));
            }
    }
    double s1[RAYS] = {0}, s2[RAYS] = {0};
    int M = mc_depths(&p, PAIRS, RAYS, ray_i, ray_k0, mean, sig, s1, s2);
    for (int r = 0; r < RAYS; r++) {
        double m = s1[r] / M, var = (s2[r] - M * m * m) / (M - 1);
        double se_m = sqrt(want_var[r] / M), se_v = want_var[r] * sqrt(2.0 / (M - 1));
        printf("ray %d: mean %.5f (closed form %.5f), variance %.6f (joint %.6f, independent samples %.6f)\n", r, m,
               want_mean[r], var, want_var[r], indep_var[r]);
        ASSERT_NEAR(m, want_mean[r], 5.0 * se_m + 1e-4 * want_mean[r]);
        ASSERT_NEAR(var, want_var[r], 5.0 * se_v);
        ASSERT_TRUE(fabs(var - indep_var[r]) > 5.0 * se_v);
    }
    blob_field_release(f);
}

TEST_MAIN(closed_form_mean_matches_quadrature, random_field_covariance, transparency_statistics_monte_carlo,
          blob_density_majorant_bounds, tabulated_gaussian_matches_the_analytic_kernel,
          tabulated_cone_kernel_is_consistent, cross_integral_matches_quadrature,
          joint_covariance_matches_monte_carlo)
