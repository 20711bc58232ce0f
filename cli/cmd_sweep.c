/* cmd_sweep.c - `brume sweep SCENE --set KEY=A,B,C [--set KEY2=X,Y] -o sheet.png`: renders
 * the scene over every combination of one or two swept keys and writes a labelled contact
 * sheet (columns: the first swept key, rows: the second). */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "cli_flags.h"
#include "brume.h"
#include "cli_job.h"
#include "commands.h"

#define MAX_SETS 32
#define MAX_VALUES 16
#define MAX_CELLS 64
#define TEXT_MAX 512

typedef struct sweep_key {
    char key[TEXT_MAX];
    char values[MAX_VALUES][TEXT_MAX];
    int n;
} sweep_key;

/* Splits "KEY=A,B,C" at the top-level commas of its value. False (with a message) when it is
 * not KEY=VALUE, has too many values, or a value is empty or too long. */
static bool parse_set(const char *text, sweep_key *k)
{
    const char *eq = strchr(text, '=');
    if (!eq || eq == text || (size_t)(eq - text) >= TEXT_MAX) {
        cli_error("sweep: --set %s: expected KEY=VALUE[,VALUE...]", text);
        return false;
    }
    snprintf(k->key, sizeof k->key, "%.*s", (int)(eq - text), text);
    k->n = 0;
    const char *p = eq + 1, *start = p;
    int depth = 0;
    bool quoted = false;
    for (;; p++) {
        char c = *p;
        if (c == '"' && (p == start || p[-1] != '\\'))
            quoted = !quoted;
        else if (!quoted && (c == '[' || c == '{'))
            depth++;
        else if (!quoted && (c == ']' || c == '}'))
            depth--;
        if (c == '\0' || (c == ',' && depth == 0 && !quoted)) {
            size_t len = (size_t)(p - start);
            if (len == 0 || len >= TEXT_MAX || k->n == MAX_VALUES) {
                cli_error("sweep: --set %s: %s", k->key,
                          len == 0 ? "an empty value" : k->n == MAX_VALUES ? "more than 16 values" : "a value too long");
                return false;
            }
            snprintf(k->values[k->n++], TEXT_MAX, "%.*s", (int)len, start);
            if (c == '\0')
                break;
            start = p + 1;
        }
    }
    return true;
}

typedef struct sweep_opts {
    const char *scene, *out, *title, *method; /* title, method: or NULL */
    sweep_key *keys;                          /* --set, MAX_SETS of room */
    int nkeys, width, height, spp, threads;   /* 0: the scene's */
    uint64_t seed;
    bool seed_given;
    double exposure;
    int swept[2], nswept;                     /* the keys with several values: columns, rows */
    int ncols, nrows;
} sweep_opts;

static bool flag_set(void *opts, const cli_flag *f, const char *v)
{
    (void)f;
    sweep_opts *o = opts;
    if (o->nkeys == MAX_SETS) {
        cli_error("sweep: more than %d --set options", MAX_SETS);
        return false;
    }
    return parse_set(v, &o->keys[o->nkeys++]);
}

static bool flag_seed(void *opts, const cli_flag *f, const char *v)
{
    sweep_opts *o = opts;
    return (o->seed_given = arg_u64(f->name, v, &o->seed));
}

#define OFF(field) offsetof(sweep_opts, field)
#define CELLS "render settings for every cell (default: the scene's)"

