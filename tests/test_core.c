/* test_core.c - vectors, frames, the counter-based generator, the sampling warps, the
 * thread pool and fixed-point sums. */
#include "test.h"

#include <stdint.h>

#include "core/fixsum.h"
#include "core/pool.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/vec.h"

TEST(frame_orthonormal)
{
    rng r = rng_make(1, 2, 3);
    for (int i = 0; i < 1000; i++) {
        vec3 n = sample_sphere(rng_next(&r), rng_next(&r));
        frame f = frame_from_n(n);
        ASSERT_NEAR(v3_dot(f.s, f.t), 0.0, 1e-12);
        ASSERT_NEAR(v3_dot(f.s, f.n), 0.0, 1e-12);
        ASSERT_NEAR(v3_length(f.s), 1.0, 1e-12);
        ASSERT_NEAR(v3_length(f.t), 1.0, 1e-12);
        vec3 c = v3_cross(f.s, f.t); /* right-handed: s x t = n */
        ASSERT_NEAR(v3_dot(c, n), 1.0, 1e-12);
        vec3 w = v3(0.3, -0.2, 0.9);
        vec3 back = frame_to_world(&f, frame_to_local(&f, w));
        ASSERT_NEAR(back.x, w.x, 1e-12);
        ASSERT_NEAR(back.z, w.z, 1e-12);
    }
}

TEST(box_intersect)
{
    box3 b = {v3(-1, -1, -1), v3(1, 1, 1)};
    double t0, t1;
    ASSERT_TRUE(box3_intersect(b, (ray){v3(-3, 0, 0), v3(1, 0, 0), 0}, 0, INFINITY, &t0, &t1));
    ASSERT_NEAR(t0, 2.0, 1e-12);
    ASSERT_NEAR(t1, 4.0, 1e-12);
    /* starting inside: t0 is clipped to tmin */
    ASSERT_TRUE(box3_intersect(b, (ray){v3(0, 0, 0), v3(0, 0, -1), 0}, 0, INFINITY, &t0, &t1));
    ASSERT_NEAR(t0, 0.0, 0);
    ASSERT_NEAR(t1, 1.0, 1e-12);
    ASSERT_TRUE(!box3_intersect(b, (ray){v3(0, 2, 0), v3(1, 0, 0), 0}, 0, INFINITY, &t0, &t1));
    ASSERT_TRUE(!box3_intersect(b, (ray){v3(-3, 0, 0), v3(-1, 0, 0), 0}, 0, INFINITY, &t0, &t1));
}

/* Same (seed, stream, sample) -> same numbers; any change -> a different sequence. */
TEST(rng_determinism)
{
    rng a = rng_make(7, 100, 3), b = rng_make(7, 100, 3);
    for (int i = 0; i < 100; i++)
        ASSERT_TRUE(rng_next_u64(&a) == rng_next_u64(&b));
    rng c = rng_make(7, 100, 4), d = rng_make(7, 101, 3), e = rng_make(8, 100, 3);
    rng f = rng_make(7, 100, 3);
    int same_c = 0, same_d = 0, same_e = 0;
    for (int i = 0; i < 100; i++) {
        uint64_t x = rng_next_u64(&f);
        same_c += rng_next_u64(&c) == x;
        same_d += rng_next_u64(&d) == x;
        same_e += rng_next_u64(&e) == x;
    }
    ASSERT_EQ_INT(same_c + same_d + same_e, 0);
}

/* Chi-square of 64 equal bins over 640,000 draws, pooled over many short streams as the
 * renderer uses them; 63 degrees of freedom, reject above the 0.9999 quantile (~116). */
TEST(rng_uniform_chi2)
{
    enum { BINS = 64, N = 640000 };
    static long hist[BINS];
    memset(hist, 0, sizeof hist);
    for (int s = 0; s < N / 16; s++) {
        rng r = rng_make(42, (uint64_t)s, (uint64_t)(s % 7));
        for (int k = 0; k < 16; k++) {
            double u = rng_next(&r);
            ASSERT_TRUE(u >= 0.0 && u < 1.0);
            hist[(int)(u * BINS)]++;
        }
    }
    double chi2 = 0.0, expect = (double)N / BINS;
    for (int i = 0; i < BINS; i++)
        chi2 += ((double)hist[i] - expect) * ((double)hist[i] - expect) / expect;
    if (chi2 > 116.0)
        TEST_FAIL("chi-square %.1f > 116 (63 dof, p = 1e-4)", chi2);
}

/* Successive dimensions must be uncorrelated: the correlation of (u_k, u_{k+1}) pairs and of
 * the first number of neighbouring pixels is within 5 standard errors of 0. */
TEST(rng_independence)
{
    enum { N = 200000 };
    double sxy = 0.0, sxy_pix = 0.0;
    for (int s = 0; s < N; s++) {
        rng r = rng_make(1, (uint64_t)s, 0), q = rng_make(1, (uint64_t)s + 1, 0);
        double u0 = rng_next(&r) - 0.5, u1 = rng_next(&r) - 0.5, v0 = rng_next(&q) - 0.5;
        sxy += u0 * u1;
        sxy_pix += u0 * v0;
    }
    /* Var(u v) for independent centered uniforms = (1/12)^2; standard error of the mean. */
    double se = (1.0 / 12.0) / sqrt((double)N);
    ASSERT_NEAR(sxy / N, 0.0, 5.0 * se);
    ASSERT_NEAR(sxy_pix / N, 0.0, 5.0 * se);
}

