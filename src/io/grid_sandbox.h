/* grid_sandbox.h - OpenVDB reading in a child process under resource limits.
 *
 * libopenvdb is not hardened against hostile files: a single flipped bit can make it loop
 * for minutes, leak, or allocate gigabytes. brume therefore never lets it run in its own
 * process: each call here starts a child program (brume-openvdb-reader, installed beside the
 * OpenVDB module; spawned, not forked: grid_sandbox.c says why) that sets RLIMIT_CPU, RLIMIT_AS (not under
 * AddressSanitizer, whose shadow memory needs terabytes of address space) and RLIMIT_CORE,
 * runs grid_vdb.cpp, and hands the result (a NanoVDB buffer, a grid list, or an error
 * message) back through a pipe. The parent reads at most `max_memory` bytes, waits at most
 * the wall-clock limit, then kills the child: a crash, a timeout or an exhausted limit is a
 * one-line error naming the file. Limits (docs/grids.md):
 *   CPU time:       5 s + 2 s per MiB of input; wall clock twice that plus 5 s
 *   address space:  1 GiB (libraries) + the smaller of 2 x max_memory and 128 x the
 *                   input's size (OpenVDB's tree and the NanoVDB copy: a leaf of about
 *                   2 KiB takes at least its 64-byte mask in the file) */
#ifndef BRUME_IO_GRID_SANDBOX_H
#define BRUME_IO_GRID_SANDBOX_H

#include <stddef.h>

#include "brume.h"
#include "io/grid_vdb.h"

/* The NanoVDB buffer of one grid of a .vdb (path, or bytes when path is NULL): *buf is
 * 32-byte aligned, malloc'd (free()), *size bytes, at most max_memory. grid and vec3 as
 * gridvdb_to_nano. */
brume_status grid_sandbox_to_nano(const char *path, const void *bytes, size_t size, const char *name,
                                  const char *grid, int vec3, size_t max_memory, void **buf, size_t *nbytes);

/* Every grid of a .vdb, as gridvdb_list (*out malloc'd). */
brume_status grid_sandbox_list(const char *path, const void *bytes, size_t size, const char *name,
                               size_t max_memory, gridvdb_info **out, int *count);

/* .vdb to .nvdb (gridvdb_vdb_to_nvdb) in the child. */
brume_status grid_sandbox_vdb_to_nvdb(const char *in, const char *out, const char *grid, size_t max_memory);

/* The child's side: main() of brume-openvdb-reader (cli/openvdb_reader.c), the program the
 * calls above start with posix_spawn; the job comes in argv, the answer goes out on fd 3. */
int grid_sandbox_child_main(int argc, char **argv);

#endif
