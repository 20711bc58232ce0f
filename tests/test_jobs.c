/* test_jobs.c - render jobs through the public API: progressive passes, cancellation,
 * AOV layers on scenes whose depth and albedo are known, adaptive sampling (thread-count
 * independence, noise targets met on scenes whose noise is known), checkpoints. */
#include "test.h"

#include <limits.h>
#include <stdint.h>

#include "brume.h"

/* A scene from JSON text through a file, as a user would load it; settings changed by fn. */
static brume_scene *load(const char *json, void (*fn)(brume_render_settings *, void *), void *user)
{
    const char *path = test_tmp_path("scene.json");
    FILE *fp = fopen(path, "w");
    ASSERT_TRUE(fp != NULL);
    fputs(json, fp);
    fclose(fp);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        TEST_FAIL("scene: %s", brume_context_last_error(ctx));
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    if (fn)
        fn(&rs, user);
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("scene: %s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    remove(path);
    return s;
}

static brume_scene *load_default(int w, int h, void (*fn)(brume_render_settings *, void *), void *user)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, NULL, NULL, &s), BRUME_OK);
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.width = w;
    rs.height = h;
    if (fn)
        fn(&rs, user);
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("scene: %s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    return s;
}

static brume_image *render(brume_scene *s)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    if (brume_render(ctx, s, &img) != BRUME_OK)
        TEST_FAIL("render: %s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    return img;
}

static int layer_index(const brume_image *img, const char *name)
{
    for (int i = 0; i < brume_image_layer_count(img); i++)
        if (strcmp(brume_image_layer_name(img, i), name) == 0)
            return i;
    TEST_FAIL("no layer '%s'", name);
}

static bool same_pixels(const brume_image *a, const brume_image *b)
{
    size_t n = (size_t)brume_image_width(a) * (size_t)brume_image_height(a) * 4;
    if (brume_image_width(a) != brume_image_width(b) || brume_image_height(a) != brume_image_height(b))
        return false;
    if (memcmp(brume_image_pixels(a), brume_image_pixels(b), n * sizeof(float)) != 0)
        return false;
    if (brume_image_layer_count(a) != brume_image_layer_count(b))
        return false;
    for (int i = 0; i < brume_image_layer_count(a); i++) { /* layers by name */
        int j = layer_index(b, brume_image_layer_name(a, i));
        size_t m = n / 4 * (size_t)brume_image_layer_channels(a, i);
        if (brume_image_layer_channels(b, j) != brume_image_layer_channels(a, i) ||
            memcmp(brume_image_layer_pixels(a, i), brume_image_layer_pixels(b, j), m * sizeof(float)) != 0)
            return false;
    }
    return true;
}

static void set_spp_threads(brume_render_settings *rs, void *user)
{
    const int *v = user;
    rs->spp = v[0];
    rs->threads = v[1];
    rs->aovs = BRUME_AOV_VARIANCE | BRUME_AOV_SAMPLES | BRUME_AOV_DEPTH | BRUME_AOV_ALBEDO;
}

/* Passes of 5, 4 and 3 samples equal one render of 12, bit for bit, with 1 and 2 threads;
 * another count differs (the comparison can fail). */
TEST(progressive_passes_equal_one_render)
{
    for (int threads = 1; threads <= 2; threads++) {
        int v[2] = {12, threads};
        brume_scene *s = load_default(40, 24, set_spp_threads, v);
        brume_image *one = render(s);
        brume_context *ctx = brume_context_new();
        brume_render_job *job = NULL;
        ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_OK);
        const int passes[3] = {5, 4, 3};
        brume_image *after_two = NULL;
        for (int p = 0; p < 3; p++) {
            ASSERT_EQ_INT(brume_render_job_add(ctx, job, passes[p]), BRUME_OK);
            if (p == 1)
                ASSERT_EQ_INT(brume_render_job_image(ctx, job, &after_two), BRUME_OK);
        }
        ASSERT_EQ_INT(brume_render_job_samples(job), 12);
        brume_image *prog = NULL;
        ASSERT_EQ_INT(brume_render_job_image(ctx, job, &prog), BRUME_OK);
        ASSERT_TRUE(same_pixels(one, prog));
        ASSERT_TRUE(!same_pixels(one, after_two));
        const float *cnt = brume_image_layer_pixels(prog, layer_index(prog, "samples"));
        ASSERT_EQ_INT((int)cnt[0], 12);
        brume_image_release(one);
        brume_image_release(prog);
        brume_image_release(after_two);
        brume_render_job_release(job);
        brume_context_release(ctx);
        brume_scene_release(s);
    }
}

typedef struct cancel_state {
    int calls, stop_after;
    uint64_t last_done, last_total;
    bool monotone;
} cancel_state;

