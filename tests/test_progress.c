/* test_progress.c - progress reports as a log reads them: with stderr not a terminal,
 * `brume render` prints a line every --progress-every seconds with the samples, the noise,
 * the elapsed time and the ETA; --quiet prints none. */
#include "test.h"

/* Runs brume with args, stderr to err_path; returns the exit status. */
static int run(const char *args, const char *err_path)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s %s >/dev/null 2>%s", BRUME_EXE, args, err_path);
    return test_system(cmd);
}

static int count_lines(const char *text, const char *needle)
{
    int n = 0;
    for (const char *p = text; (p = strstr(p, needle)) != NULL; p++)
        n++;
    return n;
}

/* A render of about a second or more at a fixed count (the default scene's noise target off),
 * a line every 0.05 s asked: several lines, each with
 * the figures, the ETA never "not known" (a fixed count's total is known) and none at 100 %
 * (the last line comes before the end); --quiet: none. */
TEST(lines_in_a_log)
{
    const char *err = test_tmp_path("err.txt"), *out = test_tmp_path("out.png");
    char args[1024];
    snprintf(args, sizeof args, "render --width 64 --height 40 --spp 48 --set render.noise=0 --progress-every 0.05 -o %s", out);
    ASSERT_EQ_INT(run(args, err), 0);
    size_t n = 0;
    char *text = test_slurp(err, &n);
    int lines = count_lines(text, "brume: render ");
    fprintf(stderr, "%d progress lines; the first: %.120s\n", lines, text);
    ASSERT_TRUE(lines >= 2);
    ASSERT_TRUE(count_lines(text, " spp, ") >= lines); /* the summary line has one too */
    ASSERT_EQ_INT(count_lines(text, " elapsed, ETA "), lines);
    ASSERT_EQ_INT(count_lines(text, "not known"), 0);
    ASSERT_EQ_INT(count_lines(text, "brume: render 100%"), 0);
    ASSERT_TRUE(strchr(text, '\r') == NULL); /* no bar drawn in place in a log */
    free(text);
    snprintf(args, sizeof args, "render --width 64 --height 40 --spp 48 --set render.noise=0 --progress-every 0.05 --quiet -o %s", out);
    ASSERT_EQ_INT(run(args, err), 0);
    text = test_slurp(err, &n);
    ASSERT_EQ_INT((int)n, 0);
    free(text);
    remove(out);
    remove(err);
}

TEST_MAIN(lines_in_a_log)
