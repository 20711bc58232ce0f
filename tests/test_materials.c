/* test_materials.c - the material types (surface/material.h, docs/surfaces.md "Materials"):
 * every sampler against its pdf (chi-square, the pdf's integral), f against the sampler's
 * weights, reciprocity, the smooth lobes against Fresnel and Snell computed here, furnaces
 * (a glass sphere under a constant sky is the sky; a smooth metal sphere is the sky times
 * the cosine-weighted mean of the conductor Fresnel term integrated here), and the scene
 * readers' refusals, each naming what it refuses. */
#include "test.h"

#include <complex.h>
#include <math.h>
#include <stdint.h>

#include "brume.h"
#include "core/error.h"
#include "core/rng.h"
#include "gpu/device_scene.h"
#include "render/integrator.h"
#include "scene/scene.h"
#include "surface/material.h"
#include "surface/surfaces_impl.h"

#define PI_D 3.14159265358979323846
#define NT 24 /* bins in cos(theta) about the normal, over [-1, 1] */
#define NP 24 /* bins in azimuth */
#define SUB 40 /* quadrature points per bin and axis (the pdf's edges need them) */
#define SUBC 6 /* the same for coateddiffuse's stochastic f, which is slow to evaluate */

/* The chi-square quantile at 1 - 1e-5 (Wilson and Hilferty 1931). */
static double chi2_quantile(int dof)
{
    const double z = 4.2649;
    double a = 2.0 / (9.0 * dof);
    double c = 1.0 - a + z * sqrt(a);
    return dof * c * c * c;
}

/* The test's own frame about n. */
typedef struct tframe {
    vec3 s, t, n;
} tframe;
static tframe tframe_of(vec3 n)
{
    vec3 a = fabs(n.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0);
    tframe f = {.n = n};
    f.s = v3_normalize(v3_cross(n, a));
    f.t = v3_cross(n, f.s);
    return f;
}
static vec3 tdir(const tframe *f, double ct, double phi)
{
    double st = sqrt(fmax(0.0, 1.0 - ct * ct));
    return v3_add(v3_add(v3_scale(f->s, st * cos(phi)), v3_scale(f->t, st * sin(phi))), v3_scale(f->n, ct));
}
static void tbin(const tframe *f, vec3 w, int *i, int *j)
{
    double ct = v3_dot(w, f->n), phi = atan2(v3_dot(w, f->t), v3_dot(w, f->s));
    if (phi < 0.0)
        phi += 2.0 * PI_D;
    *i = (int)((ct + 1.0) / 2.0 * NT);
    *j = (int)(phi / (2.0 * PI_D) * NP);
    *i = *i < 0 ? 0 : (*i >= NT ? NT - 1 : *i);
    *j = *j < 0 ? 0 : (*j >= NP ? NP - 1 : *j);
}

/* Integral over bin (i, j) of g(w) d omega, midpoint rule on SUB x SUB points of equal area. */
typedef double (*dir_fn)(const material *m, vec3 ng, vec3 wo, vec3 wi, int channel);
static double bin_integral(dir_fn g, const material *m, const tframe *f, vec3 wo, int i, int j, int channel)
{
    double sum = 0.0, da = (2.0 / NT) * (2.0 * PI_D / NP) / (SUB * SUB);
    for (int a = 0; a < SUB; a++)
        for (int b = 0; b < SUB; b++) {
            double ct = -1.0 + (i + (a + 0.5) / SUB) * 2.0 / NT, phi = (j + (b + 0.5) / SUB) * 2.0 * PI_D / NP;
            sum += g(m, f->n, wo, tdir(f, ct, phi), channel);
        }
    return sum * da;
}
/* The same integral and its standard error read as a Monte Carlo estimate from the spread
 * of the points (stratified, so this over-states it): for a stochastic integrand. */
static double bin_integral_se(dir_fn g, const material *m, const tframe *f, vec3 wo, int i, int j, int channel,
                              double *se)
{
    double sum = 0.0, sum2 = 0.0, area = (2.0 / NT) * (2.0 * PI_D / NP);
    const int n = SUBC * SUBC;
    for (int a = 0; a < SUBC; a++)
        for (int b = 0; b < SUBC; b++) {
            double ct = -1.0 + (i + (a + 0.5) / SUBC) * 2.0 / NT, phi = (j + (b + 0.5) / SUBC) * 2.0 * PI_D / NP;
            double v = g(m, f->n, wo, tdir(f, ct, phi), channel);
            sum += v;
            sum2 += v * v;
        }
    double mean = sum / n;
    *se = area * sqrt(fmax(0.0, sum2 / n - mean * mean) / n);
    return area * mean;
}
static double pdf_fn(const material *m, vec3 ng, vec3 wo, vec3 wi, int c)
{
    (void)c;
    return material_pdf(m, ng, wo, wi);
}
static double fcos_fn(const material *m, vec3 ng, vec3 wo, vec3 wi, int c)
{
    return material_eval(m, ng, wo, wi).c[c] * fabs(v3_dot(wi, ng));
}