static bool cancel_cb(void *user, uint64_t done, uint64_t total)
{
    cancel_state *c = user;
    if (done < c->last_done || total < done)
        c->monotone = false;
    c->last_done = done;
    c->last_total = total;
    return ++c->calls < c->stop_after;
}

static void set_cancel(brume_render_settings *rs, void *user)
{
    rs->progress_fn = cancel_cb;
    rs->progress_user = user;
    rs->spp = 4;
    rs->threads = ((cancel_state *)user)->stop_after == 3 ? 1 : 2;
    rs->aovs = BRUME_AOV_SAMPLES;
}

/* The callback cancels at its third call: with one thread exactly three 16 x 16 tiles are
 * rendered (none after), with two at most one more (the tile the other thread was in).
 * The render returns BRUME_ERROR_CANCELLED with a valid partial image. */
TEST(cancel_stops_within_one_tile)
{
    for (int threads = 1; threads <= 2; threads++) {
        cancel_state c = {0, threads == 1 ? 3 : 5, 0, 0, true};
        brume_scene *s = load_default(160, 96, set_cancel, &c); /* 10 x 6 tiles */
        brume_context *ctx = brume_context_new();
        brume_image *img = NULL;
        ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_ERROR_CANCELLED);
        ASSERT_TRUE(img != NULL);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "cancelled");
        ASSERT_TRUE(c.monotone);
        const float *cnt = brume_image_layer_pixels(img, layer_index(img, "samples"));
        const float *px = brume_image_pixels(img);
        int rendered = 0;
        for (int i = 0; i < 160 * 96; i++) {
            ASSERT_TRUE(cnt[i] == 0.0f || cnt[i] == 4.0f);
            for (int k = 0; k < 4; k++)
                ASSERT_TRUE(isfinite(px[4 * i + k]) && (cnt[i] > 0.0f || px[4 * i + k] == 0.0f));
            rendered += cnt[i] > 0.0f;
        }
        ASSERT_EQ_INT(rendered % 256, 0);
        fprintf(stderr, "%d thread(s): %d callback calls, %d tiles rendered\n", threads, c.calls, rendered / 256);
        if (threads == 1)
            ASSERT_EQ_INT(rendered / 256, 3);
        else
            ASSERT_TRUE(rendered / 256 >= c.stop_after && rendered / 256 <= c.stop_after + 1);
        ASSERT_EQ_INT(c.calls, c.stop_after);
        /* the partial image writes as a whole file */
        const char *out = test_tmp_path("partial.exr");
        ASSERT_EQ_INT(brume_image_write(ctx, img, out, NULL), BRUME_OK);
        brume_image *back = NULL;
        ASSERT_EQ_INT(brume_image_read(ctx, out, &back), BRUME_OK);
        ASSERT_TRUE(same_pixels(img, back));
        remove(out);
        brume_image_release(back);
        brume_image_release(img);
        brume_context_release(ctx);
        brume_scene_release(s);
    }
}

static void set_count(brume_render_settings *rs, void *user)
{
    rs->progress_fn = cancel_cb; /* stop_after INT_MAX: never cancels */
    rs->progress_user = user;
    rs->spp = 1;
    rs->threads = 2;
}

/* Two workers finishing tiles together: the callback never sees `done` go back, and its last
 * call reports every sample (cheap 1-sample tiles, many renders, to give the race room). */
TEST(progress_counts_never_go_back)
{
    for (int rep = 0; rep < 40; rep++) {
        cancel_state c = {0, INT_MAX, 0, 0, true};
        brume_scene *s = load_default(160, 96, set_count, &c);
        brume_image *img = render(s);
        ASSERT_TRUE(c.monotone);
        ASSERT_EQ_INT(c.calls, 60);
        ASSERT_TRUE(c.last_done == 160u * 96u && c.last_total == 160u * 96u);
        brume_image_release(img);
        brume_scene_release(s);
    }
}

static void set_aovs(brume_render_settings *rs, void *user)
{
    (void)user;
    rs->aovs = BRUME_AOV_DEPTH | BRUME_AOV_ALBEDO | BRUME_AOV_NORMAL | BRUME_AOV_VARIANCE | BRUME_AOV_SAMPLES;
    rs->filter = BRUME_FILTER_BOX;
    rs->filter_width = 1.0;
}

/* Depth of a pixel looking at a plane z = 0 from (0, 0, D): D / cos of the angle between its
 * ray (through the pixel centre) and the view axis, for a vertical field of view fov. */
static double pixel_cos(int x, int y, int w, int h, double fov_deg)
{
    double t = tan(0.5 * fov_deg * 3.14159265358979323846 / 180.0);
    double px = (2.0 * (x + 0.5) / w - 1.0) * t * w / h, py = (1.0 - 2.0 * (y + 0.5) / h) * t;
    return 1.0 / sqrt(1.0 + px * px + py * py);
}