static const cli_flag sweep_flags[] = {
    {"--output", "-o", "FILE", "the sheet (.png), required", NULL, CLI_FLAG_STRING, OFF(out), 0, 0, NULL},
    {"--set", NULL, "KEY=A,B,C", "a swept key and its values, or a fixed override (one value)", NULL, CLI_FLAG_CALL,
     0, 0, 0, flag_set},
    {"--width", NULL, "W", CELLS, "render.width", CLI_FLAG_INT, OFF(width), 1, 4096, NULL},
    {"--height", NULL, "H", CELLS, "render.height", CLI_FLAG_INT, OFF(height), 1, 4096, NULL},
    {"--spp", NULL, "N", CELLS, "render.spp", CLI_FLAG_INT, OFF(spp), 1, 1 << 24, NULL},
    {"--method", NULL, "M", CELLS, "render.method", CLI_FLAG_STRING, OFF(method), 0, 0, NULL},
    {"--seed", NULL, "S", CELLS, "render.seed", CLI_FLAG_CALL, 0, 0, 0, flag_seed},
    {"--threads", NULL, "N", CELLS, "render.threads", CLI_FLAG_INT, OFF(threads), 0, 1024, NULL},
    {"--exposure", NULL, "STOPS", "exposure of the sheet's cells, as for PNG renders", NULL, CLI_FLAG_DOUBLE,
     OFF(exposure), -64.0, 64.0, NULL},
    {"--title", NULL, "TEXT", "the sheet's title (default: the scene's file name)", NULL, CLI_FLAG_STRING, OFF(title),
     0, 0, NULL},
};

const cli_command cli_sweep_command = {
    "sweep", "render a scene over one or two keys into a labelled contact sheet",
    "SCENE.json --set KEY=A,B,C [--set KEY2=X,Y] -o SHEET.png [options]",
    "Renders SCENE once for every combination of the values of the swept keys and writes a\n"
    "contact sheet: the first key with several values runs along the columns, the second\n"
    "along the rows, each labelled KEY=VALUE. A --set with one value is a fixed override, as\n"
    "for brume render. Values are JSON or text as for --set; commas inside [...], {...} or\n"
    "quotes do not split (--set media.0.sigma_s=[1,1,1],[4,4,4] sweeps two colours).\n"
    "At most 2 swept keys, 16 values each, 64 renders.\n",
    sweep_flags, CLI_NFLAGS(sweep_flags), NULL, NULL};

/* The command line into *o. -1: go on; otherwise the exit status (0 after --help, 2 with a
 * message). */
static int parse_sweep(sweep_opts *o, int argc, char **argv)
{
    int n = 0;
    return cli_flags_parse(&cli_sweep_command, o, argc, argv, &o->scene, 1, &n);
}

/* The sheet's plan: the output's name, the swept keys (one or two), the number of renders.
 * 0, or 2 with a message. */
static int plan_sweep(sweep_opts *o)
{
    if (!o->scene || !o->out) {
        cli_error("sweep: need SCENE and -o SHEET.png (try `brume help sweep`)");
        return 2;
    }
    size_t olen = strlen(o->out);
    if (olen < 4 || strcmp(o->out + olen - 4, ".png") != 0) {
        cli_error("sweep: %s: the sheet is a .png", o->out);
        return 2;
    }
    o->swept[0] = o->swept[1] = -1;
    o->nswept = 0;
    for (int k = 0; k < o->nkeys; k++)
        if (o->keys[k].n > 1) {
            if (o->nswept == 2) {
                cli_error("sweep: --set %s: at most two keys take several values", o->keys[k].key);
                return 2;
            }
            o->swept[o->nswept++] = k;
        }
    if (o->nswept == 0) {
        cli_error("sweep: no --set KEY=A,B,... with several values to sweep");
        return 2;
    }
    o->ncols = o->keys[o->swept[0]].n;
    o->nrows = o->nswept == 2 ? o->keys[o->swept[1]].n : 1;
    if (o->ncols * o->nrows > MAX_CELLS) {
        cli_error("sweep: %d x %d = %d renders, at most %d", o->ncols, o->nrows, o->ncols * o->nrows, MAX_CELLS);
        return 2;
    }
    return 0;
}

/* The render of cell (c, r): the scene with every key at its value there and the command
 * line's settings. On failure returns the status (the context has the message). */
