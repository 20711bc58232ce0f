/* test_blob_threads.c - two blob scenes loaded on two threads at once are each the scene a
 * lone load makes: the blob fields' hierarchy (core/bvh.c) is built with no state shared
 * between builds, so the images agree byte for byte. */
#include <pthread.h>

#include "brume.h"
#include "test.h"

/* Two fields of a few thousand blobs, so that the builds of two threads overlap; a tiny
 * render of each with the path tracer, which reads the blobs through their hierarchy. */
static const char *const scenes[2] = {
    "{\"camera\": {\"position\": [0, 0.3, 6], \"look_at\": [0, 0, 0], \"fov\": 40},"
    " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.6, -0.55, -0.58], \"irradiance\": [7, 7, 7]}],"
    " \"media\": [{\"sigma_a\": 0.01, \"sigma_s\": 1.5, \"density\": {\"type\": \"blobs\", \"generators\":"
    " [{\"type\": \"cloud\", \"center\": [0, 0, 0], \"radii\": [1.6, 0.75, 1.0], \"count\": 6000,"
    " \"h\": [0.05, 0.15], \"density\": 0.6, \"seed\": 5}]}}],"
    " \"render\": {\"width\": 12, \"height\": 9, \"spp\": 2, \"seed\": 3}}",
    "{\"camera\": {\"position\": [0, 0.5, 9], \"look_at\": [0, 0, 0], \"fov\": 60},"
    " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, -1, -0.2], \"irradiance\": [5, 5, 5]}],"
    " \"media\": [{\"sigma_a\": 0.05, \"sigma_s\": 2.0, \"density\": {\"type\": \"blobs\", \"generators\":"
    " [{\"type\": \"cluster\", \"bounds_min\": [-4, -1, -2], \"bounds_max\": [4, 1.5, 2], \"clouds\": 5,"
    " \"radii_min\": [0.6, 0.3, 0.5], \"radii_max\": [1.5, 0.8, 1.2], \"count\": 1200, \"h\": [0.06, 0.2],"
    " \"density\": 0.3, \"falloff\": 1.0, \"seed\": 21}]}}],"
    " \"render\": {\"width\": 12, \"height\": 9, \"spp\": 2, \"seed\": 3}}",
};

typedef struct job {
    int which;
    pthread_barrier_t *start;
    brume_scene *scene;
    char error[512];
} job;

/* Loads and commits scene j->which (after the barrier when given). */
static void *load(void *arg)
{
    job *j = arg;
    if (j->start)
        pthread_barrier_wait(j->start);
    brume_context *ctx = brume_context_new();
    brume_source src = {"<blob scene>", scenes[j->which]};
    j->error[0] = '\0';
    if (brume_scene_load(ctx, &src, NULL, &j->scene) != BRUME_OK || brume_scene_commit(ctx, j->scene) != BRUME_OK)
        snprintf(j->error, sizeof j->error, "%s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    return NULL;
}

/* The RGBA bytes of the scene's image (one render thread), malloc'd; *n their count. */
static float *render(brume_scene *s, size_t *n)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    if (brume_render(ctx, s, &img) != BRUME_OK)
        TEST_FAIL("render: %s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    *n = (size_t)brume_image_width(img) * (size_t)brume_image_height(img) * 4;
    float *px = malloc(*n * sizeof *px);
    ASSERT_TRUE(px != NULL);
    memcpy(px, brume_image_pixels(img), *n * sizeof *px);
    brume_image_release(img);
    return px;
}

TEST(two_blob_scenes_loaded_at_once)
{
    float *alone[2];
    size_t n[2];
    for (int k = 0; k < 2; k++) {
        job j = {k, NULL, NULL, ""};
        load(&j);
        if (j.error[0])
            TEST_FAIL("scene %d alone: %s", k, j.error);
        alone[k] = render(j.scene, &n[k]);
        brume_scene_release(j.scene);
    }
    /* the two images differ: a mix-up of the scenes would be seen */
    ASSERT_TRUE(n[0] != n[1] || memcmp(alone[0], alone[1], n[0] * sizeof(float)) != 0);
    double lit = 0.0;
    for (size_t i = 0; i < n[0]; i++)
        lit += alone[0][i];
    ASSERT_TRUE(lit > 0.0);
    for (int round = 0; round < 4; round++) {
        pthread_barrier_t start;
        pthread_barrier_init(&start, NULL, 2);
        job j[2] = {{0, &start, NULL, ""}, {1, &start, NULL, ""}};
        pthread_t t[2];
        for (int k = 0; k < 2; k++)
            ASSERT_EQ_INT(pthread_create(&t[k], NULL, load, &j[k]), 0);
        for (int k = 0; k < 2; k++)
            pthread_join(t[k], NULL);
        pthread_barrier_destroy(&start);
        for (int k = 0; k < 2; k++) {
            if (j[k].error[0])
                TEST_FAIL("round %d, scene %d: %s", round, k, j[k].error);
            size_t m;
            float *px = render(j[k].scene, &m);
            ASSERT_EQ_INT(m, n[k]);
            if (memcmp(px, alone[k], m * sizeof *px) != 0)
                TEST_FAIL("round %d: scene %d loaded beside the other differs from its lone load", round, k);
            free(px);
            brume_scene_release(j[k].scene);
        }
    }
    free(alone[0]);
    free(alone[1]);
}

TEST_MAIN(two_blob_scenes_loaded_at_once)
