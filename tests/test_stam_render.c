/* test_stam_render.c - Stam's stochastic renderer: with eps = 0 it is single scattering of
 * the mean field, the light cache is close to exact shadow rays, thread counts do not change
 * the image, grid media and bad kernel files are refused, a tabulated kernel renders the
 * same field in stam and single, and overlapping blobs render with their joint covariance. */
#include "test.h"

#include "brume.h"
#include "core/error.h"
#include "scene/scene.h"
#include "stam_profiles.h"

static brume_image *render(const char *json, const char *method, int spp, int threads, uint64_t seed)
{
    brume_scene *s = test_scene_json(json);
    brume_context *ctx = brume_context_new();
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    ASSERT_EQ_INT(brume_method_from_name(NULL, method, &rs.method), BRUME_OK);
    rs.spp = spp;
    rs.threads = threads;
    rs.seed = seed;
    brume_image *img = NULL;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK ||
        brume_render(ctx, s, &img) != BRUME_OK)
        TEST_FAIL("render %s: %s", method, brume_context_last_error(ctx));
    brume_context_release(ctx);
    brume_scene_release(s);
    return img;
}

/* A few overlapping blobs, lit by a sun, emitting, in front of a wall that the sun lights
 * through them (background %g: black for the comparison with `single`, whose in-scattered
 * sky light Stam's source function leaves to the ambient term). The box filter
 * of width 1e-3 px makes every sample of a pixel the same camera ray. */
#define WALL "{\"type\": \"quad\", \"corner\": [-2, -2, -1], \"edge_u\": [4, 0, 0], \"edge_v\": [0, 4, 0]}"
#define FEW_BLOBS_JSON \
    "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30}," \
    " \"background\": %g, \"surfaces\": [%s]," \
    " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.5, -0.6, -0.62], \"irradiance\": 3.0}]," \
    " \"media\": [{\"sigma_a\": 0.6, \"sigma_s\": %g, \"emission\": %s, \"density\": {\"type\": \"blobs\"," \
    "   \"blobs\": [[0, 0, 0, 0.5, 0.3], [0.3, 0.1, 0, 0.3, 0.25], [-0.25, -0.1, 0.2, 0.4, 0.3], [0.1, 0.3, -0.2, 0.2, 0.2]]}}]," \
    " \"stam\": {\"eps\": %g, \"eta\": 0.5, \"alpha\": 0.05, \"steps\": %d, \"light_grid\": %d}," \
    " \"render\": {\"width\": 24, \"height\": 24, \"filter\": {\"type\": \"box\", \"width\": 0.001}}}"

/* With eps = 0 Stam's image is the deterministic emission-absorption and single-scattering
 * image of the mean field (exact shadow rays, 128 steps): it must match the `single`
 * estimator on the same blob field, once for a scattering medium in front of a lit wall and
 * once for an emitting, absorbing one alone (emitted light scattered once by the medium or
 * the wall is counted by `single`, not by Stam's source function). Tolerance: 5 standard errors of the image mean of
 * `single` (from two independent renders) plus 0.5 % for the step quadrature; each pixel
 * within 5 of its own standard errors plus 2 %. */
TEST(eps_zero_matches_single_scattering)
{
    const double sigma_s[2] = {2.5, 0.0};
    const char *emission[2] = {"0", "[0.3, 0.15, 0.05]"};
    for (int k = 0; k < 2; k++) {
        char json[2048];
        snprintf(json, sizeof json, FEW_BLOBS_JSON, 0.0, k == 0 ? WALL : "", sigma_s[k], emission[k], 0.0, 128, 0);
        brume_image *st = render(json, "stam", 1, 0, 1);
        brume_image *a = render(json, "single", 128, 0, 1), *b = render(json, "single", 128, 0, 2);
        const float *ps = brume_image_pixels(st), *pa = brume_image_pixels(a), *pb = brume_image_pixels(b);
        int n = 24 * 24;
        for (int c = 0; c < 3; c++) {
            double ms = 0, mr = 0, var = 0, sq = 0;
            for (int i = 0; i < n; i++) {
                double ref = 0.5 * (pa[4 * i + c] + pb[4 * i + c]), d = pa[4 * i + c] - pb[4 * i + c];
                var += d * d / 4.0; /* estimates the variance of the mean of the two renders */
                ms += ps[4 * i + c];
                mr += ref;
                sq += (ps[4 * i + c] - ref) * (ps[4 * i + c] - ref);
            }
            double se = sqrt(var) / n;
            printf("case %d channel %d: stam %.5f, single %.5f +- %.5f; rms difference %.5f, noise %.5f\n", k, c,
                   ms / n, mr / n, se, sqrt(sq / n), sqrt(var / n));
            ASSERT_NEAR(ms / n, mr / n, 5.0 * se + 0.005 * mr / n);
            /* pixel by pixel: the difference is the reference's noise, plus at most 1 % */
            ASSERT_TRUE(sqrt(sq / n) <= 1.3 * sqrt(var / n) + 0.01 * mr / n);
        }
        brume_image_release(st);
        brume_image_release(a);
        brume_image_release(b);
    }
}