static brume_status render_cell(brume_context *ctx, const sweep_opts *o, int c, int r, brume_image **out)
{
    static char texts[MAX_SETS][TEXT_MAX + TEXT_MAX + 2];
    const char *ov[MAX_SETS];
    for (int k = 0; k < o->nkeys; k++) {
        int j = k == o->swept[0] ? c : k == o->swept[1] ? r : 0;
        snprintf(texts[k], sizeof texts[k], "%s=%s", o->keys[k].key, o->keys[k].values[j]);
        ov[k] = texts[k];
    }
    brume_load_options lo = {0.0, 0, ov, o->nkeys, NULL, 0, false};
    brume_scene *s = NULL;
    brume_render_settings rs;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = o->scene}, &lo, &s);
    if (st != BRUME_OK)
        return st;
    /* the sheet is none of the files the scene read (its sky image, its grids) */
    if ((st = brume_output_check(ctx, "-o", o->out, BRUME_FILE_IMAGE, s, NULL, 0)) != BRUME_OK) {
        brume_scene_release(s);
        return st;
    }
    brume_scene_settings(s, &rs);
    if (o->width)
        rs.width = o->width;
    if (o->height)
        rs.height = o->height;
    if (o->spp)
        rs.spp = o->spp;
    if (o->seed_given)
        rs.seed = o->seed;
    st = o->method ? brume_method_from_name(ctx, o->method, &rs.method) : BRUME_OK;
    rs.threads = o->threads;
    if (st == BRUME_OK)
        st = brume_scene_set_settings(ctx, s, &rs);
    if (st == BRUME_OK)
        st = brume_scene_commit(ctx, s);
    if (st == BRUME_OK)
        st = brume_render(ctx, s, out);
    brume_scene_release(s);
    return st;
}

int cmd_sweep(int argc, char **argv)
{
    static sweep_key keys[MAX_SETS];
    sweep_opts o = {.keys = keys};
    int rc = parse_sweep(&o, argc, argv);
    if (rc >= 0)
        return rc;
    if ((rc = plan_sweep(&o)) != 0)
        return rc;
    if (cli_check_output("-o", o.out, BRUME_FILE_IMAGE, o.scene, NULL, NULL, 0) != 0)
        return 1;
    int ncols = o.ncols, nrows = o.nrows;
    const sweep_key *kc = &keys[o.swept[0]], *kr = o.nswept == 2 ? &keys[o.swept[1]] : NULL;
    static char col_text[MAX_VALUES][TEXT_MAX + TEXT_MAX + 2], row_text[MAX_VALUES][TEXT_MAX + TEXT_MAX + 2];
    const char *col_labels[MAX_VALUES], *row_labels[MAX_VALUES];
    brume_image *cells[MAX_CELLS] = {0};
    brume_context *ctx = brume_context_new();
    rc = 1;
    if (!ctx) {
        cli_error("sweep: out of memory");
        return 1;
    }
    for (int c = 0; c < ncols; c++) {
        snprintf(col_text[c], sizeof col_text[c], "%s=%s", kc->key, kc->values[c]);
        col_labels[c] = col_text[c];
    }
    for (int r = 0; kr && r < nrows; r++) {
        snprintf(row_text[r], sizeof row_text[r], "%s=%s", kr->key, kr->values[r]);
        row_labels[r] = row_text[r];
    }
    for (int r = 0; r < nrows; r++)
        for (int c = 0; c < ncols; c++) {
            if (render_cell(ctx, &o, c, r, &cells[r * ncols + c]) != BRUME_OK) {
                cli_error("%.1000s", brume_context_last_error(ctx));
                goto done;
            }
            fprintf(stderr, "sweep: %d of %d rendered (%s%s%s)\n", r * ncols + c + 1, ncols * nrows, col_labels[c],
                    kr ? ", " : "", kr ? row_labels[r] : "");
        }
    brume_write_options wo = {o.exposure, BRUME_TONEMAP_CLAMP};
    if (brume_image_sheet_png(ctx, o.out, o.title ? o.title : o.scene, ncols, nrows, (const brume_image *const *)cells,
                              col_labels, kr ? row_labels : NULL, NULL, &wo) != BRUME_OK) {
        cli_error("%.1000s", brume_context_last_error(ctx));
        goto done;
    }
    rc = 0;
done:
    for (int i = 0; i < MAX_CELLS; i++)
        brume_image_release(cells[i]);
    brume_context_release(ctx);
    return rc;
}
