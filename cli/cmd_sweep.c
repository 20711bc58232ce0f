/* cmd_sweep.c - `brume sweep SCENE --set KEY=A,B,C [--set KEY2=X,Y] -o sheet.png`: renders
 * the scene over every combination of one or two swept keys and writes a labelled contact
 * sheet (columns: the first swept key, rows: the second). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "brume.h"
#include "commands.h"
#include "tool/tool.h"

#define MAX_SETS 32
#define MAX_VALUES 16
#define MAX_CELLS 64
#define TEXT_MAX 512

static const char sweep_usage[] =
    "usage: brume sweep SCENE.json --set KEY=A,B,C [--set KEY2=X,Y] -o SHEET.png [options]\n"
    "Renders SCENE once for every combination of the values of the swept keys and writes a\n"
    "contact sheet: the first key with several values runs along the columns, the second\n"
    "along the rows, each labelled KEY=VALUE. A --set with one value is a fixed override, as\n"
    "for brume render. Values are JSON or text as for --set; commas inside [...], {...} or\n"
    "quotes do not split (--set media.0.sigma_s=[1,1,1],[4,4,4] sweeps two colours).\n"
    "At most 2 swept keys, 16 values each, 64 renders.\n\n"
    "  -o FILE            the sheet (.png), required\n"
    "  --width W, --height H, --spp N, --method M, --seed S, --threads N\n"
    "                     render settings for every cell (default: the scene's)\n"
    "  --exposure STOPS   exposure of the sheet's cells, as for PNG renders\n"
    "  --title TEXT       the sheet's title (default: the scene's file name)\n";

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

int cmd_sweep(int argc, char **argv)
{
    const char *scene = NULL, *out = NULL, *title = NULL, *method = NULL;
    static sweep_key keys[MAX_SETS];
    int nkeys = 0, width = 0, height = 0, spp = 0, threads = 0;
    uint64_t seed = 0;
    bool seed_given = false;
    double exposure = 0.0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            fputs(sweep_usage, stdout);
            return 0;
        } else if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
            if (!(out = arg_value(argc, argv, &i))) return 2;
        } else if (strcmp(a, "--set") == 0) {
            if (!(v = arg_value(argc, argv, &i))) return 2;
            if (nkeys == MAX_SETS) {
                cli_error("sweep: more than %d --set options", MAX_SETS);
                return 2;
            }
            if (!parse_set(v, &keys[nkeys++])) return 2;
        } else if (strcmp(a, "--width") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 1, 4096, &width)) return 2;
        } else if (strcmp(a, "--height") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 1, 4096, &height)) return 2;
        } else if (strcmp(a, "--spp") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 1, 1 << 24, &spp)) return 2;
        } else if (strcmp(a, "--threads") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 0, 1024, &threads)) return 2;
        } else if (strcmp(a, "--seed") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_u64(a, v, &seed)) return 2;
            seed_given = true;
        } else if (strcmp(a, "--method") == 0) {
            if (!(method = arg_value(argc, argv, &i))) return 2;
        } else if (strcmp(a, "--exposure") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_double(a, v, -64.0, 64.0, &exposure)) return 2;
        } else if (strcmp(a, "--title") == 0) {
            if (!(title = arg_value(argc, argv, &i))) return 2;
        } else if (!scene && a[0] != '-') {
            scene = a;
        } else {
            cli_error("sweep: unexpected argument '%s'", a);
            return 2;
        }
    }
    if (!scene || !out) {
        cli_error("sweep: need SCENE and -o SHEET.png (try `brume help sweep`)");
        return 2;
    }
    size_t olen = strlen(out);
    if (olen < 4 || strcmp(out + olen - 4, ".png") != 0) {
        cli_error("sweep: %s: the sheet is a .png", out);
        return 2;
    }
    int swept[2] = {-1, -1}, nswept = 0;
    for (int k = 0; k < nkeys; k++)
        if (keys[k].n > 1) {
            if (nswept == 2) {
                cli_error("sweep: --set %s: at most two keys take several values", keys[k].key);
                return 2;
            }
            swept[nswept++] = k;
        }
    if (nswept == 0) {
        cli_error("sweep: no --set KEY=A,B,... with several values to sweep");
        return 2;
    }
    int ncols = keys[swept[0]].n, nrows = nswept == 2 ? keys[swept[1]].n : 1;
    if (ncols * nrows > MAX_CELLS) {
        cli_error("sweep: %d x %d = %d renders, at most %d", ncols, nrows, ncols * nrows, MAX_CELLS);
        return 2;
    }
    static char texts[MAX_SETS][TEXT_MAX + TEXT_MAX + 2], col_text[MAX_VALUES][TEXT_MAX + TEXT_MAX + 2],
        row_text[MAX_VALUES][TEXT_MAX + TEXT_MAX + 2];
    const char *ov[MAX_SETS], *col_labels[MAX_VALUES], *row_labels[MAX_VALUES];
    brume_image *cells[MAX_CELLS] = {0};
    brume_context *ctx = brume_context_new();
    int rc = 1;
    if (!ctx) {
        cli_error("sweep: out of memory");
        return 1;
    }
    for (int c = 0; c < ncols; c++) {
        snprintf(col_text[c], sizeof col_text[c], "%s=%s", keys[swept[0]].key, keys[swept[0]].values[c]);
        col_labels[c] = col_text[c];
    }
    for (int r = 0; nswept == 2 && r < nrows; r++) {
        snprintf(row_text[r], sizeof row_text[r], "%s=%s", keys[swept[1]].key, keys[swept[1]].values[r]);
        row_labels[r] = row_text[r];
    }
    for (int r = 0; r < nrows; r++)
        for (int c = 0; c < ncols; c++) {
            for (int k = 0; k < nkeys; k++) {
                int j = k == swept[0] ? c : k == swept[1] ? r : 0;
                snprintf(texts[k], sizeof texts[k], "%s=%s", keys[k].key, keys[k].values[j]);
                ov[k] = texts[k];
            }
            brume_load_options lo = {0.0, 0, ov, nkeys, NULL};
            brume_scene *s = NULL;
            brume_render_settings rs;
            if (brume_scene_load_with(ctx, scene, &lo, &s) != BRUME_OK)
                goto fail;
            brume_scene_get_settings(s, &rs);
            if (width)
                rs.width = width;
            if (height)
                rs.height = height;
            if (spp)
                rs.spp = spp;
            if (seed_given)
                rs.seed = seed;
            if (method)
                snprintf(rs.method, sizeof rs.method, "%s", method);
            rs.threads = threads;
            rs.progress = false;
            brume_status st = brume_scene_set_settings(ctx, s, &rs);
            if (st == BRUME_OK)
                st = brume_scene_commit(ctx, s);
            if (st == BRUME_OK)
                st = brume_render(ctx, s, &cells[r * ncols + c]);
            brume_scene_release(s);
            if (st != BRUME_OK)
                goto fail;
            fprintf(stderr, "sweep: %d of %d rendered (%s%s%s)\n", r * ncols + c + 1, ncols * nrows,
                    col_labels[c], nswept == 2 ? ", " : "", nswept == 2 ? row_labels[r] : "");
        }
    {
        brume_write_options wo = {exposure, BRUME_TONEMAP_CLAMP};
        if (sheet_png(out, title ? title : scene, ncols, nrows, (const brume_image *const *)cells, col_labels,
                      nswept == 2 ? row_labels : NULL, NULL, &wo) != BRUME_OK) {
            cli_error("%.1000s", tool_last_error());
            goto done;
        }
    }
    rc = 0;
    goto done;
fail:
    cli_error("%.1000s", brume_context_last_error(ctx));
done:
    for (int i = 0; i < MAX_CELLS; i++)
        brume_image_release(cells[i]);
    brume_context_release(ctx);
    return rc;
}
