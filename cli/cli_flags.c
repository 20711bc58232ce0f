/* cli_flags.c - the one parser over the commands' flag tables (cli_flags.h), their help and
 * README's usage block, all read from the same tables. */
#include "cli_flags.h"

#include <stdint.h>
#include <string.h>

#include "args.h"
#include "commands.h"

#define WIDTH 100 /* columns of README's block */
#define COLUMN 22 /* where a flag's help starts in `brume help COMMAND` */

const cli_flag *cli_flags_find(const cli_command *c, const char *name)
{
    for (int k = 0; k < c->nflags; k++) {
        const cli_flag *f = &c->flags[k];
        if (strcmp(f->name, name) == 0 || (f->alias && strcmp(f->alias, name) == 0))
            return f;
    }
    return NULL;
}

/* The value v of flag f (as typed: a) into opts. false after the message. */
static bool take(const cli_flag *f, const char *a, const char *v, void *opts)
{
    char *field = (char *)opts + f->off;
    switch (f->kind) {
    case CLI_FLAG_TRUE:
        *(bool *)(void *)field = true;
        return true;
    case CLI_FLAG_INT:
        return arg_int(a, v, (long)f->lo, (long)f->hi, (int *)(void *)field);
    case CLI_FLAG_U64:
        return arg_u64(a, v, (uint64_t *)(void *)field);
    case CLI_FLAG_DOUBLE:
        return arg_double(a, v, f->lo, f->hi, (double *)(void *)field);
    case CLI_FLAG_STRING:
        *(const char **)(void *)field = v;
        return true;
    case CLI_FLAG_CALL:
        return f->call(opts, f, v);
    }
    return false;
}

int cli_flags_parse(const cli_command *c, void *opts, int argc, char **argv, const char **operands, int max, int *n)
{
    *n = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            cli_flags_help(stdout, c);
            return 0;
        }
        if (a[0] != '-' || a[1] == '\0') { /* "-" is an operand: standard input or output */
            if (*n == max) {
                cli_error("%s: unexpected argument '%s' (try `brume help %.*s`)", c->name, a,
                          (int)strcspn(c->name, " "), c->name);
                return 2;
            }
            operands[(*n)++] = a;
            continue;
        }
        const cli_flag *f = cli_flags_find(c, a);
        if (!f) {
            cli_error("%s: unknown option '%s' (try `brume help %.*s`)", c->name, a, (int)strcspn(c->name, " "),
                      c->name);
            return 2;
        }
        const char *v = NULL;
        if (f->arg && !(v = arg_value(argc, argv, &i)))
            return 2;
        if (!take(f, a, v, opts))
            return 2;
    }
    return -1;
}

/* "  -o, --output FILE" */
static int flag_left(char *buf, size_t n, const cli_flag *f)
{
    return snprintf(buf, n, "  %s%s%s%s%s", f->alias ? f->alias : "", f->alias ? ", " : "", f->name,
                    f->arg ? " " : "", f->arg ? f->arg : "");
}

void cli_flags_help(FILE *out, const cli_command *c)
{
    const char *u = c->usage;
    bool first = true;
    do { /* an empty synopsis is one line too: the command alone */
        size_t len = strcspn(u, "\n");
        fprintf(out, "%s brume %s%s%.*s\n", first ? "usage:" : "      ", c->name, len ? " " : "", (int)len, u);
        u += len + (u[len] == '\n');
        first = false;
    } while (*u);
    if (c->about)
        fprintf(out, "%s", c->about);
    if (c->nflags)
        fputc('\n', out);
    for (int k = 0; k < c->nflags; k++) {
        const cli_flag *f = &c->flags[k];
        char left[256];
        int w = flag_left(left, sizeof left, f);
        if (w + 1 > COLUMN) /* a long flag: its help on the next line */
            fprintf(out, "%s\n%*s", left, COLUMN, "");
        else
            fprintf(out, "%s%*s", left, COLUMN - w, "");
        int col = COLUMN;
        for (const char *h = f->help; *h;) {
            size_t len = strcspn(h, "\n");
            fprintf(out, "%.*s", (int)len, h);
            col += (int)len;
            h += len + (h[len] == '\n');
            if (*h) {
                fprintf(out, "\n%*s", COLUMN, "");
                col = COLUMN;
            }
        }
        if (f->sets && col + 3 + (int)strlen(f->sets) > WIDTH)
            fprintf(out, "\n%*s(%s)", COLUMN, "", f->sets);
        else if (f->sets)
            fprintf(out, " (%s)", f->sets);
        fputc('\n', out);
    }
    if (c->notes)
        fprintf(out, "\n%s", c->notes);
    if (c->epilogue)
        c->epilogue(out);
}

