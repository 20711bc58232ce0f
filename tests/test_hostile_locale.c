/* test_hostile_locale.c - numbers read and printed the same in every locale: a program that
 * links libbrume and calls setlocale(LC_ALL, "") in a German locale (decimal comma) reads
 * .pbrt scenes, phase tables and kernel tables as written, with '.', and gets messages with
 * '.'. Skipped (77) where the locale is not installed (`localedef -i de_DE -f UTF-8
 * de_DE.UTF-8` makes it). */
#include "test.h"

#include <locale.h>

#include "brume.h"
#include "core/error.h"
#include "density/blob_kernel.h"
#include "phase/phase.h"

static void german(void)
{
    if (!setlocale(LC_ALL, "de_DE.UTF-8") && !setlocale(LC_ALL, "de_DE.utf8")) {
        fprintf(stderr, "skipped: no de_DE.UTF-8 locale\n");
        exit(77);
    }
    char probe[16];
    snprintf(probe, sizeof probe, "%.1f", 0.5);
    ASSERT_TRUE(strcmp(probe, "0,5") == 0); /* the locale is in effect */
}

/* Before: strtod stopped at the '.', and "0.5" was 0 followed by junk: the pbrt reader refused
 * "Scale 0.5 0.5 0.5" ... and a phase table's angles did not increase. */
TEST(pbrt_scene_reads_in_a_german_locale)
{
    german();
    const char *path = test_tmp_path("de.pbrt");
    test_write_file(path, "LookAt 0 0 4.5  0 0 0  0 1 0\n"
                          "Camera \"perspective\" \"float fov\" [37.5]\n"
                          "Film \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
                          "WorldBegin\n"
                          "LightSource \"distant\" \"point3 from\" [0 1 0] \"point3 to\" [0 0 0] \"float scale\" [1.5]\n"
                          "Shape \"sphere\" \"float radius\" [0.75]\n");
    brume_context *ctx = brume_context_new();
    char *json = NULL;
    brume_status st = brume_scene_text(ctx, &(brume_source){path, NULL}, NULL, &json);
    if (st != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    /* the camera 4.5 from the origin, not 4 */
    ASSERT_CONTAINS(json, "4.5");
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){path, NULL}, NULL, &s), BRUME_OK);
    brume_scene_release(s);
    free(json);
    brume_context_release(ctx);
    remove(path);
}

TEST(phase_and_kernel_tables_read_in_a_german_locale)
{
    german();
    const char *table = test_tmp_path("de_phase.txt");
    test_write_file(table, "0.5 2.5\n90.25 1.5\n179.5 0.5\n");
    phase *p = phase_load_tabulated(table);
    if (!p)
        TEST_FAIL("%s", err_message());
    /* forward over backward: 2.5 / 0.5 at the ends (held beyond the first and last angles) */
    ASSERT_NEAR(phase_eval(p, 1.0) / phase_eval(p, -1.0), 5.0, 1e-9);
    phase_release(p);
    remove(table);
    const char *kernel = test_tmp_path("de_kernel.txt");
    test_write_file(kernel, "0 1\n0.5 0.5\n1.0 0\n");
    blob_kernel *k = blob_kernel_read(kernel, "stam.kernel_file");
    if (!k)
        TEST_FAIL("%s", err_message());
    blob_kernel_release(k);
    remove(kernel);
}

/* A message quotes numbers with '.', whatever the locale. */
TEST(messages_print_numbers_with_a_point)
{
    german();
    char out[64];
    err_format(out, sizeof out, "%g %.17g %.3f", 0.5, 0.25, 1.5);
    ASSERT_TRUE(strcmp(out, "0.5 0.25 1.500") == 0);
}

TEST_MAIN(pbrt_scene_reads_in_a_german_locale, phase_and_kernel_tables_read_in_a_german_locale,
          messages_print_numbers_with_a_point)