/* A diffuse plane: depth D / cos, albedo the material's, normal +z, exactly (up to the
 * spread of the rays over a pixel); then a homogeneous chromatic fog slab whose first
 * collisions are exponential: albedo sigma_s / sigma_t per channel, mean depth
 * (D + E[t | t < L]) with E[t | t < L] = 1/s - L exp(-s L) / (1 - exp(-s L)). */
TEST(aovs_known_depth_albedo_normal)
{
    const char *plane = "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 20},"
                        " \"lights\": [{\"type\": \"distant\", \"direction\": [0, 0, -1], \"irradiance\": 1}],"
                        " \"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1], \"size\": 100,"
                        "   \"material\": {\"albedo\": [0.2, 0.5, 0.8]}}],"
                        " \"render\": {\"width\": 24, \"height\": 16, \"spp\": 4}}";
    brume_scene *s = load(plane, set_aovs, NULL);
    brume_image *img = render(s);
    const float *d = brume_image_layer_pixels(img, layer_index(img, "depth"));
    const float *a = brume_image_layer_pixels(img, layer_index(img, "albedo"));
    const float *nrm = brume_image_layer_pixels(img, layer_index(img, "normal"));
    ASSERT_EQ_INT(brume_image_layer_channels(img, layer_index(img, "depth")), 1);
    ASSERT_EQ_INT(brume_image_layer_channels(img, layer_index(img, "albedo")), 3);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 24; x++) {
            int i = y * 24 + x;
            double expect = 10.0 / pixel_cos(x, y, 24, 16, 20.0);
            ASSERT_NEAR(d[i], expect, 2e-3 * expect); /* the rays spread over the pixel */
            ASSERT_NEAR(a[3 * i + 0], 0.2, 1e-6);
            ASSERT_NEAR(a[3 * i + 1], 0.5, 1e-6);
            ASSERT_NEAR(a[3 * i + 2], 0.8, 1e-6);
            ASSERT_NEAR(nrm[3 * i + 2], 1.0, 1e-6);
            ASSERT_NEAR(nrm[3 * i + 0], 0.0, 1e-6);
        }
    brume_image_release(img);
    brume_scene_release(s);

    const char *fog = "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 2},"
                      " \"background\": 1.0,"
                      " \"media\": [{\"sigma_a\": [1, 2, 3], \"sigma_s\": [3, 2, 1],"
                      "   \"density\": {\"type\": \"constant\", \"bounds\": [[-50, -50, -1], [50, 50, 1]]}}],"
                      " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 16}}";
    s = load(fog, set_aovs, NULL);
    img = render(s);
    d = brume_image_layer_pixels(img, layer_index(img, "depth"));
    a = brume_image_layer_pixels(img, layer_index(img, "albedo"));
    double sig = 4.0, L = 2.0, Et = 1.0 / sig - L * exp(-sig * L) / (1.0 - exp(-sig * L));
    double sd = 1.0 / sig; /* at most that of the untruncated exponential */
    double sum = 0.0, expect = 0.0;
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++) {
            sum += d[y * 32 + x];
            expect += (9.0 + Et) / pixel_cos(x, y, 32, 32, 2.0);
        }
    double se = sd / sqrt(32.0 * 32.0 * 16.0);
    fprintf(stderr, "fog depth: mean %.5f, expected %.5f (standard error %.5f)\n", sum / 1024, expect / 1024, se);
    ASSERT_NEAR(sum / 1024, expect / 1024, 5.0 * se);
    double albedo[3] = {0.75, 0.5, 0.25}, escape = exp(-sig * L); /* escaped samples count 0 */
    for (int c = 0; c < 3; c++) {
        double m = 0.0;
        for (int i = 0; i < 1024; i++)
            m += a[3 * i + c];
        ASSERT_NEAR(m / 1024, albedo[c] * (1.0 - escape), 5.0 * albedo[c] * sqrt(escape / 16384.0) + 1e-6);
    }
    /* the layers go into one EXR and come back by name */
    brume_context *ctx = brume_context_new();
    const char *out = test_tmp_path("aovs.exr");
    ASSERT_EQ_INT(brume_image_write(ctx, img, out, NULL), BRUME_OK);
    brume_image *back = NULL;
    ASSERT_EQ_INT(brume_image_read(ctx, out, &back), BRUME_OK);
    ASSERT_EQ_INT(brume_image_layer_count(back), 5);
    ASSERT_TRUE(same_pixels(img, back));
    remove(out);
    brume_image_release(back);
    brume_context_release(ctx);
    brume_image_release(img);
    brume_scene_release(s);
}

