/* test_inputs_checked.c - images checked on the way in: compare, denoise (every layer),
 * environment maps and checkpoints refuse NaN, infinities and negative values in one line
 * (the "normal" layer is signed: only finite), and a checkpoint's sums must be what its
 * sample counts can give. */
#include "test.h"

#include <stdint.h>

#include "brume.h"

static brume_image *flat(int w, int h, float v)
{
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_new(NULL, w, h, &img), BRUME_OK);
    float *p = brume_image_pixels(img);
    for (int i = 0; i < w * h; i++)
        for (int c = 0; c < 4; c++)
            p[4 * i + c] = c == 3 ? 1.0f : v;
    return img;
}

/* brume_image_compare and its kin refuse an image or a reference holding NaN, an infinity or
 * a negative value, naming which and where; `brume compare` names the file, exit 1. */
TEST(compare_refuses_bad_values)
{
    const float bad[3] = {NAN, INFINITY, -0.5f};
    brume_context *ctx = brume_context_new();
    for (int k = 0; k < 3; k++)
        for (int which = 0; which < 2; which++) {
            brume_image *a = flat(5, 3, 1.0f), *b = flat(5, 3, 2.0f);
            brume_image_pixels(which ? b : a)[4 * 7 + 1] = bad[k];
            brume_image_diff d;
            brume_region_stats r;
            ASSERT_EQ_INT(brume_image_compare(ctx, a, b, &d), BRUME_ERROR_RANGE);
            ASSERT_CONTAINS(brume_context_last_error(ctx), which ? "the reference" : "the image");
            ASSERT_CONTAINS(brume_context_last_error(ctx), "pixel (2, 1) G");
            ASSERT_EQ_INT(brume_image_compare_region(ctx, a, b, NULL, 10, 1, &r), BRUME_ERROR_RANGE);
            brume_image *pic = NULL;
            ASSERT_EQ_INT(brume_image_diff_picture(ctx, a, b, 0.5, &pic), BRUME_ERROR_RANGE);
            ASSERT_TRUE(pic == NULL);
            brume_image_release(a);
            brume_image_release(b);
        }
    /* the command, on files */
    const char *good = test_tmp_path("good.pfm"), *nan = test_tmp_path("nan.pfm"), *err = test_tmp_path("err");
    brume_image *a = flat(4, 4, 1.0f);
    ASSERT_EQ_INT(brume_image_write(ctx, a, good, NULL), BRUME_OK);
    brume_image_pixels(a)[0] = NAN;
    ASSERT_EQ_INT(brume_image_write(ctx, a, nan, NULL), BRUME_OK);
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s compare %s %s 2> %s", BRUME_EXE, good, nan, err);
    ASSERT_EQ_INT(test_system(cmd), 1);
    size_t n;
    char *e = test_slurp(err, &n);
    ASSERT_CONTAINS(e, nan);
    ASSERT_CONTAINS(e, "is nan");
    ASSERT_TRUE(strchr(e, '\n') == e + n - 1);
    free(e);
    remove(good);
    remove(nan);
    remove(err);
    brume_image_release(a);
    brume_context_release(ctx);
}

/* brume_denoise refuses a NaN or a negative value in RGB or in any layer it is given (the
 * variance, albedo and depth features), and takes a negative normal (a signed layer). */
TEST(denoise_checks_every_layer)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    const char *sets[] = {"render.width=12", "render.height=8", "render.spp=4"};
    brume_load_options lo = {0.0, 0, sets, 3, NULL, 0, false};
    ASSERT_EQ_INT(brume_scene_load(ctx, NULL, &lo, &s), BRUME_OK);
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.aovs = BRUME_AOV_VARIANCE | BRUME_AOV_ALBEDO | BRUME_AOV_NORMAL | BRUME_AOV_DEPTH;
    ASSERT_EQ_INT(brume_scene_set_settings(ctx, s, &rs), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    static const char *const layers[] = {"variance", "albedo", "depth", "normal"};
    for (int k = 0; k < 4; k++)
        for (int neg = 0; neg < 2; neg++) {
            brume_image *img = NULL, *out = NULL;
            ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_OK);
            int li = -1;
            for (int i = 0; i < brume_image_layer_count(img); i++)
                if (strcmp(brume_image_layer_name(img, i), layers[k]) == 0)
                    li = i;
            ASSERT_TRUE(li >= 0);
            /* the test forges a hostile image: the layer's pixels are the image's own */
            float *px = (float *)brume_image_layer_pixels(img, li);
            px[brume_image_layer_channels(img, li) * 5] = neg ? -0.25f : NAN;
            brume_status st = brume_denoise(ctx, img, 1, &out);
            if (k == 3 && neg) { /* a normal's component may be negative */
                ASSERT_EQ_INT(st, BRUME_OK);
            } else {
                ASSERT_EQ_INT(st, BRUME_ERROR_RANGE);
                ASSERT_CONTAINS(brume_context_last_error(ctx), layers[k]);
                ASSERT_TRUE(out == NULL);
            }
            brume_image_release(out);
            brume_image_release(img);
        }
    /* and RGB */
    brume_image *img = NULL, *out = NULL;
    ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_OK);
    brume_image_pixels(img)[2] = INFINITY;
    ASSERT_EQ_INT(brume_denoise(ctx, img, 1, &out), BRUME_ERROR_RANGE);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "pixel (0, 0) B is inf");
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* An environment map holding a NaN or a negative value is refused when the scene is read,
 * naming the key, the pixel and the channel. */
