/* test_pbrt_structure.c - the structure of a .pbrt file checked as pbrt-v4's parser and scene
 * builder check it (src/pbrt/parser.cpp, scene.cpp): the block of each directive, matched
 * AttributeBegin/End, a truncated file, unterminated strings, degenerate and non-finite
 * transforms, a parameter given twice, a degenerate LookAt. Each refusal is one line
 * "FILE:LINE: cause" naming the line of the fault, and the cause, not a consequence. */
#include "test.h"

#include <math.h>

#include "brume.h"
#include "core/error.h"
#include "io/json.h"
#include "scene/scene_pbrt.h"

/* Options of a valid file: 5 lines, the world block opened on line 5. */
#define OPTIONS                                                                                  \
    "Film \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"                     \
    "Scale -1 1 1\n"                                                                             \
    "LookAt 0 0 -5  0 0 0  0 1 0\n"                                                              \
    "Camera \"perspective\" \"float fov\" [30]\n"
#define WORLD "WorldBegin\n"
#define SPHERE "Shape \"sphere\" \"float radius\" 0.5\n"

/* The translation of text, or NULL with the message in msg. */
static char *translate(const char *text, char *msg, size_t n, const char **path_out)
{
    const char *path = test_tmp_path("s.pbrt");
    test_write_file(path, text);
    char *json = NULL;
    msg[0] = '\0';
    if (scene_pbrt_json(path, &json) != BRUME_OK)
        snprintf(msg, n, "%s", err_message());
    if (path_out)
        *path_out = path;
    return json;
}

/* text is refused in one line "PATH:LINE: ..." holding frag. */
static void refused(const char *text, int line, const char *frag)
{
    char msg[2048], want[1200];
    const char *path;
    char *json = translate(text, msg, sizeof msg, &path);
    if (json)
        TEST_FAIL("accepted, expected a refusal at line %d holding \"%s\":\n%s", line, frag, text);
    snprintf(want, sizeof want, "%s:%d: ", path, line);
    if (strncmp(msg, want, strlen(want)) != 0)
        TEST_FAIL("\"%s\": expected it to begin with \"%s\"", msg, want);
    ASSERT_CONTAINS(msg, frag);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
}

/* text translates; the JSON parsed (cJSON_Delete it). */
static cJSON *accepted(const char *text)
{
    char msg[2048];
    char *json = translate(text, msg, sizeof msg, NULL);
    if (!json)
        TEST_FAIL("refused: %s", msg);
    cJSON *root = cJSON_Parse(json);
    free(json);
    ASSERT_TRUE(root != NULL);
    return root;
}

/* Options before WorldBegin, the scene description after it, as pbrt-v4's VERIFY_OPTIONS and
 * VERIFY_WORLD; transforms, media and colour spaces in either block. */
TEST(directives_in_their_block)
{
    const char *world_only[] = {"Shape \"sphere\"", "LightSource \"point\"", "Material \"diffuse\"",
                                "AttributeBegin", "AttributeEnd", "ObjectBegin \"o\"", "Texture \"t\" \"float\" \"constant\"",
                                "ReverseOrientation", "NamedMaterial \"m\"", "TransformBegin"};
    for (size_t i = 0; i < sizeof world_only / sizeof world_only[0]; i++) {
        char text[1024], dir[64];
        snprintf(text, sizeof text, OPTIONS "%s\n" WORLD SPHERE, world_only[i]);
        sscanf(world_only[i], "%63s", dir);
        char frag[128];
        snprintf(frag, sizeof frag, "%s before WorldBegin", dir);
        refused(text, 5, frag);
    }
    const char *options_only[] = {"Camera \"perspective\"", "Film \"rgb\"", "Sampler \"halton\"",
                                  "Integrator \"volpath\"", "PixelFilter \"box\"", "Accelerator \"bvh\"",
                                  "TransformTimes 0 1"};
    for (size_t i = 0; i < sizeof options_only / sizeof options_only[0]; i++) {
        char text[1024], dir[64], frag[128];
        snprintf(text, sizeof text, OPTIONS WORLD SPHERE "%s\n", options_only[i]);
        sscanf(options_only[i], "%63s", dir);
        snprintf(frag, sizeof frag, "%s after WorldBegin (line 5)", dir);
        refused(text, 7, frag);
    }
    refused(OPTIONS WORLD SPHERE WORLD, 7, "WorldBegin given twice (first at line 5)");
    refused(OPTIONS WORLD "Shpae \"sphere\"\n", 6, "unknown directive \"Shpae\"");
    refused(OPTIONS WORLD SPHERE "WorldEnd\n", 7, "pbrt-v3");
    /* what belongs to either block is taken in both */
    cJSON *root = accepted("ColorSpace \"srgb\"\nMakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n" OPTIONS WORLD
                           "ColorSpace \"srgb\"\nTranslate 1 0 0\n" SPHERE);
    ASSERT_EQ_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "surfaces")), 1);
    cJSON_Delete(root);
}

