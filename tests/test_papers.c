/* test_papers.c - the papers from the command line: scene overrides (--set), Stam's printed
 * and corrected variants, the period of Q, Blasi on blob fields, per-run statistics, scoring
 * a given phase fit and `brume figures`. */
#include "test.h"

#include "brume.h"
#include "core/error.h"
#include "density/blobs.h"
#include "density/randfield.h"
#include "figures_table.h"
#include "io/json.h"
#include "method/blasi_options.h"
#include "scene/scene.h"
#include "render/stam.h"

#define SCENE(name) BRUME_SOURCE_DIR "/scenes/" name

static brume_scene *load_with(const char *path, const char *const *ov, int n, brume_status want, const char *msg_part)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_load_options o = {0.0, 0, ov, n, NULL, 0, false};
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = path}, &o, &s);
    if (st != want)
        TEST_FAIL("load %s with %d overrides: status %d, want %d (%s)", path ? path : "default", n, (int)st, (int)want,
                  brume_context_last_error(ctx));
    if (msg_part) {
        printf("message: %s\n", brume_context_last_error(ctx));
        ASSERT_CONTAINS(brume_context_last_error(ctx), msg_part);
        ASSERT_TRUE(strchr(brume_context_last_error(ctx), '\n') == NULL); /* one line */
    }
    brume_context_release(ctx);
    return s;
}

/* --set on every kind of key: numbers, arrays as values, array indices in the path (both
 * spellings), keys nested in arrays of objects, bare strings, JSON strings, booleans,
 * objects created on the way; later overrides win. */
TEST(set_every_kind_of_key)
{
    const char *ov[] = {
        "camera.fov=30",                                   /* number */
        "camera.position=[0, 1, 7]",                       /* array value */
        "media.0.sigma_s=5",                               /* array index, grey colour */
        "media[0].sigma_a=[0.1, 0.2, 0.3]",                /* bracket spelling, RGB */
        "media.0.density.generators.0.count=50",           /* inside an array of objects */
        "stam.eps=0.1",                                    /* a method's key */
        "stam.variant=paper",                              /* a bare word is a string */
        "stam.bvh=false",                                  /* boolean */
        "render.spp=64",
        "render.method=\"path\"",                          /* a JSON string */
        "blasi.r=0.25",                                    /* "blasi" is created */
        "render.spp=65",                                   /* the later one wins */
    };
    brume_scene *s = load_with(SCENE("stam-fig5-a.json"), ov, (int)(sizeof ov / sizeof *ov), BRUME_OK, NULL);
    ASSERT_NEAR(s->cam.fov, 30.0, 0.0);
    ASSERT_NEAR(s->cam.position.z, 7.0, 0.0);
    ASSERT_NEAR(s->media[0].sigma_s.c[1], 5.0, 0.0);
    ASSERT_NEAR(s->media[0].sigma_a.c[2], 0.3, 1e-15);
    ASSERT_EQ_INT(density_get_blobs(s->media[0].rho)->n, 50);
    ASSERT_NEAR(((const stam_params *)scene_options(s, METHOD_OPTIONS_STAM))->eps, 0.1, 0.0);
    ASSERT_TRUE(((const stam_params *)scene_options(s, METHOD_OPTIONS_STAM))->paper);
    ASSERT_TRUE(!((const stam_params *)scene_options(s, METHOD_OPTIONS_STAM))->bvh);
    ASSERT_EQ_INT(s->settings.spp, 65);
    ASSERT_EQ_INT((int)s->settings.method, (int)BRUME_METHOD_PATH);
    ASSERT_NEAR(((const blasi_options *)scene_options(s, METHOD_OPTIONS_BLASI))->r, 0.25, 0.0);
    brume_scene_release(s);

    /* the built-in default scene (path NULL): a key of a generated grid changes the grid */
    const char *small[] = {"media.0.density.dims=[12, 8, 12]"};
    const char *seeded[] = {"media.0.density.dims=[12, 8, 12]", "media.0.density.seed=3"};
    brume_scene *a = load_with(NULL, small, 1, BRUME_OK, NULL), *b = load_with(NULL, seeded, 2, BRUME_OK, NULL);
    density_info ia;
    density_get_info(a->media[0].rho, &ia);
    ASSERT_EQ_INT(ia.n[0], 12);
    double diff = 0.0;
    for (int k = 0; k < 12; k++)
        for (int j = 0; j < 8; j++)
            for (int i = 0; i < 12; i++)
                diff += fabs(density_voxel(a->media[0].rho, i, j, k) - density_voxel(b->media[0].rho, i, j, k));
    ASSERT_TRUE(diff > 0.0);
    brume_scene_release(a);
    brume_scene_release(b);
}

