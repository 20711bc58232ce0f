/* test_phase.c - phase functions: normalization, mean cosine, chi-square of every sampler
 * against its own pdf, sign conventions, the Schlick fit against Blasi's Figure 7, and
 * the rejection of bad input. */
#include "test.h"

#include "core/error.h"
#include "core/rng.h"
#include "phase/phase.h"

/* ---- the functions under test ---------------------------------------------------------------- */

#define MAX_CASES 24

typedef struct phase_case {
    char label[64];
    phase *p;
} phase_case;

static int ncases;
static phase_case cases[MAX_CASES];

static void add_case(const char *label, phase *p)
{
    if (!p)
        TEST_FAIL("constructing %s failed: %s", label, err_message());
    snprintf(cases[ncases].label, sizeof cases[ncases].label, "%s", label);
    cases[ncases++].p = p;
}

/* A made-up forward-peaked table with a back lobe, unnormalized, written to a file. */
static const char *write_table_file(void)
{
    const char *path = test_tmp_path("table.txt");
    FILE *f = fopen(path, "w");
    if (!f)
        TEST_FAIL("cannot write %s", path);
    fprintf(f, "# angle value\n0 40\n2 30  # peak\n5 18\n10 7\n\n20 2.5\n45 0.6\n90 0.3\n"
               "135 0.45\n170 0.9\n180 1.0\n");
    fclose(f);
    return path;
}

static void make_cases(void)
{
    if (ncases)
        return;
    add_case("isotropic", phase_new_isotropic());
    add_case("rayleigh", phase_new_rayleigh());
    add_case("hazy", phase_new_mie_hazy());
    add_case("murky", phase_new_mie_murky());
    const double gs[] = {0.3, -0.3, 0.9, -0.9, 1e-7};
    for (int i = 0; i < 5; i++) {
        char l[64];
        snprintf(l, sizeof l, "hg %g", gs[i]);
        add_case(l, phase_new_hg(gs[i]));
    }
    const double ks[] = {0.5, -0.5, 0.95, -0.95, 1e-7};
    for (int i = 0; i < 5; i++) {
        char l[64];
        snprintf(l, sizeof l, "schlick %g", ks[i]);
        add_case(l, phase_new_schlick(ks[i]));
    }
    add_case("schlick mix fig 7 murky", phase_new_schlick_mix(0.19, -0.65, 0.91));
    phase *lobes[3] = {phase_new_hg(0.6), phase_new_rayleigh(), phase_new_mie_murky()};
    const double w[3] = {3.0, 5.0, 2.0}; /* unnormalized on purpose */
    add_case("mixture hg rayleigh murky", phase_new_mixture(3, w, lobes));
    const char *table = write_table_file();
    add_case("tabulated file", phase_load_tabulated(table));
    remove(table); /* loaded: the file is no longer needed */
    /* A table with an end short of 0 and of 180 degrees: values are held there. */
    const double ang[] = {10.0, 60.0, 120.0}, val[] = {5.0, 1.0, 2.0};
    add_case("tabulated short", phase_new_tabulated(3, ang, val));
}

/* ---- independent numerical integration ----------------------------------------------------- */

typedef double (*fn_t)(const phase *p, double t);

/* 2 pi p(t): the density of t. */
static double dens(const phase *p, double t) { return 2.0 * PI * phase_eval(p, t); }
static double dens_t(const phase *p, double t) { return t * 2.0 * PI * phase_eval(p, t); }

static double simpson_rec(fn_t f, const phase *p, double a, double b, double fa, double fm, double fb,
                          double whole, double tol, int depth)
{
    double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    double flm = f(p, lm), frm = f(p, rm);
    double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm), right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    if (depth <= 0 || fabs(left + right - whole) <= 15.0 * tol)
        return left + right + (left + right - whole) / 15.0;
    return simpson_rec(f, p, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1) +
           simpson_rec(f, p, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1);
}

/* Adaptive Simpson over [a, b], started on 64 panels so that no peak is missed. */
static double integrate(fn_t f, const phase *p, double a, double b)
{
    double s = 0.0;
    const int panels = 64;
    for (int i = 0; i < panels; i++) {
        double x0 = a + (b - a) * i / panels, x1 = a + (b - a) * (i + 1) / panels;
        double f0 = f(p, x0), f1 = f(p, x1), fm = f(p, 0.5 * (x0 + x1));
        double whole = (x1 - x0) / 6.0 * (f0 + 4.0 * fm + f1);
        s += simpson_rec(f, p, x0, x1, f0, fm, f1, whole, 1e-13, 40);
    }
    return s;
}