/* Moments of the warps, with tolerances of 5 standard errors of the estimator. */
TEST(sampling_moments)
{
    enum { N = 200000 };
    rng r = rng_make(3, 0, 0);
    double sz = 0.0, sz2 = 0.0, scos = 0.0, sd2 = 0.0, sexp = 0.0, scone = 0.0;
    double cos_max = cos(0.3);
    for (int i = 0; i < N; i++) {
        vec3 s = sample_sphere(rng_next(&r), rng_next(&r));
        ASSERT_NEAR(v3_length(s), 1.0, 1e-12);
        sz += s.z;
        sz2 += s.z * s.z;
        vec3 h = sample_cosine_hemisphere(rng_next(&r), rng_next(&r));
        scos += h.z;
        vec3 d = sample_disk(rng_next(&r), rng_next(&r));
        ASSERT_TRUE(d.x * d.x + d.y * d.y <= 1.0 + 1e-12);
        sd2 += d.x * d.x + d.y * d.y;
        sexp += sample_exponential(rng_next(&r), 2.0);
        vec3 c = sample_cone(rng_next(&r), rng_next(&r), cos_max);
        ASSERT_TRUE(c.z >= cos_max - 1e-12);
        scone += c.z;
    }
    /* sphere: E[z] = 0 (sd 1/sqrt3), E[z^2] = 1/3 (sd sqrt(4/45)) */
    ASSERT_NEAR(sz / N, 0.0, 5.0 * sqrt(1.0 / 3.0 / N));
    ASSERT_NEAR(sz2 / N, 1.0 / 3.0, 5.0 * sqrt(4.0 / 45.0 / N));
    /* cosine hemisphere: E[cos] = 2/3, Var = 1/2 - 4/9 */
    ASSERT_NEAR(scos / N, 2.0 / 3.0, 5.0 * sqrt((0.5 - 4.0 / 9.0) / N));
    /* disk: r^2 uniform on [0,1]: mean 1/2, var 1/12 */
    ASSERT_NEAR(sd2 / N, 0.5, 5.0 * sqrt(1.0 / 12.0 / N));
    /* exponential with sigma 2: mean 1/2, var 1/4 */
    ASSERT_NEAR(sexp / N, 0.5, 5.0 * sqrt(0.25 / N));
    /* cone: cos uniform on [cos_max, 1] */
    ASSERT_NEAR(scone / N, 0.5 * (1.0 + cos_max), 5.0 * (1.0 - cos_max) * sqrt(1.0 / 12.0 / N));
}

static void count_task(size_t task, int thread, void *user)
{
    (void)thread;
    long *out = user;
    out[task] += (long)task + 1;
}

/* Every task runs exactly once, whatever the thread count. */
TEST(pool_runs_each_task_once)
{
    enum { N = 1000 };
    static long out[N];
    for (int threads = 1; threads <= 4; threads++) {
        memset(out, 0, sizeof out);
        pool_run(threads, N, count_task, out);
        for (int i = 0; i < N; i++)
            ASSERT_EQ_INT(out[i], i + 1);
    }
}

/* Fixed-point sums (core/fixsum.h): carries into the high word, terms of 2^63 units and
 * more split exactly, and the same bits in any order and any split into partial sums. */
TEST(fixsum_is_exact_in_any_order)
{
    fixsum a = {0, 0};
    for (int i = 0; i < 8; i++) /* 8 (2^62 - 2^10) = 2^65 - 2^13: carries into the high word */
        fixsum_add(&a, 0x1p62 - 0x1p10);
    ASSERT_TRUE(a.hi == 1 && a.lo == UINT64_MAX - 8191);
    fixsum b = {0, 0};
    fixsum_add(&b, 0x1p70 + 0x1p20); /* a large term: 2^6 in the high word, 2^20 in the low */
    fixsum_add(&b, 3.75);            /* truncated to 3 */
    ASSERT_TRUE(b.hi == 64 && b.lo == (1ULL << 20) + 3);
    ASSERT_NEAR(fixsum_value(b), 0x1p70, 1e-12 * 0x1p70);
    fixsum c = {0, 0};
    fixsum_add(&c, 1e300); /* beyond the ceiling: 2^127 */
    ASSERT_TRUE(c.hi == 1ULL << 63 && c.lo == 0);

    /* terms over 30 orders of magnitude, summed forwards, backwards, and in three
     * interleaved partial sums merged: the same bits, and the exact sum within one unit per
     * term (the truncations) and the double rounding of the reference */
    enum { N = 5000 };
    static double x[N];
    rng g = rng_make(11, 0, 0);
    long double ref = 0.0L;
    for (int i = 0; i < N; i++) {
        x[i] = ldexp(rng_next(&g), (int)(rng_next(&g) * 100.0)); /* [0, 2^100) */
        ref += (long double)x[i];
    }
    fixsum fwd = {0, 0}, bwd = {0, 0}, part[3] = {{0, 0}, {0, 0}, {0, 0}}, merged = {0, 0};
    for (int i = 0; i < N; i++) {
        fixsum_add(&fwd, x[i]);
        fixsum_add(&bwd, x[N - 1 - i]);
        fixsum_add(&part[(i * 7) % 3], x[i]);
    }
    for (int k = 2; k >= 0; k--)
        fixsum_merge(&merged, part[k]);
    ASSERT_TRUE(fwd.lo == bwd.lo && fwd.hi == bwd.hi);
    ASSERT_TRUE(fwd.lo == merged.lo && fwd.hi == merged.hi);
    ASSERT_NEAR(fixsum_value(fwd), (double)ref, 1e-15 * (double)ref + N);
    ASSERT_TRUE(fwd.hi > 0); /* the sum passed 2^64: the high word was exercised */
}

TEST_MAIN(frame_orthonormal, box_intersect, rng_determinism, rng_uniform_chi2, rng_independence,
          sampling_moments, pool_runs_each_task_once, fixsum_is_exact_in_any_order)
