/* cli_grid.h - flags shared by the grid subcommands (info, convert, gen): parsing of
 * dimensions, boxes, transforms, sizes, and of the grid loading options (brume.h's
 * brume_grid_file_options, --max-memory in bytes turned into max_memory_mb, exactly). */
#ifndef BRUME_CLI_CLI_GRID_H
#define BRUME_CLI_CLI_GRID_H

#include <stdbool.h>
#include <stddef.h>

#include "brume.h"

/* "NXxNYxNZ" (or one number N for a cube), each in [1, 2^31). */
bool cli_parse_dims(const char *s, int n[3]);
/* count comma-separated finite numbers. */
bool cli_parse_doubles(const char *s, double *out, int count);
/* A byte count with an optional K, M, G or T suffix (powers of 1024). */
bool cli_parse_bytes(const char *s, size_t *out);

/* If argv[*i] is a loading flag, consumes it (and its value) and returns 1; returns 0 when
 * it is not one, and -1 (after printing the usage error) when its value is bad. Flags:
 *   --format F  --dims NXxNYxNZ  --bounds X0,Y0,Z0,X1,Y1,Z1  --transform 12 numbers (row-major 3x4)
 *   --filter nearest|trilinear  --scale S  --max-memory BYTES  --grid NAME */
int cli_load_flag(const char *cmd, int argc, char **argv, int *i, brume_grid_file_options *o);
#define CLI_LOAD_FLAGS_HELP                                                                     \
    "  --format raw|df3|vol|nvdb|vdb   override detection by extension and magic\n"            \
    "  --dims NXxNYxNZ                 raw dimensions when there is no FILE.hdr sidecar\n"      \
    "  --bounds X0,Y0,Z0,X1,Y1,Z1      place the voxels on this world box\n"                    \
    "  --transform M00,...,M23         then apply this affine map (row-major 3x4)\n"            \
    "  --filter nearest|trilinear      lookup between samples (default trilinear)\n"            \
    "  --scale S                       multiply densities by S (default 1)\n"                   \
    "  --max-memory BYTES              refuse grids larger than this (K/M/G suffixes; default 4G)\n" \
    "  --grid NAME                     .vdb/.nvdb: the grid to read (default: \"density\", else the only float grid)\n"

#endif
