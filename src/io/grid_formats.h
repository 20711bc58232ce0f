/* grid_formats.h - the grid file formats' readers and writers and what they share, for
 * src/io/grid_*.c only: grid_io.c dispatches to them by format (grid_io.h is the interface).
 * Each reader takes the file's bytes and its name for messages ("NAME: reason", err_set),
 * never crashes on a malformed file and never allocates more than max_memory for voxels. */
#ifndef BRUME_IO_GRID_FORMATS_H
#define BRUME_IO_GRID_FORMATS_H

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "io/atomic.h"
#include "io/grid_options.h"
#include "io/grid_vdb.h"

/* ---- little-endian numbers ---- */
static inline uint32_t rd_le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static inline uint64_t rd_le64(const unsigned char *p) { return (uint64_t)rd_le32(p) | (uint64_t)rd_le32(p + 4) << 32; }
static inline float rd_lef(const unsigned char *p)
{
    uint32_t u = rd_le32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}
static inline void wr_le32(unsigned char *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(v >> (8 * i));
}

/* A dense grid being read: voxels and placement. */
typedef struct dense_read {
    int n[3];
    float *data;
    affine3 v2w;
} dense_read;

/* ---- shared by the formats (grid_io.c) ---- */

/* n0 n1 n2 voxels of `bytes_per` bytes each: the total, or 0 when it overflows size_t or
 * exceeds max_memory as floats (err_set). */
size_t grid_voxel_count(const char *name, const int64_t n[3], size_t max_memory);
/* Voxel box [0, n) onto the axis-aligned box b. */
affine3 grid_box_map(box3 b, const int n[3]);
/* out->data for count voxels (malloc'd) and out->n from n; false with err_set. */
bool grid_dense_alloc(dense_read *out, const int64_t n[3], size_t count, const char *name);
/* A write through io/atomic.h: a temporary file beside the destination (NULL with err_set),
 * renamed over it by grid_commit_tmp when ok, else removed (err_set naming the path). */
FILE *grid_open_tmp(atomic_file *af, const char *path);
brume_status grid_commit_tmp(atomic_file *af, bool ok);
/* d's voxels as float32 little-endian, x fastest; false when a write fails. */
bool grid_write_floats(FILE *f, const density *d, const int n[3]);

/* ---- the formats: read into a dense_read (out->data malloc'd) or write d (info in) ---- */

/* grid_raw.c: float32 little-endian, x fastest, and the sidecar PATH.hdr */
int grid_raw_sidecar(const char *path, int n[3], bool *has_v2w, affine3 *v2w);
bool grid_raw_read(const unsigned char *b, size_t size, const char *name, const int dims[3], bool has_v2w,
                   const affine3 *v2w, size_t max_memory, dense_read *out);
brume_status grid_raw_write(const density *d, const density_info *in, const char *path);
/* grid_df3.c: POV-Ray density files */
bool grid_df3_read(const unsigned char *b, size_t size, const char *name, size_t max_memory, dense_read *out);
brume_status grid_df3_write(const density *d, const density_info *in, const char *path);
/* grid_vol.c: Mitsuba 0.6 grid volumes */
bool grid_vol_read(const unsigned char *b, size_t size, const char *name, size_t max_memory, dense_read *out);
brume_status grid_vol_write(const density *d, const density_info *in, const char *path);
/* grid_nvdb.c: NanoVDB files, read in C; `count` fields (1, or 3 of a vec3 grid) into out */
bool grid_nvdb_read(const unsigned char *b, size_t size, const char *name, const density_load_options *o, int count,
                    density **out);
/* Every grid of the NanoVDB file held in b (n bytes), as grid_list_file lists them. */
brume_status grid_nvdb_list(const unsigned char *b, size_t n, const char *path, size_t max_memory, gridvdb_info **out,
                            int *count);
/* grid_openvdb.c: .vdb through OpenVDB in a child process (io/grid_sandbox.h) */
bool grid_vdb_read(const char *path, const unsigned char *b, size_t size, const char *name,
                   const density_load_options *o, int count, density **out);
#if BRUME_HAVE_OPENVDB
/* .vdb, or .nvdb when nano, through OpenVDB (the dense voxels of d) */
brume_status grid_openvdb_write(const density *d, const density_info *in, const char *path, int nano);
#endif

#endif