/* The light-transparency cache stays within 2 % of exact shadow rays on the image mean. */
TEST(light_cache_close_to_exact_shadow_rays)
{
    char json[2048];
    snprintf(json, sizeof json, FEW_BLOBS_JSON, 0.3, WALL, 2.5, "[0.3, 0.15, 0.05]", 0.3, 16, 0);
    brume_image *exact = render(json, "stam", 1, 0, 1);
    snprintf(json, sizeof json, FEW_BLOBS_JSON, 0.3, WALL, 2.5, "[0.3, 0.15, 0.05]", 0.3, 16, 32);
    brume_image *cached = render(json, "stam", 1, 0, 1);
    double se = 0, sc = 0;
    for (int i = 0; i < 24 * 24 * 4; i++)
        if (i % 4 != 3) {
            se += brume_image_pixels(exact)[i];
            sc += brume_image_pixels(cached)[i];
        }
    ASSERT_NEAR(sc, se, 0.02 * se);
    brume_image_release(exact);
    brume_image_release(cached);
}

/* Stam's 24 x 24 image of `json` is bit-identical with 1 and 2 threads, and `other`'s differs. */
static void threads_same_other_differs(const char *json, const char *other)
{
    brume_image *a = render(json, "stam", 2, 1, 1), *b = render(json, "stam", 2, 2, 1);
    brume_image *c = render(other, "stam", 2, 2, 1);
    size_t bytes = 24 * 24 * 4 * sizeof(float);
    ASSERT_TRUE(memcmp(brume_image_pixels(a), brume_image_pixels(b), bytes) == 0);
    ASSERT_TRUE(memcmp(brume_image_pixels(a), brume_image_pixels(c), bytes) != 0);
    brume_image_release(a);
    brume_image_release(b);
    brume_image_release(c);
}

/* Renders with 1 and 2 threads are bit-identical, and eps changes the image. */
TEST(threads_do_not_change_the_image)
{
    char json[2048], other[2048];
    snprintf(json, sizeof json, FEW_BLOBS_JSON, 0.3, WALL, 2.5, "[0.3, 0.15, 0.05]", 0.3, 16, 16);
    snprintf(other, sizeof other, FEW_BLOBS_JSON, 0.3, WALL, 2.5, "[0.3, 0.15, 0.05]", 0.0, 16, 16);
    threads_same_other_differs(json, other);
}

/* A medium that is not a blob field: --method stam says so plainly. */
TEST(grid_media_are_refused)
{
    const char *json = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0]},"
                       " \"media\": [{\"name\": \"fog\", \"sigma_a\": 1, \"sigma_s\": 1, \"density\": {\"type\": \"constant\"}}],"
                       " \"render\": {\"width\": 8, \"height\": 8, \"method\": \"stam\"}}";
    brume_scene *s = test_scene_json(json);
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_ERROR_UNSUPPORTED);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "media[0] fog: method stam renders blob fields only");
    ASSERT_TRUE(img == NULL);
    brume_context_release(ctx);
    brume_scene_release(s);
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
        brume_context *ctx = brume_context_new();
        ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s), BRUME_OK);
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
        brume_context *ctx = brume_context_new();
        ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s), BRUME_OK);
        ASSERT_TRUE(brume_scene_commit(ctx, s) != BRUME_OK);
        printf("%s\n", brume_context_last_error(ctx));
        ASSERT_CONTAINS(brume_context_last_error(ctx), bad[c][1]);
        brume_context_release(ctx);
        brume_scene_release(s);
    }
}

/* ---- rendering ----------------------------------------------------------------------------- */

/* Overlapping blobs, a sun, a black sky (Stam's source function has no sky light); the box
 * filter of width 1e-3 px makes every sample of a pixel the same camera ray. %s: blobs,
 * then the extra "stam" keys. */
#define SWITCH_JSON                                                                                                \
    "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30}, \"background\": 0,"             \
    " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.5, -0.6, -0.62], \"irradiance\": 3.0}],"             \
    " \"media\": [{\"sigma_a\": 0.6, \"sigma_s\": 2.5, \"density\": {\"type\": \"blobs\", \"blobs\": [%s]}}],"       \
    " \"stam\": {\"eps\": %g, \"eta\": 0.5, \"alpha\": 0.05%s},"                 \
    " \"render\": {\"width\": 24, \"height\": 24, \"filter\": {\"type\": \"box\", \"width\": 0.001}}}"