static void set_adaptive(brume_render_settings *rs, void *user)
{
    const int *threads = user;
    rs->threads = *threads;
    rs->spp = 256;
    rs->min_spp = 8;
    rs->noise_target = 0.08;
    rs->aovs = BRUME_AOV_SAMPLES;
}

/* Adaptive sampling decides at pass boundaries from each pixel's own sums: 1 and 2 threads
 * give the same image and the same sample counts, which differ between pixels. The parts
 * of an MPI-style split add up to the whole, bit for bit. */
TEST(adaptive_sampling_independent_of_threads)
{
    brume_image *img[2];
    brume_scene *s[2];
    for (int t = 0; t < 2; t++) {
        int threads = t + 1;
        s[t] = load_default(48, 32, set_adaptive, &threads);
        img[t] = render(s[t]);
    }
    ASSERT_TRUE(same_pixels(img[0], img[1]));
    const float *cnt = brume_image_layer_pixels(img[0], 0);
    float lo = 1e30f, hi = 0.0f;
    for (int i = 0; i < 48 * 32; i++) {
        lo = fminf(lo, cnt[i]);
        hi = fmaxf(hi, cnt[i]);
    }
    fprintf(stderr, "samples per pixel: %g to %g\n", (double)lo, (double)hi);
    ASSERT_TRUE(lo >= 8.0f && hi > lo);
    /* parts: each pixel from one part, the same bits */
    brume_context *ctx = brume_context_new();
    brume_image *sum = NULL;
    ASSERT_EQ_INT(brume_image_new(ctx, 48, 32, &sum), BRUME_OK);
    for (int p = 0; p < 3; p++) {
        brume_image *part = NULL;
        ASSERT_EQ_INT(brume_render_part(ctx, s[1], p, 3, &part), BRUME_OK);
        float *dst = brume_image_pixels(sum);
        const float *src = brume_image_pixels(part);
        for (int i = 0; i < 48 * 32 * 4; i++)
            dst[i] += src[i];
        brume_image_release(part);
    }
    ASSERT_TRUE(memcmp(brume_image_pixels(sum), brume_image_pixels(img[0]), 48 * 32 * 4 * sizeof(float)) == 0);
    brume_image_release(sum);
    brume_context_release(ctx);
    for (int t = 0; t < 2; t++) {
        brume_image_release(img[t]);
        brume_scene_release(s[t]);
    }
}

static void set_noise(brume_render_settings *rs, void *user)
{
    rs->noise_target = *(const double *)user;
    rs->min_spp = 16;
    rs->spp = 1 << 16;
    rs->aovs = BRUME_AOV_SAMPLES;
}

/* Absorbing fog of optical depth 1 before a background B: each sample is B (probability
 * T = exp(-1)) or 0, so a pixel's relative standard error after n samples is
 * sqrt((1 - T) / (T n)) and the target e needs n = (1 - T) / (T e^2) samples. The render
 * must stop near that count, and the pixels' actual spread about B T must be the target. */
TEST(noise_target_constant_fog_closed_form)
{
    const char *json = "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 5},"
                       " \"background\": [2.0, 1.0, 0.5],"
                       " \"media\": [{\"sigma_a\": 0.5, \"sigma_s\": 0,"
                       "   \"density\": {\"type\": \"constant\", \"bounds\": [[-5, -5, -1], [5, 5, 1]]}}],"
                       " \"render\": {\"width\": 24, \"height\": 24}}";
    double e = 0.1, T = exp(-1.0), n_expect = (1.0 - T) / (T * e * e);
    brume_scene *s = load(json, set_noise, &e);
    brume_image *img = render(s);
    const float *px = brume_image_pixels(img);
    const float *cnt = brume_image_layer_pixels(img, 0);
    double nsum = 0.0, err2 = 0.0;
    int np = 24 * 24;
    for (int i = 0; i < np; i++) {
        nsum += cnt[i];
        double rel = px[4 * i] / (2.0 * T) - 1.0;
        err2 += rel * rel;
    }
    double rms = sqrt(err2 / np);
    fprintf(stderr, "mean samples %.1f (closed form %.1f), pixels' relative error %.4f (target %.3f)\n", nsum / np,
            n_expect, rms, e);
    /* a pixel stops at the first pass boundary past its need, and passes add a quarter of
     * the count: up to 25 % more (12 % on average); the estimate's scatter adds 10 % */
    ASSERT_TRUE(nsum / np >= 0.85 * n_expect && nsum / np <= 1.35 * n_expect);
    /* the spread of 576 pixels estimates rms to about 1/sqrt(2 * 576) = 3 %; stopping on a
     * low estimate makes some pixels noisier: allow 20 % */
    ASSERT_NEAR(rms, e, 0.2 * e);
    brume_image_release(img);
    brume_scene_release(s);
}