/* x of the translation of surface i */
static double surface_x(const cJSON *root, int i)
{
    const cJSON *s = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "surfaces"), i);
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(s, "transform"), "translate");
    const cJSON *x = cJSON_GetArrayItem(t, 0);
    if (!cJSON_IsNumber(x))
        TEST_FAIL("surfaces[%d].transform.translate[0]: not a number", i);
    return x->valuedouble;
}

/* Blocks in pairs: an AttributeEnd closes an open AttributeBegin (pbrt-v4 ignores an extra one
 * with a warning: brume refuses it), a file never ends inside one (refused at the line of the
 * begin left open), TransformBegin/End are pbrt-v4's AttributeBegin/End. */
TEST(blocks_in_pairs)
{
    refused(OPTIONS WORLD SPHERE "AttributeEnd\n", 7, "AttributeEnd without an open AttributeBegin");
    refused(OPTIONS WORLD "AttributeBegin\n" SPHERE "AttributeBegin\n" SPHERE "AttributeEnd\n", 6,
            "AttributeBegin never closed");
    refused(OPTIONS WORLD "AttributeBegin\n" SPHERE "AttributeEnd\nAttributeBegin\n" SPHERE, 9,
            "AttributeBegin never closed");
    refused(OPTIONS WORLD "ObjectEnd\n", 6, "ObjectEnd without an open ObjectBegin");
    refused(OPTIONS WORLD "TransformEnd\n", 6, "TransformEnd without an open AttributeBegin");
    /* the transform inside a TransformBegin/End pair is undone at its end: the second sphere
     * sits at the origin, the first at x = +-5 (the view's mirror flips x) */
    cJSON *root = accepted(OPTIONS WORLD "TransformBegin\nTranslate 5 0 0\n" SPHERE "TransformEnd\n" SPHERE);
    ASSERT_NEAR(fabs(surface_x(root, 0)), 5.0, 1e-12);
    ASSERT_NEAR(surface_x(root, 1), 0.0, 1e-12);
    cJSON_Delete(root);
}

/* A file cut anywhere is refused, never read as the shorter scene it happens to spell: every
 * prefix of a scene whose world is one AttributeBegin/End pair, cut before the pair's end,
 * ends inside a block, a directive, a parameter list or a string. */
TEST(truncated_file_is_refused)
{
    refused(OPTIONS WORLD "Translate 1 2", 6, "Translate: expected a number (3 of 3), found the end of the file");
    refused(OPTIONS WORLD "Shape \"sphere\" \"float radius\" [ 1", 6, "expected ], found the end of the file");
    refused(OPTIONS WORLD "Shape", 6, "Shape: expected its type (a quoted string), found the end of the file");
    refused(OPTIONS, 4, "the file ends before WorldBegin");
    const char *full = OPTIONS WORLD "LightSource \"infinite\" \"rgb L\" [1 1 1]\n"
                                     "AttributeBegin\n  Translate 0.25 0 0\n  Material \"diffuse\" \"rgb reflectance\" "
                                     "[0.5 0.5 0.5]\n  Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n";
    cJSON *root = accepted(full);
    cJSON_Delete(root);
    size_t n = strlen(full), end = (size_t)(strstr(full, "AttributeEnd") - full) + strlen("AttributeEnd");
    size_t open = (size_t)(strstr(full, "AttributeBegin") - full) + strlen("AttributeBegin");
    char *text = malloc(n + 1);
    ASSERT_TRUE(text != NULL);
    int refusals = 0;
    for (size_t k = open; k < end; k++) {
        memcpy(text, full, k);
        text[k] = '\0';
        char msg[2048];
        const char *path;
        char *json = translate(text, msg, sizeof msg, &path);
        if (json)
            TEST_FAIL("the first %zu bytes were accepted:\n%s", k, text);
        ASSERT_TRUE(strncmp(msg, path, strlen(path)) == 0 && msg[strlen(path)] == ':');
        ASSERT_TRUE(strchr(msg, '\n') == NULL);
        refusals++;
    }
    printf("%d prefixes refused\n", refusals);
    free(text);
}

/* Strings end on their line with a quote (pbrt-v4's tokenizer): refused at the string's own
 * line; escapes are pbrt-v4's; a string is never cut to fit. */
TEST(unterminated_strings_are_refused)
{
    refused(OPTIONS WORLD "\n\nShape \"sphere\n\"float radius\" 1\n", 8, "unterminated string");
    refused(OPTIONS WORLD SPHERE "Shape \"sphere", 7, "unterminated string (the file ends in it)");
    refused(OPTIONS WORLD "Shape \"sphere\" \"float radius\" [1] \"string name\" \"a\\qb\"\n", 6, "unknown escape");
    char *big = malloc(3000);
    ASSERT_TRUE(big != NULL);
    snprintf(big, 3000, OPTIONS WORLD "Shape \"sphere\" \"string x\" \"%01500d\"\n", 0);
    refused(big, 6, "a string longer than 1023 bytes");
    free(big);
    /* an escaped quote does not end the string: the type read is `sph"ere`, refused as a type */
    refused(OPTIONS WORLD "Shape \"sph\\\"ere\"\n", 6, "Shape \"sph\"ere\"");
}

