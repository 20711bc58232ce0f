/* cmd_convert.c - `brume convert IN OUT`: between raw, df3, .vol, .nvdb and .vdb; formats
 * by extension (or --format for IN, --to for OUT). .vdb to .nvdb keeps the sparse tree. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_flags.h"
#include "cli_grid.h"
#include "commands.h"
#include "cli_job.h"

typedef struct convert_opts {
    brume_grid_file_options grid; /* first: the loading flags' */
    const char *to;
} convert_opts;

static bool flag_to(void *opts, const cli_flag *f, const char *v)
{
    (void)f;
    brume_grid_format unused;
    if (!brume_grid_format_from_name(v, &unused)) {
        cli_error("convert: --to needs one of raw, df3, vol, nvdb, vdb");
        return false;
    }
    ((convert_opts *)opts)->to = v;
    return true;
}

static const cli_flag convert_flags[] = {
    {"--to", NULL, "raw|df3|vol|nvdb|vdb", "output format (default: OUT's extension)", NULL, CLI_FLAG_CALL, 0, 0, 0,
     flag_to},
    CLI_LOAD_FLAGS};

const cli_command cli_convert_command = {
    "convert", "convert a grid file between raw, df3, vol, nvdb and vdb",
    "[options] IN OUT",
    "Formats by extension (or --format for IN, --to for OUT). .vdb to .nvdb keeps the sparse tree.\n",
    convert_flags, CLI_NFLAGS(convert_flags), NULL, NULL};

/* Whether a flag that places the voxels was given (the sparse tree cannot keep it). */
static bool placed(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        const cli_flag *f = cli_flags_find(&cli_convert_command, argv[i]);
        if (f && f->call != flag_to && f->call != cli_grid_format && f->call != cli_grid_max_memory)
            return true;
        i += f && f->arg; /* its value */
    }
    return false;
}

int cmd_convert(int argc, char **argv)
{
    convert_opts co = {.to = NULL};
    brume_grid_file_options_default(&co.grid);
    const char *files[2] = {NULL, NULL};
    int n = 0, rc = cli_flags_parse(&cli_convert_command, &co, argc, argv, files, 2, &n);
    if (rc >= 0)
        return rc;
    const char *in = files[0], *out = files[1];
    if (!in || !out) {
        cli_error("convert: need IN and OUT (see brume convert --help)");
        return 2;
    }
    brume_grid_file_options o = co.grid;
    const char *to = co.to;
    brume_grid_format fin = o.format != BRUME_GRID_FORMAT_AUTO ? o.format : brume_grid_format_of(in);
    brume_grid_format fout = BRUME_GRID_FORMAT_AUTO;
    if (!(to && brume_grid_format_from_name(to, &fout) && fout != BRUME_GRID_FORMAT_AUTO))
        fout = brume_grid_format_of(out); /* OUT does not exist yet: its extension says */
    if (fout == BRUME_GRID_FORMAT_AUTO) {
        cli_error("%s: unknown output format (use .raw, .df3, .vol, .nvdb, .vdb or --to)", out);
        return 2;
    }
    /* before any work: never over the source (a converted grid over its source would drop
     * its other grids), and only over a grid file */
    if (cli_check_output("OUT", out, BRUME_FILE_GRID, NULL, NULL, &in, 1) != 0)
        return 1;
    brume_context *ctx = brume_context_new();
    if (!ctx) {
        cli_error("convert: out of memory");
        return 1;
    }
    brume_status st;
    if (fin == BRUME_GRID_FORMAT_VDB && fout == BRUME_GRID_FORMAT_NVDB && !placed(argc, argv)) {
        /* OpenVDB to NanoVDB directly: the sparse tree is kept, nothing is densified */
        st = brume_grid_convert_vdb_to_nvdb(ctx, in, out, o.grid);
    } else {
        brume_density *d = NULL;
        st = brume_density_load(ctx, in, &o, &d);
        if (st == BRUME_OK)
            st = brume_density_write(ctx, d, out, fout);
        brume_density_release(d);
    }
    if (st != BRUME_OK)
        cli_error("%.1000s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    return st != BRUME_OK;
}