/* Stam's source function with exact shadow rays and 128 steps (against `single`). */
#define EXACT ", \"steps\": 128, \"light_grid\": 0"
#define FEW "[0, 0, 0, 0.5, 0.3], [0.3, 0.1, 0, 0.3, 0.25], [-0.25, -0.1, 0.2, 0.4, 0.3], [0.1, 0.3, -0.2, 0.2, 0.2]"

/* Every method renders the same field with a tabulated kernel: with eps = 0, Stam's image
 * of a cone-kernel field (its ray integrals from the line table) matches `single` on the same
 * field (its point densities and majorants from the 1-D table), within 5 standard errors of
 * single's image mean plus 0.5 % for the step quadrature, as
 * eps_zero_matches_single_scattering does for the gaussian; the gaussian's image differs. */
TEST(tabulated_kernel_renders_the_same_field_in_stam_and_single)
{
    const char *path = write_profile("cone3.txt", cone, 64, 2.0 / 64);
    char json[4096], extra[1100], json_g[4096];
    snprintf(extra, sizeof extra, "%s, \"kernel\": \"table\", \"kernel_file\": \"%s\"", EXACT, path);
    snprintf(json, sizeof json, SWITCH_JSON, FEW, 0.0, extra);
    snprintf(json_g, sizeof json_g, SWITCH_JSON, FEW, 0.0, EXACT);
    brume_image *st = render(json, "stam", 1, 0, 1), *g = render(json_g, "stam", 1, 0, 1);
    brume_image *a = render(json, "single", 128, 0, 1), *b = render(json, "single", 128, 0, 2);
    const float *ps = brume_image_pixels(st), *pa = brume_image_pixels(a), *pb = brume_image_pixels(b);
    const float *pg = brume_image_pixels(g);
    int n = 24 * 24;
    for (int c = 0; c < 3; c++) {
        double ms = 0, mr = 0, var = 0, mg = 0;
        for (int i = 0; i < n; i++) {
            double d = pa[4 * i + c] - pb[4 * i + c];
            var += d * d / 4.0;
            ms += ps[4 * i + c];
            mg += pg[4 * i + c];
            mr += 0.5 * (pa[4 * i + c] + pb[4 * i + c]);
        }
        double se = sqrt(var) / n;
        printf("channel %d: stam (cone) %.5f, single (cone) %.5f +- %.5f, stam (gaussian) %.5f\n", c, ms / n, mr / n, se,
               mg / n);
        ASSERT_NEAR(ms / n, mr / n, 5.0 * se + 0.005 * mr / n);
        ASSERT_TRUE(fabs(mg - ms) / n > 5.0 * se + 0.005 * mr / n);
    }
    brume_image_release(st);
    brume_image_release(g);
    brume_image_release(a);
    brume_image_release(b);
    remove(path);
}

/* stam.overlap = joint: bit-identical with 1 and 2 threads; different from independent where
 * blobs overlap; equal to it (to rounding) where each ray meets one blob, whose joint variance
 * is its own. (Q on the paper's 32^3 lattice: its period does not matter here, and its
 * synthesis is 60 times cheaper than the covering lattice's.) */
TEST(joint_overlap_renders)
{
    char json[4096], other[4096];
    snprintf(json, sizeof json, SWITCH_JSON, FEW, 0.4, ", \"lattice\": 32, \"overlap\": \"joint\"");
    snprintf(other, sizeof other, SWITCH_JSON, FEW, 0.4, ", \"lattice\": 32");
    threads_same_other_differs(json, other);
    snprintf(json, sizeof json, SWITCH_JSON, "[0, 0, 0, 0.5, 0.3]", 0.4, ", \"lattice\": 32, \"overlap\": \"joint\"");
    brume_image *j = render(json, "stam", 1, 0, 1);
    snprintf(json, sizeof json, SWITCH_JSON, "[0, 0, 0, 0.5, 0.3]", 0.4, ", \"lattice\": 32");
    brume_image *i = render(json, "stam", 1, 0, 1);
    double worst = 0.0;
    for (int k = 0; k < 24 * 24 * 4; k++)
        worst = fmax(worst, fabs(brume_image_pixels(j)[k] - brume_image_pixels(i)[k]));
    printf("one blob: joint and independent differ by at most %.3g\n", worst);
    ASSERT_TRUE(worst < 1e-6);
    brume_image_release(j);
    brume_image_release(i);
}

TEST_MAIN(eps_zero_matches_single_scattering, light_cache_close_to_exact_shadow_rays, threads_do_not_change_the_image,
          grid_media_are_refused, bad_kernel_files_are_refused,
          tabulated_kernel_renders_the_same_field_in_stam_and_single, joint_overlap_renders)