/* Bad overrides: one line each, naming the key and what may be there. */
TEST(set_bad_keys)
{
    const char *unknown[] = {"stam.epz=0.1"};
    load_with(SCENE("stam-fig5-a.json"), unknown, 1, BRUME_ERROR_PARSE, "stam.epz: unknown key (known here: eps, eta");
    const char *top[] = {"cmaera.fov=30"};
    load_with(SCENE("stam-fig5-a.json"), top, 1, BRUME_ERROR_PARSE, "known here: camera, lights, media");
    const char *index[] = {"media.3.sigma_s=1"};
    load_with(SCENE("stam-fig5-a.json"), index, 1, BRUME_ERROR_PARSE, "media has 1 element: index 0 to 0");
    const char *through[] = {"camera.fov.x=1"};
    load_with(SCENE("stam-fig5-a.json"), through, 1, BRUME_ERROR_PARSE,
              "camera.fov is a number and has no key 'x' (the document has here: position, look_at, fov)");
    const char *range[] = {"camera.fov=400"};
    load_with(SCENE("stam-fig5-a.json"), range, 1, BRUME_ERROR_RANGE, "(set by override camera.fov=400)");
    const char *variant[] = {"stam.variant=printed"};
    load_with(SCENE("stam-fig5-a.json"), variant, 1, BRUME_ERROR_PARSE,
              "stam.variant: 'printed' is not one of corrected, paper");
    const char *noeq[] = {"camera.fov"};
    load_with(SCENE("stam-fig5-a.json"), noeq, 1, BRUME_ERROR_PARSE, "expected KEY=VALUE");

    /* the tool: exit status 1, one line on stderr naming the key */
    const char *err = test_tmp_path("set-err.txt");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s render %s --set stam.epz=0.1 -o %s 2>%s", BRUME_EXE, SCENE("stam-fig5-a.json"),
             test_tmp_path("never.png"), err);
    ASSERT_EQ_INT(test_system(cmd), 1);
    size_t n;
    char *text = test_slurp(err, &n);
    ASSERT_CONTAINS(text, "stam.epz: unknown key");
    ASSERT_TRUE(n > 0 && strchr(text, '\n') == text + n - 1);
    free(text);
    ASSERT_TRUE(!test_exists(test_tmp_path("never.png")));
    remove(err);
}

static brume_image *render_scene(brume_scene *s, const char *method, int threads, bool stats)
{
    brume_context *ctx = brume_context_new();
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    ASSERT_EQ_INT(brume_method_from_name(NULL, method, &rs.method), BRUME_OK);
    rs.threads = threads;
    rs.stats = stats;
    brume_image *img = NULL;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK ||
        brume_render(ctx, s, &img) != BRUME_OK)
        TEST_FAIL("render %s: %s", method, brume_context_last_error(ctx));
    brume_context_release(ctx);
    return img;
}

/* Three blobs on the left half of the picture, sky on the right; peaks 0.44-0.88 above eta. */
#define BLOBS_JSON                                                                                                     \
    "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}, \"background\": 0.5,"                 \
    " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.5, -0.6, -0.62], \"irradiance\": 3.0}],"                  \
    " \"media\": [{\"sigma_a\": 0.2, \"sigma_s\": 3, \"density\": {\"type\": \"blobs\","                               \
    "   \"blobs\": [[-0.8, 0, 0, 0.3, 0.3], [-0.6, 0.2, 0, 0.2, 0.25], [-0.9, -0.2, 0.2, 0.3, 0.3]]}}],"              \
    " \"stam\": {\"eps\": %g, \"eta\": 0.2, \"alpha\": 0.05, \"variant\": \"%s\", \"ambient\": 0.2},"                \
    " \"render\": {\"width\": 48, \"height\": 32, \"spp\": 1, \"filter\": {\"type\": \"box\", \"width\": 0.001}}%s}"

static brume_image *stam_image(double eps, const char *variant)
{
    char json[4096];
    snprintf(json, sizeof json, BLOBS_JSON, eps, variant, "");
    brume_scene *s = test_scene_json(json);
    brume_image *img = render_scene(s, "stam", 2, false);
    brume_scene_release(s);
    return img;
}