/* White furnaces. With no medium every sample is the background: zero variance, so every
 * pixel stops after exactly min_spp samples. With an albedo-1 cloud each pixel's
 * expectation is 1: the render stops with the target met, and the pixels' actual relative
 * error is within the target. */
TEST(noise_target_white_furnace)
{
    const char *empty = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30},"
                        " \"background\": 1.0, \"render\": {\"width\": 16, \"height\": 16}}";
    double e = 0.01;
    brume_scene *s = load(empty, set_noise, &e);
    brume_image *img = render(s);
    const float *cnt = brume_image_layer_pixels(img, 0);
    for (int i = 0; i < 256; i++)
        ASSERT_EQ_INT((int)cnt[i], 16);
    brume_image_release(img);
    brume_scene_release(s);

    const char *cloud = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30},"
                        " \"background\": 1.0,"
                        " \"media\": [{\"sigma_a\": 0, \"sigma_s\": 8,"
                        "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 24, \"seed\": 3},"
                        "   \"phase\": {\"type\": \"hg\", \"g\": 0.5}}],"
                        " \"render\": {\"width\": 16, \"height\": 16, \"max_depth\": 100000}}";
    e = 0.03;
    s = load(cloud, set_noise, &e);
    img = render(s);
    const float *px = brume_image_pixels(img);
    cnt = brume_image_layer_pixels(img, 0);
    double err2 = 0.0, nmax = 0.0;
    for (int i = 0; i < 256; i++) {
        double y = (px[4 * i] + px[4 * i + 1] + px[4 * i + 2]) / 3.0 - 1.0;
        err2 += y * y;
        nmax = fmax(nmax, cnt[i]);
    }
    double rms = sqrt(err2 / 256);
    fprintf(stderr, "white furnace: pixels' relative error %.4f (target %.3f), at most %g samples\n", rms, e, nmax);
    ASSERT_TRUE(rms <= 1.25 * e);
    ASSERT_TRUE(nmax < 65536.0); /* stopped by the target, not by the maximum */
    brume_image_release(img);
    brume_scene_release(s);
}

static void set_ckpt(brume_render_settings *rs, void *user)
{
    const int *v = user;
    rs->spp = 64;
    rs->threads = v[0];
    rs->noise_target = 0.1;
    rs->min_spp = 4;
    rs->width = v[1];
}

static bool cut_cb(void *user, uint64_t done, uint64_t total)
{
    (void)done;
    (void)total;
    int *left = user;
    return --*left > 0;
}

/* Cut a job at several points (inside passes, at a boundary), save it, resume it from the
 * file with a fresh job and finish: the image is the uninterrupted one, bit for bit. Bad
 * checkpoints are refused: other scene key, other settings, truncated, corrupt. */
TEST(checkpoint_resume_is_bit_identical)
{
    const char *ck = test_tmp_path("job.ckpt");
    for (int threads = 1; threads <= 2; threads++) {
        int v[2] = {threads, 40};
        brume_scene *s = load_default(40, 24, set_ckpt, v);
        brume_image *full = render(s);
        brume_context *ctx = brume_context_new();
        const int cuts[3] = {2, 7, 13};
        for (int c = 0; c < 3; c++) {
            /* the same scene and settings, with a callback that cancels after cuts[c] tiles */
            int left = cuts[c];
            brume_render_settings rs;
            brume_scene *cs = NULL;
            ASSERT_EQ_INT(brume_scene_load(ctx, NULL, NULL, &cs), BRUME_OK);
            brume_scene_settings(s, &rs);
            rs.progress_fn = cut_cb;
            rs.progress_user = &left;
            ASSERT_EQ_INT(brume_scene_set_settings(ctx, cs, &rs), BRUME_OK);
            ASSERT_EQ_INT(brume_scene_commit(ctx, cs), BRUME_OK);
            brume_render_job *job = NULL;
            ASSERT_EQ_INT(brume_render_begin(ctx, cs, &job), BRUME_OK);
            ASSERT_EQ_INT(brume_render_job_run(ctx, job), BRUME_ERROR_CANCELLED);
            ASSERT_EQ_INT(brume_render_job_save(ctx, job, 42, ck), BRUME_OK);
            brume_render_job_release(job);
            /* resume on the plain scene */
            ASSERT_EQ_INT(brume_render_job_resume(ctx, s, 42, ck, &job), BRUME_OK);
            ASSERT_EQ_INT(brume_render_job_run(ctx, job), BRUME_OK);
            brume_image *img = NULL;
            ASSERT_EQ_INT(brume_render_job_image(ctx, job, &img), BRUME_OK);
            if (!same_pixels(full, img))
                TEST_FAIL("%d thread(s), cut after %d tiles: resumed image differs", threads, cuts[c]);
            brume_image_release(img);
            brume_render_job_release(job);
            brume_scene_release(cs);
        }
        /* refusals, each with one line naming the file */
        brume_render_job *job = NULL;
        ASSERT_EQ_INT(brume_render_job_resume(ctx, s, 43, ck, &job), BRUME_ERROR_STATE);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "another scene");
        ASSERT_TRUE(job == NULL);
        int w[2] = {threads, 32};
        brume_scene *other = load_default(32, 24, set_ckpt, w);
        ASSERT_EQ_INT(brume_render_job_resume(ctx, other, 42, ck, &job), BRUME_ERROR_STATE);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "render.width");
        brume_scene_release(other);
        size_t n;
        char *bytes = test_slurp(ck, &n);
        const char *bad = test_tmp_path("bad.ckpt");
        FILE *fp = fopen(bad, "wb");
        fwrite(bytes, 1, n / 2, fp);
        fclose(fp);
        ASSERT_EQ_INT(brume_render_job_resume(ctx, s, 42, bad, &job), BRUME_ERROR_PARSE);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "truncated");
        bytes[n / 2] ^= 0x10;
        fp = fopen(bad, "wb");
        fwrite(bytes, 1, n, fp);
        fclose(fp);
        ASSERT_EQ_INT(brume_render_job_resume(ctx, s, 42, bad, &job), BRUME_ERROR_PARSE);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "corrupt");
        bytes[n / 2] ^= 0x10;
        memcpy(bytes + 16, "0.0.0-other", 12); /* the version field (the version is checked first) */
        fp = fopen(bad, "wb");
        fwrite(bytes, 1, n, fp);
        fclose(fp);
        ASSERT_EQ_INT(brume_render_job_resume(ctx, s, 42, bad, &job), BRUME_ERROR_UNSUPPORTED);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "0.0.0-other");
        ASSERT_TRUE(strchr(brume_context_last_error(ctx), '\n') == NULL);
        free(bytes);
        remove(bad);
        remove(ck);
        brume_image_release(full);
        brume_context_release(ctx);
        brume_scene_release(s);
    }
}

