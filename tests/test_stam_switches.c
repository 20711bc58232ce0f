/* test_stam_switches.c - Stam's two optional models (docs/stam.md): the tabulated radial
 * kernel W of Section 6.1 (`stam.kernel = table`, density/blob_kernel.h) against the
 * analytic gaussian and against quadrature of its own point field, with its file
 * validation; and the joint covariance of overlapping blobs (`stam.overlap = joint`)
 * against Monte Carlo over explicit 3-D realizations. */
#include "test.h"

#include "brume.h"
#include "core/error.h"
#include "core/rng.h"
#include "density/blobs.h"
#include "density/randfield.h"
#include "render/stam_stats.h"
#include "scene/scene.h"

/* Writes n + 1 rows "k ds  w(k ds)" of a profile to a temporary file. */
static const char *write_profile(const char *name, double (*w)(double), int n, double ds)
{
    const char *path = test_tmp_path(name);
    FILE *f = fopen(path, "w");
    ASSERT_TRUE(f);
    fprintf(f, "# r/h  W\n");
    for (int k = 0; k <= n; k++)
        fprintf(f, "%.17g %.17g\n", k * ds, w(k * ds));
    fclose(f);
    return path;
}

static double gaussian(double s) { return exp(-0.5 * s * s); }
static double cone(double s) { return 1.0 - s / 2.0; } /* on [0, 2] */

/* Composite Simpson over [a, b] (n even) of blob 0's truncated mean along o + u d. */
static double quad_mean(const blob_field *f, vec3 o, vec3 d, double a, double b, double eta, int n)
{
    double hstep = (b - a) / n, sum = 0.0;
    for (int k = 0; k <= n; k++)
        sum += stam_clamp(blob_mean_at(f, 0, v3_madd(o, d, a + k * hstep)), eta) *
               (k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0));
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

/* A gaussian written as a table (s = 0 .. 8, 2049 points) renders Appendix A's field: the
 * point density within the linear interpolation's error (ds^2 / 8 max|w''| = 1.9e-6 of the
 * peak, plus the normalisation's, of the same order), the ray integrals T_mean and I_F
 * within the bilinear error of the line table, gs^2 / 8 (max|G_xx| + max|G_dd|) <=
 * 1.2e-4 (0.61 + 2.51) = 3.8e-4 of peak h (gs = 8 / 256; G_xx = w'(r) x / r, |G_dd| <= the
 * integral of |w''| along the line, sqrt(2 pi)). */
TEST(tabulated_gaussian_matches_the_analytic_kernel)
{
    stam_stats_init();
    const char *path = write_profile("gauss.txt", gaussian, 2048, 8.0 / 2048);
    blob_kernel *k = blob_kernel_read(path, "stam.kernel_file");
    if (!k)
        TEST_FAIL("%s", err_message());
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
                vec3 d = v3_normalize(v3(0.2, 0.1, 1.0));
                vec3 side = v3_normalize(v3_cross(d, v3(0, 1, 0)));
                vec3 o = v3_sub(v3_add(b.x, v3_scale(side, offsets[oi])), v3_scale(d, 10.0));
                one_hit h = {0, 0, 0};
                blob_field_query_ray(ft, o, d, 0.0, 1e9, take_hit, &h);
                ASSERT_EQ_INT(h.count, 1);
                blob_ray ba = blob_ray_make(fa, 0, h.u, h.d2), bt = blob_ray_make(ft, 0, h.u, h.d2);
                double a = ends[ei][0], z = ends[ei][1];
                double want = isinf(etas[e]) ? blob_T_mean(&ba, a, z) : blob_T_clamped(&ba, etas[e], a, z);
                double got = isinf(etas[e]) ? blob_T_mean(&bt, a, z) : blob_T_clamped(&bt, etas[e], a, z);
                wt = fmax(wt, fabs(got - want));
                ASSERT_NEAR(got, want, tol);
            }
    printf("ray integrals: worst difference %.2e of peak h (bound 3.8e-4)\n", wt / (peak * b.h));
    blob_field_release(fa);
    blob_field_release(ft);
    remove(path);
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
    const char *path = write_profile("cone.txt", cone, 64, 2.0 / 64);
    blob_kernel *k = blob_kernel_read(path, "stam.kernel_file");
    if (!k)
        TEST_FAIL("%s", err_message());
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
                double want = quad_mean(f, o, d, a, z, etas[e], 200000);
                double got = isinf(etas[e]) ? blob_T_mean(&br, a, z) : blob_T_clamped(&br, etas[e], a, z);
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
    rng g = rng_make(5, 0, 0);
    for (int r = 0; r < 100; r++) {
        vec3 o = v3(6 * rng_next(&g) - 3, 6 * rng_next(&g) - 3, 6);
        vec3 t = v3(2 * rng_next(&g) - 1, rng_next(&g) - 0.5, 2 * rng_next(&g) - 1);
        ray ry = {o, v3_normalize(v3_sub(t, o)), 0.0};
        majorant_iter it;
        majorant_seg seg;
        density_majorant_begin(dn, ry, 0.0, 20.0, &it);
        while (majorant_next(&it, &seg))
            for (int q = 0; q < 8; q++) {
                vec3 x = ray_at(ry, seg.t0 + (seg.t1 - seg.t0) * rng_next(&g));
                ASSERT_TRUE(density_eval(dn, x) <= seg.rho_maj);
            }
    }
    density_release(dn);
    blob_list_free(&l);
    remove(path);
}