/* stam.variant: with eps = 0 both variants are the mean field's image, bit for bit; with eps > 0
 * they agree where no blob is (the right half) and differ where the paper's variance
 * (Eq. 12-13: K_Q(0)^2 eps I_F, here 4e6 times ours) does: the perturbation's spread over the
 * blobs' pixels, against the eps = 0 image, is far larger as printed. */
TEST(stam_variants_differ_where_the_variance_differs)
{
    brume_image *m0 = stam_image(0.0, "corrected"), *m1 = stam_image(0.0, "paper");
    const float *a = brume_image_pixels(m0), *b = brume_image_pixels(m1);
    for (int i = 0; i < 48 * 32 * 4; i++)
        ASSERT_TRUE(a[i] == b[i]);
    brume_image *c = stam_image(0.3, "corrected"), *p = stam_image(0.3, "paper");
    const float *pc = brume_image_pixels(c), *pp = brume_image_pixels(p);
    double dev_c = 0.0, dev_p = 0.0;
    int cloud = 0;
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 48; x++) {
            size_t i = 4 * ((size_t)y * 48 + (size_t)x);
            if (x >= 30) { /* sky only: no blob on the ray, nothing random */
                for (size_t ch = 0; ch < 4; ch++)
                    ASSERT_TRUE(pc[i + ch] == pp[i + ch] && pc[i + ch] == a[i + ch]);
                continue;
            }
            if (a[i + 3] < 0.05f) /* the mean field's opacity: outside the blobs */
                continue;
            cloud++;
            for (size_t ch = 0; ch < 3; ch++) {
                dev_c += (pc[i + ch] - a[i + ch]) * (pc[i + ch] - a[i + ch]);
                dev_p += (pp[i + ch] - a[i + ch]) * (pp[i + ch] - a[i + ch]);
            }
        }
    printf("blob pixels %d: rms deviation from the mean field, corrected %.4f, paper %.4f\n", cloud,
           sqrt(dev_c / (3 * cloud)), sqrt(dev_p / (3 * cloud)));
    ASSERT_TRUE(cloud > 50);
    ASSERT_TRUE(dev_c > 0.0);
    ASSERT_TRUE(dev_p > 9.0 * dev_c); /* 3 times the spread at least */
    brume_image_release(m0);
    brume_image_release(m1);
    brume_image_release(c);
    brume_image_release(p);
}

/* Q as the renderer reads it over the Figure 5 cloud: its autocorrelation at every lag up to
 * the cloud's size must be the gaussian K_Q (no periodic image inside the field), measured over
 * 8 realizations (tolerance: 5 standard errors of the mean over realizations, plus 0.01 for the
 * lattice's aliasing). The paper's 32^3 lattice repeats inside the same cloud: there the
 * correlation at a lag of one period is 1. */
static void autocorrelation(const randfield_params *rp, vec3 lo, vec3 ext, const double *lags, int nlags, int reps,
                            double *mean, double *se)
{
    for (int l = 0; l < nlags; l++)
        mean[l] = se[l] = 0.0;
    for (int r = 0; r < reps; r++) {
        randfield_params p = *rp;
        p.seed = rp->seed + (uint64_t)r;
        randfield *q = randfield_new(&p);
        ASSERT_TRUE(q);
        for (int l = 0; l < nlags; l++) {
            double s = 0.0, s0 = 0.0;
            int n = 0;
            /* lattice nodes on 64 lines along x through the cloud's box */
            for (int line = 0; line < 64; line++) {
                double y = lo.y + ext.y * (line % 8 + 0.5) / 8.0, z = lo.z + ext.z * (line / 8 + 0.5) / 8.0;
                y = floor(y / p.cell) * p.cell;
                z = floor(z / p.cell) * p.cell;
                for (double x = floor(lo.x / p.cell) * p.cell; x + lags[l] <= lo.x + ext.x; x += p.cell) {
                    double a = randfield_eval(q, v3(x, y, z)), b = randfield_eval(q, v3(x + lags[l], y, z));
                    s += a * b;
                    s0 += a * a;
                    n++;
                }
            }
            double rho = n > 0 ? s / s0 : 0.0;
            mean[l] += rho / reps;
            se[l] += rho * rho / reps;
        }
        randfield_release(q);
    }
    for (int l = 0; l < nlags; l++)
        se[l] = sqrt(fmax(0.0, se[l] - mean[l] * mean[l]) / (reps - 1));
}

