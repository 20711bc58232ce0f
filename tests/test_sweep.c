/* test_sweep.c - `brume sweep`: every cell of the contact sheet is the render of its own
 * combination of values (found pixel for pixel in the sheet), JSON arrays are values, and
 * bad sweeps are usage errors. */
#include "test.h"

#include <unistd.h>

#include "brume.h"

#define SCENE BRUME_SOURCE_DIR "/scenes/stam-compare.json"
#define SIZE "--width 16 --height 12 --spp 1"

static brume_image *read_png(const char *path)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    if (brume_image_read(ctx, path, &img) != BRUME_OK)
        TEST_FAIL("%s: %s", path, brume_context_last_error(ctx));
    brume_context_release(ctx);
    return img;
}

/* Where cell (w x h pixels of img) appears in sheet, or -1. */
static long find_block(const brume_image *sheet, const brume_image *cell)
{
    int W = brume_image_width(sheet), H = brume_image_height(sheet);
    int w = brume_image_width(cell), h = brume_image_height(cell);
    const float *S = brume_image_pixels(sheet), *C = brume_image_pixels(cell);
    for (int y = 0; y + h <= H; y++)
        for (int x = 0; x + w <= W; x++) {
            bool same = true;
            for (int j = 0; same && j < h; j++)
                for (int i = 0; same && i < w; i++)
                    for (int c = 0; c < 3; c++)
                        same = same && S[4 * ((long)(y + j) * W + x + i) + c] == C[4 * ((long)j * w + i) + c];
            if (same)
                return (long)y * W + x;
        }
    return -1;
}

TEST(sheet_cells_are_the_renders)
{
    const char *sheet = test_tmp_path("sheet.png"), *one = test_tmp_path("one.png");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s sweep %s " SIZE " --set camera.fov=20,60 --set stam.eps=0,1.6 -o %s 2>/dev/null",
             BRUME_EXE, SCENE, sheet);
    ASSERT_EQ_INT(test_system(cmd), 0);
    brume_image *sh = read_png(sheet);
    long at[2][2];
    const char *fov[2] = {"20", "60"}, *eps[2] = {"0", "1.6"};
    for (int r = 0; r < 2; r++)
        for (int c = 0; c < 2; c++) {
            snprintf(cmd, sizeof cmd, "%s render %s -q " SIZE " --set camera.fov=%s --set stam.eps=%s -o %s", BRUME_EXE,
                     SCENE, fov[c], eps[r], one);
            ASSERT_EQ_INT(test_system(cmd), 0);
            brume_image *cell = read_png(one);
            at[r][c] = find_block(sh, cell);
            printf("fov %s eps %s: at %ld\n", fov[c], eps[r], at[r][c]);
            ASSERT_TRUE(at[r][c] >= 0);
            brume_image_release(cell);
        }
    /* columns: the first swept key; rows: the second */
    int W = brume_image_width(sh);
    ASSERT_EQ_INT((int)(at[0][0] / W), (int)(at[0][1] / W));
    ASSERT_TRUE(at[0][1] % W > at[0][0] % W);
    ASSERT_EQ_INT((int)(at[0][0] % W), (int)(at[1][0] % W));
    ASSERT_TRUE(at[1][0] / W > at[0][0] / W);
    brume_image_release(sh);
    remove(sheet);
    remove(one);
}

TEST(json_arrays_are_values_and_bad_sweeps_are_refused)
{
    const char *sheet = test_tmp_path("sheet2.png");
    char cmd[2048];
    snprintf(cmd, sizeof cmd,
             "%s sweep %s " SIZE " --set 'media.0.sigma_s=[1,1,1],[4,4,4]' --set stam.eps=0 -o %s 2>/dev/null",
             BRUME_EXE, SCENE, sheet);
    ASSERT_EQ_INT(test_system(cmd), 0);
    brume_image *sh = read_png(sheet);
    /* two cells of 16 pixels side by side: the sheet is narrower than three */
    ASSERT_TRUE(brume_image_width(sh) >= 32 && brume_image_width(sh) < 3 * 16 + 4 * 8);
    brume_image_release(sh);
    remove(sheet);
    static const char *const bad[] = {
        "--set camera.fov=20,30 --set stam.eps=0,1 --set stam.eta=0.1,0.2", /* three swept keys */
        "--set camera.fov=20",                                              /* nothing swept */
        "--set camera.fov=20,,30",                                          /* an empty value */
        "--set camera.fov=20,30 -o x.exr",                                  /* not a PNG */
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        snprintf(cmd, sizeof cmd, "%s sweep %s %s %s 2>/dev/null", BRUME_EXE, SCENE, bad[i],
                 strstr(bad[i], " -o ") ? "" : "-o /nonexistent/x.png");
        ASSERT_EQ_INT(test_system(cmd), 2);
    }
    /* a bad value is the scene reader's error, naming the key: exit 1 */
    snprintf(cmd, sizeof cmd, "%s sweep %s " SIZE " --set camera.fov=20,400 -o %s 2>/dev/null", BRUME_EXE, SCENE,
             sheet);
    ASSERT_EQ_INT(test_system(cmd), 1);
    ASSERT_TRUE(access(sheet, 0) != 0); /* no sheet written */
}

TEST_MAIN(sheet_cells_are_the_renders, json_arrays_are_values_and_bad_sweeps_are_refused)
