/* test_scene.c - scene files: valid ones load, every kind of bad one fails with a one-line
 * message naming the file and the offending key. */
#include "test.h"

#include "brume.h"

static const char *write_text(const char *name, const char *text)
{
    const char *path = test_tmp_path(name);
    FILE *fp = fopen(path, "wb");
    ASSERT_TRUE(fp != NULL);
    fputs(text, fp);
    fclose(fp);
    return path;
}

#define MINIMAL_CAMERA "\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]}"

/* Loads text from a temp file and expects failure with a message containing the file name,
 * every fragment given, and no newline. */
static void expect_error(const char *text, brume_status want, const char *frag1, const char *frag2)
{
    const char *path = write_text("bad.json", text);
    brume_context *ctx = brume_context_new();
    brume_scene *s = (brume_scene *)1;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s);
    if (st == BRUME_OK)
        TEST_FAIL("scene loaded but should fail: %s", text);
    ASSERT_TRUE(s == NULL);
    ASSERT_EQ_INT(st, want);
    const char *msg = brume_context_last_error(ctx);
    ASSERT_CONTAINS(msg, path);
    ASSERT_CONTAINS(msg, frag1);
    if (frag2)
        ASSERT_CONTAINS(msg, frag2);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
    brume_context_release(ctx);
    remove(path);
}

TEST(minimal_scene_loads)
{
    const char *path = write_text("ok.json", "{" MINIMAL_CAMERA "}");
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s), BRUME_OK);
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    ASSERT_EQ_INT(rs.width, 640); /* documented defaults */
    ASSERT_EQ_INT((int)rs.method, (int)BRUME_METHOD_PATH);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    /* settings are frozen after commit */
    ASSERT_EQ_INT(brume_scene_set_settings(ctx, s, &rs), BRUME_ERROR_STATE);
    brume_scene_release(s);
    brume_context_release(ctx);
    remove(path);
}

TEST(default_scene_loads)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, NULL, NULL, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    brume_scene_release(s);
    brume_context_release(ctx);
}

TEST(syntax_error_names_line)
{
    expect_error("{\n  \"camera\": {\"position\": [0, 0, 5],\n  \"look_at\": [0, 0 0]}}", BRUME_ERROR_PARSE, "line 3",
                 "syntax");
}

TEST(unknown_keys_are_errors)
{
    expect_error("{" MINIMAL_CAMERA ", \"lites\": []}", BRUME_ERROR_PARSE, "lites", "unknown key");
    expect_error("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"fovy\": 30}}", BRUME_ERROR_PARSE,
                 "camera.fovy", "unknown key");
    expect_error("{" MINIMAL_CAMERA ", \"media\": [{\"sigma_a\": 1, \"sigma_s\": 1, \"density\": {\"type\": "
                 "\"constant\"}, \"phase\": {\"type\": \"hg\", \"gg\": 0.5}}]}",
                 BRUME_ERROR_PARSE, "media[0].phase.gg", "unknown key");
    expect_error("{" MINIMAL_CAMERA ", \"render\": {\"filter\": {\"type\": \"box\", \"radius\": 1}}}",
                 BRUME_ERROR_PARSE, "render.filter.radius", NULL);
}

TEST(wrong_types_are_errors)
{
    expect_error("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"fov\": \"wide\"}}",
                 BRUME_ERROR_PARSE, "camera.fov", "number");
    expect_error("{\"camera\": {\"position\": [0, 0], \"look_at\": [0, 0, 0]}}", BRUME_ERROR_PARSE,
                 "camera.position", "3 numbers");
    expect_error("{" MINIMAL_CAMERA ", \"lights\": {}}", BRUME_ERROR_PARSE, "lights", "array");
    expect_error("{" MINIMAL_CAMERA ", \"render\": {\"spp\": 2.5}}", BRUME_ERROR_PARSE, "render.spp", "integer");
    expect_error("{" MINIMAL_CAMERA ", \"render\": {\"method\": 3}}", BRUME_ERROR_PARSE, "render.method", "string");
}

TEST(missing_required_keys_are_errors)
{
    expect_error("{}", BRUME_ERROR_PARSE, "camera", "required");
    expect_error("{\"camera\": {\"position\": [0, 0, 5]}}", BRUME_ERROR_PARSE, "camera.look_at", "required");
    expect_error("{" MINIMAL_CAMERA ", \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0]}]}",
                 BRUME_ERROR_PARSE, "lights[0].irradiance", "required");
    expect_error("{" MINIMAL_CAMERA ", \"media\": [{\"sigma_a\": 1, \"sigma_s\": 1}]}", BRUME_ERROR_PARSE,
                 "media[0].density", "required");
}

TEST(bad_values_are_errors)
{
    expect_error("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"fov\": 400}}", BRUME_ERROR_RANGE,
                 "camera.fov", "400");
    expect_error("{" MINIMAL_CAMERA ", \"render\": {\"spp\": -1}}", BRUME_ERROR_RANGE, "render.spp", "-1");
    expect_error("{" MINIMAL_CAMERA ", \"render\": {\"width\": 100000}}", BRUME_ERROR_RANGE, "render.width", NULL);
    expect_error("{" MINIMAL_CAMERA ", \"render\": {\"method\": \"magic\"}}", BRUME_ERROR_UNSUPPORTED,
                 "render.method", "magic");
    expect_error("{" MINIMAL_CAMERA ", \"media\": [{\"sigma_a\": -1, \"sigma_s\": 1, \"density\": {\"type\": "
                 "\"constant\"}}]}",
                 BRUME_ERROR_RANGE, "media[0].sigma_a", "-1");
    expect_error("{" MINIMAL_CAMERA ", \"media\": [{\"sigma_a\": 1, \"sigma_s\": 1, \"density\": {\"type\": "
                 "\"constant\"}, \"phase\": {\"type\": \"hg\", \"g\": 1.5}}]}",
                 BRUME_ERROR_RANGE, "media[0].phase.g", "1.5");
    expect_error("{" MINIMAL_CAMERA ", \"media\": [{\"sigma_a\": 1, \"sigma_s\": 1, \"density\": {\"type\": "
                 "\"constant\", \"bounds\": [[1, 1, 1], [0, 0, 0]]}}]}",
                 BRUME_ERROR_RANGE, "media[0].density.bounds", NULL);
    expect_error("{" MINIMAL_CAMERA ", \"lights\": [{\"type\": \"laser\"}]}", BRUME_ERROR_PARSE, "lights[0].type",
                 "laser");
    expect_error("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]}, \"camera\": {}}",
                 BRUME_ERROR_PARSE, "camera", "twice");
}