TEST(q_autocorrelation_has_no_period_in_the_field)
{
    brume_scene *s = load_with(SCENE("stam-fig5-a.json"), NULL, 0, BRUME_OK, NULL);
    vec3 ext = stam_blob_extent(s);
    box3 b = density_get_blobs(s->media[0].rho)->bounds;
    randfield_params rp;
    stam_randfield_params(scene_options(s, METHOD_OPTIONS_STAM), 0.0, ext, &rp);
    double alpha = ((const stam_params *)scene_options(s, METHOD_OPTIONS_STAM))->alpha;
    printf("cloud %.3f x %.3f x %.3f, lattice %d x %d x %d, cell %.4f (alpha / %.2f), period along x %.3f\n", ext.x,
           ext.y, ext.z, rp.n[0], rp.n[1], rp.n[2], rp.cell, alpha / rp.cell, rp.n[0] * rp.cell);
    ASSERT_TRUE(rp.n[0] * rp.cell >= ext.x + 6.0 * alpha);
    enum { NL = 12, REPS = 8 };
    double lags[NL], mean[NL], se[NL];
    for (int l = 0; l < NL; l++) /* 0, cell, 2 cells, then spread up to the cloud's length */
        lags[l] = l < 3 ? l * rp.cell : rp.cell * round((ext.x - 4.0 * rp.cell) * (l - 2) / (NL - 3) / rp.cell);
    autocorrelation(&rp, b.lo, ext, lags, NL, REPS, mean, se);
    for (int l = 0; l < NL; l++) {
        double want = exp(-lags[l] * lags[l] / (2.0 * alpha * alpha));
        printf("lag %.3f (%.2f alpha): autocorrelation %.4f +- %.4f, K_Q %.4f\n", lags[l], lags[l] / alpha, mean[l],
               se[l], want);
        ASSERT_NEAR(mean[l], want, 5.0 * se[l] + 0.01);
    }
    /* the paper's lattice: 32 points of alpha / 3, a period of 0.64 inside a cloud 3.5 long */
    ASSERT_EQ_INT(brume_scene_set_option(NULL, s, "stam.lattice", "32"), BRUME_OK);
    stam_randfield_params(scene_options(s, METHOD_OPTIONS_STAM), 0.0, ext, &rp);
    double period = rp.n[0] * rp.cell, m1, s1;
    ASSERT_TRUE(period < ext.x);
    autocorrelation(&rp, b.lo, ext, &period, 1, 2, &m1, &s1);
    printf("lattice 32: period %.3f, autocorrelation there %.4f\n", period, m1);
    ASSERT_TRUE(m1 > 0.99);
    brume_scene_release(s);
}

/* Blasi's method on a blob field: refused with the way out in the message; with blasi.voxels
 * it renders one realization of the field (stam.eps carried: eps > 0 changes the image). */
TEST(blasi_on_blobs_refused_or_voxelized)
{
    char json[4096];
    snprintf(json, sizeof json, BLOBS_JSON, 0.0, "corrected", "");
    brume_scene *s = test_scene_json(json);
    brume_context *ctx = brume_context_new();
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.method = BRUME_METHOD_BLASI;
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_scene_set_settings(ctx, s, &rs), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_ERROR_UNSUPPORTED);
    printf("message: %s\n", brume_context_last_error(ctx));
    ASSERT_CONTAINS(brume_context_last_error(ctx), "blob field: give blasi.voxels=N");
    ASSERT_TRUE(img == NULL);
    brume_scene_release(s);
    brume_context_release(ctx);

    brume_image *im[2];
    for (int k = 0; k < 2; k++) {
        snprintf(json, sizeof json, BLOBS_JSON, k ? 0.3 : 0.0, "corrected",
                 ", \"blasi\": {\"voxels\": 40, \"light_rays\": 20000}");
        s = test_scene_json(json);
        ASSERT_EQ_INT(((const blasi_options *)scene_options(s, METHOD_OPTIONS_BLASI))->voxels, 40);
        im[k] = render_scene(s, "blasi", 2, true);
        brume_stats st;
        ctx = brume_context_new();
        brume_scene_stats(s, &st);
        brume_context_release(ctx);
        ASSERT_TRUE(st.blasi.interceptions > 0);
        brume_scene_release(s);
    }
    const float *a = brume_image_pixels(im[0]), *b = brume_image_pixels(im[1]);
    double d = 0.0, cloud = 0.0;
    for (int i = 0; i < 48 * 32; i++) {
        d += fabs(a[4 * i] - b[4 * i]);
        cloud += a[4 * i] != 0.5f;
    }
    ASSERT_TRUE(cloud > 0.0);
    ASSERT_TRUE(d > 0.0);
    brume_image_release(im[0]);
    brume_image_release(im[1]);
}

