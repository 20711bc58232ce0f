/* cmd_options.c - `brume options [--markdown]`: the rendering methods' options (METHOD.KEY,
 * for --set and the scene file's method objects), listed from the library's own tables
 * (brume_option_get): their values, defaults and meanings. --markdown writes the tables of
 * docs/scene-format.md, "Method options" (ctest options.doc_is_generated compares them). */
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "brume.h"
#include "cli_flags.h"
#include "commands.h"

#define WIDTH 100 /* columns of the plain list */

/* text from column `indent`, wrapped at WIDTH on spaces. */
static void wrap(FILE *out, const char *text, int indent)
{
    int col = indent;
    fprintf(out, "%*s", indent, "");
    for (const char *p = text; *p;) {
        size_t word = strcspn(p, " ");
        if (col > indent && col + 1 + (int)word > WIDTH) {
            fprintf(out, "\n%*s", indent, "");
            col = indent;
        } else if (col > indent) {
            fputc(' ', out);
            col++;
        }
        fprintf(out, "%.*s", (int)word, p);
        col += (int)word;
        p += word;
        while (*p == ' ')
            p++;
    }
    fputc('\n', out);
}

/* The method of a key: "stam" for "stam.voxelize.resolution". */
static size_t method_len(const char *key) { return strcspn(key, "."); }

void cli_options_keys(FILE *out)
{
    char line[8192];
    size_t len = 0;
    line[0] = '\0';
    for (int i = 0; i < brume_option_count(); i++) {
        brume_option o;
        if (brume_option_get(NULL, i, &o) != BRUME_OK)
            break;
        int w = snprintf(line + len, sizeof line - len, "%s%s", i ? ", " : "", o.key);
        if (w < 0 || (size_t)w >= sizeof line - len)
            break;
        len += (size_t)w;
    }
    wrap(out, line, 2);
}

/* A markdown table cell: '|' escaped, so that the row keeps its columns. */
static void cell(FILE *out, const char *text, bool code)
{
    fputs(code ? " `" : " ", out);
    for (const char *p = text; *p; p++) {
        if (*p == '|')
            fputc('\\', out);
        fputc(*p, out);
    }
    fputs(code ? "` |" : " |", out);
}

void cli_options_markdown(FILE *out)
{
    const char *method = "";
    size_t mlen = 0;
    for (int i = 0; i < brume_option_count(); i++) {
        brume_option o;
        if (brume_option_get(NULL, i, &o) != BRUME_OK)
            break;
        if (method_len(o.key) != mlen || strncmp(o.key, method, mlen) != 0) {
            method = o.key;
            mlen = method_len(o.key);
            fprintf(out, "%s### `%.*s`\n\n| key | values | default | meaning |\n| --- | --- | --- | --- |\n",
                    i ? "\n" : "", (int)mlen, method);
        }
        fputc('|', out);
        cell(out, o.key + mlen + 1, true);
        cell(out, o.values, false);
        cell(out, o.default_value, o.kind == BRUME_OPTION_ENUM && o.default_value[0]);
        cell(out, o.doc, false);
        fputc('\n', out);
    }
}

static void list(FILE *out)
{
    for (int i = 0; i < brume_option_count(); i++) {
        brume_option o;
        if (brume_option_get(NULL, i, &o) != BRUME_OK)
            break;
        fprintf(out, "%s\n    %s%s%s\n", o.key, o.values, o.default_value[0] ? "; default " : "", o.default_value);
        wrap(out, o.doc, 4);
    }
}

typedef struct options_opts {
    bool markdown;
} options_opts;

static void options_epilogue(FILE *out)
{
    fputc('\n', out);
    list(out);
}

static const cli_flag options_flags[] = {
    {"--markdown", NULL, NULL, "the tables of docs/scene-format.md's \"Method options\" instead", NULL, CLI_FLAG_TRUE,
     offsetof(options_opts, markdown), 0, 0, NULL},
};

const cli_command cli_options_command = {
    "options", "the rendering methods' options (METHOD.KEY for --set): values, defaults, meanings",
    "[options]",
    "Lists the options of the rendering methods: a scene file's \"path\", \"blasi\" and \"stam\" objects,\n"
    "`brume render --set METHOD.KEY=VALUE`, brume_scene_set_option (docs/scene-format.md, \"Method options\").\n",
    options_flags, CLI_NFLAGS(options_flags), NULL, options_epilogue};

int cmd_options(int argc, char **argv)
{
    options_opts o = {false};
    int n = 0, rc = cli_flags_parse(&cli_options_command, &o, argc, argv, NULL, 0, &n);
    if (rc >= 0)
        return rc;
    if (o.markdown)
        cli_options_markdown(stdout);
    else
        list(stdout);
    return 0;
}
