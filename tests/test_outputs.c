/* test_outputs.c - outputs never destroy (docs/render-jobs.md, "Outputs"): every writer
 * replaces only a file of its own kind, never one of the command's inputs or another of its
 * outputs, and a write that fails (a full file system, here the file-size limit: EFBIG as
 * ENOSPC would be) leaves the old file as it was and no temporary file. */
#include "test.h"

#include <dirent.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include "brume.h"

#define NOTES "my notes, which brume must never replace\n"

/* A fresh folder for one case, and a path in it. */
static const char *dir_of(const char *name)
{
    static char dir[512];
    snprintf(dir, sizeof dir, "%s", test_tmp_path(name));
    char cmd[1100];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", dir, dir);
    ASSERT_EQ_INT(test_system(cmd), 0);
    return dir;
}

static const char *in_dir(const char *dir, const char *name)
{
    static char buf[4][640];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
    return buf[k];
}

/* Runs a brume command line in dir (stderr to dir/err); its exit status. */
static int brume_in(const char *dir, const char *args)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "cd '%s' && %s %s 2> err", dir, BRUME_EXE, args);
    return test_system(cmd);
}

/* dir/err holds exactly one line, containing `want`. */
static void one_line(const char *dir, const char *want)
{
    size_t n;
    char *e = test_slurp(in_dir(dir, "err"), &n);
    ASSERT_CONTAINS(e, want);
    ASSERT_TRUE(n > 0 && e[n - 1] == '\n' && strchr(e, '\n') == e + n - 1);
    free(e);
}

static void still_notes(const char *path)
{
    size_t n;
    char *t = test_slurp(path, &n);
    ASSERT_EQ_STR(t, NOTES);
    free(t);
}

/* No temporary ".NAME.tmp-" file (mkstemp's six random characters after it) left in dir. */
static void no_temporary(const char *dir)
{
    DIR *d = opendir(dir);
    ASSERT_TRUE(d != NULL);
    struct dirent *e;
    while ((e = readdir(d)))
        if (strstr(e->d_name, ".tmp-"))
            TEST_FAIL("%s: temporary file %s left", dir, e->d_name);
    closedir(d);
}

static void write_pfm(const char *path, int w, int h, float v)
{
    FILE *f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    fprintf(f, "PF\n%d %d\n-1.0\n", w, h);
    for (int i = 0; i < 3 * w * h; i++)
        ASSERT_EQ_INT(fwrite(&v, sizeof v, 1, f), 1);
    fclose(f);
}

static const char *blasi_scene = BRUME_SOURCE_DIR "/scenes/blasi-picture1.json";

/* A light file replaces only a brume light file: a user's notes named by --save-light, by
 * --set blasi.save_light or by the scene's own blasi.save_light stay as they were, refused
 * before the light pass in one line; a light file replaces the one brume wrote. */
TEST(light_file_replaces_only_a_light_file)
{
    const char *dir = dir_of("light");
    test_write_file(in_dir(dir, "notes.txt"), NOTES);
    char args[1024];
    snprintf(args, sizeof args, "render %s -q --width 8 --height 6 --spp 1 --save-light notes.txt -o a.png", blasi_scene);
    ASSERT_EQ_INT(brume_in(dir, args), 1);
    one_line(dir, "brume replaces only its own light files");
    snprintf(args, sizeof args, "render %s -q --width 8 --height 6 --spp 1 --set blasi.save_light=notes.txt -o a.png",
             blasi_scene);
    ASSERT_EQ_INT(brume_in(dir, args), 1);
    one_line(dir, "notes.txt");
    still_notes(in_dir(dir, "notes.txt"));
    ASSERT_TRUE(!test_exists(in_dir(dir, "a.png")));
    /* the library's own check: a scene that names the file itself, through the C API */
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    const char *sets[] = {"render.width=8", "render.height=6", "render.spp=1"};
    brume_load_options lo = {0.0, 0, sets, 3, NULL, 0, false};
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = blasi_scene}, &lo, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.save_light", in_dir(dir, "notes.txt")), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    brume_image *img = NULL;
    ASSERT_TRUE(brume_render(ctx, s, &img) != BRUME_OK);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "holds text");
    still_notes(in_dir(dir, "notes.txt"));
    brume_scene_release(s);
    brume_context_release(ctx);
    /* a light file over a light file */
    snprintf(args, sizeof args, "render %s -q --width 8 --height 6 --spp 1 --save-light l.bl -o a.png", blasi_scene);
    ASSERT_EQ_INT(brume_in(dir, args), 0);
    ASSERT_EQ_INT(brume_in(dir, args), 0);
    no_temporary(dir);
}

/* A checkpoint replaces only a checkpoint (brume_render_job_save itself refuses), an image
 * only an image: a text file named -o or --checkpoint is refused, before any work. */