/* ---- normalization and mean cosine ------------------------------------------------------------ */

TEST(normalized)
{
    make_cases();
    for (int i = 0; i < ncases; i++) {
        double total = integrate(dens, cases[i].p, -1.0, 1.0);
        if (!(fabs(total - 1.0) <= 1e-6))
            TEST_FAIL("%s: integral over the sphere %.12f, want 1 within 1e-6", cases[i].label, total);
    }
}

TEST(mean_cosine)
{
    make_cases();
    for (int i = 0; i < ncases; i++) {
        double numeric = integrate(dens_t, cases[i].p, -1.0, 1.0);
        double claimed = phase_mean_cosine(cases[i].p);
        if (!(fabs(numeric - claimed) <= 1e-6))
            TEST_FAIL("%s: mean cosine %.10f, numerical integral %.10f", cases[i].label, claimed, numeric);
    }
    /* Closed forms that a wrong sign or constant would miss. */
    phase *p = phase_new_mie_hazy();
    ASSERT_NEAR(phase_mean_cosine(p), 0.4, 1e-12);
    phase_release(p);
    p = phase_new_mie_murky();
    ASSERT_NEAR(phase_mean_cosine(p), 8.0 / 17.0, 1e-12);
    phase_release(p);
    p = phase_new_hg(-0.7);
    ASSERT_NEAR(phase_mean_cosine(p), -0.7, 1e-15);
    phase_release(p);
}

/* ---- sampling ------------------------------------------------------------------------------- */

#define THETA_BINS 40
#define PHI_BINS 8
#define NSAMPLES 400000

/* The chi-square quantile at 1 - 1e-5 (Wilson and Hilferty 1931). */
static double chi2_quantile(int dof)
{
    const double z = 4.2649;
    double a = 2.0 / (9.0 * dof);
    double c = 1.0 - a + z * sqrt(a);
    return dof * c * c * c;
}

/* A frame around wi built independently of the library's, for the azimuth. */
static void test_frame(vec3 wi, vec3 *s, vec3 *t)
{
    vec3 a = fabs(wi.x) < 0.9 ? v3(1.0, 0.0, 0.0) : v3(0.0, 1.0, 0.0);
    *s = v3_normalize(v3_cross(wi, a));
    *t = v3_cross(wi, *s);
}

/* Chi-square of the joint histogram of (theta, azimuth) of sampled directions against
 * the integral of the pdf over each bin; bins expecting fewer than 5 are pooled. */
