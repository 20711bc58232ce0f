/* cmd_info.c - `brume info FILE`: every grid of a .vdb/.nvdb (name, value type, class,
 * index box, active voxels, value range, NanoVDB memory), then the grid brume reads (or the
 * one of --grid): format, dimensions, world bounds, value range, memory and active voxels. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_grid.h"
#include "commands.h"
#include "tool/tool.h"

static const char usage[] = "usage: brume info [flags] FILE\n"
                            "  FILE may be a frame pattern (smoke_%04d.vdb, smoke_####.vdb): the range and the bounds over it\n"
                            CLI_LOAD_FLAGS_HELP;

/* A frame pattern: the range of files present and the world box over all of them (each
 * file loaded in turn, one in memory at a time). */
static int info_sequence(const char *pattern, const density_load_options *o)
{
    long first, last;
    if (tool_seq_range(pattern, &first, &last) != BRUME_OK) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    printf("sequence:       %s\n", pattern);
    printf("frames:         files %ld to %ld (%ld files)\n", first, last, last - first + 1);
    box3 b = box3_empty();
    double rho_max = 0.0;
    for (long n = first; n <= last; n++) {
        char name[4096];
        tool_seq_name(pattern, n, name, sizeof name);
        density *d = density_load_file(name, o);
        if (!d) {
            cli_error("%.1000s", tool_last_error());
            return 1;
        }
        box3 a = density_bounds(d);
        b.lo = v3_min(b.lo, a.lo);
        b.hi = v3_max(b.hi, a.hi);
        rho_max = fmax(rho_max, density_max(d));
        density_release(d);
    }
    printf("world bounds:   (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g) over the sequence\n", b.lo.x, b.lo.y, b.lo.z,
           b.hi.x, b.hi.y, b.hi.z);
    printf("values:         up to %.6g\n", rho_max);
    return 0;
}

int cmd_info(int argc, char **argv)
{
    density_load_options o;
    density_load_options_default(&o);
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        int r = cli_load_flag("info", argc, argv, &i, &o);
        if (r < 0)
            return 2;
        if (r > 0)
            continue;
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) {
            fputs(usage, stdout);
            return 0;
        }
        if (argv[i][0] == '-' || path) {
            cli_error("info: unexpected argument %s (see brume info --help)", argv[i]);
            return 2;
        }
        path = argv[i];
    }
    if (!path) {
        cli_error("info: no FILE given (see brume info --help)");
        return 2;
    }
    int pat = tool_seq_is_pattern(path);
    if (pat < 0) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    if (pat)
        return info_sequence(path, &o);
    unsigned char head[16] = {0};
    size_t nhead = 0;
    FILE *f = fopen(path, "rb");
    if (f) {
        nhead = fread(head, 1, sizeof head, f);
        fclose(f);
    }
    grid_format fmt = o.format != GRID_FORMAT_AUTO ? o.format : grid_format_detect(path, head, nhead);
    int ngrids = 0;
    if (fmt == GRID_FORMAT_VDB || fmt == GRID_FORMAT_NVDB) {
        gridvdb_info *gi = NULL;
        if (grid_list_file(path, o.max_memory, &gi, &ngrids) != BRUME_OK) {
            cli_error("%.1000s", tool_last_error());
            return 1;
        }
        printf("file:           %s\n", path);
        printf("grids:          %d\n", ngrids);
        for (int g = 0; g < ngrids; g++) {
            printf("  grid \"%s\": %s, %s, index box (%d, %d, %d) to (%d, %d, %d), %llu active voxels, values %.6g to "
                   "%.6g, NanoVDB %.2f MiB\n",
                   gi[g].name, gi[g].type, gi[g].cls, gi[g].bbmin[0], gi[g].bbmin[1], gi[g].bbmin[2], gi[g].bbmax[0],
                   gi[g].bbmax[1], gi[g].bbmax[2], gi[g].active, gi[g].vmin, gi[g].vmax,
                   (double)gi[g].nano_bytes / 1048576.0);
        }
        free(gi);
    }
    density *d = density_load_file(path, &o);
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
    density_info in;
    density_get_info(d, &in);
    const double *m = in.voxel_to_world.m;
    printf("file:           %s\n", path);
    printf("format:         %s (%s grid)\n", grid_format_name(fmt), in.kind == DENSITY_NANOVDB ? "sparse NanoVDB" : "dense");
    printf("dimensions:     %d x %d x %d voxels\n", in.n[0], in.n[1], in.n[2]);
    printf("world bounds:   (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g)\n", in.bounds.lo.x, in.bounds.lo.y, in.bounds.lo.z,
           in.bounds.hi.x, in.bounds.hi.y, in.bounds.hi.z);
    printf("voxel to world: [%.6g %.6g %.6g %.6g; %.6g %.6g %.6g %.6g; %.6g %.6g %.6g %.6g]\n", m[0], m[1], m[2], m[3],
           m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11]);
    printf("values:         %.6g to %.6g\n", in.rho_min, in.rho_max);
    printf("memory:         %zu bytes (%.2f MiB)\n", in.memory_bytes, (double)in.memory_bytes / 1048576.0);
    printf("active voxels:  %llu\n", (unsigned long long)in.active_voxels);
    if (in.majorant_tree)
        printf("majorants:      from the tree: %d blocks of 128^3 voxels with bounds per 8^3 leaf cell\n",
               in.majorant_n[0]);
    else
        printf("majorant grid:  %d x %d x %d cells of %d^3 voxels\n", in.majorant_n[0], in.majorant_n[1],
               in.majorant_n[2], in.majorant_cell);
    density_release(d);
    return 0;
}