TEST(each_writer_replaces_only_its_kind)
{
    const char *dir = dir_of("kind");
    const char *notes = in_dir(dir, "notes.exr");
    test_write_file(notes, NOTES);
    ASSERT_EQ_INT(brume_in(dir, "render -q --width 8 --height 6 --spp 1 -o notes.exr"), 1);
    one_line(dir, "brume replaces only images");
    ASSERT_EQ_INT(brume_in(dir, "render -q --width 8 --height 6 --spp 1 --checkpoint notes.exr -o a.png"), 1);
    one_line(dir, "checkpoint");
    still_notes(notes);
    /* an image replaces an image */
    ASSERT_EQ_INT(brume_in(dir, "render -q --width 8 --height 6 --spp 1 -o a.png"), 0);
    ASSERT_EQ_INT(brume_in(dir, "render -q --width 8 --height 6 --spp 1 -o a.png"), 0);
    /* the library's writers check too */
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_new(ctx, 4, 4, &img), BRUME_OK);
    ASSERT_EQ_INT(brume_image_write(ctx, img, notes, NULL), BRUME_ERROR_INVALID_ARGUMENT);
    still_notes(notes);
    brume_scene *s = NULL;
    const char *sets[] = {"render.width=8", "render.height=6", "render.spp=1"};
    brume_load_options lo = {0.0, 0, sets, 3, NULL, 0, false};
    ASSERT_EQ_INT(brume_scene_load(ctx, NULL, &lo, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    brume_render_job *job = NULL;
    ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_OK);
    ASSERT_TRUE(brume_render_job_save(ctx, job, 1, notes) != BRUME_OK);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "its own checkpoints");
    still_notes(notes);
    /* brume_file_write of text replaces text, not an image */
    ASSERT_EQ_INT(brume_file_write(ctx, in_dir(dir, "a.png"), BRUME_FILE_TEXT, "x", 1), BRUME_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ_INT(brume_file_write(ctx, notes, BRUME_FILE_TEXT, "new\n", 4), BRUME_OK);
    brume_render_job_release(job);
    brume_scene_release(s);
    brume_image_release(img);
    brume_context_release(ctx);
    no_temporary(dir);
}

/* No output over an input or over another output of the same command: compare's picture
 * over the image, the reference or the mask; convert over its source; a checkpoint or a
 * light file named like the image; --denoise's raw companion named like the checkpoint; a
 * contact sheet over the scene's sky image; -o over the scene. Each refused in one line,
 * before any work, the file unchanged. */
