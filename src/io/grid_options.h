/* grid_options.h - how to read a grid file (density_load_options), shared by the reader
 * that chooses the format (io/grid_io.h) and the formats themselves (io/grid_formats.h). */
#ifndef BRUME_IO_GRID_OPTIONS_H
#define BRUME_IO_GRID_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>

#include "density/density.h"

typedef enum grid_format {
    GRID_FORMAT_AUTO = 0, /* by extension, else by magic number */
    GRID_FORMAT_RAW,      /* float32 little-endian, x fastest, no header; dims from a sidecar or options */
    GRID_FORMAT_DF3,      /* POV-Ray density file: 3 big-endian uint16 dims, then 1, 2 or 4-byte samples */
    GRID_FORMAT_VOL,      /* Mitsuba 0.6 grid volume: "VOL" 3, encoding, dims, channels, bbox, data */
    GRID_FORMAT_NVDB,     /* NanoVDB file (uncompressed), a grid chosen by name (below), kept sparse */
    GRID_FORMAT_VDB       /* OpenVDB file, a grid chosen by name, read into NanoVDB (kept sparse)
                             in a child process under resource limits (io/grid_sandbox.h) */
} grid_format;

/* Default limit on the memory a loaded grid may take: 4 GiB. */
#define DENSITY_DEFAULT_MAX_MEMORY ((size_t)4 << 30)

/* How to read a grid. Units: bounds and transform in world units; densities unitless. */
typedef struct density_load_options {
    grid_format format; /* AUTO: by extension (.raw .df3 .vol .nvdb .vdb), else by magic */
    int raw_dims[3];    /* raw only: nx, ny, nz when there is no sidecar "FILE.hdr"; all 0 =
                           from the sidecar, else a cube if the size is 4 n^3 bytes */
    bool has_bounds;    /* place the grid's voxel box on `bounds` (axis-aligned), replacing the
                           file's own placement: VDB/NanoVDB transform, df3 unit cube [0, 1]^3
                           (as POV-Ray), .vol its bbox, raw its sidecar or else the cube
                           [-0.5, 0.5]^3 scaled to the dims' aspect with cubic voxels */
    box3 bounds;
    bool has_transform; /* then world = transform(placement(voxel)), any invertible affine map */
    affine3 transform;
    grid_filter filter; /* GRID_NEAREST (Blasi: constant per voxel) or GRID_TRILINEAR */
    double scale;       /* multiplies every density, > 0 (0 is taken as 1) */
    size_t max_memory;  /* bytes the voxels may take; 0 = DENSITY_DEFAULT_MAX_MEMORY */
    bool any_sign;      /* .vdb/.nvdb: values may be negative (velocity components, medium.h);
                           only finiteness is checked */
    char grid[128];     /* .vdb/.nvdb: the grid's name; "" = the grid named "density", else the
                           only float grid (several float grids and none named density is an
                           error that lists them) */
    bool edge_zero;     /* .vdb/.nvdb, trilinear: pbrt-v4's NanoVDB lookup, zero beyond the
                           voxels, cut to the index box [min, max + 1] (density_new_nanovdb_fields) */
} density_load_options;

#endif