static void chi_square_case(const phase_case *c, uint64_t stream)
{
    static double observed[THETA_BINS][PHI_BINS];
    memset(observed, 0, sizeof observed);
    vec3 wi = v3_normalize(v3(0.3, -0.5, 0.8)), s, t;
    test_frame(wi, &s, &t);
    rng r = rng_make(12345, stream, 0);
    for (int n = 0; n < NSAMPLES; n++) {
        double u1 = rng_next(&r), u2 = rng_next(&r), pdf;
        vec3 wo = phase_sample(c->p, wi, u1, u2, &pdf);
        double ct = v3_dot(wo, wi);
        if (!(fabs(v3_length(wo) - 1.0) < 1e-9))
            TEST_FAIL("%s: sampled direction of length %.12f", c->label, v3_length(wo));
        double want = phase_pdf(c->p, ct);
        if (!(fabs(pdf - want) <= 1e-6 * want))
            TEST_FAIL("%s: sample pdf %.12g, phase_pdf at its cosine %.12g", c->label, pdf, want);
        if (!(fabs(pdf - phase_eval(c->p, ct)) <= 1e-12 * pdf))
            TEST_FAIL("%s: pdf %.12g != eval %.12g for an exact sampler", c->label, pdf, phase_eval(c->p, ct));
        double theta = acos(fmin(1.0, fmax(-1.0, ct)));
        double az = atan2(v3_dot(wo, t), v3_dot(wo, s)) + PI;
        int bt = (int)(theta / PI * THETA_BINS), bp = (int)(az / (2.0 * PI) * PHI_BINS);
        bt = bt < 0 ? 0 : (bt >= THETA_BINS ? THETA_BINS - 1 : bt);
        bp = bp < 0 ? 0 : (bp >= PHI_BINS ? PHI_BINS - 1 : bp);
        observed[bt][bp] += 1.0;
    }
    double chi2 = 0.0, pool_obs = 0.0, pool_exp = 0.0;
    int bins = 0;
    for (int i = 0; i < THETA_BINS; i++) {
        double t_hi = cos(PI * i / THETA_BINS), t_lo = cos(PI * (i + 1) / THETA_BINS);
        double mass = integrate(dens, c->p, t_lo, t_hi);
        for (int j = 0; j < PHI_BINS; j++) {
            double e = NSAMPLES * mass / PHI_BINS, o = observed[i][j];
            if (e < 5.0) {
                pool_obs += o;
                pool_exp += e;
                continue;
            }
            chi2 += (o - e) * (o - e) / e;
            bins++;
        }
    }
    if (pool_exp >= 5.0) {
        chi2 += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        bins++;
    } else if (pool_obs > 5.0 + 10.0 * pool_exp) {
        TEST_FAIL("%s: %g samples fell in bins expecting %g", c->label, pool_obs, pool_exp);
    }
    double limit = chi2_quantile(bins - 1);
    if (!(chi2 <= limit))
        TEST_FAIL("%s: chi-square %.1f with %d dof exceeds %.1f (p < 1e-5)", c->label, chi2, bins - 1, limit);
    printf("  %-28s chi2 %7.1f  dof %3d  limit %6.1f\n", c->label, chi2, bins - 1, limit);
}

TEST(chi_square)
{
    make_cases();
    for (int i = 0; i < ncases; i++)
        chi_square_case(&cases[i], (uint64_t)i);
}

/* Sampled cosines of HG and Schlick lean forward for g, k > 0 and backward for g, k < 0,
 * and their means match the mean cosines. */
TEST(sign_forward)
{
    vec3 wi = v3_normalize(v3(-0.2, 0.9, 0.1));
    const double params[] = {0.5, -0.5};
    for (int kind = 0; kind < 2; kind++)
        for (int i = 0; i < 2; i++) {
            phase *p = kind ? phase_new_schlick(params[i]) : phase_new_hg(params[i]);
            rng r = rng_make(7, (uint64_t)(2 * kind + i), 0);
            double sum = 0.0;
            const int n = 200000;
            for (int s = 0; s < n; s++) {
                double pdf, u1 = rng_next(&r), u2 = rng_next(&r);
                sum += v3_dot(phase_sample(p, wi, u1, u2, &pdf), wi);
            }
            double mean = sum / n;
            if (!(mean * params[i] > 0.0))
                TEST_FAIL("%s %g: mean sampled cosine %.4f has the wrong sign", kind ? "schlick" : "hg",
                          params[i], mean);
            ASSERT_NEAR(mean, phase_mean_cosine(p), 0.005);
            ASSERT_TRUE((phase_eval(p, 1.0) > phase_eval(p, -1.0)) == (params[i] > 0.0));
            phase_release(p);
        }
    phase *hazy = phase_new_mie_hazy(), *murky = phase_new_mie_murky();
    ASSERT_TRUE(phase_sample_cos(hazy, 0.999) > 0.9 && phase_sample_cos(murky, 0.5) > 0.5);
    phase_release(hazy);
    phase_release(murky);
}

/* Blasi Eq. 23 by hand at three points, and the closed forms at the ends. */
TEST(schlick_eq23)
{
    phase *p = phase_new_schlick(0.6);
    ASSERT_NEAR(phase_sample_cos(p, 0.0), -1.0, 1e-15);
    ASSERT_NEAR(phase_sample_cos(p, 0.5), 0.6, 1e-15);
    ASSERT_NEAR(phase_sample_cos(p, 0.25), (0.5 + 0.6 - 1.0) / (1.2 * 0.25 - 0.6 + 1.0), 1e-15);
    ASSERT_NEAR(4.0 * PI * phase_eval(p, 0.2), (1.0 - 0.36) / ((1.0 - 0.12) * (1.0 - 0.12)), 1e-14);
    phase_release(p);
    p = phase_new_rayleigh();
    for (double u = 0.0; u <= 1.0; u += 0.125) { /* F(t) = (t^3 + 3t + 4) / 8 */
        double t = phase_sample_cos(p, u);
        ASSERT_NEAR((t * t * t + 3.0 * t + 4.0) / 8.0, u, 1e-14);
    }
    phase_release(p);
}