/* --stats: exact counts that do not depend on the thread count, the identities between
 * them, and nothing counted when statistics are off. */
TEST(stats_per_method)
{
    char json[4096];
    snprintf(json, sizeof json, BLOBS_JSON, 0.3, "corrected", ", \"blasi\": {\"voxels\": 32, \"light_rays\": 20000}");
    brume_stats st[2];
    const char *methods[] = {"path", "stam", "blasi"};
    for (int m = 0; m < 3; m++) {
        for (int t = 0; t < 2; t++) {
            brume_scene *s = test_scene_json(json);
            brume_image_release(render_scene(s, methods[m], t + 1, true));
            brume_context *ctx = brume_context_new();
            brume_scene_stats(s, &st[t]);
            brume_context_release(ctx);
            brume_scene_release(s);
        }
        printf("%s: %llu rays, path %.3f vertices %.3f collisions %.3f null; stam %.2f blobs/ray %.2f nodes/query; "
               "blasi %llu interceptions %llu deposits, stored %.4g of %.4g\n",
               methods[m], (unsigned long long)st[0].camera_rays, st[0].path.vertices, st[0].path.collisions,
               st[0].path.null_collisions, st[0].stam.blobs_per_ray, st[0].stam.nodes_per_query,
               (unsigned long long)st[0].blasi.interceptions, (unsigned long long)st[0].blasi.deposits,
               st[0].blasi.power_stored, st[0].blasi.power_emitted);
        ASSERT_TRUE(st[0].rendered && st[1].rendered);
        ASSERT_EQ_STR(brume_method_name(st[0].method), methods[m]);
        ASSERT_EQ_INT(st[0].camera_rays, 48 * 32);
        ASSERT_NEAR(st[0].path.vertices, st[1].path.vertices, 0.0);
        ASSERT_NEAR(st[0].path.null_collisions, st[1].path.null_collisions, 0.0);
        ASSERT_NEAR(st[0].path.majorant_cells, st[1].path.majorant_cells, 0.0);
        ASSERT_NEAR(st[0].path.density_lookups, st[1].path.density_lookups, 0.0);
        ASSERT_TRUE(m == 0 || (st[0].path.majorant_cells == 0.0 && st[0].path.density_lookups == 0.0));
        ASSERT_NEAR(st[0].stam.blobs_per_ray, st[1].stam.blobs_per_ray, 0.0);
        ASSERT_EQ_INT(st[0].blasi.deposits, st[1].blasi.deposits);
        /* each method fills its own struct only */
        ASSERT_TRUE(m == 0 || (st[0].path.vertices == 0.0 && st[0].path.tracking_cpu_seconds == 0.0));
        ASSERT_TRUE(m == 1 || (st[0].stam.blobs_per_ray == 0.0 && st[0].stam.queries_per_ray == 0.0));
        ASSERT_TRUE(m == 2 || (st[0].blasi.deposits == 0 && st[0].blasi.power_emitted == 0.0));
        if (m == 0) {
            ASSERT_TRUE(st[0].path.collisions > 0.0 && st[0].path.null_collisions > 0.0);
            /* every walk crosses at least one cell to reach a collision, and every collision of
             * a flight through the blobs looks them up (they have no control density) */
            ASSERT_TRUE(st[0].path.majorant_cells >= st[0].path.collisions);
            ASSERT_TRUE(st[0].path.density_lookups >= st[0].path.collisions + st[0].path.null_collisions);
            ASSERT_TRUE(st[0].path.vertices >= st[0].path.collisions); /* no surfaces: equal */
            ASSERT_NEAR(st[0].path.vertices, st[0].path.collisions, 0.0);
            ASSERT_TRUE(st[0].path.tracking_cpu_seconds > 0.0 && st[0].path.nee_cpu_seconds > 0.0);
        } else if (m == 1) {
            /* the left third of the picture meets the blobs, the rest none */
            ASSERT_TRUE(st[0].stam.blobs_per_ray > 0.1 && st[0].stam.blobs_per_ray < 3.0);
        } else {
            ASSERT_TRUE(st[0].blasi.deposits >= st[0].blasi.interceptions && st[0].blasi.interceptions > 0);
            ASSERT_TRUE(st[0].blasi.power_stored > 0.0 && st[0].blasi.power_stored <= st[0].blasi.power_emitted);
            ASSERT_EQ_INT(st[0].blasi.light_rays, 20000);
        }
    }
    /* off: the path counters stay zero */
    brume_scene *s = test_scene_json(json);
    brume_image_release(render_scene(s, "path", 2, false));
    brume_context *ctx = brume_context_new();
    brume_scene_stats(s, &st[0]);
    brume_context_release(ctx);
    brume_scene_release(s);
    ASSERT_EQ_INT(st[0].camera_rays, 0);
    ASSERT_NEAR(st[0].path.vertices, 0.0, 0.0);
}

