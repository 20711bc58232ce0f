/* grid_io.h - density grids from and to files: raw float32, POV-Ray df3, Mitsuba .vol,
 * NanoVDB .nvdb (read in C through PNanoVDB) and OpenVDB .vdb (through libopenvdb, when
 * the build found it). Formats, placements and limits are described in docs/grids.md.
 *
 * Every reader rejects, with a one-line message "FILE: reason" (err_message()) and never a
 * crash: truncated files, wrong magic numbers, dimensions whose product overflows or whose
 * voxels exceed max_memory, and NaN, infinite or negative densities (naming the voxel). */
#ifndef BRUME_IO_GRID_IO_H
#define BRUME_IO_GRID_IO_H

#include <stddef.h>

#include "brume.h"
#include "density/density.h"
#include "io/grid_options.h"
#include "io/grid_vdb.h"


/* Defaults: AUTO format, file placement, trilinear, scale 1, 4 GiB. */
void density_load_options_default(density_load_options *o);

/* Loads a grid. opts may be NULL (defaults). The caller owns the result; on failure NULL
 * and err_message() reads "PATH: reason". */
density *density_load_file(const char *path, const density_load_options *opts);
/* The same from bytes already in memory (fuzz targets, tests); `name` names them in
 * messages and, with format AUTO, gives the extension. A raw sidecar is not looked for. */
density *density_load_memory(const void *bytes, size_t size, const char *name, const density_load_options *opts);

/* `count` fields from one grid: 1 = a float grid (as density_load_file); 3 = the components
 * of a vec3 grid (a float grid gives the same field three times), sharing one NanoVDB
 * buffer: .vdb and .nvdb only. out[0..count-1] receive them (the caller releases each);
 * false with err_message() "PATH: reason" on failure. */
bool density_load_file_fields(const char *path, const density_load_options *opts, int count, density **out);

/* Every grid of a .vdb or .nvdb file, as `brume info` lists it: *out malloc'd (free()), *count
 * entries. Returns BRUME_OK or sets "PATH: reason". */
brume_status grid_list_file(const char *path, size_t max_memory, gridvdb_info **out, int *count);

/* Writes d to path (format AUTO = by extension), atomically: a temporary file in the same
 * folder renamed over path when complete. raw also writes the sidecar PATH.hdr (dims and
 * placement); df3 stores values in [0, 1] with the fewest bytes per sample that represent
 * every value exactly (else 4-byte samples, rounded) and loses the placement; .vol keeps
 * the world AABB; .nvdb and .vdb need the OpenVDB build. Returns BRUME_OK or sets
 * "PATH: reason". Only voxel values are written (not the filter). */
brume_status density_write_file(const density *d, const char *path, grid_format format);

/* Converts a .vdb file straight to .nvdb (OpenVDB -> NanoVDB, keeping the trees and the
 * names): every grid NanoVDB can hold, or only `grid` when not NULL/"". */
brume_status grid_convert_vdb_to_nvdb(const char *in, const char *out, const char *grid);

const char *grid_format_name(grid_format f);     /* "raw", "df3", ... ; "auto" */
grid_format grid_format_from_name(const char *s); /* AUTO when unknown */
/* The format of path by extension, else by its first bytes (head, n may be 0). */
grid_format grid_format_detect(const char *path, const unsigned char *head, size_t n);
/* Whether this build reads and writes .vdb and writes .nvdb. */
bool grid_have_openvdb(void);

/* Call before fork() in a process that then does more than exec: stops the idle threads
 * OpenVDB's logging library starts at load (gridvdb_before_fork, io/grid_vdb.h), so that no
 * other thread can hold a lock the child needs. Nothing without OpenVDB. */
void grid_before_fork(void);

#endif
