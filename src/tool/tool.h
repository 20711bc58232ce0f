/* tool.h - what the brume tool (cli/) still uses from the library beyond include/brume.h.
 *
 * The one internal header cli/ includes (docs/architecture.md, checked by
 * tests/arch_includes.py), and a remainder: the services a library user would also want
 * moved to brume.h. What stays, and why: the message formatter (cli/ formats its messages
 * exactly as the library does), the removal of every temporary file of the process (the
 * CLI's fatal-signal handler; no public call acts on the whole process), and the grid files of
 * `brume info`, `convert` and `gen`, not yet public (docs/architecture.md). Not a stable
 * interface. Implemented in src/tool/ (the top layer: it may call any other). */
#ifndef BRUME_TOOL_TOOL_H
#define BRUME_TOOL_TOOL_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "brume.h"

/* ---- Messages (tool.c) ---------------------------------------------------------------- */

/* printf-style formatting into out[n] as the library formats its messages: control
 * characters in string arguments escaped, a plain %s cut after 200 bytes, a "%.1000s" cut
 * at its precision (core/error.h's err_vformat). One line. */
void tool_vformat(char *out, size_t n, const char *fmt, va_list ap);
/* The message of the calling thread's last failure in a call declared here ("" when none;
 * brume_* calls report to their context instead). */
const char *tool_last_error(void);

/* ---- Temporary files (tool.c over io/atomic.h) ------------------------------------------ */

/* Removes the temporary file of every write in progress in this process, the library's
 * (any context's) and the tool's own: for brume's fatal-signal handler, which then calls
 * _exit. Async-signal-safe. */
void tool_remove_temporaries(void);

/* ---- Grid files: `brume info`, `convert`, `gen` (grids.c, gen_sparse.c) ---------------- */

/* The options of reading a grid file are brume.h's brume_grid_file_options, taken as given
 * (the command line checked them): format from tool_grid_format_parse, max_memory_mb any
 * size > 0 (the command line's --max-memory counts bytes). */
typedef struct density density; /* a density field (density/density.h), opaque to the tool */
/* Whether name is a grid format: "raw", "df3", "vol", "nvdb", "vdb". */
bool tool_grid_format_known(const char *name);
/* The format a name says; BRUME_GRID_FORMAT_AUTO for NULL, "" or a name not known. */
brume_grid_format tool_grid_format_parse(const char *name);
/* The name of path's format: `format` when not AUTO, else by extension, else (when head has
 * n > 0 bytes) by its magic number; NULL when none of them says. */
const char *tool_grid_format_of(const char *path, brume_grid_format format, const unsigned char *head, size_t n);
/* Whether this build reads and writes .vdb and writes .nvdb (OpenVDB). */
bool tool_grid_have_openvdb(void);
/* A grid file; NULL on failure (tool_last_error: "PATH: reason"). */
density *tool_grid_load(const char *path, const brume_grid_file_options *o);
void tool_grid_release(density *d); /* accepts NULL */
/* Writes d to path in format (NULL or "": by extension), atomically; errors name path. */
brume_status tool_grid_write(const density *d, const char *path, const char *format);
/* A .vdb straight to .nvdb, keeping the sparse trees: every grid, or only `grid` ("": all). */
brume_status tool_grid_convert_vdb_to_nvdb(const char *in, const char *out, const char *grid);
/* `brume info`: the grids of a .vdb/.nvdb file, one line each, on out; *count of them. */
brume_status tool_grid_print_list(FILE *out, const char *path, const brume_grid_file_options *o, int *count);
/* `brume info`: d's format (as named), dimensions, bounds, placement, values, memory, active
 * voxels and majorants, one line each, on out. */
void tool_grid_print_info(FILE *out, const char *path, const char *format, const density *d);
/* The world box (xmin, ymin, zmin, xmax, ymax, zmax) and the largest value over the files
 * first..last of a frame pattern, each loaded in turn (one in memory at a time). */
brume_status tool_grid_sequence_extent(const char *pattern, long first, long last, const brume_grid_file_options *o,
                                       double bounds[6], double *rho_max);
/* `brume gen cloud`: the fractal cloud (brume.h's brume_fractal, its bounds and filter
 * used as given); NULL on failure (tool_last_error). */
density *tool_gen_cloud(const brume_fractal *f);

/* `brume gen fire` and `gen upres` (gen_sparse.c): sparse grids written through OpenVDB to
 * out (.vdb or .nvdb, atomically). What was written: */
typedef struct tool_gen_result {
    unsigned long long active; /* active voxels of the density grid */
    long box[3];               /* index box, voxels per axis */
    double voxel;              /* voxel size, world units */
} tool_gen_result;
/* A procedural flame: grids "density" and "temperature" (kelvin), n voxels up its height
 * (world units), n/2 across; with velocity > 0 also a vec3 grid "vel", its updraft
 * (velocity (0.5 + h) up at height fraction h, world units per second). At time t (seconds)
 * its turbulence has risen by t times the updraft's speed at mid-height (velocity, or 1 world
 * unit per second without one): frames at f / fps flicker and rise. */
brume_status tool_gen_fire(const char *out, int n, uint64_t seed, double height, double velocity, double time,
                           tool_gen_result *res);
/* How far tool_gen_fire's turbulence has risen at time t, in flame heights; it refuses
 * |rise| > 1e6 (the noise's lattice index is an int). */
double tool_gen_fire_rise(double height, double velocity, double time);
/* in's density grid upsampled factor times per axis (trilinear) with fractal detail of
 * amplitude detail in [0, 1], kept sparse. */
brume_status tool_gen_upres(const char *in, const brume_grid_file_options *o, int factor, uint64_t seed, double detail,
                            const char *out, tool_gen_result *res);

#endif
