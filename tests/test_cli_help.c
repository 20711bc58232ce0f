/* test_cli_help.c - the commands' flag tables (cli/cli_flags.h) against what is made from
 * them: README's usage block, `brume help` and `brume help COMMAND`, the parser; and the
 * tool's exit status when its standard output cannot be written. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_flags.h"
#include "cli_render.h"
#include "commands.h"
#include "test.h"

static char *source_file(const char *rel)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", BRUME_SOURCE_DIR, rel);
    size_t n;
    return test_slurp(path, &n);
}

/* The lines of text strictly between the line holding begin and the one holding end. */
static char *between(const char *text, const char *begin, const char *end, const char *where)
{
    const char *a = strstr(text, begin);
    if (!a)
        TEST_FAIL("%s: no line with '%s'", where, begin);
    a = strchr(a, '\n') + 1;
    const char *b = strstr(a, end);
    if (!b)
        TEST_FAIL("%s: no line with '%s' after '%s'", where, end, begin);
    while (b > a && b[-1] != '\n')
        b--;
    char *out = malloc((size_t)(b - a) + 1);
    memcpy(out, a, (size_t)(b - a));
    out[b - a] = '\0';
    return out;
}

/* Fails with the first line where got and want differ, and the whole of want. */
static void same_text(const char *got, const char *want, const char *what, const char *how)
{
    if (strcmp(got, want) == 0)
        return;
    int line = 1;
    const char *g = got, *w = want;
    while (*g && *g == *w) {
        if (*g == '\n')
            line++;
        g++;
        w++;
    }
    while (g > got && g[-1] != '\n')
        g--, w--;
    fprintf(stderr, "%s differs from the flag tables at its line %d:\n  has:    %.*s\n  tables: %.*s\n"
                    "%s; the text the tables give:\n%s",
            what, line, (int)strcspn(g, "\n"), g, (int)strcspn(w, "\n"), w, how, want);
    TEST_FAIL("%s drifted from the flag tables", what);
}

/* What fn writes, as a string. */
static char *captured(void (*fn)(FILE *, const cli_command *), const cli_command *c)
{
    char *text = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&text, &n);
    fn(f, c);
    fclose(f);
    return text;
}

static void usage_block(FILE *f, const cli_command *c)
{
    (void)c;
    cli_flags_usage_block(f);
}

/* The stdout of `brume ARGS`, which must exit 0. */
static char *run_brume(const char *args)
{
    const char *out = test_tmp_path("help.txt");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s %s > %s", BRUME_EXE, args, out);
    ASSERT_EQ_INT(test_system(cmd), 0);
    size_t n;
    return test_slurp(out, &n);
}

/* README's usage block under "## The tool" is `brume help --usage`'s. */
TEST(readme_usage_is_generated)
{
    char *readme = source_file("README.md");
    char *got = between(readme, "<!-- BEGIN brume help --usage -->", "<!-- END brume help --usage -->", "README.md");
    char *want = captured(usage_block, NULL);
    same_text(got, want, "README.md's usage block", "scripts/usage-docs.sh rewrites it (`brume help --usage`)");
    char *tool = run_brume("help --usage");
    ASSERT_EQ_STR(tool, want);
    free(tool);
    free(want);
    free(got);
    free(readme);
}

/* Every command `brume help` lists has a table, README names it, and every table's command
 * is one `brume help` lists: the command list is complete (denoise and gen fire included). */
TEST(command_list_is_complete)
{
    char *help = run_brume("help");
    char *readme = source_file("README.md");
    static const char *const names[] = {
#define X(name, summary) #name,
        BRUME_COMMANDS(X)
#undef X
    };
    for (size_t k = 0; k < sizeof names / sizeof *names; k++) {
        char line[64];
        snprintf(line, sizeof line, "\n  %-10s ", names[k]);
        ASSERT_CONTAINS(help, line);
        bool tabled = false;
        for (int i = 0; i < cli_ncommands; i++) {
            size_t len = strlen(names[k]);
            const char *t = cli_all_commands[i]->name;
            tabled |= strncmp(t, names[k], len) == 0 && (t[len] == '\0' || t[len] == ' ');
        }
        if (!tabled)
            TEST_FAIL("`brume help` lists %s, which has no flag table (cli/cli_flags.h)", names[k]);
    }
    for (int i = 0; i < cli_ncommands; i++) {
        char cmd[64], line[64];
        snprintf(cmd, sizeof cmd, "\nbrume %s ", cli_all_commands[i]->name);
        const char *alone = strstr(readme, cmd);
        cmd[strlen(cmd) - 1] = '\n'; /* a command without operands nor flags */
        if (!alone && !strstr(readme, cmd))
            TEST_FAIL("README.md's usage block lacks `brume %s`", cli_all_commands[i]->name);
        snprintf(line, sizeof line, "\n  %-10.*s ", (int)strcspn(cli_all_commands[i]->name, " "),
                 cli_all_commands[i]->name);
        ASSERT_CONTAINS(help, line);
    }
    ASSERT_CONTAINS(readme, "\nbrume denoise ");
    ASSERT_CONTAINS(readme, "\nbrume gen fire ");
    free(readme);
    free(help);
}