/* `brume phase fit NAME --given r,k,kprime` scores a given mixture in the fit's own norm: the
 * fit's own parameters score its error; Figure 7's published murky fit scores worse than
 * brume's fit (which minimizes that norm); a bad triple is a command-line error. */
static double fit_line(const char *args, const char *key)
{
    char cmd[1024], out[512];
    snprintf(out, sizeof out, "%s", test_tmp_path("fit.txt"));
    snprintf(cmd, sizeof cmd, "%s phase fit %s > %s", BRUME_EXE, args, out);
    ASSERT_EQ_INT(test_system(cmd), 0);
    size_t n;
    char *text = test_slurp(out, &n);
    const char *at = strstr(text, key);
    ASSERT_TRUE(at);
    double v = atof(at + strlen(key));
    free(text);
    remove(out);
    return v;
}

TEST(phase_fit_given)
{
    double r = fit_line("murky", "r "), k = fit_line("murky", "\nk "), kp = fit_line("murky", "\nkprime ");
    double e = fit_line("murky", "\nerror ");
    char args[256];
    snprintf(args, sizeof args, "murky --given %.4f,%.4f,%.4f", r, k, kp);
    double eg = fit_line(args, "\nerror ");
    printf("murky (angle norm): our error %.5f, the same parameters given %.5f\n", e, eg);
    ASSERT_NEAR(eg, e, 0.02 * e); /* the printed parameters are rounded to 4 decimals */
    double e7 = fit_line("murky --given 0.19,-0.65,0.91", "\nerror ");
    printf("murky (angle norm): Fig. 7 error %.5f (r 0.19, k -0.65, k' 0.91)\n", e7);
    ASSERT_TRUE(e7 > e);
    char cmd[512];
    snprintf(cmd, sizeof cmd, "%s phase fit murky --given 0.5,2,0 >/dev/null 2>&1", BRUME_EXE);
    ASSERT_EQ_INT(test_system(cmd), 2);
}

/* The captions say what the scenes hold: Figure 5's eps and eta are read from the scene
 * files, the equation numbers from the paper (Blasi Eq. 17 is Rayleigh, Eq. 18 both Mie
 * functions), and docs/gallery.md carries every caption as `brume figures` writes it.
 * docs/stam.md's standard error of a sample variance over M = 1000 realizations
 * (test_stam.c's Monte-Carlo check) is sqrt(2 / (M - 1)) = 4.5 %. */
