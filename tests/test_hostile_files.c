/* test_hostile_files.c - every file brume reads is a regular file or refused: /dev/zero, a
 * FIFO with no writer and a folder named as each input (the scene, a .pbrt scene, Stam's
 * kernel table, Blasi's light file, a tabulated phase) end in one line naming the path, a
 * non-zero exit, at once (a FIFO blocked the open itself, /dev/zero never ended). */
#include "test.h"

#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

/* The special files, made fresh in a folder of this process. */
static char dir[512];

static const char *special_dir(void)
{
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "%s", test_tmp_path("special"));
        char cmd[2048];
        snprintf(cmd, sizeof cmd, "rm -rf %s && mkdir -p %s/folder && mkfifo %s/fifo", dir, dir, dir);
        ASSERT_EQ_INT(test_system(cmd), 0);
    }
    return dir;
}

/* The path of the special file `which`: /dev/zero, or the FIFO or folder made above. */
static const char *special(const char *which, char *path, size_t n)
{
    if (strcmp(which, "zero") == 0)
        snprintf(path, n, "/dev/zero");
    else
        snprintf(path, n, "%s/%s", special_dir(), which);
    return path;
}

/* brume ARGS, which name `path` or a scene naming it: exit 1 or 2 within 10 s (at once, but a
 * loaded machine starts slowly; the FIFO and /dev/zero blocked forever), stderr one line
 * naming the path. */
static void refused(const char *what, const char *args, const char *path)
{
    char err[600];
    snprintf(err, sizeof err, "%s", test_tmp_path("err.txt"));
    int rc = test_wait_exit(test_spawn(BRUME_EXE, args, err), 10.0);
    size_t n = 0;
    char *text = test_slurp(err, &n);
    if (rc <= 0 || rc >= 128)
        TEST_FAIL("%s as %s: exit %d (want a refusal, 1 or 2): %s", path, what, rc, text);
    if (n == 0 || strchr(text, '\n') != text + n - 1)
        TEST_FAIL("%s as %s: stderr is not one line: \"%s\"", path, what, text);
    if (!strstr(text, path))
        TEST_FAIL("%s as %s: the message does not name it: %s", path, what, text);
    free(text);
}

static const char *const specials[] = {"zero", "fifo", "folder"};

static void special_dir_remove(void)
{
    char cmd[1100];
    snprintf(cmd, sizeof cmd, "rm -rf %s", special_dir());
    ASSERT_EQ_INT(test_system(cmd), 0);
    dir[0] = '\0';
}

/* A scene whose keys are `before` path `after` (a JSON fragment), written beside the special
 * files; returns its path. */
static const char *scene_with(const char *name, const char *before, const char *path, const char *after)
{
    static char scene[600];
    char json[4096], body[2000];
    snprintf(body, sizeof body, "%s%s%s", before, path, after);
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},\n"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}],\n"
             " \"render\": {\"width\": 4, \"height\": 4, \"spp\": 1, \"threads\": 1},\n %s}\n",
             body);
    snprintf(scene, sizeof scene, "%s/%s.json", special_dir(), name);
    test_write_file(scene, json);
    return scene;
}

TEST(special_scene_files_are_refused)
{
    char path[600], args[2048];
    for (size_t i = 0; i < sizeof specials / sizeof specials[0]; i++) {
        special(specials[i], path, sizeof path);
        snprintf(args, sizeof args, "render %s -o %s/out.png --quiet", path, special_dir());
        refused("the scene", args, path);
        snprintf(args, sizeof args, "info %s", path);
        refused("brume info's file", args, path);
    }
    /* a .pbrt name: the pbrt reader opens it */
    char cmd[1400];
    snprintf(cmd, sizeof cmd, "cd %s && rm -rf z.pbrt d.pbrt f.pbrt && ln -s /dev/zero z.pbrt && mkdir d.pbrt && "
             "mkfifo f.pbrt", special_dir());
    ASSERT_EQ_INT(test_system(cmd), 0);
    static const char *const pbrt[] = {"z.pbrt", "d.pbrt", "f.pbrt"};
    for (size_t i = 0; i < 3; i++) {
        special(pbrt[i], path, sizeof path);
        snprintf(args, sizeof args, "render %s -o %s/out.png --quiet", path, special_dir());
        refused("a pbrt scene", args, path);
    }
    special_dir_remove();
}

/* The inputs a scene names: each special file as each, through the scene's key. */
TEST(special_inputs_of_a_scene_are_refused)
{
    static const struct {
        const char *name, *before, *after;
    } inputs[] = {
        {"kernel", "\"media\": [{\"density\": {\"type\": \"blobs\", \"blobs\": [[0, 0, 0, 1, 0.3]]}, \"sigma_a\": 0.1, "
                   "\"sigma_s\": 1}], \"stam\": {\"kernel\": \"table\", \"kernel_file\": \"", "\"}"},
        {"light", "\"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1, \"bounds\": [[-1, -1, -1], [1, 1, "
                  "1]]}, \"sigma_a\": 0.1, \"sigma_s\": 1}], \"blasi\": {\"load_light\": \"", "\"}"},
        {"phase", "\"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1, \"bounds\": [[-1, -1, -1], [1, 1, "
                  "1]]}, \"sigma_a\": 0.1, \"sigma_s\": 1, \"phase\": {\"type\": \"tabulated\", \"file\": \"", "\"}}]"},
    };
    for (size_t k = 0; k < sizeof inputs / sizeof inputs[0]; k++)
        for (size_t i = 0; i < sizeof specials / sizeof specials[0]; i++) {
            char path[600], name[64], args[2048];
            special(specials[i], path, sizeof path);
            snprintf(name, sizeof name, "%s_%zu", inputs[k].name, i);
            const char *scene = scene_with(name, inputs[k].before, path, inputs[k].after);
            snprintf(args, sizeof args, "render %s -o %s/out.png --quiet%s", scene, special_dir(),
                     strcmp(inputs[k].name, "light") == 0 ? " --method blasi" : "");
            refused(inputs[k].name, args, path);
        }
    special_dir_remove();
}

TEST_MAIN(special_scene_files_are_refused, special_inputs_of_a_scene_are_refused)