TEST(environment_map_refuses_bad_values)
{
    brume_context *ctx = brume_context_new();
    const char *sky = test_tmp_path("sky.pfm"), *scene = test_tmp_path("sky.json");
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, -3], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0], \"fov\": 40},\n"
             " \"background\": {\"file\": \"%s\"}, \"render\": {\"width\": 4, \"height\": 4, \"spp\": 1}}\n",
             sky);
    test_write_file(scene, json);
    const float bad[3] = {NAN, -1.0f, INFINITY};
    for (int k = 0; k < 3; k++) {
        brume_image *m = flat(8, 4, 0.5f);
        brume_image_pixels(m)[4 * 3] = bad[k];
        ASSERT_EQ_INT(brume_image_write(ctx, m, sky, NULL), BRUME_OK);
        brume_scene *s = NULL;
        ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = scene}, NULL, &s), BRUME_ERROR_RANGE);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "must be finite and >= 0");
        ASSERT_TRUE(s == NULL);
        brume_image_release(m);
    }
    remove(sky);
    remove(scene);
    brume_context_release(ctx);
}

static uint64_t fnv1a(const unsigned char *p, size_t n)
{
    uint64_t h = 0xcbf29ce484222325ULL;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ULL;
    }
    return h;
}

/* A checkpoint whose sums its sample counts cannot give is refused in one line before the
 * render resumes: NaN sums, zeroed sums beside their squares, negative sums, sums for a pixel
 * of no sample. The forger rewrites the checksum, as an attacker would (docs/render-jobs.md
 * gives the layout: the pixels' counts, flags, 4 sums and 4 squares each, then the hash). */
TEST(forged_checkpoint_sums_are_refused)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    const char *sets[] = {"render.width=8", "render.height=4", "render.spp=4"};
    brume_load_options lo = {0.0, 0, sets, 3, NULL, 0, false};
    ASSERT_EQ_INT(brume_scene_load(ctx, NULL, &lo, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    brume_render_job *job = NULL;
    ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_OK);
    ASSERT_EQ_INT(brume_render_job_add(ctx, job, 4), BRUME_OK);
    ASSERT_EQ_INT(brume_render_job_run(ctx, job), BRUME_OK);
    const char *path = test_tmp_path("job.ckpt"), *forged = test_tmp_path("forged.ckpt");
    ASSERT_EQ_INT(brume_render_job_save(ctx, job, 7, path), BRUME_OK);
    brume_render_job_release(job);
    size_t size;
    unsigned char *data = (unsigned char *)test_slurp(path, &size);
    const size_t np = 32, per = 4 + 1 + 8 * 8, head = size - 8 - np * per;
    const size_t sums = head + np * 5; /* the squares follow: np * 4 doubles */
    ASSERT_TRUE(size > 8 + np * per);
    /* the untouched file resumes */
    ASSERT_EQ_INT(brume_render_job_resume(ctx, s, 7, path, &job), BRUME_OK);
    brume_render_job_release(job);
    for (int k = 0; k < 4; k++) {
        unsigned char *f = malloc(size);
        memcpy(f, data, size);
        double v;
        const size_t pix = 9;
        switch (k) {
        case 0: /* a NaN sum */
            v = NAN;
            memcpy(f + sums + (4 * pix + 1) * 8, &v, 8);
            break;
        case 1: /* every sum zeroed, the squares kept */
            memset(f + sums, 0, np * 4 * 8);
            break;
        case 2: /* a negative sum */
            v = -1.0;
            memcpy(f + sums + 4 * pix * 8, &v, 8);
            break;
        case 3: /* a pixel of no sample with sums */
            memset(f + head + 4 * pix, 0, 4);
            break;
        }
        uint64_t h = fnv1a(f, size - 8);
        memcpy(f + size - 8, &h, 8);
        FILE *fp = fopen(forged, "wb");
        ASSERT_TRUE(fp && fwrite(f, 1, size, fp) == size);
        fclose(fp);
        free(f);
        job = NULL;
        ASSERT_EQ_INT(brume_render_job_resume(ctx, s, 7, forged, &job), BRUME_ERROR_PARSE);
        ASSERT_TRUE(job == NULL);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "checkpoint corrupt");
        ASSERT_TRUE(strchr(brume_context_last_error(ctx), '\n') == NULL);
    }
    free(data);
    remove(path);
    remove(forged);
    brume_scene_release(s);
    brume_context_release(ctx);
}

TEST_MAIN(compare_refuses_bad_values, denoise_checks_every_layer, environment_map_refuses_bad_values,
          forged_checkpoint_sums_are_refused)