static material conductor(double alpha)
{
    return (material){.type = MATERIAL_CONDUCTOR, .eta_c = col_rgb(0.2, 0.92, 1.1), .k_c = col_rgb(3.9, 2.45, 2.14),
                      .alpha = alpha};
}
static material dielectric(double eta, double alpha)
{
    return (material){.type = MATERIAL_DIELECTRIC, .eta = eta, .alpha = alpha};
}
static material coated(double alpha, double layer_albedo, double thickness, int nsamples)
{
    return (material){.type = MATERIAL_COATEDDIFFUSE, .albedo = col_rgb(0.6, 0.4, 0.2), .eta = 1.5, .alpha = alpha,
                      .thickness = thickness, .layer_albedo = col(layer_albedo), .g = 0.3, .max_depth = 10,
                      .nsamples = nsamples};
}

typedef struct bsdf_case {
    const char *label;
    material m;
    double wo_cos; /* cos(theta) of wo about the front normal; < 0: from behind */
} bsdf_case;

#define NSAMPLES 400000
static const vec3 NG = {0.2, -0.3, 0.9327379053088815};

/* Directions from material_sample against material_pdf: the chi-square of the (cos theta,
 * azimuth) histogram, the failed samples a bin of their own (expected: 1 minus the pdf's
 * integral); each sample's pdf and f equal material_pdf and material_eval there. */
static void chi_square_case(const bsdf_case *c, uint64_t stream)
{
    static double observed[NT][NP];
    memset(observed, 0, sizeof observed);
    tframe f = tframe_of(NG);
    vec3 wo = tdir(&f, c->wo_cos, 0.7);
    rng r = rng_make(777, stream, 0);
    double failed = 0.0;
    for (int n = 0; n < NSAMPLES; n++) {
        bsdf_sample s;
        double u0 = rng_next(&r), u1 = rng_next(&r), u2 = rng_next(&r);
        if (!material_sample(&c->m, NG, wo, u0, u1, u2, &s)) {
            failed += 1.0;
            continue;
        }
        if (s.delta)
            TEST_FAIL("%s: a delta sample from a rough lobe", c->label);
        double want = material_pdf(&c->m, NG, wo, s.wi);
        color fw = material_eval(&c->m, NG, wo, s.wi);
        if (!(fabs(s.pdf - want) <= 1e-6 * want) || !(fabs(s.f.c[1] - fw.c[1]) <= 1e-6 * fw.c[1]))
            TEST_FAIL("%s: sample pdf %.12g f %.12g; at its direction pdf %.12g f %.12g", c->label, s.pdf, s.f.c[1],
                      want, fw.c[1]);
        int i, j;
        tbin(&f, s.wi, &i, &j);
        observed[i][j] += 1.0;
    }
    double chi2 = 0.0, pool_obs = 0.0, pool_exp = 0.0, mass_total = 0.0;
    int bins = 0;
    for (int i = 0; i < NT; i++)
        for (int j = 0; j < NP; j++) {
            double mass = bin_integral(pdf_fn, &c->m, &f, wo, i, j, 0);
            mass_total += mass;
            double e = NSAMPLES * mass, o = observed[i][j];
            if (e < 5.0) {
                pool_obs += o;
                pool_exp += e;
                continue;
            }
            chi2 += (o - e) * (o - e) / e;
            bins++;
        }
    double e_fail = NSAMPLES * (1.0 - mass_total);
    pool_obs += failed;
    pool_exp += fmax(e_fail, 0.0);
    if (pool_exp >= 5.0) {
        chi2 += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        bins++;
    }
    double limit = chi2_quantile(bins - 1);
    printf("  %-36s chi2 %7.1f dof %3d limit %6.1f  integral of pdf %.5f, samples sent %.5f\n", c->label, chi2,
           bins - 1, limit, mass_total, 1.0 - failed / NSAMPLES);
    if (!(chi2 <= limit))
        TEST_FAIL("%s: chi-square %.1f with %d dof exceeds %.1f (p < 1e-5)", c->label, chi2, bins - 1, limit);
    /* the pdf integrates to the share of samples the lobes send (binomial error, 5 sigma,
       plus the quadrature's 0.3 %) */
    double p = 1.0 - failed / NSAMPLES;
    ASSERT_NEAR(mass_total, p, 5.0 * sqrt(p * (1.0 - p) / NSAMPLES) + 3e-3);
}

static const bsdf_case rough_cases[] = {
    {"diffuse (Lambert + Phong)", {.type = MATERIAL_DIFFUSE, .albedo = {{0.5, 0.5, 0.5}}, .specular = {{0.3, 0.3, 0.3}}, .exponent = 20}, 0.6},
    {"conductor alpha 0.3", {.type = MATERIAL_CONDUCTOR, .eta_c = {{0.2, 0.92, 1.1}}, .k_c = {{3.9, 2.45, 2.14}}, .alpha = 0.3}, 0.64},
    {"conductor alpha 0.3 from behind", {.type = MATERIAL_CONDUCTOR, .eta_c = {{0.2, 0.92, 1.1}}, .k_c = {{3.9, 2.45, 2.14}}, .alpha = 0.3}, -0.5},
    {"conductor alpha 0.7 grazing", {.type = MATERIAL_CONDUCTOR, .eta_c = {{0.2, 0.92, 1.1}}, .k_c = {{3.9, 2.45, 2.14}}, .alpha = 0.7}, 0.15},
    {"dielectric 1.5 alpha 0.3", {.type = MATERIAL_DIELECTRIC, .eta = 1.5, .alpha = 0.3}, 0.7},
    {"dielectric 1.5 alpha 0.3 inside", {.type = MATERIAL_DIELECTRIC, .eta = 1.5, .alpha = 0.3}, -0.8},
    {"dielectric 1.5 alpha 0.5 inside, TIR", {.type = MATERIAL_DIELECTRIC, .eta = 1.5, .alpha = 0.5}, -0.4},
    {"dielectric 1.33 alpha 0.6", {.type = MATERIAL_DIELECTRIC, .eta = 1.33, .alpha = 0.6}, 0.3},
};

