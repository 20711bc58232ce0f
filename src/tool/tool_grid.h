/* tool_grid.h - what grids.c and gen_sparse.c share: the public grid file options as the
 * readers take them. */
#ifndef BRUME_TOOL_TOOL_GRID_H
#define BRUME_TOOL_TOOL_GRID_H

#include "brume.h"
#include "io/grid_io.h"

/* in's format, max_memory_mb and grid name as density_load_options (the rest default; in may
 * be NULL): BRUME_OK or err_set()s "FN: opts.FIELD: what is wrong". */
brume_status tool_grid_options(const char *fn, const brume_grid_file_options *in, density_load_options *out);

#endif
