/* test_cli_render.c - what `brume render` chooses and says for a user who gives little: a
 * bare grid file's defaults (a time budget and the denoiser, as `make render`), why a render
 * with a budget stopped, and --set values read whole. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"

/* Runs `brume ARGS`, stdout to /dev/null, stderr into *err (malloc'd); the exit status. */
static int run(const char *args, char **err)
{
    const char *path = test_tmp_path("render-err.txt");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s %s >/dev/null 2>%s", BRUME_EXE, args, path);
    int st = test_system(cmd);
    size_t n;
    *err = test_slurp(path, &n);
    return st;
}

/* The 21-voxel fog box as .nvdb (read in-process, also under a sanitizer), or NULL when this
 * build cannot write it (no OpenVDB). */
static const char *box_nvdb(void)
{
    static char path[512];
    snprintf(path, sizeof path, "%s", test_tmp_path("box.nvdb"));
    char args[2048], *err = NULL;
    snprintf(args, sizeof args, "convert %s/box_fog_21cube.vdb %s", BRUME_DATA_DIR, path);
    int st = run(args, &err);
    free(err);
    return st == 0 ? path : NULL;
}

/* `brume render FILE.nvdb` alone: a time budget with render.spp a cap, then the denoiser
 * (the raw image kept beside it); stderr says so, and the summary gives the samples and what
 * stopped the render. On a 16 x 12 image the 1024-sample cap comes well within the 15 s. */
TEST(bare_grid_renders_with_a_budget_and_the_denoiser)
{
    const char *grid = box_nvdb();
    if (!grid) {
        printf("skipped: no OpenVDB (brume convert to .nvdb)\n");
        exit(77);
    }
    char png[512], raw[512], args[2048], *err = NULL;
    snprintf(png, sizeof png, "%s", test_tmp_path("bare.png"));
    snprintf(raw, sizeof raw, "%s", test_tmp_path("bare-raw.png"));
    snprintf(args, sizeof args, "render %s --width 16 --height 12 -o %s", grid, png);
    ASSERT_EQ_INT(run(args, &err), 0);
    ASSERT_CONTAINS(err, "a grid file without --spp, --time or --noise: 15 s of rendering, then the denoiser");
    ASSERT_CONTAINS(err, "on average)");
    ASSERT_CONTAINS(err, "of a 15 s budget); stopped: ");
    ASSERT_TRUE(test_exists(png) && test_exists(raw));
    free(err);
    remove(png);
    remove(raw);
    /* --spp: the deterministic choice, N samples, no budget, no denoiser */
    snprintf(args, sizeof args, "render %s --width 16 --height 12 --spp 2 -o %s", grid, png);
    ASSERT_EQ_INT(run(args, &err), 0);
    ASSERT_CONTAINS(err, ": 16 x 12, 2 spp, method path");
    ASSERT_TRUE(strstr(err, "a grid file without") == NULL);
    ASSERT_TRUE(test_exists(png) && !test_exists(raw));
    free(err);
    remove(png);
    remove(grid);
}

/* --time on a scene whose spp comes first: the summary says the sample maximum stopped it. */
TEST(summary_says_why_the_render_stopped)
{
    char png[512], args[2048], *err = NULL;
    snprintf(png, sizeof png, "%s", test_tmp_path("stop.png"));
    snprintf(args, sizeof args, "render --width 8 --height 6 --spp 3 --time 60 --set render.noise=0 -o %s", png);
    ASSERT_EQ_INT(run(args, &err), 0);
    ASSERT_CONTAINS(err, "3 to 3 spp");
    ASSERT_CONTAINS(err, "of a 60 s budget); stopped: the sample maximum, 3 spp (render.spp or --spp), before the time budget");
    free(err);
    remove(png);
}

/* --set values are whole JSON values: "1,024" is refused in one line, never read as 1; a
 * bare word is still a string. */
TEST(set_values_are_whole_json)
{
    char png[512], args[2048], *err = NULL;
    snprintf(png, sizeof png, "%s", test_tmp_path("set.png"));
    static const char *const bad[] = {"render.width=1,024", "render.width=12px", "camera.fov=[30", "render.spp=\"4"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        snprintf(args, sizeof args, "render --spp 1 --quiet --set '%s' -o %s", bad[k], png);
        ASSERT_EQ_INT(run(args, &err), 1);
        ASSERT_CONTAINS(err, "is not one whole JSON value");
        ASSERT_TRUE(strchr(err, '\n') == err + strlen(err) - 1); /* one line */
        ASSERT_TRUE(!test_exists(png));
        free(err);
    }
    snprintf(args, sizeof args, "render --spp 1 --quiet --width 8 --height 6 --set render.method=single -o %s", png);
    ASSERT_EQ_INT(run(args, &err), 0);
    free(err);
    remove(png);
}

TEST_MAIN(bare_grid_renders_with_a_budget_and_the_denoiser, summary_says_why_the_render_stopped,
          set_values_are_whole_json)