TEST(samplers_follow_their_pdf)
{
    for (int k = 0; k < (int)(sizeof rough_cases / sizeof rough_cases[0]); k++)
        chi_square_case(&rough_cases[k], (uint64_t)k);
}

/* The mean of f cos / pdf over samples (the albedo a path sees) against the integral of
 * f cos over the sphere by quadrature, per channel: 5 standard errors plus 0.5 % for the
 * quadrature. */
TEST(albedo_matches_integral_of_f_cos)
{
    for (int k = 0; k < (int)(sizeof rough_cases / sizeof rough_cases[0]); k++) {
        const bsdf_case *c = &rough_cases[k];
        tframe f = tframe_of(NG);
        vec3 wo = tdir(&f, c->wo_cos, 0.7);
        rng r = rng_make(778, (uint64_t)k, 0);
        double sum[3] = {0}, sum2[3] = {0};
        const int n = 200000;
        for (int i = 0; i < n; i++) {
            bsdf_sample s;
            double u0 = rng_next(&r), u1 = rng_next(&r), u2 = rng_next(&r);
            if (!material_sample(&c->m, NG, wo, u0, u1, u2, &s))
                continue;
            for (int ch = 0; ch < 3; ch++) {
                double w = s.f.c[ch] * fabs(v3_dot(s.wi, NG)) / s.pdf;
                sum[ch] += w;
                sum2[ch] += w * w;
            }
        }
        for (int ch = 0; ch < 3; ch++) {
            double q = 0.0;
            for (int i = 0; i < NT; i++)
                for (int j = 0; j < NP; j++)
                    q += bin_integral(fcos_fn, &c->m, &f, wo, i, j, ch);
            double mean = sum[ch] / n, se = sqrt(fmax(0.0, sum2[ch] / n - mean * mean) / n);
            if (ch == 0)
                printf("  %-36s albedo sampled %.5f +- %.5f, integrated %.5f\n", c->label, mean, se, q);
            ASSERT_NEAR(mean, q, 5.0 * se + 5e-3 * q);
        }
    }
}

/* f(wi, wo) = f(wo, wi) for reflection, at random pairs of directions on one side. */
TEST(reflection_is_reciprocal)
{
    const material ms[] = {conductor(0.2), conductor(0.8), dielectric(1.5, 0.3), dielectric(1.7, 0.05)};
    rng r = rng_make(779, 0, 0);
    for (int k = 0; k < (int)(sizeof ms / sizeof ms[0]); k++)
        for (int n = 0; n < 2000; n++) {
            double side = n % 2 ? 1.0 : -1.0; /* a dielectric is reciprocal on each side */
            vec3 a = v3_normalize(v3(rng_next(&r) - 0.5, rng_next(&r) - 0.5, side * (0.05 + rng_next(&r))));
            vec3 b = v3_normalize(v3(rng_next(&r) - 0.5, rng_next(&r) - 0.5, side * (0.05 + rng_next(&r))));
            double f1 = material_eval(&ms[k], v3(0, 0, 1), a, b).c[0], f2 = material_eval(&ms[k], v3(0, 0, 1), b, a).c[0];
            if (!(fabs(f1 - f2) <= 1e-9 * fmax(f1, f2)))
                TEST_FAIL("material %d: f(a, b) %.15g != f(b, a) %.15g", k, f1, f2);
            ASSERT_TRUE(f1 >= 0.0);
        }
}

/* The test's own unpolarized Fresnel reflectance of an interface into the (complex) index n
 * from a medium of index 1, at cos_i (textbook form: r_s, r_p through sqrt(n^2 - sin^2)). */
static double fresnel_test(double complex n, double cos_i)
{
    double sin2 = 1.0 - cos_i * cos_i;
    double complex w = csqrt(n * n - sin2);
    double complex rs = (cos_i - w) / (cos_i + w), rp = (n * n * cos_i - w) / (n * n * cos_i + w);
    return 0.5 * (cabs(rs) * cabs(rs) + cabs(rp) * cabs(rp));
}

/* Smooth dielectric: reflection is chosen with probability R (Fresnel, computed here), its
 * weight f cos / pdf is 1; refraction obeys Snell's law, its weight is 1 / eta'^2 (radiance). */
