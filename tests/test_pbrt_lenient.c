/* test_pbrt_lenient.c - `--lenient` for pbrt-v4 files (docs/pbrt.md): what brume cannot
 * honour is skipped with one warning per construct and counted in the summary; malformed
 * input stays an error; without the flag the first construct is refused by name. */
#include "test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brume.h"

/* A sphere with pbrt's "zmin" (a cut sphere: brume draws whole spheres) at line 5 and a
 * cone at line 6, lit by a point light at the camera. */
static const char two_unsupported[] =
    "LookAt 0 0 -5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [30]\n"
    "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
    "WorldBegin\n"
    "Shape \"sphere\" \"float radius\" [1] \"float zmin\" [-0.5]\n"
    "Shape \"cone\" \"float radius\" [1] \"float height\" [2]\n"
    "LightSource \"point\" \"point3 from\" [0 0 -5] \"rgb I\" [10 10 10]\n";

static const char *write_scene(const char *name, const char *text)
{
    const char *path = test_tmp_path(name);
    test_write_file(path, text);
    return path;
}

/* Loads path with or without lenient: the status, the message, the scene (or NULL). */
static brume_status load(const char *path, bool lenient, char *msg, size_t cap, brume_scene **out)
{
    brume_context *ctx = brume_context_new();
    brume_load_options lo = {.lenient = lenient};
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = path}, &lo, out);
    snprintf(msg, cap, "%s", st == BRUME_OK ? "" : brume_context_last_error(ctx));
    brume_context_release(ctx);
    return st;
}

/* Without --lenient: one line naming the file, the line and the first construct. */
TEST(strict_refuses_the_first_by_name)
{
    const char *path = write_scene("strict.pbrt", two_unsupported);
    char msg[2048], want[1200];
    brume_scene *s = NULL;
    ASSERT_EQ_INT(load(path, false, msg, sizeof msg, &s), BRUME_ERROR_UNSUPPORTED);
    ASSERT_TRUE(s == NULL);
    snprintf(want, sizeof want, "%s:5: Shape \"sphere\": parameter \"float zmin\": not supported", path);
    ASSERT_CONTAINS(msg, want);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
}

/* With it: both listed once each, in file order, the sphere kept without its zmin and the
 * cone left out. */
