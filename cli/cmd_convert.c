/* cmd_convert.c - `brume convert IN OUT`: between raw, df3, .vol, .nvdb and .vdb; formats
 * by extension (or --format for IN, --to for OUT). .vdb to .nvdb keeps the sparse tree. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_flags.h"
#include "cli_grid.h"
#include "commands.h"
#include "cli_job.h"
#include "tool/tool.h"

typedef struct convert_opts {
    brume_grid_file_options grid; /* first: the loading flags' */
    const char *to;
} convert_opts;

static bool flag_to(void *opts, const cli_flag *f, const char *v)
{
    (void)f;
    if (!tool_grid_format_known(v)) {
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
    const char *fin = tool_grid_format_of(in, o.format, NULL, 0), *fout = tool_grid_format_of(out, tool_grid_format_parse(to), NULL, 0);
    if (!fout) {
        cli_error("%s: unknown output format (use .raw, .df3, .vol, .nvdb, .vdb or --to)", out);
        return 2;
    }
    /* before any work: never over the source (a converted grid over its source would drop
     * its other grids), and only over a grid file */
    if (cli_check_output("OUT", out, BRUME_FILE_GRID, NULL, NULL, &in, 1) != 0)
        return 1;
    /* OpenVDB to NanoVDB directly: the sparse tree is kept, nothing is densified */
    if (fin && strcmp(fin, "vdb") == 0 && strcmp(fout, "nvdb") == 0 && !placed(argc, argv)) {
        if (tool_grid_convert_vdb_to_nvdb(in, out, o.grid) != BRUME_OK) {
            cli_error("%.1000s", tool_last_error());
            return 1;
        }
        return 0;
    }
    density *d = tool_grid_load(in, &o);
    if (!d) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    brume_status s = tool_grid_write(d, out, fout);
    tool_grid_release(d);
    if (s != BRUME_OK) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    return 0;
}