#define MEDIUM_WITH(PHASE)                                                                           \
    "{" MINIMAL_CAMERA ", \"media\": [{\"sigma_a\": 1, \"sigma_s\": 1, \"density\": {\"type\": \"constant\"}, " \
    "\"phase\": " PHASE "}]}"

/* Every phase function of the Blasi family can be named in a scene. */
TEST(phase_functions_in_scenes)
{
    const char *ok[] = {
        "{\"type\": \"isotropic\"}", "{\"type\": \"rayleigh\"}", "{\"type\": \"hazy\"}", "{\"type\": \"murky\"}",
        "{\"type\": \"hg\", \"g\": -0.2}", "{\"type\": \"schlick\", \"k\": 0.5}", "{\"type\": \"schlick\", \"g\": 0.5}",
        "{\"type\": \"schlick_mix\", \"r\": 0.19, \"k\": -0.65, \"kprime\": 0.91}",
        ("{\"type\": \"mixture\", \"lobes\": [{\"weight\": 1, \"phase\": {\"type\": \"rayleigh\"}},"
         " {\"weight\": 3, \"phase\": {\"type\": \"hg\", \"g\": 0.8}}]}")};
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        char text[1024];
        snprintf(text, sizeof text, MEDIUM_WITH("%s"), ok[i]);
        const char *path = write_text("phase.json", text);
        brume_context *ctx = brume_context_new();
        brume_scene *s = NULL;
        if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
            TEST_FAIL("%s: %s", ok[i], brume_context_last_error(ctx));
        brume_scene_release(s);
        brume_context_release(ctx);
        remove(path);
    }
    expect_error(MEDIUM_WITH("{\"type\": \"schlick\", \"k\": 1.2}"), BRUME_ERROR_RANGE, "media[0].phase.k", "1.2");
    expect_error(MEDIUM_WITH("{\"type\": \"schlick\", \"k\": 0.2, \"g\": 0.1}"), BRUME_ERROR_PARSE, "media[0].phase",
                 "exactly one");
    expect_error(MEDIUM_WITH("{\"type\": \"schlick_mix\", \"r\": 1.5, \"k\": 0, \"kprime\": 0}"), BRUME_ERROR_RANGE,
                 "media[0].phase.r", "1.5");
    expect_error(MEDIUM_WITH("{\"type\": \"mixture\", \"lobes\": [{\"weight\": 1, \"phase\": {\"type\": \"hg\", "
                             "\"g\": 2}}]}"),
                 BRUME_ERROR_RANGE, "media[0].phase.lobes[0].phase.g", NULL);
    expect_error(MEDIUM_WITH("{\"type\": \"tabulated\", \"file\": \"no-such-table.txt\"}"), BRUME_ERROR_IO,
                 "media[0].phase", "no-such-table.txt");
    expect_error(MEDIUM_WITH("{\"type\": \"mie\"}"), BRUME_ERROR_PARSE, "media[0].phase.type", "mie");
}

TEST(missing_file_is_io_error)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "/nonexistent/dir/scene.json"}, NULL, &s), BRUME_ERROR_IO);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "/nonexistent/dir/scene.json");
    ASSERT_TRUE(s == NULL);
    brume_context_release(ctx);
}

static int callback_calls;
static void on_error(void *user, brume_status st, const char *msg)
{
    (void)user;
    (void)msg;
    ASSERT_TRUE(st != BRUME_OK);
    callback_calls++;
}

TEST(error_callback_receives_errors)
{
    brume_context *ctx = brume_context_new();
    brume_context_set_error_callback(ctx, on_error, NULL);
    brume_scene *s = NULL;
    callback_calls = 0;
    brume_scene_load(ctx, &(brume_source){.path = "/nonexistent.json"}, NULL, &s);
    ASSERT_EQ_INT(callback_calls, 1);
    ASSERT_EQ_INT(brume_context_last_status(ctx), BRUME_ERROR_IO);
    brume_context_release(ctx);
}

/* The scene files shipped in scenes/ all load and commit. */
TEST(shipped_scenes_load)
{
    const char *names[] = {"default.json"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/scenes/%s", BRUME_SOURCE_DIR, names[i]);
        brume_context *ctx = brume_context_new();
        brume_scene *s = NULL;
        if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
            TEST_FAIL("%s", brume_context_last_error(ctx));
        ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
        brume_scene_release(s);
        brume_context_release(ctx);
    }
}

TEST_MAIN(minimal_scene_loads, default_scene_loads, syntax_error_names_line, unknown_keys_are_errors,
          wrong_types_are_errors, missing_required_keys_are_errors, bad_values_are_errors, phase_functions_in_scenes,
          missing_file_is_io_error,
          error_callback_receives_errors, shipped_scenes_load)
