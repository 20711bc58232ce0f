/* cmd_info.c - `brume info FILE`: every grid of a .vdb/.nvdb (name, value type, class,
 * index box, active voxels, value range, NanoVDB memory, role by name), then the grid brume
 * reads (or the one of --grid): format, dimensions, world bounds, value range, memory and
 * active voxels. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_flags.h"
#include "cli_grid.h"
#include "commands.h"

typedef struct info_opts {
    brume_grid_file_options grid; /* first: the loading flags' */
} info_opts;

static const cli_flag info_flags[] = {CLI_LOAD_FLAGS};

const cli_command cli_info_command = {
    "info", "a grid file's format, dimensions, bounds, values and memory",
    "[options] FILE",
    "Prints every grid of a .vdb/.nvdb (name, value type, class, index box, active voxels, value\n"
    "range, NanoVDB memory, and the role a medium's field takes it in by its name: density,\n"
    "temperature, emission, albedo, velocity or none), then the grid brume reads: format,\n"
    "dimensions, world bounds, values, memory and active voxels. FILE may be a frame pattern\n"
    "(smoke_%04d.vdb, smoke_####.vdb): the range and the bounds over it.\n",
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
    ctx = brume_context_new();
    st = ctx ? brume_grid_sequence_extent(ctx, pattern, first, last, o, b, &rho_max) : BRUME_ERROR_OUT_OF_MEMORY;
    if (st != BRUME_OK)
        cli_error("%.1000s", ctx ? brume_context_last_error(ctx) : "out of memory");
    brume_context_release(ctx);
    if (st != BRUME_OK)
        return 1;
    printf("world bounds:   (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g) over the sequence\n", b[0], b[1], b[2], b[3],
           b[4], b[5]);
    printf("values:         up to %.6g\n", rho_max);
    return 0;
}

/* The grids of a .vdb/.nvdb, one line each: 0, or 1 after the message. */
static int print_list(brume_context *ctx, const char *path, const brume_grid_file_options *o, int *count)
{
    brume_grid_entry *e = NULL;
    int n = 0;
    brume_status st = brume_grid_file_list(ctx, path, o, NULL, 0, &n);
    if (st == BRUME_OK && n > 0 && !(e = calloc((size_t)n, sizeof *e))) {
        cli_error("info: out of memory for %d grids", n);
        return 1;
    }
    if (st == BRUME_OK && n > 0)
        st = brume_grid_file_list(ctx, path, o, e, n, &n);
    if (st != BRUME_OK) {
        cli_error("%.1000s", brume_context_last_error(ctx));
        free(e);
        return 1;
    }
    printf("file:           %s\n", path);
    printf("grids:          %d\n", n);
    for (int g = 0; g < n; g++) {
        /* the role a medium's field takes it in when the scene names no grid (docs/grids.md) */
        const char *role = brume_grid_role(e, n, g);
        printf("  grid \"%s\": %s, %s, index box (%d, %d, %d) to (%d, %d, %d), %llu active voxels, values %.6g to "
               "%.6g, NanoVDB %.2f MiB, role %s\n",
               e[g].name, e[g].type, e[g].grid_class, e[g].index_min[0], e[g].index_min[1], e[g].index_min[2],
               e[g].index_max[0], e[g].index_max[1], e[g].index_max[2], e[g].active_voxels, e[g].value_min,
               e[g].value_max, (double)e[g].nanovdb_bytes / 1048576.0, role[0] ? role : "none");
    }
    free(e);
    *count = n;
    return 0;
}

/* The density's format (as named), dimensions, bounds, placement, values, memory, active
 * voxels and majorants, one line each. */
static void print_info(const char *path, const char *format, const brume_density_info *in)
{
    const double *m = in->voxel_to_world, *b = in->bounds;
    printf("file:           %s\n", path);
    printf("format:         %s (%s grid)\n", format, in->sparse ? "sparse NanoVDB" : "dense");
    printf("dimensions:     %d x %d x %d voxels\n", in->dims[0], in->dims[1], in->dims[2]);
    printf("world bounds:   (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g)\n", b[0], b[1], b[2], b[3], b[4], b[5]);
    printf("voxel to world: [%.6g %.6g %.6g %.6g; %.6g %.6g %.6g %.6g; %.6g %.6g %.6g %.6g]\n", m[0], m[1], m[2], m[3],
           m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11]);
    printf("values:         %.6g to %.6g\n", in->rho_min, in->rho_max);
    printf("memory:         %zu bytes (%.2f MiB)\n", in->memory_bytes, (double)in->memory_bytes / 1048576.0);
    printf("active voxels:  %llu\n", in->active_voxels);
    if (in->majorant_tree)
        printf("majorants:      from the tree: %d blocks of 128^3 voxels with bounds per 8^3 leaf cell\n",
               in->majorant_dims[0]);
    else
        printf("majorant grid:  %d x %d x %d cells of %d^3 voxels\n", in->majorant_dims[0], in->majorant_dims[1],
               in->majorant_dims[2], in->majorant_cell);
}

/* One grid file: its grids (a .vdb/.nvdb), then the one brume reads. */
static int info_file(brume_context *ctx, const char *path, const brume_grid_file_options *o)
{
    brume_grid_format f = o->format != BRUME_GRID_FORMAT_AUTO ? o->format : brume_grid_format_of(path);
    int ngrids = 0;
    if ((f == BRUME_GRID_FORMAT_VDB || f == BRUME_GRID_FORMAT_NVDB) && print_list(ctx, path, o, &ngrids) != 0)
        return 1;
    brume_density *d = NULL;
    if (brume_density_load(ctx, path, o, &d) != BRUME_OK) {
        if (ngrids > 0 && !o->grid[0]) { /* the listing stands; no default grid to detail */
            printf("density grid:   none by default (%s)\n", brume_context_last_error(ctx));
            return 0;
        }
        cli_error("%.1000s", brume_context_last_error(ctx));
        return 1;
    }
    if (ngrids > 0)
        printf("density grid:   %s\n", o->grid[0] ? o->grid : "the default (see docs/grids.md)");
    brume_density_info in;
    (void)brume_density_get_info(ctx, d, &in); /* d is a density: it cannot fail */
    print_info(path, brume_grid_format_name(f), &in);
    brume_density_release(d);
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
    bool pat = false;
    brume_context *ctx = brume_context_new();
    brume_status st = ctx ? brume_sequence_pattern(ctx, path, &pat) : BRUME_ERROR_OUT_OF_MEMORY;
    if (st != BRUME_OK)
        cli_error("%.1000s", ctx ? brume_context_last_error(ctx) : "out of memory");
    else
        rc = pat ? info_sequence(path, &io.grid) : info_file(ctx, path, &io.grid);
    brume_context_release(ctx);
    return st != BRUME_OK ? 1 : rc;
}