/* ---- k and g ----------------------------------------------------------------------------------- */

TEST(k_g_map)
{
    ASSERT_NEAR(phase_schlick_k_from_g(0.5), 1.55 * 0.5 - 0.55 * 0.125, 1e-15);
    ASSERT_NEAR(phase_schlick_k_from_g(-0.3), -(1.55 * 0.3 - 0.55 * 0.027), 1e-15);
    for (double g = -0.93; g <= 0.93; g += 0.01)
        ASSERT_NEAR(phase_hg_g_from_schlick_k(phase_schlick_k_from_g(g)), g, 1e-12);
    ASSERT_TRUE(phase_schlick_k_from_g(0.99) < 1.0 && phase_schlick_k_from_g(-0.99) > -1.0);
    phase *p = phase_new_schlick(phase_schlick_k_from_g(0.99));
    ASSERT_TRUE(p != NULL);
    phase_release(p);
    ASSERT_NEAR(phase_hg_g_from_schlick_k(0.0), 0.0, 1e-15);
}

/* ---- fit ---------------------------------------------------------------------------------------- */

/* The fit is at least as close as Figure 7's parameters, in every norm, with the backward
 * lobe first. */
TEST(fit_beats_figure7)
{
    const char *names[3] = {"rayleigh", "hazy", "murky"};
    const double paper[3][3] = {{0.50, -0.46, 0.46}, {0.12, -0.50, 0.70}, {0.19, -0.65, 0.91}};
    const brume_phase_fit_norm norms[3] = {BRUME_PHASE_FIT_ANGLE, BRUME_PHASE_FIT_COS, BRUME_PHASE_FIT_LOG};
    for (int i = 0; i < 3; i++) {
        brume_phase *p = NULL;
        ASSERT_EQ_INT(brume_phase_new_named(NULL, names[i], &p), BRUME_OK);
        for (int j = 0; j < 3; j++) {
            brume_phase_fit fit;
            ASSERT_EQ_INT(brume_phase_fit_schlick_mix(NULL, p, norms[j], &fit), BRUME_OK);
            double e_paper = brume_phase_fit_error(p, norms[j], paper[i][0], paper[i][1], paper[i][2]);
            double e_fit = brume_phase_fit_error(p, norms[j], fit.r, fit.k, fit.kprime);
            printf("  %-8s %-5s fit r %.4f k %.4f k' %.4f error %.5f | figure 7 error %.5f\n", names[i],
                   brume_phase_fit_norm_name(norms[j]), fit.r, fit.k, fit.kprime, fit.error, e_paper);
            ASSERT_NEAR(e_fit, fit.error, 1e-12);
            if (!(fit.error <= e_paper))
                TEST_FAIL("%s, %s norm: fit error %.6f worse than figure 7's %.6f", names[i],
                          brume_phase_fit_norm_name(norms[j]), fit.error, e_paper);
            ASSERT_TRUE(fit.k < 0.0 && fit.kprime > 0.0 && fit.r >= 0.0 && fit.r <= 1.0);
        }
        brume_phase_release(p);
    }
}

/* A Schlick mixture is recovered exactly, and a Schlick function with r at an end. */
TEST(fit_recovers_mixture)
{
    brume_phase *p = NULL;
    ASSERT_EQ_INT(brume_phase_new_schlick_mix(NULL, 0.3, -0.4, 0.8, &p), BRUME_OK);
    brume_phase_fit fit;
    ASSERT_EQ_INT(brume_phase_fit_schlick_mix(NULL, p, BRUME_PHASE_FIT_ANGLE, &fit), BRUME_OK);
    ASSERT_NEAR(fit.r, 0.3, 1e-5);
    ASSERT_NEAR(fit.k, -0.4, 1e-5);
    ASSERT_NEAR(fit.kprime, 0.8, 1e-5);
    ASSERT_TRUE(fit.error < 1e-6);
    brume_phase_release(p);
    ASSERT_EQ_INT(brume_phase_new_schlick(NULL, 0.7, &p), BRUME_OK);
    ASSERT_EQ_INT(brume_phase_fit_schlick_mix(NULL, p, BRUME_PHASE_FIT_COS, &fit), BRUME_OK);
    ASSERT_TRUE(fit.error < 1e-5);
    ASSERT_NEAR((1 - 0.7 * 0.7) / pow(1 - 0.9 * 0.7, 2), /* 4 pi p of Schlick's k = 0.7 at cos 0.9 */
                fit.r * (1 - fit.k * fit.k) / pow(1 - 0.9 * fit.k, 2) +
                    (1 - fit.r) * (1 - fit.kprime * fit.kprime) / pow(1 - 0.9 * fit.kprime, 2),
                1e-4);
    brume_phase_release(p);
}