TEST(captions_match_the_scenes)
{
    static const char *const fig5[] = {"stam-fig5-a", "stam-fig5-b", "stam-fig5-c", "stam-fig5-d"};
    char path[1024], want[64];
    size_t n;
    snprintf(path, sizeof path, "%s/docs/gallery.md", BRUME_SOURCE_DIR);
    char *gallery = test_slurp(path, &n);
    for (int i = 0; i < 4; i++) {
        const char *scene = NULL, *cap = figures_caption(fig5[i], &scene);
        ASSERT_TRUE(cap != NULL);
        snprintf(path, sizeof path, "%s/scenes/%s.json", BRUME_SOURCE_DIR, scene);
        char *text = test_slurp(path, &n);
        cJSON *doc = NULL;
        ASSERT_EQ_INT(json_parse(text, path, &doc), BRUME_OK);
        const cJSON *stam = cJSON_GetObjectItemCaseSensitive(doc, "stam");
        const cJSON *eps = cJSON_GetObjectItemCaseSensitive(stam, "eps");
        const cJSON *eta = cJSON_GetObjectItemCaseSensitive(stam, "eta");
        ASSERT_TRUE(cJSON_IsNumber(eps) && cJSON_IsNumber(eta));
        snprintf(want, sizeof want, "eps = %g,", eps->valuedouble);
        ASSERT_CONTAINS(cap, want);
        snprintf(want, sizeof want, "eta = %g", eta->valuedouble);
        ASSERT_CONTAINS(cap, want);
        ASSERT_CONTAINS(gallery, cap);
        cJSON_Delete(doc);
        free(text);
    }
    ASSERT_CONTAINS(figures_caption("blasi-fig2", NULL), "(Eq. 17)");
    ASSERT_CONTAINS(figures_caption("blasi-fig3", NULL), "(Eq. 18)");
    ASSERT_CONTAINS(figures_caption("blasi-fig4", NULL), "(Eq. 18)");
    static const char *const phase_figs[] = {"blasi-fig2", "blasi-fig3", "blasi-fig4"};
    for (int i = 0; i < 3; i++)
        ASSERT_CONTAINS(gallery, figures_caption(phase_figs[i], NULL));
    free(gallery);
    snprintf(path, sizeof path, "%s/docs/stam.md", BRUME_SOURCE_DIR);
    char *stam = test_slurp(path, &n);
    snprintf(want, sizeof want, "se(var) = Var sqrt(2 / (M - 1)) = %.1f %%", 100.0 * sqrt(2.0 / 999.0));
    ASSERT_CONTAINS(stam, want);
    free(stam);
}

/* `brume figures --compare` puts a figure as printed, as corrected and by `path` side by
 * side: three cells of the quick width (256) in one PNG; a figure without variants is refused. */
TEST(figures_compare_side_by_side)
{
    char dir[512], cmd[2048], path[1024];
    snprintf(dir, sizeof dir, "%s", test_tmp_path("figcmp"));
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && %s figures --compare --quick --only blasi-picture1 -o '%s' --scenes %s/scenes",
             dir, BRUME_EXE, dir, BRUME_SOURCE_DIR);
    ASSERT_EQ_INT(test_system(cmd), 0);
    size_t n;
    snprintf(path, sizeof path, "%s/blasi-picture1-compare.png", dir);
    unsigned char *png = (unsigned char *)test_slurp(path, &n);
    ASSERT_TRUE(n > 33 && memcmp(png, "\x89PNG\r\n\x1a\n", 8) == 0);
    unsigned width = (unsigned)png[16] << 24 | (unsigned)png[17] << 16 | (unsigned)png[18] << 8 | png[19];
    ASSERT_TRUE(width >= 3 * 256 && width < 4 * 256);
    free(png);
    snprintf(cmd, sizeof cmd, "%s figures --compare --quick --only blasi-fig2 -o '%s' --scenes %s/scenes 2>/dev/null",
             BRUME_EXE, dir, BRUME_SOURCE_DIR);
    ASSERT_EQ_INT(test_system(cmd), 2);
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    test_system(cmd);
}

/* The width of figure `name`'s render at the quick size: 256 pixels, or the scene's own
 * width when it is narrower; 0 for a figure that is no render of a scene. */
static unsigned quick_width(const char *name)
{
    const char *scene = NULL;
    ASSERT_TRUE(figures_caption(name, &scene) != NULL);
    if (!*scene)
        return 0;
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/%s.json", BRUME_SOURCE_DIR, scene);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s: %s", path, brume_context_last_error(ctx));
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    brume_scene_release(s);
    brume_context_release(ctx);
    return rs.width < 256 ? (unsigned)rs.width : 256u;
}

/* `brume figures --quick` writes every figure of both papers, at the quick size, with both
 * indexes naming each; it refuses to write into the source tree's docs/ unless told. */