TEST(smooth_dielectric_is_fresnel_and_snell)
{
    const double etas[] = {1.5, 1.33, 2.4};
    rng r = rng_make(780, 0, 0);
    for (int k = 0; k < 3; k++)
        for (int side = 0; side < 2; side++) {
            material m = dielectric(etas[k], 0.0);
            double ci = side ? -0.35 : 0.8, etap = side ? 1.0 / etas[k] : etas[k];
            vec3 wo = v3(sqrt(1.0 - ci * ci), 0, ci);
            double sin_t = sqrt(1.0 - ci * ci) / etap;
            double R = sin_t >= 1.0 ? 1.0 : fresnel_test(etap, fabs(ci));
            int n = 100000, refl = 0;
            for (int i = 0; i < n; i++) {
                bsdf_sample s;
                ASSERT_TRUE(material_sample(&m, v3(0, 0, 1), wo, rng_next(&r), rng_next(&r), rng_next(&r), &s));
                ASSERT_TRUE(s.delta);
                double w = s.f.c[0] * fabs(s.wi.z) / s.pdf;
                if (s.wi.z * ci > 0.0) {
                    refl++;
                    ASSERT_NEAR(s.wi.x, -wo.x, 1e-12);
                    ASSERT_NEAR(w, 1.0, 1e-12);
                } else {
                    ASSERT_NEAR(sqrt(s.wi.x * s.wi.x + s.wi.y * s.wi.y), sin_t, 1e-12);
                    ASSERT_NEAR(w, 1.0 / (etap * etap), 1e-12);
                }
                ASSERT_EQ_INT(material_pdf(&m, v3(0, 0, 1), wo, s.wi) == 0.0, 1);
            }
            printf("  eta %.2f %s: reflected %.5f, Fresnel %.5f\n", etas[k], side ? "inside" : "outside",
                   (double)refl / n, R);
            ASSERT_NEAR((double)refl / n, R, 5.0 * sqrt(R * (1.0 - R) / n) + 1e-12);
        }
}

/* Coated diffuse: its samples' weights f cos / pdf, summed per bin of the sphere, against the
 * quadrature of its (estimated) f cos over the bin; each bin within 5 standard errors of both
 * (the quadrature's from its points' spread: f is stochastic) plus 1 %, and the albedo within
 * 5 se plus 1 %. */
TEST(coated_diffuse_samples_match_its_f)
{
    const material ms[] = {coated(0.3, 0.0, 0.01, 8), coated(0.4, 0.5, 0.3, 8)};
    for (int k = 0; k < 2; k++) {
        const material *m = &ms[k];
        tframe f = tframe_of(NG);
        vec3 wo = tdir(&f, 0.6, 0.7);
        static double w[NT][NP], w2[NT][NP];
        memset(w, 0, sizeof w);
        memset(w2, 0, sizeof w2);
        rng r = rng_make(781, (uint64_t)k, 0);
        const int n = 200000;
        double total = 0.0, total2 = 0.0;
        for (int i = 0; i < n; i++) {
            bsdf_sample s;
            if (!material_sample(m, NG, wo, rng_next(&r), rng_next(&r), rng_next(&r), &s))
                continue;
            double x = s.f.c[0] * fabs(v3_dot(s.wi, NG)) / s.pdf;
            int bi, bj;
            tbin(&f, s.wi, &bi, &bj);
            w[bi][bj] += x;
            w2[bi][bj] += x * x;
            total += x;
            total2 += x * x;
        }
        double q_total = 0.0;
        for (int i = 0; i < NT; i++)
            for (int j = 0; j < NP; j++) {
                double se_q, q = bin_integral_se(fcos_fn, m, &f, wo, i, j, 0, &se_q), mean = w[i][j] / n;
                double se = sqrt(fmax(0.0, w2[i][j] / n - mean * mean) / n);
                q_total += q;
                if (!(fabs(mean - q) <= 5.0 * sqrt(se * se + se_q * se_q) + 0.01 * q + 1e-4))
                    TEST_FAIL("coated %d: bin (%d, %d): sampled %.6f +- %.6f, f cos integrated %.6f", k, i, j, mean, se,
                              q);
            }
        double mean = total / n, se = sqrt(fmax(0.0, total2 / n - mean * mean) / n);
        printf("  coated %d: albedo sampled %.5f +- %.5f, integrated %.5f\n", k, mean, se, q_total);
        ASSERT_NEAR(mean, q_total, 5.0 * se + 0.01 * q_total);
        ASSERT_TRUE(mean < 1.0);
    }
}

/* ---- furnaces: whole renders -------------------------------------------------------------- */

/* A sphere of radius 1 seen from 1000 away through a 0.15 degree view (its disk about 58 %
 * of the frame), under a sky of radiance 1, with the material JSON mat. */
static brume_image *sphere_under_sky(const char *mat, unsigned long long seed)
{
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 1000], \"look_at\": [0, 0, 0], \"fov\": 0.15},"
             " \"background\": [1, 1, 1], \"lights\": [],"
             " \"surfaces\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": %s}],"
             " \"render\": {\"width\": 48, \"height\": 48, \"spp\": 16, \"method\": \"path\", \"max_depth\": 400}}",
             mat);
    return test_render_json(json, seed);
}