static void set_time(brume_render_settings *rs, void *user)
{
    (void)user;
    rs->time_budget = 0.5;
    rs->noise_target = 0.0; /* no adaptive sampling: a pixel the default scene's 3 % target stops
                               would end with fewer samples than the others */
    rs->spp = 1 << 24;
    rs->aovs = BRUME_AOV_SAMPLES;
}

/* A time budget ends the render (the sample maximum is out of reach) with every pixel
 * sampled, within the budget: the clock is read before every sample, so it ends within a
 * sample per thread and the joining of the threads (0.2 s allowed for a machine shared
 * with other work; bench/bench_budget.sh measures the real margin), and the job says it
 * is finished. */
TEST(time_budget_ends_the_render)
{
    brume_scene *s = load_default(64, 40, set_time, NULL);
    brume_context *ctx = brume_context_new();
    brume_render_job *job = NULL;
    ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_OK);
    ASSERT_EQ_INT(brume_render_job_run(ctx, job), BRUME_OK);
    brume_render_progress p;
    brume_render_job_progress(job, &p);
    fprintf(stderr, "time budget 0.5 s: %.3f s, %d to %d spp\n", p.elapsed, p.spp_min, p.spp_max);
    ASSERT_TRUE(p.finished);
    ASSERT_TRUE(p.fraction == 1.0 && p.eta == 0.0);
    ASSERT_TRUE(p.spp_min >= 1 && p.spp_max < (1 << 24));
    /* passes are sized to fit the budget, but the clock read before each sample may cut the last
     * one (the load of a shared machine changes a sample's cost): the pixels then differ by at
     * most one pass, PASS_MAX = 16 samples (render.c) */
    ASSERT_TRUE(p.spp_max - p.spp_min <= 16);
    ASSERT_TRUE(p.elapsed <= 0.5 + 0.2);
    brume_render_job_release(job);
    brume_context_release(ctx);
    brume_scene_release(s);
}

/* A resumed job takes another time budget (docs/render-jobs.md): it continues from the
 * samples the checkpoint saved and spends its own budget, the seconds the checkpoint had
 * spent counted in the progress but not against the new budget. Before, the saved seconds
 * were charged to it: a job that had spent its budget resumed with nothing left. */