TEST(lenient_lists_each_and_skips)
{
    const char *path = write_scene("lenient.pbrt", two_unsupported);
    char msg[2048], want[1200];
    brume_scene *s = NULL;
    ASSERT_EQ_INT(load(path, true, msg, sizeof msg, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_ignored_count(s), 2);
    snprintf(want, sizeof want, "%s:5: Shape \"sphere\": parameter \"float zmin\"", path);
    ASSERT_CONTAINS(brume_scene_ignored(s, 0), want);
    snprintf(want, sizeof want, "%s:6: Shape \"cone\": not supported", path);
    ASSERT_CONTAINS(brume_scene_ignored(s, 1), want);
    ASSERT_TRUE(brume_scene_ignored(s, 2) == NULL && brume_scene_ignored(s, -1) == NULL);
    brume_scene_release(s);

    brume_context *ctx = brume_context_new();
    char *json = NULL;
    brume_load_options lo = {.lenient = true};
    ASSERT_EQ_INT(brume_scene_text(ctx, &(brume_source){.path = path}, &lo, &json), BRUME_OK);
    const char *surfaces = strstr(json, "\"surfaces\"");
    ASSERT_TRUE(surfaces != NULL);
    ASSERT_TRUE(strstr(surfaces, "\"sphere\"") != NULL);
    ASSERT_TRUE(strstr(json, "\"cone\"") == NULL || strstr(json, "\"cone\"") > strstr(json, "\"ignored\""));
    free(json);
    brume_context_release(ctx);
}

/* A directive refused at its name is skipped with its arguments; one replayed by two
 * instances of an object is listed once; the directives after it are read. */
TEST(lenient_skips_arguments_and_lists_once)
{
    const char *path = write_scene("skip.pbrt",
                                   "LookAt 0 0 -5  0 0 0  0 1 0\n"
                                   "Camera \"perspective\"\n"
                                   "WorldBegin\n"
                                   "CoordinateSystem \"here\"\n"
                                   "ObjectBegin \"o\"\n"
                                   "Shape \"paraboloid\" \"float radius\" [1]\n"
                                   "Shape \"sphere\" \"float radius\" [0.5]\n"
                                   "ObjectEnd\n"
                                   "ObjectInstance \"o\"\n"
                                   "Translate 2 0 0\n"
                                   "ObjectInstance \"o\"\n");
    char msg[2048];
    brume_scene *s = NULL;
    ASSERT_EQ_INT(load(path, true, msg, sizeof msg, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_ignored_count(s), 2);
    ASSERT_CONTAINS(brume_scene_ignored(s, 0), ":4: CoordinateSystem");
    ASSERT_CONTAINS(brume_scene_ignored(s, 1), ":6: Shape \"paraboloid\"");
    brume_scene_release(s);
}

/* Malformed input is refused with --lenient too. */
TEST(lenient_keeps_syntax_errors)
{
    const char *path = write_scene("bad.pbrt",
                                   "LookAt 0 0 -5  0 0 0  0 1 0\n"
                                   "Camera \"perspective\"\n"
                                   "WorldBegin\n"
                                   "Shape \"cone\"\n"
                                   "Shape \"sphere\" \"float radius\" [1] \"float radius\" [2]\n");
    char msg[2048];
    brume_scene *s = NULL;
    ASSERT_EQ_INT(load(path, true, msg, sizeof msg, &s), BRUME_ERROR_PARSE);
    ASSERT_CONTAINS(msg, ":5: parameter \"radius\" given twice");
    ASSERT_TRUE(s == NULL);
}

/* `brume render --lenient`: two warnings, an image, and the summary's count of 2; without
 * the flag one line and a non-zero exit. */
TEST(cli_lenient_warns_renders_and_counts)
{
    const char *path = write_scene("cli.pbrt", two_unsupported);
    const char *out = test_tmp_path("cli_lenient.png"), *err = test_tmp_path("cli_lenient.err");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "'%s' render '%s' --lenient --spp 1 -o '%s' 2> '%s'", BRUME_EXE, path, out, err);
    ASSERT_EQ_INT(test_system(cmd), 0);
    ASSERT_TRUE(test_exists(out));
    size_t n;
    char *text = test_slurp(err, &n);
    int warnings = 0;
    for (const char *p = text; (p = strstr(p, "brume: warning: ")) != NULL; p++)
        warnings++;
    ASSERT_EQ_INT(warnings, 2);
    ASSERT_CONTAINS(text, ":5: Shape \"sphere\": parameter \"float zmin\"");
    ASSERT_CONTAINS(text, ":6: Shape \"cone\"");
    ASSERT_CONTAINS(text, "brume: 2 pbrt constructs ignored (--lenient)");
    free(text);

    snprintf(cmd, sizeof cmd, "'%s' render '%s' --spp 1 -o '%s' 2> '%s'", BRUME_EXE, path,
             test_tmp_path("cli_strict.png"), err);
    ASSERT_TRUE(test_system(cmd) != 0);
    text = test_slurp(err, &n);
    ASSERT_CONTAINS(text, ":5: Shape \"sphere\": parameter \"float zmin\"");
    ASSERT_TRUE(strstr(text, "cone") == NULL);
    ASSERT_TRUE(strchr(text, '\n') == strrchr(text, '\n')); /* one line */
    free(text);
}

TEST_MAIN(strict_refuses_the_first_by_name, lenient_lists_each_and_skips, lenient_skips_arguments_and_lists_once,
          lenient_keeps_syntax_errors, cli_lenient_warns_renders_and_counts)