/* A smooth dielectric sphere of any index under a constant sky is the sky: at every bounce
 * the Fresnel choice's weight is 1 (reflection) or 1 / eta'^2 (refraction, undone on the
 * way out), and the sphere absorbs nothing. Every path brings 1 but for Russian roulette
 * inside (where 1 / eta^2 < 0.25) and paths longer than max_depth (well under 1e-4):
 * within 5 standard errors of the image's mean plus 1e-4. */
TEST(glass_sphere_furnace_is_the_sky)
{
    const char *mats[] = {"{\"type\": \"dielectric\", \"eta\": 1.5}", "{\"type\": \"dielectric\", \"eta\": 2.4}",
                          "{\"type\": \"dielectric\", \"eta\": \"glass-BK7\"}"};
    for (int k = 0; k < 3; k++) {
        brume_image *img = sphere_under_sky(mats[k], 5);
        const float *px = brume_image_pixels(img);
        int n = brume_image_width(img) * brume_image_height(img);
        for (int c = 0; c < 3; c++) {
            double mean, se;
            test_channel_mean(px, n, c, &mean, &se);
            printf("  %s channel %d: %.7f +- %.7f\n", mats[k], c, mean, se);
            ASSERT_NEAR(mean, 1.0, 5.0 * se + 1e-4);
        }
        brume_image_release(img);
    }
}

/* A smooth conductor sphere under a sky of 1: a camera ray hitting it at cosine mu sees
 * F(mu), and over the disk (seen from far away) mu has density 2 mu, so the disk's mean is
 * the hemispherical average 2 int F(mu) mu d mu, integrated here by Simpson's rule with the
 * test's own Fresnel. The disk's share of the image comes from the same render with a black
 * sphere (the same camera samples): mean = (1 - share) + share F_avg. Tolerance: the view's
 * 1e-3 departure from parallel rays and the pixels' spread. */
TEST(metal_sphere_furnace_is_the_fresnel_average)
{
    brume_image *black = sphere_under_sky("{\"albedo\": 0}", 6);
    brume_image *metal = sphere_under_sky("{\"type\": \"conductor\", \"eta\": [0.2, 0.92, 1.1], \"k\": [3.9, 2.45, 2.14]}", 6);
    const double eta[3] = {0.2, 0.92, 1.1}, k[3] = {3.9, 2.45, 2.14};
    int n = brume_image_width(black) * brume_image_height(black);
    for (int c = 0; c < 3; c++) {
        double mb, sb, mm, sm;
        test_channel_mean(brume_image_pixels(black), n, c, &mb, &sb);
        test_channel_mean(brume_image_pixels(metal), n, c, &mm, &sm);
        double share = 1.0 - mb, F_avg = 0.0;
        const int steps = 2000;
        for (int i = 0; i <= steps; i++) {
            double mu = (double)i / steps, w = (i == 0 || i == steps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
            F_avg += w * 2.0 * mu * fresnel_test(eta[c] + I * k[c], mu);
        }
        F_avg /= 3.0 * steps;
        double got = (mm - (1.0 - share)) / share;
        printf("  channel %d: disk share %.4f, metal mean %.5f, Fresnel average %.5f\n", c, share, got, F_avg);
        ASSERT_TRUE(share > 0.3);
        ASSERT_NEAR(got, F_avg, 3e-3);
    }
    brume_image_release(black);
    brume_image_release(metal);
}

/* Light reached after a delta bounce counts in full: a smooth mirror of normal reflectance
 * 0.5 (pbrt-v4's reflectance form: eta 1, k = 2 sqrt(0.5) / sqrt(0.5)) seen head-on through
 * a 2 degree view reflects a 20 x 20 emitter 10 above it, behind the camera (Le = 2), which
 * fills the reflected view: every pixel is F Le, F within 2e-5 of 0.5 over the view (the
 * test's Fresnel). Weighing the hit against light sampling (the emitter's solid-angle pdf is
 * 10^2 / 20^2 = 0.25) takes 6 % off; sampling the emitter at the mirror as well adds to it. */
TEST(delta_bounce_sees_emitter_in_full)
{
    brume_image *img = test_render_json(
        "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"fov\": 2}, \"lights\": [],"
        " \"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1], \"size\": 100,"
        "   \"material\": {\"type\": \"conductor\", \"reflectance\": 0.5}},"
        "  {\"type\": \"quad\", \"corner\": [-10, -10, 10], \"edge_u\": [0, 20, 0], \"edge_v\": [20, 0, 0],"
        "   \"material\": {\"albedo\": 0, \"emission\": 2}}],"
        " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 8, \"method\": \"path\"}}",
        8);
    const double F = fresnel_test(1.0 + I * 2.0, 1.0), F_edge = fresnel_test(1.0 + I * 2.0, cos(1.5 * PI_D / 180.0));
    ASSERT_NEAR(F, 0.5, 1e-12);
    const float *px = brume_image_pixels(img);
    for (int i = 0; i < 16 * 16; i++)
        for (int c = 0; c < 3; c++)
            if (!(fabs(px[4 * i + c] - 2.0 * F) <= 2.0 * fabs(F_edge - F) + 1e-5))
                TEST_FAIL("pixel %d channel %d: %.7f, want F Le = %.7f", i, c, px[4 * i + c], 2.0 * F);
    brume_image_release(img);
}

/* A refracting surface changes the path's media: an index-matched (eta 1: every ray goes
 * straight through, weight 1) dielectric sphere of radius 1 holding an absorbing ink
 * (sigma_a 0.7, bounded by the sphere: medium_inside) in a box of it 8 wide, under a sky of 1.
 * Through the disk, at impact parameter b, the ink's chord is 2 sqrt(1 - b^2): over the disk
 * (mu = sqrt(1 - b^2) with density 2 mu, far view) the mean is 2 int exp(-2 sigma mu) mu d mu,
 * integrated here; the disk's share from a black sphere, as above; within 5 standard errors
 * of the image's mean (from the pixels' spread, which the chords' range across the disk
 * dominates: 0.07) plus 1e-3. A path that kept the outside's media inside sees no ink (mean
 * 1); one that kept the ink outside sees the whole box (about 0). */
TEST(refraction_changes_the_media)
{
    const char *ink = "\"media\": [{\"name\": \"ink\", \"sigma_a\": 0.7, \"sigma_s\": 0, \"density\": {\"type\":"
                      " \"constant\", \"value\": 1, \"bounds\": [[-4, -4, -4], [4, 4, 4]]}}],";
    char json[2048];
    const char *mats[] = {"{\"albedo\": 0}", "{\"type\": \"dielectric\", \"eta\": 1}"};
    double mean[2], se[2];
    int n = 0;
    for (int k = 0; k < 2; k++) {
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 0, 1000], \"look_at\": [0, 0, 0], \"fov\": 0.15},"
                 " \"background\": [1, 1, 1], \"lights\": [], %s"
                 " \"surfaces\": [{\"type\": \"sphere\", \"radius\": 1, \"material\": %s, \"medium_inside\": \"ink\"}],"
                 " \"render\": {\"width\": 48, \"height\": 48, \"spp\": 64, \"method\": \"path\"}}",
                 ink, mats[k]);
        brume_image *img = test_render_json(json, 9);
        n = brume_image_width(img) * brume_image_height(img);
        test_channel_mean(brume_image_pixels(img), n, 0, &mean[k], &se[k]);
        brume_image_release(img);
    }
    double share = 1.0 - mean[0], want = 0.0;
    const int steps = 2000;
    for (int i = 0; i <= steps; i++) {
        double mu = (double)i / steps, w = (i == 0 || i == steps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        want += w * 2.0 * mu * exp(-2.0 * 0.7 * mu);
    }
    want /= 3.0 * steps;
    double got = (mean[1] - (1.0 - share)) / share;
    printf("  disk share %.4f: mean transmittance through the inked sphere %.5f +- %.5f, want %.5f\n", share, got,
           se[1] / share, want);
    ASSERT_TRUE(share > 0.3);
    ASSERT_NEAR(got, want, 5.0 * se[1] / share + 1e-3);
}