TEST(resumed_job_spends_its_own_budget)
{
    brume_scene *s = load_default(40, 24, set_time, NULL);
    brume_context *ctx = brume_context_new();
    const char *ck = test_tmp_path("budget.ckpt");
    brume_render_job *job = NULL;
    ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_OK);
    ASSERT_EQ_INT(brume_render_job_run(ctx, job), BRUME_OK); /* the 0.5 s budget spent */
    brume_render_progress before, after;
    brume_render_job_progress(job, &before);
    ASSERT_EQ_INT(brume_render_job_save(ctx, job, 42, ck), BRUME_OK);
    brume_render_job_release(job);
    ASSERT_EQ_INT(brume_render_job_resume(ctx, s, 42, ck, &job), BRUME_OK);
    brume_render_progress resumed;
    brume_render_job_progress(job, &resumed);
    ASSERT_EQ_INT(resumed.spp_min, before.spp_min); /* the saved samples, none lost */
    ASSERT_EQ_INT(resumed.spp_max, before.spp_max);
    ASSERT_TRUE(!resumed.finished); /* a new budget: work left */
    ASSERT_EQ_INT(brume_render_job_run(ctx, job), BRUME_OK);
    brume_render_job_progress(job, &after);
    fprintf(stderr, "0.5 s budget: %.3f s, %d to %d spp; resumed with another 0.5 s: %.3f s, %d to %d spp\n",
            before.elapsed, before.spp_min, before.spp_max, after.elapsed, after.spp_min, after.spp_max);
    ASSERT_TRUE(after.finished);
    /* every pixel past what the first budget gave it: the cut pass completed, then more */
    ASSERT_TRUE(after.spp_min > before.spp_max);
    /* the seconds across both runs; the second ends within half a pass of its budget
     * (render-jobs.md: a pass that does not half fit is not begun) or past it by the join
     * of the threads */
    ASSERT_TRUE(after.elapsed > before.elapsed + 0.25);
    ASSERT_TRUE(after.elapsed <= before.elapsed + 0.5 + 0.2);
    brume_render_job_release(job);
    remove(ck);
    brume_context_release(ctx);
    brume_scene_release(s);
}

static void set_tiny_time(brume_render_settings *rs, void *user)
{
    (void)user;
    rs->time_budget = *(const double *)user;
    rs->spp = 1 << 24;
    rs->threads = 2;
    rs->aovs = BRUME_AOV_SAMPLES;
}

/* A budget shorter than one sample per pixel: the first pass is cut too (no pass is owed
 * to the budget), the pixels it reached keep their samples, the others none, and the
 * render still ends within the budget. The image is what the samples make: a pixel's
 * value is its own samples' mean, so a pixel that got one sample here equals the same
 * pixel of a 1-sample render. */
TEST(time_budget_cuts_the_first_pass)
{
    /* a budget that reaches some pixels and not all: 5 ms, doubled while none is reached
     * (a loaded machine may spend the first milliseconds starting threads) */
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    brume_render_job *job = NULL;
    brume_image *img = NULL;
    brume_render_progress p;
    double budget = 0.005;
    for (int attempt = 0; attempt < 8; attempt++, budget *= 2.0) {
        s = load_default(240, 160, set_tiny_time, &budget);
        double t0 = test_now();
        ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_OK);
        brume_status st = brume_render_job_run(ctx, job);
        double wall = test_now() - t0;
        brume_render_job_progress(job, &p);
        /* a budget spent before the first sample is an error naming render.time */
        if (p.spp_max == 0) {
            ASSERT_EQ_INT(st, BRUME_ERROR_RANGE);
            ASSERT_CONTAINS(brume_context_last_error(ctx), "render.time");
        } else {
            ASSERT_EQ_INT(st, BRUME_OK);
        }
        fprintf(stderr, "budget %.3f s: %.3f s in the job, %.3f s wall, %d to %d spp\n", budget, p.elapsed, wall,
                p.spp_min, p.spp_max);
        ASSERT_TRUE(p.finished);
        ASSERT_TRUE(p.elapsed <= budget + 0.2);
        if (p.spp_max >= 1)
            break;
        brume_render_job_release(job);
        brume_scene_release(s);
    }
    ASSERT_EQ_INT(p.spp_min, 0); /* 240 x 160 samples of the default cloud take longer than that */
    ASSERT_TRUE(p.spp_max >= 1);
    ASSERT_EQ_INT(brume_render_job_image(ctx, job, &img), BRUME_OK);
    /* the pixels that got a sample equal a fixed 1-sample render's (another count differs) */
    const float *cnt = brume_image_layer_pixels(img, layer_index(img, "samples"));
    int spp1[2] = {1, 2}, spp2[2] = {2, 2};
    brume_scene *s1 = load_default(240, 160, set_spp_threads, spp1), *s2 = load_default(240, 160, set_spp_threads, spp2);
    brume_image *ref1 = render(s1), *ref2 = render(s2);
    const float *px = brume_image_pixels(img), *r1 = brume_image_pixels(ref1),
                *r2 = brume_image_pixels(ref2);
    int seen = 0, same1 = 0, noisy = 0, same2 = 0;
    for (int i = 0; i < 240 * 160; i++) {
        if (cnt[i] != 1.0f)
            continue;
        seen++;
        same1 += memcmp(px + 4 * i, r1 + 4 * i, 3 * sizeof(float)) == 0;
        if (memcmp(r1 + 4 * i, r2 + 4 * i, 3 * sizeof(float)) != 0) { /* not the noiseless sky */
            noisy++;
            same2 += memcmp(px + 4 * i, r2 + 4 * i, 3 * sizeof(float)) == 0;
        }
    }
    fprintf(stderr, "%d pixels with one sample: %d equal the 1-spp render's; of the %d whose 1- and 2-spp values "
            "differ, %d equal the 2-spp one\n", seen, same1, noisy, same2);
    ASSERT_TRUE(seen > 0 && seen < 240 * 160);
    ASSERT_EQ_INT(same1, seen);
    ASSERT_EQ_INT(same2, 0);
    brume_image_release(ref1);
    brume_image_release(ref2);
    brume_scene_release(s1);
    brume_scene_release(s2);
    brume_image_release(img);
    brume_render_job_release(job);
    brume_context_release(ctx);
    brume_scene_release(s);
}

