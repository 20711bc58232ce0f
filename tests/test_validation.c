/* test_validation.c - the path tracer's random walk against published radiative-transfer
 * results and independent quadratures (brume slab runs the renderer's own flight, phase
 * and scattering code).
 *
 * Each check asserts |estimate - reference| <= 5 standard errors (plus the rounding of the
 * published figure) AND 5 standard errors < 1 % of the reference, so that a 1 % energy
 * error would fail. Seeds are fixed. */
#include "test.h"

#include "render/slab.h"

#ifndef M_PI_VALUE
#define M_PI_VALUE 3.14159265358979323846
#endif

static slab_result slab(double albedo, double tau, phase *ph, uint64_t samples, int max_depth)
{
    slab_params p = {albedo, tau, ph, samples, 12345, 0, max_depth, BRUME_SAMPLER_INDEPENDENT};
    slab_result r;
    ASSERT_EQ_INT(slab_run(&p, &r), BRUME_OK);
    phase_release(ph);
    return r;
}

static void check(const char *what, double est, double se, double ref, double ref_rounding)
{
    fprintf(stderr, "%s: %.6f +- %.6f, reference %.6f\n", what, est, se, ref);
    ASSERT_NEAR(est, ref, 5.0 * se + ref_rounding);
    if (!(5.0 * se < 0.01 * ref))
        TEST_FAIL("%s: standard error %.3g too large to detect a 1%% error of %.5g", what, se, ref);
}

/* van de Hulst 1980 (Multiple Light Scattering, Table 35), as used to validate MCML
 * (Wang, Jacques, Zheng 1995, Table 2): albedo 0.9, tau 2, HG g = 0.75. */
TEST(slab_van_de_hulst)
{
    slab_result r = slab(0.9, 2.0, phase_new_hg(0.75), 4000000, 1 << 30);
    check("Rd", r.Rd, r.Rd_stderr, 0.09739, 5e-6);
    check("Tt", r.Tt, r.Tt_stderr, 0.66096, 5e-6);
}

/* Prahl's adding-doubling program, its own regression case: albedo 0.9, tau 1, g = 0.8. */
TEST(slab_adding_doubling)
{
    slab_result r = slab(0.9, 1.0, phase_new_hg(0.8), 8000000, 1 << 30);
    check("Rd", r.Rd, r.Rd_stderr, 0.04242, 5e-6);
    check("Tt", r.Tt, r.Tt_stderr, 0.84561, 5e-6);
}

/* Chandrasekhar's H function for isotropic scattering of albedo a, by iterating
 *   1 / H(mu) = sqrt(1 - a) + (a / 2) int_0^1 mu' H(mu') / (mu + mu') dmu'
 * (Chandrasekhar 1960, Eq. V.41's alternative form) on a 200-point Gauss-Legendre rule,
 * independent of anything in brume. Returns H(1). */
static double chandrasekhar_H1(double a)
{
    enum { N = 200 };
    double x[N], w[N], H[N];
    for (int i = 0; i < N; i++) { /* Gauss-Legendre on [0, 1] by Newton on P_N */
        double z = cos(M_PI_VALUE * (i + 0.75) / (N + 0.5)), dp = 0.0;
        for (int it = 0; it < 100; it++) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= N; k++) {
                double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = N * (z * p1 - p0) / (z * z - 1.0);
            double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-15)
                break;
        }
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp); /* 2 / ((1 - z^2) P'^2), halved for [0, 1] */
        H[i] = 1.0;
    }
    double H1 = 1.0;
    for (int it = 0; it < 2000; it++) {
        double Hn[N];
        for (int i = 0; i < N; i++) {
            double s = 0.0;
            for (int j = 0; j < N; j++)
                s += w[j] * x[j] * H[j] / (x[i] + x[j]);
            Hn[i] = 1.0 / (sqrt(1.0 - a) + 0.5 * a * s);
        }
        double s1 = 0.0;
        for (int j = 0; j < N; j++)
            s1 += w[j] * x[j] * Hn[j] / (1.0 + x[j]);
        double H1n = 1.0 / (sqrt(1.0 - a) + 0.5 * a * s1);
        memcpy(H, Hn, sizeof H);
        if (fabs(H1n - H1) < 1e-13)
            return H1n;
        H1 = H1n;
    }
    return H1;
}