/* Zero scales, rotations about no axis and overflowing products are refused where they are
 * given; a singular or projective matrix where something is placed by it (pbrt-v4 inverts
 * the current transform there). */
TEST(degenerate_transforms_are_refused)
{
    refused(OPTIONS WORLD "Scale 1 0 1\n" SPHERE, 6, "a zero scale flattens space");
    refused(OPTIONS WORLD "Rotate 30 0 0 0\n" SPHERE, 6, "the axis (0, 0, 0) has zero length");
    refused(OPTIONS WORLD "Scale 1e200 1e200 1e200\nScale 1e200 1 1\n" SPHERE, 7, "the current transform overflows");
    refused(OPTIONS WORLD "Translate 1e308 0 0\nTranslate 1e308 0 0\n" SPHERE, 7, "overflows");
    refused(OPTIONS WORLD "Translate nan 0 0\n", 6, "Translate: expected a number (1 of 3), found \"nan\"");
    refused(OPTIONS WORLD "Translate 1 inf 0\n", 6, "found \"inf\"");
    refused(OPTIONS WORLD "Transform [1 0 0 0  0 1 0 0  0 0 0 0  0 0 0 1]\n" SPHERE, 7,
            "Shape \"sphere\": the current transform is singular");
    refused(OPTIONS WORLD "ConcatTransform [1 0 0 0  2 0 0 0  0 0 1 0  0 0 0 1]\n"
                          "LightSource \"point\" \"rgb I\" [1 1 1]\n", 7, "LightSource \"point\": the current transform is singular");
    refused(OPTIONS WORLD "ConcatTransform [1 0 0 0.5  0 1 0 0  0 0 1 0  0 0 0 1]\n" SPHERE, 7, "is projective");
    refused("Film \"rgb\"\nTransform [1 0 0 0  0 1 0 0  0 0 0 0  0 0 0 1]\nCamera \"perspective\"\n" WORLD, 3,
            "Camera \"perspective\": the current transform is singular");
    /* a singular matrix replaced before anything is placed is no fault, as in pbrt-v4 */
    cJSON *root = accepted(OPTIONS WORLD "Transform [1 0 0 0  0 1 0 0  0 0 0 0  0 0 0 1]\nIdentity\n" SPHERE);
    cJSON_Delete(root);
}

/* LookAt: eye = look has no view direction, a zero or parallel up no frame, each said so. */
TEST(degenerate_look_at_is_refused)
{
    refused("LookAt 1 2 3  1 2 3  0 1 0\nCamera \"perspective\"\n" WORLD, 1, "eye and look are the same point");
    refused("LookAt 0 0 -5  0 0 0  0 0 0\nCamera \"perspective\"\n" WORLD, 1, "up is the zero vector");
    refused("LookAt 0 0 -5  0 0 0  0 0 2\nCamera \"perspective\"\n" WORLD, 1, "up parallel to the view direction");
    refused("LookAt -1e308 0 0  1e308 0 0  0 1 0\nCamera \"perspective\"\n" WORLD, 1, "overflows");
}

/* A parameter list names each parameter once, with a type pbrt-v4 knows, values of one kind;
 * an integer parameter holds integers. */
TEST(parameter_lists_never_guess)
{
    refused(OPTIONS WORLD "Shape \"sphere\"\n  \"float radius\" 1\n  \"float radius\" 2\n", 8,
            "parameter \"radius\" given twice in one parameter list (lines 7 and 8)");
    refused(OPTIONS WORLD "Shape \"sphere\" \"float radius\" 1 \"integer radius\" 2\n", 6, "given twice");
    refused(OPTIONS WORLD "Shape \"sphere\" \"flaot radius\" 1\n", 6, "unknown type \"flaot\"");
    /* once read as type "rgbrgbrgbrgbrgb" and name "L": a declaration is two words */
    refused(OPTIONS WORLD "LightSource \"infinite\" \"rgbrgbrgbrgbrgbL\" [1 1 1]\n", 6, "expected \"type name\"");
    refused(OPTIONS WORLD "Shape \"sphere\" \"float radius extra\" 1\n", 6, "expected \"type name\"");
    refused("Film \"rgb\" \"integer xresolution\" [8.5]\n", 1, "\"integer xresolution\": 8.5 is not an integer");
    refused(OPTIONS WORLD "Shape \"sphere\" \"float radius\" [1 \"two\"]\n", 6, "mixes strings and numbers");
    /* the same name in two directives' lists is no repetition */
    cJSON *root = accepted(OPTIONS WORLD "Shape \"sphere\" \"float radius\" 1\nShape \"sphere\" \"float radius\" 2\n");
    cJSON_Delete(root);
}

TEST_MAIN(directives_in_their_block, blocks_in_pairs, truncated_file_is_refused, unterminated_strings_are_refused,
          degenerate_transforms_are_refused, degenerate_look_at_is_refused, parameter_lists_never_guess)