static void set_spp_and_time(brume_render_settings *rs, void *user)
{
    (void)user;
    rs->aovs = BRUME_AOV_SAMPLES;
}

/* render.spp is the maximum under a budget as --spp and the library setting are: a file
 * with spp 3 and a long time budget stops at 3 samples; a file with a budget and no spp
 * has no maximum (2^24). */
TEST(spp_is_the_maximum_under_a_budget)
{
    const char *with = "{\"camera\": {\"position\": [0, 0, 1], \"look_at\": [0, 0, 0]}, \"render\": {\"width\": 32, \"height\": 16, \"spp\": 3, \"time\": 1000}}";
    brume_scene *s = load(with, set_spp_and_time, NULL);
    brume_image *img = render(s);
    const float *cnt = brume_image_layer_pixels(img, layer_index(img, "samples"));
    for (int i = 0; i < 32 * 16; i++)
        ASSERT_TRUE(cnt[i] == 3.0f);
    brume_image_release(img);
    brume_scene_release(s);
    const char *without = "{\"camera\": {\"position\": [0, 0, 1], \"look_at\": [0, 0, 0]}, \"render\": {\"width\": 32, \"height\": 16, \"noise\": 0.5}}";
    s = load(without, NULL, NULL);
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    ASSERT_EQ_INT(rs.spp, 1 << 24);
    brume_scene_release(s);
}

/* Under a noise target the ETA is unknown until the pixels have error estimates, and the
 * fraction never says 1 before the end; the callback sees the same figures. */
typedef struct eta_state {
    brume_render_job *job;
    int calls, unknown, full_before_end;
} eta_state;

static bool eta_cb(void *user, uint64_t done, uint64_t total)
{
    (void)done;
    (void)total;
    eta_state *e = user;
    if (!e->job)
        return true;
    brume_render_progress p;
    brume_render_job_progress(e->job, &p);
    e->calls++;
    e->unknown += p.eta < 0.0;
    e->full_before_end += p.fraction >= 1.0;
    ASSERT_TRUE((p.eta < 0.0) == (p.fraction < 0.0));
    return true;
}

static void set_noise_eta(brume_render_settings *rs, void *user)
{
    rs->noise_target = 0.05;
    rs->min_spp = 4;
    rs->spp = 256;
    rs->progress_fn = eta_cb;
    rs->progress_user = user;
}

TEST(noise_eta_unknown_then_known_never_full_early)
{
    eta_state e = {NULL, 0, 0, 0};
    brume_scene *s = load_default(64, 40, set_noise_eta, &e);
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(brume_render_begin(ctx, s, &e.job), BRUME_OK);
    ASSERT_EQ_INT(brume_render_job_run(ctx, e.job), BRUME_OK);
    brume_render_progress p;
    brume_render_job_progress(e.job, &p);
    fprintf(stderr, "%d calls, %d with the ETA unknown, %d at 100 %% before the end\n", e.calls, e.unknown,
            e.full_before_end);
    ASSERT_TRUE(e.unknown > 0 && e.unknown < e.calls);
    ASSERT_EQ_INT(e.full_before_end, 0);
    ASSERT_TRUE(p.finished && p.fraction == 1.0);
    brume_render_job_release(e.job);
    brume_context_release(ctx);
    brume_scene_release(s);
}

TEST_MAIN(progressive_passes_equal_one_render, cancel_stops_within_one_tile, progress_counts_never_go_back, aovs_known_depth_albedo_normal,
          adaptive_sampling_independent_of_threads, noise_target_constant_fog_closed_form, noise_target_white_furnace,
          checkpoint_resume_is_bit_identical, time_budget_ends_the_render, time_budget_cuts_the_first_pass,
          spp_is_the_maximum_under_a_budget, noise_eta_unknown_then_known_never_full_early,
          resumed_job_spends_its_own_budget)