TEST(outputs_are_never_inputs)
{
    const char *dir = dir_of("inputs");
    write_pfm(in_dir(dir, "a.pfm"), 4, 4, 1.0f);
    write_pfm(in_dir(dir, "b.pfm"), 4, 4, 1.5f);
    brume_image *skyimg = NULL;
    ASSERT_EQ_INT(brume_image_new(NULL, 8, 4, &skyimg), BRUME_OK);
    ASSERT_EQ_INT(brume_image_write(NULL, skyimg, in_dir(dir, "sky.png"), NULL), BRUME_OK);
    brume_image_release(skyimg);
    size_t n0;
    char *before = test_slurp(in_dir(dir, "a.pfm"), &n0);
    static const char *const refused[][2] = {
        {"compare a.pfm b.pfm -o a.pfm", "another file of this command"},
        {"compare a.pfm b.pfm -o b.pfm", "another file of this command"},
        {"compare a.pfm b.pfm --mask a.pfm -o ./a.pfm", "another file of this command"},
        {"denoise a.pfm -o a.pfm", "another file of this command"},
        {"render -q --width 8 --height 6 --spp 1 -o a.png --checkpoint a.png", "another file of this command"},
        {"render -q --width 8 --height 6 --spp 1 --denoise -o c.png --checkpoint c-raw.png", "c-raw.png"},
        {"render scene.json -q -o sky.png", "an input of the scene"},
        {"sweep scene.json --set render.spp=1,2 -o sky.png", "an input of the scene"},
        {"compare --scene scene.json --seeds 2 a.pfm -o sky.png", "an input of the scene"},
    };
    test_write_file(in_dir(dir, "scene.json"),
                    "{\"camera\": {\"position\": [0, 0, -3], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0], \"fov\": 40},\n"
                    " \"background\": {\"file\": \"sky.png\"},\n"
                    " \"render\": {\"width\": 4, \"height\": 4, \"spp\": 1}}\n");
    size_t ns, nj;
    char *sky = test_slurp(in_dir(dir, "sky.png"), &ns), *scene = test_slurp(in_dir(dir, "scene.json"), &nj);
    for (size_t i = 0; i < sizeof refused / sizeof refused[0]; i++) {
        int rc = brume_in(dir, refused[i][0]);
        if (rc != 1)
            TEST_FAIL("`brume %s`: exit %d, not 1", refused[i][0], rc);
        one_line(dir, refused[i][1]);
    }
    size_t n1;
    char *after = test_slurp(in_dir(dir, "a.pfm"), &n1), *sky2 = test_slurp(in_dir(dir, "sky.png"), &ns),
         *scene2 = test_slurp(in_dir(dir, "scene.json"), &nj);
    ASSERT_TRUE(n0 == n1 && memcmp(before, after, n0) == 0);
    ASSERT_TRUE(memcmp(sky, sky2, ns) == 0);
    ASSERT_EQ_STR(scene, scene2);
    ASSERT_TRUE(!test_exists(in_dir(dir, "a.png")) && !test_exists(in_dir(dir, "c.png")));
    free(before);
    free(after);
    free(sky);
    free(sky2);
    free(scene);
    free(scene2);
    /* the same checks through the API: a name not yet written counts as the same file */
    brume_context *ctx = brume_context_new();
    const char *others[] = {in_dir(dir, "x.png"), NULL};
    ASSERT_EQ_INT(brume_output_check(ctx, "-o", in_dir(dir, "./x.png"), BRUME_FILE_IMAGE, NULL, others, 2),
                  BRUME_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ_INT(brume_output_check(ctx, "-o", in_dir(dir, "y.png"), BRUME_FILE_IMAGE, NULL, others, 2), BRUME_OK);
    brume_context_release(ctx);
}

/* A full file system (here the file-size limit, which fails the write as ENOSPC would):
 * one line, non-zero exit, the old file intact, no temporary file; for the CLI's image and
 * for the library's image, checkpoint and file writers. */
TEST(a_full_disk_keeps_the_old_file)
{
    const char *dir = dir_of("full");
    write_pfm(in_dir(dir, "old.pfm"), 2, 2, 0.25f);
    size_t n0;
    char *before = test_slurp(in_dir(dir, "old.pfm"), &n0);
    char cmd[2048];
    snprintf(cmd, sizeof cmd,
             "cd '%s' && trap '' XFSZ && ulimit -f 1 && %s render -q --width 64 --height 64 --spp 1 -o old.pfm 2> err",
             dir, BRUME_EXE);
    int rc = test_system(cmd);
    ASSERT_TRUE(rc != 0);
    one_line(dir, "old.pfm");
    /* the library, in this process: the limit on, SIGXFSZ ignored so that write fails */
    struct rlimit old, small = {1024, 0};
    ASSERT_EQ_INT(getrlimit(RLIMIT_FSIZE, &old), 0);
    small.rlim_max = old.rlim_max;
    void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_new(ctx, 64, 64, &img), BRUME_OK);
    static char big[1 << 16];
    memset(big, 'x', sizeof big);
    ASSERT_EQ_INT(setrlimit(RLIMIT_FSIZE, &small), 0);
    brume_status a = brume_image_write(ctx, img, in_dir(dir, "old.pfm"), NULL);
    brume_status b = brume_file_write(ctx, in_dir(dir, "t.txt"), BRUME_FILE_TEXT, big, sizeof big);
    ASSERT_EQ_INT(setrlimit(RLIMIT_FSIZE, &old), 0);
    signal(SIGXFSZ, prev);
    ASSERT_EQ_INT(a, BRUME_ERROR_IO);
    ASSERT_EQ_INT(b, BRUME_ERROR_IO);
    ASSERT_TRUE(strchr(brume_context_last_error(ctx), '\n') == NULL);
    size_t n1;
    char *after = test_slurp(in_dir(dir, "old.pfm"), &n1);
    ASSERT_TRUE(n0 == n1 && memcmp(before, after, n0) == 0);
    ASSERT_TRUE(!test_exists(in_dir(dir, "t.txt")));
    no_temporary(dir);
    free(before);
    free(after);
    brume_image_release(img);
    brume_context_release(ctx);
}

/* A folder brume may not write in: one line, the old file intact. root writes anywhere,
 * so the case is meaningful only for another user. */
TEST(a_read_only_folder_keeps_the_old_file)
{
    if (geteuid() == 0) {
        printf("skipped: root writes in read-only folders\n");
        return;
    }
    const char *dir = dir_of("ro");
    write_pfm(in_dir(dir, "old.pfm"), 2, 2, 0.25f);
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "chmod 555 '%s'", dir);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(cmd, sizeof cmd, "cd '%s' && %s render -q --width 8 --height 6 --spp 1 -o old.pfm 2> /dev/null", dir,
             BRUME_EXE);
    int rc = test_system(cmd);
    snprintf(cmd, sizeof cmd, "chmod 755 '%s'", dir);
    test_system(cmd);
    ASSERT_TRUE(rc != 0);
    no_temporary(dir);
}

TEST_MAIN(light_file_replaces_only_a_light_file, each_writer_replaces_only_its_kind, outputs_are_never_inputs,
          a_full_disk_keeps_the_old_file, a_read_only_folder_keeps_the_old_file)
