/* cmd_convert.c - `brume convert IN OUT`: between raw, df3, .vol, .nvdb and .vdb; formats
 * by extension (or --format for IN, --to for OUT). .vdb to .nvdb keeps the sparse tree. */
#include <stdio.h>
#include <string.h>

#include "cli_grid.h"
#include "commands.h"
#include "tool/tool.h"

static const char usage[] =
    "usage: brume convert [flags] IN OUT\n"
    "  --to raw|df3|vol|nvdb|vdb       output format (default: OUT's extension)\n" CLI_LOAD_FLAGS_HELP;

int cmd_convert(int argc, char **argv)
{
    brume_grid_file_options o;
    brume_grid_file_options_default(&o);
    const char *in = NULL, *out = NULL, *to = NULL;
    bool placed = false;
    for (int i = 1; i < argc; i++) {
        int r = cli_load_flag("convert", argc, argv, &i, &o);
        if (r < 0)
            return 2;
        if (r > 0) {
            placed |= strcmp(argv[i - 1], "--format") != 0 && strcmp(argv[i - 1], "--max-memory") != 0;
            continue;
        }
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) {
            fputs(usage, stdout);
            return 0;
        }
        if (strcmp(argv[i], "--to") == 0) {
            if (i + 1 >= argc || !tool_grid_format_known(to = argv[i + 1])) {
                cli_error("convert: --to needs one of raw, df3, vol, nvdb, vdb");
                return 2;
            }
            i++;
            continue;
        }
        if (argv[i][0] == '-' && argv[i][1] != '\0') {
            cli_error("convert: unknown flag %s (see brume convert --help)", argv[i]);
            return 2;
        }
        if (!in)
            in = argv[i];
        else if (!out)
            out = argv[i];
        else {
            cli_error("convert: unexpected argument %s", argv[i]);
            return 2;
        }
    }
    if (!in || !out) {
        cli_error("convert: need IN and OUT (see brume convert --help)");
        return 2;
    }
    const char *fin = tool_grid_format_of(in, o.format, NULL, 0), *fout = tool_grid_format_of(out, tool_grid_format_parse(to), NULL, 0);
    if (!fout) {
        cli_error("%s: unknown output format (use .raw, .df3, .vol, .nvdb, .vdb or --to)", out);
        return 2;
    }
    /* OpenVDB to NanoVDB directly: the sparse tree is kept, nothing is densified */
    if (fin && strcmp(fin, "vdb") == 0 && strcmp(fout, "nvdb") == 0 && !placed) {
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