/* `brume help COMMAND` (and COMMAND --help) print the table's help, every flag with its
 * value's name; the parser finds every flag by its name and its alias. */
TEST(help_is_the_table)
{
    for (int i = 0; i < cli_ncommands; i++) {
        const cli_command *c = cli_all_commands[i];
        char args[128];
        snprintf(args, sizeof args, "help %.*s", (int)strcspn(c->name, " "), c->name);
        char *help = run_brume(args);
        char *want = captured(cli_flags_help, c);
        ASSERT_CONTAINS(help, want);
        snprintf(args, sizeof args, "%s --help", c->name);
        char *own = run_brume(args);
        ASSERT_EQ_STR(own, want);
        for (int k = 0; k < c->nflags; k++) {
            const cli_flag *f = &c->flags[k];
            ASSERT_TRUE(cli_flags_find(c, f->name) == f);
            ASSERT_TRUE(!f->alias || cli_flags_find(c, f->alias) == f);
            char entry[256];
            snprintf(entry, sizeof entry, "%s%s%s", f->name, f->arg ? " " : "", f->arg ? f->arg : "");
            ASSERT_CONTAINS(help, entry);
            ASSERT_TRUE(f->kind != CLI_FLAG_CALL || f->call);
            ASSERT_TRUE((f->kind == CLI_FLAG_TRUE) == (f->arg == NULL) || f->kind == CLI_FLAG_CALL);
        }
        free(own);
        free(want);
        free(help);
    }
}

/* The one parser reads render's table: values into their fields, both spellings of a flag,
 * operands in order, and refuses an unknown flag, a missing value and one out of range. */
TEST(parser_reads_the_table)
{
    static render_opts o; /* large: the --set buffers */
    char *ok[] = {"render", "scene.json", "--spp", "7", "-o", "x.exr", "--quiet", "--exposure", "-1.5", "--grid", "g",
                  "--seed", "9", "--set", "camera.fov=30", NULL};
    ASSERT_EQ_INT(render_parse_options(&o, 15, ok), -1);
    ASSERT_EQ_STR(o.scene_path, "scene.json");
    ASSERT_EQ_INT(o.spp, 7);
    ASSERT_EQ_STR(o.out_path, "x.exr");
    ASSERT_TRUE(o.quiet && o.have_seed && o.seed == 9);
    ASSERT_NEAR(o.wopts.exposure, -1.5, 0.0);
    ASSERT_EQ_STR(o.studio.grid, "g");
    ASSERT_EQ_INT(o.nsets, 1);
    ASSERT_EQ_STR(o.sets[0], "camera.fov=30");
    char *unknown[] = {"render", "--bogus", NULL}, *missing[] = {"render", "--spp", NULL},
         *range[] = {"render", "--spp", "0", NULL}, *two[] = {"render", "a.json", "b.json", NULL};
    memset(&o, 0, sizeof o);
    ASSERT_EQ_INT(render_parse_options(&o, 2, unknown), 2);
    memset(&o, 0, sizeof o);
    ASSERT_EQ_INT(render_parse_options(&o, 2, missing), 2);
    memset(&o, 0, sizeof o);
    ASSERT_EQ_INT(render_parse_options(&o, 3, range), 2);
    memset(&o, 0, sizeof o);
    ASSERT_EQ_INT(render_parse_options(&o, 3, two), 2);
}

/* A command whose standard output cannot be written exits non-zero with one line. */
TEST(stdout_write_error_fails)
{
    static const char *const cmds[] = {"help", "help render", "--version", "options", "options --markdown",
                                       "help --usage", "slab --albedo 0.5 --tau 1 --phase isotropic --samples 100",
                                       "info " BRUME_DATA_DIR "/spiral.df3"};
    const char *err = test_tmp_path("full.err");
    for (size_t k = 0; k < sizeof cmds / sizeof *cmds; k++) {
        char cmd[4096];
        snprintf(cmd, sizeof cmd, "%s %s > /dev/full 2> %s", BRUME_EXE, cmds[k], err);
        int st = test_system(cmd);
        if (st == 0)
            TEST_FAIL("`brume %s > /dev/full` exited 0", cmds[k]);
        size_t n;
        char *msg = test_slurp(err, &n);
        ASSERT_CONTAINS(msg, "brume: cannot write to standard output");
        free(msg);
    }
}

TEST_MAIN(readme_usage_is_generated, command_list_is_complete, help_is_the_table, parser_reads_the_table,
          stdout_write_error_fails)
