/* cli_grid.h - flags shared by the grid subcommands (info, convert, gen): parsing of
 * dimensions, boxes, transforms, sizes, and of the grid loading options (brume.h's
 * brume_grid_file_options, --max-memory in bytes turned into max_memory_mb, exactly). */
#ifndef BRUME_CLI_CLI_GRID_H
#define BRUME_CLI_CLI_GRID_H

#include <stdbool.h>
#include <stddef.h>

#include "brume.h"
#include "cli_flags.h"

/* "NXxNYxNZ" (or one number N for a cube), each in [1, 2^31). */
bool cli_parse_dims(const char *s, int n[3]);
/* count comma-separated finite numbers. */
bool cli_parse_doubles(const char *s, double *out, int count);
/* A byte count with an optional K, M, G or T suffix (powers of 1024). */
bool cli_parse_bytes(const char *s, size_t *out);

/* The grid loading flags (cli_flags.h), for a command whose options begin with a
 * brume_grid_file_options: CLI_LOAD_FLAGS in its table. Each false after the message. */
bool cli_grid_format(void *opts, const cli_flag *f, const char *value);
bool cli_grid_dims(void *opts, const cli_flag *f, const char *value);
bool cli_grid_bounds(void *opts, const cli_flag *f, const char *value);
bool cli_grid_transform(void *opts, const cli_flag *f, const char *value);
bool cli_grid_filter(void *opts, const cli_flag *f, const char *value);
bool cli_grid_scale(void *opts, const cli_flag *f, const char *value);
bool cli_grid_name(void *opts, const cli_flag *f, const char *value);
bool cli_grid_max_memory(void *opts, const cli_flag *f, const char *value);
#define CLI_LOAD_FLAG(name, arg, help, field, fn) {name, NULL, arg, help, "grid." field, CLI_FLAG_CALL, 0, 0, 0, fn}
#define CLI_LOAD_FLAGS                                                                                             \
    CLI_LOAD_FLAG("--format", "raw|df3|vol|nvdb|vdb", "override detection by extension and magic", "format",      \
                  cli_grid_format),                                                                                \
    CLI_LOAD_FLAG("--dims", "NXxNYxNZ", "raw dimensions when there is no FILE.hdr sidecar", "dims", cli_grid_dims), \
    CLI_LOAD_FLAG("--bounds", "X0,Y0,Z0,X1,Y1,Z1", "place the voxels on this world box", "bounds",                \
                  cli_grid_bounds),                                                                                \
    CLI_LOAD_FLAG("--transform", "M00,...,M23", "then apply this affine map (row-major 3x4)", "transform",        \
                  cli_grid_transform),                                                                             \
    CLI_LOAD_FLAG("--filter", "nearest|trilinear", "lookup between samples (default trilinear)", "filter",        \
                  cli_grid_filter),                                                                                \
    CLI_LOAD_FLAG("--scale", "S", "multiply densities by S (default 1)", "scale", cli_grid_scale),                \
    CLI_LOAD_FLAG("--max-memory", "BYTES", "refuse grids larger than this (K/M/G suffixes; default 4G)",          \
                  "max_memory_mb", cli_grid_max_memory),                                                           \
    CLI_LOAD_FLAG("--grid", "NAME", ".vdb/.nvdb: the grid to read (default: \"density\", else the only float grid)", \
                  "grid", cli_grid_name)

#endif
