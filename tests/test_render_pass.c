/* test_render_pass.c - the pass interface (render/pass.h), on the CPU:
 *   - a pass's sums do not depend on how the samples are split into passes or on the
 *     order of its pixel list, and a pass cut by its callback keeps whole samples only;
 *   - a sample whose estimate is NaN or infinite adds 0 and is counted, in brume_stats'
 *     samples_nonfinite, the same with one thread or two; a valid scene counts none. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "brume.h"
#include "render/integrator.h"
#include "render/pass.h"
#include "scene/scene.h"
#include "test.h"

/* a fog box lit by a sun travelling towards the camera through it, forward scattering:
 * the in-scattered radiance near the image's centre is about 15 x the sun's irradiance */
#define FOG_SCENE(IRRADIANCE)                                                                                        \
    "{\"camera\": {\"position\": [0, -3, 0], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1], \"fov\": 30},"               \
    " \"background\": 0,"                                                                                            \
    " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": " IRRADIANCE "}],"             \
    " \"media\": [{\"name\": \"fog\", \"density\": {\"type\": \"constant\", \"value\": 1,"                            \
    "   \"bounds\": [[-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]]}, \"sigma_a\": 0.1, \"sigma_s\": 1.0,"                       \
    "   \"phase\": {\"type\": \"hg\", \"g\": 0.9}}],"                                                                \
    " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 8, \"seed\": 3, \"method\": \"path\", \"max_depth\": 8}}"

typedef struct pass_buffers {
    uint32_t list[8], n[8];
    double sum[8][JOB_SUMS], sq[8][JOB_SQS];
} pass_buffers;

/* A pass over the listed pixels of s, with empty sums, to `target` samples. */
static render_pass make_pass(const brume_scene *s, const void *state, pass_buffers *b, const uint32_t *pixels,
                             size_t np, uint32_t target)
{
    memset(b, 0, sizeof *b);
    memcpy(b->list, pixels, np * sizeof *pixels);
    sample_params sp = {.kind = INTEGRATOR_PATH,
                        .width = s->settings.width,
                        .height = s->settings.height,
                        .seed = 3,
                        .filter = s->settings.filter,
                        .filter_width = s->settings.filter_width,
                        .qmc_dims = RENDER_SOBOL_DIMS,
                        .squares = true};
    return (render_pass){.s = s, .state = state, .sp = sp, .pixels = b->list, .npixels = np, .target = target,
                         .n = b->n, .sum = b->sum, .sq = b->sq};
}

static int cut_after; /* cut_at_count: samples let through before the cut */
static bool cut_at_count(void *user)
{
    (void)user;
    return cut_after-- <= 0;
}

TEST(split_and_order_do_not_change_the_sums)
{
    brume_scene *s = test_scene_json(FOG_SCENE("3.0"));
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    void *state = NULL;
    ASSERT_EQ_INT(integrator_prepare(INTEGRATOR_PATH, s, &state), BRUME_OK);
    const uint32_t pixels[4] = {0, 119, 136, 255}, reversed[4] = {255, 136, 119, 0};
    pass_buffers a, b;
    /* one pass of 7 samples */
    render_pass pa = make_pass(s, state, &a, pixels, 4, 7);
    pass_render_cpu(&pa);
    ASSERT_EQ_INT((int)pa.taken, 28);
    /* the same samples in passes of 2 and 5, the list reversed */
    render_pass pb = make_pass(s, state, &b, reversed, 4, 2);
    pass_render_cpu(&pb);
    pb.target = 7;
    pass_render_cpu(&pb);
    ASSERT_EQ_INT((int)pb.taken, 28);
    double total = 0.0;
    for (int j = 0; j < 4; j++) {
        ASSERT_EQ_INT((int)a.n[j], 7);
        ASSERT_EQ_INT((int)b.n[3 - j], 7);
        ASSERT_TRUE(memcmp(a.sum[j], b.sum[3 - j], sizeof a.sum[j]) == 0);
        ASSERT_TRUE(memcmp(a.sq[j], b.sq[3 - j], sizeof a.sq[j]) == 0);
        total += a.sum[j][0] + a.sum[j][1] + a.sum[j][2];
    }
    ASSERT_TRUE(total > 0.0); /* the fog is lit: the sums hold radiance */
    /* a pass cut after 10 samples keeps 10 whole ones, pixel by pixel in list order */
    render_pass pc = make_pass(s, state, &b, pixels, 4, 7);
    cut_after = 10;
    pc.cut = cut_at_count;
    pass_render_cpu(&pc);
    ASSERT_EQ_INT((int)pc.taken, 10);
    ASSERT_EQ_INT((int)b.n[0], 7);
    ASSERT_EQ_INT((int)b.n[1], 3);
    ASSERT_TRUE(memcmp(a.sum[0], b.sum[0], sizeof a.sum[0]) == 0);
    /* completed by the same pass again: the same sums as one pass */
    pc.cut = NULL;
    pass_render_cpu(&pc);
    ASSERT_EQ_INT((int)pc.taken, 28);
    for (int j = 0; j < 4; j++)
        ASSERT_TRUE(memcmp(a.sum[j], b.sum[j], sizeof a.sum[j]) == 0);
    integrator_finish(INTEGRATOR_PATH, state);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* samples_nonfinite after rendering the fog scene, its sun's irradiance set to E (past the
 * reader's bound of 1e30, as no scene file may: the test's hook), with `threads` threads;
 * *peak is the image's largest R, G or B */
static uint64_t nonfinite_of(double E, int threads, float *peak)
{
    brume_scene *s = test_scene_json(FOG_SCENE("3.0"));
    s->lights[0].L = col(E);
    brume_image *img = test_render_scene(s, threads, 3);
    const float *px = brume_image_pixels(img);
    *peak = 0.0f;
    for (int i = 0; i < brume_image_width(img) * brume_image_height(img); i++)
        for (int c = 0; c < 3; c++)
            *peak = fmaxf(*peak, px[4 * i + c]);
    brume_stats st;
    brume_scene_stats(s, &st);
    brume_image_release(img);
    brume_scene_release(s);
    return st.samples_nonfinite;
}

TEST(nonfinite_samples_counted)
{
    const uint64_t rays = 16 * 16 * 8;
    float peak = 0.0f;
    /* a sun of 3: none, and a lit fog */
    ASSERT_EQ_INT((int)nonfinite_of(3.0, 2, &peak), 0);
    ASSERT_TRUE(peak > 0.0f);
    /* a sun of 1e308: the forward-scattered radiance near the centre overflows in some
     * samples, the same ones with one thread or two */
    uint64_t bad1 = nonfinite_of(1e308, 1, &peak), bad2 = nonfinite_of(1e308, 2, &peak);
    /* an infinite sun: every sample it lights is infinite or NaN, and each adds 0, so the
     * image is black (the background is) */
    uint64_t bad_inf = nonfinite_of(INFINITY, 2, &peak);
    printf("samples_nonfinite of %llu: sun 1e308 %llu (1 thread), %llu (2 threads); infinite sun %llu\n",
           (unsigned long long)rays, (unsigned long long)bad1, (unsigned long long)bad2, (unsigned long long)bad_inf);
    ASSERT_TRUE(bad1 > 0 && bad1 < rays);
    ASSERT_EQ_INT((int)bad1, (int)bad2);
    ASSERT_TRUE(bad_inf > bad1 && bad_inf <= rays);
    ASSERT_TRUE(peak == 0.0f);
}

TEST_MAIN(split_and_order_do_not_change_the_sums, nonfinite_samples_counted)