/* ---- the readers: what they accept and what they refuse, by name -------------------------- */

static brume_status load(const char *path, const char *text, brume_scene **out, char *msg, size_t cap)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = path, .text = text}, NULL, &s);
    if (st == BRUME_OK)
        st = brume_scene_commit(ctx, s);
    snprintf(msg, cap, "%s", st == BRUME_OK ? "" : brume_context_last_error(ctx));
    if (out && st == BRUME_OK)
        *out = s;
    else
        brume_scene_release(s);
    brume_context_release(ctx);
    return st;
}

#define CAMERA "{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0]}, "

static void json_refused(const char *mat, const char *frag)
{
    char json[1024], msg[2048];
    snprintf(json, sizeof json, CAMERA "\"surfaces\": [{\"type\": \"sphere\", \"material\": %s}]}", mat);
    ASSERT_TRUE(load("<test>", json, NULL, msg, sizeof msg) != BRUME_OK);
    ASSERT_CONTAINS(msg, frag);
    ASSERT_CONTAINS(msg, "surfaces[0].material");
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
}

TEST(json_material_refusals_name_the_key)
{
    json_refused("{\"type\": \"glass\"}", "unknown material type 'glass'");
    json_refused("{\"type\": \"dielectric\", \"albedo\": 0.5}", "albedo");
    json_refused("{\"type\": \"dielectric\", \"eta\": [1.4, 1.5, 1.6]}", "does not disperse");
    json_refused("{\"type\": \"conductor\", \"eta\": \"metal-Xx-eta\"}", "unknown spectrum \"metal-Xx-eta\"");
    json_refused("{\"type\": \"conductor\", \"eta\": 1, \"reflectance\": 0.5}", "either eta and k or reflectance");
    json_refused("{\"type\": \"conductor\", \"uroughness\": 0.1, \"vroughness\": 0.2}", "isotropic");
    json_refused("{\"type\": \"coateddiffuse\", \"thickness\": 0}", "thickness");
}

