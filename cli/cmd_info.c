/* cmd_info.c - `brume info FILE`: every grid of a .vdb/.nvdb (name, value type, class,
 * index box, active voxels, value range, NanoVDB memory), then the grid brume reads (or the
 * one of --grid): format, dimensions, world bounds, value range, memory and active voxels. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli_flags.h"
#include "cli_grid.h"
#include "commands.h"
#include "tool/tool.h"

typedef struct info_opts {
    brume_grid_file_options grid; /* first: the loading flags' */
} info_opts;

static const cli_flag info_flags[] = {CLI_LOAD_FLAGS};

const cli_command cli_info_command = {
    "info", "a grid file's format, dimensions, bounds, values and memory",
    "[options] FILE",
    "Prints every grid of a .vdb/.nvdb (name, value type, class, index box, active voxels, value\n"
    "range, NanoVDB memory), then the grid brume reads: format, dimensions, world bounds, values,\n"
    "memory and active voxels. FILE may be a frame pattern (smoke_%04d.vdb, smoke_####.vdb): the\n"
    "range and the bounds over it.\n",
    info_flags, CLI_NFLAGS(info_flags), NULL, NULL};

/* A frame pattern: the range of files present and the world box over all of them (each
 * file loaded in turn, one in memory at a time). */
static int info_sequence(const char *pattern, const brume_grid_file_options *o)
{
    long first, last;
    brume_context *ctx = brume_context_new();
    brume_status st = ctx ? brume_sequence_range(ctx, pattern, &first, &last) : BRUME_ERROR_OUT_OF_MEMORY;
    if (st != BRUME_OK)
        cli_error("%.1000s", ctx ? brume_context_last_error(ctx) : "out of memory");
    brume_context_release(ctx);
    if (st != BRUME_OK)
        return 1;
    printf("sequence:       %s\n", pattern);
    printf("frames:         files %ld to %ld (%ld files)\n", first, last, last - first + 1);
    double b[6], rho_max;
    if (tool_grid_sequence_extent(pattern, first, last, o, b, &rho_max) != BRUME_OK) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    printf("world bounds:   (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g) over the sequence\n", b[0], b[1], b[2], b[3],
           b[4], b[5]);
    printf("values:         up to %.6g\n", rho_max);
    return 0;
}

int cmd_info(int argc, char **argv)
{
    info_opts io;
    brume_grid_file_options_default(&io.grid);
    const char *path = NULL;
    int n = 0, rc = cli_flags_parse(&cli_info_command, &io, argc, argv, &path, 1, &n);
    if (rc >= 0)
        return rc;
    if (!path) {
        cli_error("info: no FILE given (see brume info --help)");
        return 2;
    }
    brume_grid_file_options o = io.grid;
    bool pat = false;
    brume_context *ctx = brume_context_new();
    brume_status st = ctx ? brume_sequence_pattern(ctx, path, &pat) : BRUME_ERROR_OUT_OF_MEMORY;
    if (st != BRUME_OK)
        cli_error("%.1000s", ctx ? brume_context_last_error(ctx) : "out of memory");
    brume_context_release(ctx);
    if (st != BRUME_OK)
        return 1;
    if (pat)
        return info_sequence(path, &o);
    unsigned char head[16] = {0};
    size_t nhead = 0;
    struct stat sb; /* only a regular file is read: opening a FIFO waits for a writer (the load refuses it) */
    FILE *f = stat(path, &sb) == 0 && S_ISREG(sb.st_mode) ? fopen(path, "rb") : NULL;
    if (f) {
        nhead = fread(head, 1, sizeof head, f);
        fclose(f);
    }
    const char *fmt = tool_grid_format_of(path, o.format, head, nhead);
    int ngrids = 0;
    if (fmt && (strcmp(fmt, "vdb") == 0 || strcmp(fmt, "nvdb") == 0) &&
        tool_grid_print_list(stdout, path, &o, &ngrids) != BRUME_OK) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    density *d = tool_grid_load(path, &o);
    if (!d) {
        if (ngrids > 0 && !o.grid[0]) { /* the listing stands; no default grid to detail */
            printf("density grid:   none by default (%s)\n", tool_last_error());
            return 0;
        }
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    if (ngrids > 0)
        printf("density grid:   %s\n", o.grid[0] ? o.grid : "the default (see docs/grids.md)");
    tool_grid_print_info(stdout, path, fmt ? fmt : "auto", d);
    tool_grid_release(d);
    return 0;
}