TEST(figures_quick_makes_every_file)
{
    static const char *const want[] = {
        "blasi-fig2", "blasi-fig3", "blasi-fig4", "blasi-fig5", "blasi-fig6", "blasi-fig7", "blasi-picture1",
        "blasi-picture2", "blasi-picture3", "stam-fig1", "stam-fig4", "stam-fig5-a", "stam-fig5-b", "stam-fig5-c",
        "stam-fig5-d", "stam-fig6-shadow", "stam-fig6-cluster-a", "stam-fig6-cluster-b", "stam-fig6-city",
        "stam-fig7-t0", "stam-fig7-t1", "stam-fig7-t2", "stam-fig7-t3", "stam-fig8"};
    char dir[512], cmd[2048], path[1024];
    snprintf(dir, sizeof dir, "%s", test_tmp_path("figures"));
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && %s figures -o '%s/sub' --quick --scenes %s/scenes 2>/dev/null", dir,
             BRUME_EXE, dir, BRUME_SOURCE_DIR);
    ASSERT_EQ_INT(test_system(cmd), 0);
    size_t n;
    snprintf(path, sizeof path, "%s/sub/index.md", dir);
    char *md = test_slurp(path, &n);
    snprintf(path, sizeof path, "%s/sub/index.html", dir);
    char *html = test_slurp(path, &n);
    for (size_t i = 0; i < sizeof want / sizeof *want; i++) {
        snprintf(path, sizeof path, "%s/sub/%s.png", dir, want[i]);
        unsigned char *png = (unsigned char *)test_slurp(path, &n);
        /* a PNG, a render at the quick width, and no figure under 240 pixels wide (the
         * narrowest scene, Figure 7's, is 240 wide at full size) */
        ASSERT_TRUE(n > 33 && memcmp(png, "\x89PNG\r\n\x1a\n", 8) == 0);
        unsigned width = (unsigned)png[16] << 24 | (unsigned)png[17] << 16 | (unsigned)png[18] << 8 | png[19];
        unsigned quick = quick_width(want[i]);
        if (quick)
            ASSERT_EQ_INT(width, quick);
        ASSERT_TRUE(width >= 240);
        free(png);
        char ref[128];
        snprintf(ref, sizeof ref, "](%s.png)", want[i]);
        ASSERT_CONTAINS(md, ref);
        snprintf(ref, sizeof ref, "<img src=\"%s.png\"", want[i]);
        ASSERT_CONTAINS(html, ref);
    }
    ASSERT_CONTAINS(md, "`brume render scenes/stam-fig5-a.json --width 256 --height 192 --spp 1 -o stam-fig5-a.png`");
    ASSERT_CONTAINS(html, "<table>");
    free(md);
    free(html);
    /* docs/ of the source tree: refused, nothing created */
    snprintf(cmd, sizeof cmd, "%s figures -o %s/docs/figures-test-never --quick --scenes %s/scenes 2>/dev/null",
             BRUME_EXE, BRUME_SOURCE_DIR, BRUME_SOURCE_DIR);
    ASSERT_EQ_INT(test_system(cmd), 2);
    ASSERT_TRUE(!test_exists(BRUME_SOURCE_DIR "/docs/figures-test-never"));
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    test_system(cmd);
}

/* The light pass's files named on the command line are relative to the working directory and
 * may be anywhere the user says (a scene file may write only inside its folder): --save-light
 * and --set blasi.save_light write there, --load-light reads it back, with --set beside them. */
TEST(cli_light_files_beside_overrides)
{
    char dir[512], cmd[4096];
    snprintf(dir, sizeof dir, "%s", test_tmp_path("lightdir"));
    snprintf(cmd, sizeof cmd,
             "rm -rf '%s' && mkdir -p '%s' && cd '%s' && %s render %s --save-light a.light --set blasi.light_rays=2000 "
             "--width 16 --height 16 --spp 1 -q -o a.png && %s render %s --set blasi.save_light=b.light "
             "--set blasi.light_rays=2000 --width 16 --height 16 --spp 1 -q -o b.png && cmp a.light b.light && "
             "%s render %s --load-light a.light --set blasi.light_rays=2000 --set camera.fov=30 --width 16 "
             "--height 16 --spp 1 -q -o c.png",
             dir, dir, dir, BRUME_EXE, SCENE("blasi-picture1.json"), BRUME_EXE, SCENE("blasi-picture1.json"), BRUME_EXE,
             SCENE("blasi-picture2.json"));
    ASSERT_EQ_INT(test_system(cmd), 0);
    char path[1024];
    snprintf(path, sizeof path, "%s/c.png", dir);
    ASSERT_TRUE(test_exists(path));
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    test_system(cmd);
}

TEST_MAIN(captions_match_the_scenes, figures_compare_side_by_side, set_every_kind_of_key, set_bad_keys, stam_variants_differ_where_the_variance_differs,
          q_autocorrelation_has_no_period_in_the_field, blasi_on_blobs_refused_or_voxelized, stats_per_method,
          phase_fit_given, figures_quick_makes_every_file, cli_light_files_beside_overrides)