/* What the JSON reader makes of each type: pbrt-v4's defaults and its roughness remap. */
TEST(json_materials_read_with_pbrt_defaults)
{
    brume_scene *s = NULL;
    char msg[2048];
    ASSERT_EQ_INT(load("<test>",
                       CAMERA "\"surfaces\": [{\"type\": \"sphere\", \"material\": {\"type\": \"conductor\", \"roughness\": 0.09}},"
                       " {\"type\": \"sphere\", \"material\": {\"type\": \"conductor\", \"reflectance\": 0.5,"
                       "  \"roughness\": 0.09, \"remaproughness\": false}},"
                       " {\"type\": \"sphere\", \"material\": {\"type\": \"coateddiffuse\"}},"
                       " {\"type\": \"sphere\", \"material\": {\"type\": \"conductor\", \"eta\": \"metal-Au-eta\", \"k\": \"metal-Au-k\"}}]}",
                       &s, msg, sizeof msg),
                  BRUME_OK);
    const material *m0 = &s->surf->obj[0].mat, *m1 = &s->surf->obj[1].mat, *m2 = &s->surf->obj[2].mat,
                   *m3 = &s->surf->obj[3].mat;
    ASSERT_EQ_INT(m0->type, MATERIAL_CONDUCTOR);
    ASSERT_NEAR(m0->alpha, 0.3, 1e-15);      /* sqrt(0.09) */
    ASSERT_NEAR(m0->eta_c.c[0], 0.104495, 1e-12); /* pbrt-v4's default, metal-Cu */
    ASSERT_NEAR(m1->alpha, 0.09, 1e-15);
    /* reflectance r: eta 1, k = 2 sqrt(r) / sqrt(1 - r), whose normal-incidence Fresnel is r */
    ASSERT_NEAR(m1->eta_c.c[1], 1.0, 0.0);
    ASSERT_NEAR(fresnel_test(m1->eta_c.c[1] + I * m1->k_c.c[1], 1.0), 0.5, 1e-12);
    ASSERT_EQ_INT(m2->type, MATERIAL_COATEDDIFFUSE);
    ASSERT_NEAR(m2->albedo.c[0], 0.5, 0.0);
    ASSERT_NEAR(m2->thickness, 0.01, 0.0);
    ASSERT_NEAR(m2->eta, 1.5, 0.0);
    ASSERT_EQ_INT(m2->max_depth, 10);
    ASSERT_EQ_INT(m2->nsamples, 1);
    ASSERT_NEAR(m3->k_c.c[2], 1.770891, 1e-12);
    brume_scene_release(s);
}

static const char *pbrt_path(void) { return test_tmp_path("mat.pbrt"); }

/* A pbrt file whose world holds `world`, loaded. */
static brume_status load_pbrt(const char *world, brume_scene **out, char *msg, size_t cap)
{
    char text[4096];
    snprintf(text, sizeof text,
             "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [30]\nWorldBegin\n%s", world);
    test_write_file(pbrt_path(), text);
    return load(pbrt_path(), NULL, out, msg, cap);
}

static void pbrt_refused(const char *world, int line, const char *frag)
{
    char msg[2048], want[1200];
    ASSERT_TRUE(load_pbrt(world, NULL, msg, sizeof msg) != BRUME_OK);
    snprintf(want, sizeof want, "%s:%d: ", pbrt_path(), line);
    ASSERT_CONTAINS(msg, want);
    ASSERT_CONTAINS(msg, frag);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
}

TEST(pbrt_materials_refused_by_name)
{
    pbrt_refused("Material \"coatedconductor\"\n", 4, "Material \"coatedconductor\": not supported by brume");
    pbrt_refused("Material \"conductor\" \"spectrum eta\" \"metal-Zz-eta\"\n", 4, "unknown named spectrum \"metal-Zz-eta\"");
    pbrt_refused("Material \"diffuse\" \"string normalmap\" \"n.png\"\n", 4, "\"normalmap\"");
    pbrt_refused("Material \"coateddiffuse\" \"texture displacement\" \"d\"\n", 4, "no float Texture named \"d\"");
    pbrt_refused("Material \"dielectric\" \"texture roughness\" \"t\"\n", 4, "no float Texture named \"t\"");
    pbrt_refused("Material \"dielectric\" \"texture eta\" \"t\"\n", 4, "\"eta\": a texture");
    pbrt_refused("Material \"dielectric\" \"float uroughness\" 0.1 \"float vroughness\" 0.2\n", 4, "isotropic");
    pbrt_refused("Material \"dielectric\" \"rgb eta\" [1.4 1.5 1.6]\n", 4, "does not disperse");
    pbrt_refused("MakeNamedMaterial \"m\" \"string type\" \"conductor\" \"float shininess\" 3\n", 4, "shininess");
}