/* Appends " word" to README's line, or wraps it to a new line at column indent. */
static void put_word(FILE *out, const char *word, int indent, int *col)
{
    int len = (int)strlen(word);
    if (*col > indent && *col + 1 + len > WIDTH) {
        fprintf(out, "\n%*s%s", indent, "", word);
        *col = indent + len;
    } else {
        fprintf(out, " %s", word);
        *col += 1 + len;
    }
}

/* Whether flag stands in the synopsis words (" A B [C] ") as a word of its own. */
static bool named(const char *words, const char *flag)
{
    size_t n = strlen(flag);
    for (const char *p = strstr(words, flag); p; p = strstr(p + 1, flag))
        if ((p[-1] == ' ' || p[-1] == '[') && (p[n] == ' ' || p[n] == ']'))
            return true;
    return false;
}

/* One command in README's block: "# summary", then its first synopsis with "[options]"
 * spelled out from the table, then its other synopses. */
static void usage_entry(FILE *out, const cli_command *c)
{
    fprintf(out, "# %s\n", c->summary);
    const char *u = c->usage;
    bool first = true;
    do {
        size_t len = strcspn(u, "\n");
        char line[512];
        snprintf(line, sizeof line, "%.*s", (int)len, u);
        u += len + (u[len] == '\n');
        int indent = 7 + (int)strlen(c->name), col = indent - 1;
        fprintf(out, "brume %s", c->name);
        char words[sizeof line + 2];
        snprintf(words, sizeof words, " %s ", line); /* the flags the synopsis names already */
        for (char *w = strtok(line, " "); w; w = strtok(NULL, " ")) {
            if (w[0] == '-') { /* a flag stays on one line with its value: "-o OUT" */
                char *v = strtok(NULL, " "), pair[512];
                snprintf(pair, sizeof pair, "%s%s%s", w, v ? " " : "", v ? v : "");
                put_word(out, pair, indent, &col);
                if (!v)
                    break;
                continue;
            }
            if (!(first && strcmp(w, "[options]") == 0)) {
                put_word(out, w, indent, &col);
                continue;
            }
            for (int k = 0; k < c->nflags; k++) {
                const cli_flag *f = &c->flags[k];
                if (named(words, f->name) || (f->alias && named(words, f->alias)))
                    continue;
                char item[256];
                snprintf(item, sizeof item, "[%s%s%s]", f->alias ? f->alias : f->name, f->arg ? " " : "",
                         f->arg ? f->arg : "");
                put_word(out, item, indent, &col);
            }
        }
        fputc('\n', out);
        first = false;
    } while (*u);
}

void cli_flags_usage_block(FILE *out)
{
    fputs("```\n", out);
    for (int k = 0; k < cli_ncommands; k++)
        usage_entry(out, cli_all_commands[k]);
    fputs("# the commands, or one command's flags\nbrume help [COMMAND]\nbrume --version\n```\n", out);
}

void cli_usage(FILE *out)
{
    fprintf(out, "usage: brume COMMAND [ARGS]\n\ncommands:\n");
#define X(name, summary) fprintf(out, "  %-10s %s\n", #name, summary);
    BRUME_COMMANDS(X)
#undef X
    fprintf(out, "  %-10s %s\n", "help", "this text, `brume help COMMAND` (its flags) or `brume help --usage`");
    fprintf(out, "\noptions:\n  --version  print the version\n"
                 "\nenvironment:\n  BRUME_MODULE_PATH  the folder of libbrume-openvdb.so (.vdb files), when not beside\n"
                 "                     libbrume or in the install's library folder\n"
                 "\nSee `man brume`, and README.md and docs/ (installed in PREFIX/share/doc/brume);\n"
                 "example scenes and their data are installed in PREFIX/share/brume.\n");
}

int cli_help(int argc, char **argv)
{
    if (argc < 2) {
        cli_usage(stdout);
        return 0;
    }
    if (strcmp(argv[1], "--usage") == 0) {
        cli_flags_usage_block(stdout);
        return 0;
    }
    size_t len = strlen(argv[1]);
    bool found = false;
    for (int k = 0; k < cli_ncommands; k++) { /* "gen": gen cloud, gen fire and gen upres */
        const char *name = cli_all_commands[k]->name;
        if (strncmp(name, argv[1], len) == 0 && (name[len] == '\0' || name[len] == ' ')) {
            if (found)
                fputc('\n', stdout);
            cli_flags_help(stdout, cli_all_commands[k]);
            found = true;
        }
    }
    if (!found) {
        cli_error("help: unknown command '%s'", argv[1]);
        return 2;
    }
    return 0;
}