/* Bad kernel files: each refused when the scene is committed, with one line naming the file,
 * the field (stam.kernel_file) and what is wrong. */
TEST(bad_kernel_files_are_refused)
{
    static const struct {
        const char *text, *says;
    } cases[] = {
        {"0 1\n0.5 -0.1\n1 0\n", "line 2: W = -0.1 is negative"},
        {"0 1\n0.5 nan\n", "must be finite"},
        {"0 1\n0.5 inf\n", "must be finite"},
        {"0.1 1\n0.5 0.5\n", "line 1: the first r/h must be 0"},
        {"0 1\n0.5 0.8\n1 0.9\n", "line 3: W = 0.9 increases"},
        {"0 1\n0.5 0.5\n1.2 0\n", "line 3: r/h = 1.2, expected 1: the points must be evenly spaced"},
        {"0 1\n", "need at least two points"},
        {"# nothing\n", "need at least two points"},
        {"0 1\n0.5 0.5 7\n", "line 2: expected two numbers"},
        {"0 0\n1 0\n", "W(0) must be > 0"},
        {"0 1\n0 0.5\n", "line 2: r/h must increase"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        const char *path = test_tmp_path("bad-kernel.txt");
        FILE *fp = fopen(path, "w");
        fputs(cases[c].text, fp);
        fclose(fp);
        char json[2048];
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0]},"
                 " \"media\": [{\"sigma_a\": 1, \"sigma_s\": 1, \"density\": {\"type\": \"blobs\", \"blobs\": [[0, 0, 0, 1, 0.3]]}}],"
                 " \"stam\": {\"kernel\": \"table\", \"kernel_file\": \"%s\"}, \"render\": {\"width\": 8, \"height\": 8}}",
                 path);
        brume_scene *s = NULL;
        ASSERT_EQ_INT(scene_parse_json(json, "<test>", &s), BRUME_OK);
        brume_context *ctx = brume_context_new();
        ASSERT_TRUE(brume_scene_commit(ctx, s) != BRUME_OK);
        const char *msg = brume_context_last_error(ctx);
        printf("%s\n", msg);
        ASSERT_CONTAINS(msg, path);
        ASSERT_CONTAINS(msg, "stam.kernel_file");
        ASSERT_CONTAINS(msg, cases[c].says);
        ASSERT_TRUE(strchr(msg, '\n') == NULL);
        brume_context_release(ctx);
        brume_scene_release(s);
        remove(path);
    }
    /* a missing file, a table without a file, a file without the table */
    const char *bad[][2] = {
        {"\"kernel\": \"table\", \"kernel_file\": \"/nonexistent/k.txt\"", "/nonexistent/k.txt: stam.kernel_file: cannot open"},
        {"\"kernel\": \"table\"", "stam.kernel: table needs stam.kernel_file"},
        {"\"kernel_file\": \"k.txt\"", "stam.kernel_file: given, but stam.kernel is gaussian"},
    };
    for (int c = 0; c < 3; c++) {
        char json[2048];
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0]},"
                 " \"media\": [{\"sigma_a\": 1, \"sigma_s\": 1, \"density\": {\"type\": \"blobs\", \"blobs\": [[0, 0, 0, 1, 0.3]]}}],"
                 " \"stam\": {%s}, \"render\": {\"width\": 8, \"height\": 8}}",
                 bad[c][0]);
        brume_scene *s = NULL;
        ASSERT_EQ_INT(scene_parse_json(json, "<test>", &s), BRUME_OK);
        brume_context *ctx = brume_context_new();
        ASSERT_TRUE(brume_scene_commit(ctx, s) != BRUME_OK);
        printf("%s\n", brume_context_last_error(ctx));
        ASSERT_CONTAINS(brume_context_last_error(ctx), bad[c][1]);
        brume_context_release(ctx);
        brume_scene_release(s);
    }
}

TEST_MAIN(tabulated_gaussian_matches_the_analytic_kernel, tabulated_cone_kernel_is_consistent,
          bad_kernel_files_are_refused)