/* pbrt-v4's materials read with their parameters, by Material and MakeNamedMaterial. */
TEST(pbrt_materials_read)
{
    brume_scene *s = NULL;
    char msg[2048];
    ASSERT_EQ_INT(load_pbrt("Material \"dielectric\" \"spectrum eta\" \"glass-BK7\" \"float roughness\" 0.04\n"
                            "Shape \"sphere\"\n"
                            "MakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\""
                            " \"spectrum k\" \"metal-Au-k\" \"bool remaproughness\" false \"float roughness\" 0.2\n"
                            "NamedMaterial \"gold\"\nShape \"sphere\"\n"
                            "Material \"coateddiffuse\" \"rgb reflectance\" [0.1 0.2 0.3] \"float thickness\" 0.05"
                            " \"rgb albedo\" [0.5 0.5 0.5] \"float g\" 0.2 \"integer maxdepth\" 7 \"integer nsamples\" 2\n"
                            "Shape \"sphere\"\n",
                            &s, msg, sizeof msg),
                  BRUME_OK);
    const material *g = &s->surf->obj[0].mat, *au = &s->surf->obj[1].mat, *c = &s->surf->obj[2].mat;
    ASSERT_EQ_INT(g->type, MATERIAL_DIELECTRIC);
    ASSERT_NEAR(g->eta, 1.518537, 1e-12);
    ASSERT_NEAR(g->alpha, 0.2, 1e-15);
    ASSERT_EQ_INT(au->type, MATERIAL_CONDUCTOR);
    ASSERT_NEAR(au->alpha, 0.2, 0.0);
    ASSERT_NEAR(au->eta_c.c[0], 0.080051, 1e-12);
    ASSERT_EQ_INT(c->type, MATERIAL_COATEDDIFFUSE);
    ASSERT_NEAR(c->albedo.c[2], 0.3, 0.0);
    ASSERT_NEAR(c->layer_albedo.c[0], 0.5, 0.0);
    ASSERT_NEAR(c->thickness, 0.05, 0.0);
    ASSERT_NEAR(c->g, 0.2, 0.0);
    ASSERT_EQ_INT(c->max_depth, 7);
    ASSERT_EQ_INT(c->nsamples, 2);
    brume_scene_release(s);
}

/* A dielectric's inside is behind pbrt's normal, (p1 - p0) x (p2 - p0) for a triangle (+z
 * here), also where the reader mirrors the world (a view without "Scale -1 1 1") or the
 * transform does (mirroring x keeps z): brume's front normal, the counter-clockwise side in
 * world space, must point along +z in every case. */
TEST(pbrt_dielectric_mesh_faces_pbrt_normal)
{
    const char *views[] = {"", "Scale -1 1 1\n"};
    const char *xforms[] = {"", "Scale -1 1 1\n"};
    for (int v = 0; v < 2; v++)
        for (int x = 0; x < 2; x++) {
            char text[1024], msg[2048];
            snprintf(text, sizeof text,
                     "%sLookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [30]\nWorldBegin\n%s"
                     "Material \"dielectric\"\nShape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0]"
                     " \"integer indices\" [0 1 2]\n",
                     views[v], xforms[x]);
            test_write_file(pbrt_path(), text);
            brume_scene *s = NULL;
            ASSERT_EQ_INT(load(pbrt_path(), NULL, &s, msg, sizeof msg), BRUME_OK);
            const surface_object *o = &s->surf->obj[0];
            vec3 p[3];
            for (int k = 0; k < 3; k++)
                p[k] = v3(o->pos[3 * o->idx[k]], o->pos[3 * o->idx[k] + 1], o->pos[3 * o->idx[k] + 2]);
            vec3 n = v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
            if (!(n.z > 0.0))
                TEST_FAIL("view %d, transform %d: front normal (%g, %g, %g), pbrt's is +z", v, x, n.x, n.y, n.z);
            brume_scene_release(s);
        }
}

/* The GPU and the methods without BSDF sampling refuse the new types by name. */
TEST(gpu_and_blasi_refuse_the_new_types)
{
    const char *mats[] = {"dielectric", "conductor", "coateddiffuse"};
    for (int k = 0; k < 3; k++) {
        char json[1024], msg[2048];
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0]},"
                 " \"surfaces\": [{\"type\": \"sphere\", \"name\": \"ball\", \"material\": {\"type\": \"%s\"}}],"
                 " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 1.0, \"density\": {\"type\": \"constant\","
                 " \"bounds\": [[-2,-2,-2],[2,2,2]]}}], \"render\": {\"width\": 4, \"height\": 4, \"spp\": 1,"
                 " \"method\": \"blasi\"}}",
                 mats[k]);
        brume_scene *s = NULL;
        ASSERT_EQ_INT(load("<test>", json, &s, msg, sizeof msg), BRUME_OK);
        ASSERT_EQ_INT(device_scene_check(s, INTEGRATOR_PATH), BRUME_ERROR_UNSUPPORTED);
        ASSERT_CONTAINS(err_message(), "ball: material '");
        ASSERT_CONTAINS(err_message(), mats[k]);
        ASSERT_CONTAINS(err_message(), "renders on the CPU only (--device cpu)");
        brume_context *ctx = brume_context_new();
        brume_image *img = NULL;
        ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_ERROR_UNSUPPORTED);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "needs the path or single method");
        brume_context_release(ctx);
        brume_scene_release(s);
    }
}

TEST_MAIN(samplers_follow_their_pdf, albedo_matches_integral_of_f_cos, reflection_is_reciprocal,
          smooth_dielectric_is_fresnel_and_snell, coated_diffuse_samples_match_its_f, glass_sphere_furnace_is_the_sky,
          metal_sphere_furnace_is_the_fresnel_average, delta_bounce_sees_emitter_in_full, refraction_changes_the_media,
          json_material_refusals_name_the_key,
          json_materials_read_with_pbrt_defaults, pbrt_materials_refused_by_name, pbrt_materials_read,
          pbrt_dielectric_mesh_faces_pbrt_normal, gpu_and_blasi_refuse_the_new_types)