/* Semi-infinite isotropic medium at normal incidence: Rd = 1 - H(1) sqrt(1 - albedo). */
TEST(semi_infinite_isotropic)
{
    /* the tabulated H(1) of docs/validation.md (Chandrasekhar), and the quadrature above agree */
    ASSERT_NEAR(chandrasekhar_H1(0.9), 1.850099, 2e-6);
    ASSERT_NEAR(chandrasekhar_H1(0.5), 1.251260, 2e-6);
    slab_result r = slab(0.9, 0.0, phase_new_isotropic(), 1000000, 1 << 30);
    check("Rd(0.9)", r.Rd, r.Rd_stderr, 0.41495, 5e-6);
    ASSERT_EQ_INT(r.Tt, 0);
    r = slab(0.5, 0.0, phase_new_isotropic(), 2000000, 1 << 30);
    check("Rd(0.5)", r.Rd, r.Rd_stderr, 0.11523, 5e-6);
    const double albedos[2] = {0.3, 0.99};
    const uint64_t samples[2] = {8000000, 250000};
    for (int i = 0; i < 2; i++) {
        double ref = 1.0 - chandrasekhar_H1(albedos[i]) * sqrt(1.0 - albedos[i]);
        r = slab(albedos[i], 0.0, phase_new_isotropic(), samples[i], 1 << 30);
        check(i ? "Rd(0.99)" : "Rd(0.3)", r.Rd, r.Rd_stderr, ref, 1e-9);
    }
}

/* Single scattering in a half-space, isotropic, normal incidence:
 * R1 = (albedo / 2) (1 - ln 2) = 0.153426 albedo. */
TEST(single_scattering_half_space)
{
    slab_result r = slab(0.8, 0.0, phase_new_isotropic(), 2000000, 1);
    check("R1", r.Rd, r.Rd_stderr, 0.8 * 0.5 * (1.0 - log(2.0)), 1e-12);
}

/* Single scattering in a finite slab with a forward HG lobe, against a quadrature of
 *   R1 = 2 pi a int_0^1 p(-mu) (1 - exp(-tau (1 + 1/mu))) / (1 + 1/mu) dmu
 *   T1 = 2 pi a int_0^1 p(mu) exp(-tau / mu) (1 - exp(-tau (1 - 1/mu))) / (1 - 1/mu) dmu
 * (a photon scatters once at depth z with density exp(-z) and leaves with cosine mu);
 * Tt adds the unscattered exp(-tau). A sign error in the phase sampling swaps R1 and T1. */
TEST(single_scattering_slab_quadrature)
{
    const double a = 0.9, tau = 2.0, g = 0.75;
    double R1 = 0.0, T1 = 0.0;
    enum { M = 200000 };
    for (int i = 0; i < M; i++) { /* midpoint rule */
        double mu = (i + 0.5) / M;
        double pf = (1 - g * g) / (4 * M_PI_VALUE * pow(1 + g * g - 2 * g * mu, 1.5));
        double pb = (1 - g * g) / (4 * M_PI_VALUE * pow(1 + g * g + 2 * g * mu, 1.5));
        R1 += pb * (1 - exp(-tau * (1 + 1 / mu))) / (1 + 1 / mu);
        double c = 1 - 1 / mu;
        /* exp(-tau / mu) (1 - exp(-tau c)) / c, written without overflow for small mu */
        T1 += pf * (fabs(c) > 1e-9 ? (exp(-tau / mu) - exp(-tau)) / c : tau * exp(-tau));
    }
    R1 *= 2 * M_PI_VALUE * a / M;
    T1 *= 2 * M_PI_VALUE * a / M;
    slab_result r = slab(a, tau, phase_new_hg(g), 16000000, 1);
    check("R1", r.Rd, r.Rd_stderr, R1, 1e-6);
    check("T1 + exp(-tau)", r.Tt, r.Tt_stderr, T1 + exp(-tau), 1e-6);
}

/* Albedo 1: nothing is absorbed, every photon leaves by one face with weight 1, so
 * Rd + Tt = 1 to rounding, for any thickness and phase function. */
TEST(white_furnace_slab)
{
    slab_result r = slab(1.0, 3.0, phase_new_hg(0.9), 200000, 1 << 30);
    ASSERT_NEAR(r.Rd + r.Tt, 1.0, 1e-12);
    r = slab(1.0, 0.5, phase_new_rayleigh(), 200000, 1 << 30);
    ASSERT_NEAR(r.Rd + r.Tt, 1.0, 1e-12);
}

/* The estimate depends on the seed only, not on the thread count. */
TEST(slab_threads_identical)
{
    phase *ph = phase_new_hg(0.5);
    slab_params p1 = {0.9, 1.0, ph, 100000, 7, 1, 1 << 30, BRUME_SAMPLER_INDEPENDENT}, p2 = p1;
    p2.threads = 2;
    slab_result r1, r2;
    ASSERT_EQ_INT(slab_run(&p1, &r1), BRUME_OK);
    ASSERT_EQ_INT(slab_run(&p2, &r2), BRUME_OK);
    ASSERT_TRUE(r1.Rd == r2.Rd && r1.Tt == r2.Tt && r1.Rd_stderr == r2.Rd_stderr);
    phase_release(ph);
}

TEST_MAIN(slab_van_de_hulst, slab_adding_doubling, semi_infinite_isotropic, single_scattering_half_space,
          single_scattering_slab_quadrature, white_furnace_slab, slab_threads_identical)