/* ---- bad input ---------------------------------------------------------------------------------- */

static void expect_null(phase *p, const char *needle)
{
    if (p)
        TEST_FAIL("expected a rejection mentioning \"%s\"", needle);
    ASSERT_CONTAINS(err_message(), needle);
}

static void expect_file_rejected(const char *name, const char *content, const char *needle)
{
    const char *path = test_tmp_path(name);
    FILE *f = fopen(path, "w");
    ASSERT_TRUE(f != NULL);
    fputs(content, f);
    fclose(f);
    expect_null(phase_load_tabulated(path), needle);
    ASSERT_CONTAINS(err_message(), path);
    expect_null(phase_new_from_name(path), needle);
    remove(path);
}

TEST(bad_input)
{
    expect_null(phase_new_hg(1.0), "g = 1");
    expect_null(phase_new_hg(-1.5), "-1.5");
    expect_null(phase_new_hg(NAN), "nan");
    expect_null(phase_new_schlick(1.0), "k = 1");
    expect_null(phase_new_schlick(-1.25), "-1.25");
    expect_null(phase_new_schlick_mix(1.2, 0.1, 0.2), "r = 1.2");
    expect_null(phase_new_schlick_mix(-0.1, 0.1, 0.2), "r = -0.1");
    expect_null(phase_new_schlick_mix(0.5, 0.1, 1.3), "1.3");
    expect_null(phase_new_schlick_mix(0.5, -2.5, 0.3), "-2.5");
    phase *lobes[2] = {phase_new_isotropic(), phase_new_rayleigh()};
    const double bad_w[2] = {1.0, -0.5}, zero_w[2] = {0.0, 0.0};
    expect_null(phase_new_mixture(2, bad_w, lobes), "-0.5");
    expect_null(phase_new_mixture(2, zero_w, lobes), "sum to 0");
    phase_release(lobes[0]); /* still ours after the failures */
    phase_release(lobes[1]);
    const double ang[3] = {0.0, 90.0, 45.0}, val[3] = {1.0, 1.0, 1.0};
    expect_null(phase_new_tabulated(3, ang, val), "45");
    const double ang2[2] = {0.0, 190.0};
    expect_null(phase_new_tabulated(2, ang2, val), "190");
    expect_null(phase_new_from_name("hg:abc"), "hg:abc");
    expect_null(phase_new_from_name("schlick:1.5"), "1.5");
    expect_null(phase_new_from_name("no-such-phase"), "no-such-phase");

    expect_file_rejected("dup.txt", "0 1\n# comment\n10 2\n10 3\n180 1\n", ":4: angle 10 after 10");
    expect_file_rejected("down.txt", "0 1\n30 2\n20 3\n", ":3: angle 20 after 30");
    expect_file_rejected("neg.txt", "0 1\n30 -2\n180 3\n", ":2: value -2");
    expect_file_rejected("nan.txt", "0 1\n30 nan\n180 3\n", ":2: value nan");
    expect_file_rejected("range.txt", "0 1\n200 2\n", ":2: angle 200");
    expect_file_rejected("text.txt", "0 1\nfoo 2\n", ":2: expected an angle");
    expect_file_rejected("three.txt", "0 1 7\n", ":1: unexpected \"7\"");
    expect_file_rejected("zero.txt", "0 0\n180 0\n", "every value is 0");
}

TEST_MAIN(normalized, mean_cosine, chi_square, sign_forward, schlick_eq23, k_g_map, fit_beats_figure7,
          fit_recovers_mixture, bad_input)
