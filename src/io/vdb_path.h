/* vdb_path.h - where the OpenVDB module (libbrume-openvdb.so, io/grid_vdb_load.c) and the
 * program that reads a .vdb in a process of its own (brume-openvdb-reader,
 * io/grid_sandbox.c) are found: the two are built and installed side by side.
 *
 * The places, in order:
 *   0. the directory the environment variable BRUME_MODULE_PATH names, when set: for a
 *      program linking the static libbrume.a from somewhere the others do not reach;
 *   1. the build tree, when the object holding this code (the program, or libbrume.so) is
 *      inside it: the tests, benches and tools of a build use that build's files;
 *   2. the directory of that object: libbrume.so's, for programs linking the shared library
 *      and the Python package;
 *   3. that directory's BIN_TO_LIB: an installed brume tool finds the library directory
 *      beside its own, also after `cmake --install --prefix` to another place;
 *   4. the library directory the build was configured to install into. */
#ifndef BRUME_IO_VDB_PATH_H
#define BRUME_IO_VDB_PATH_H

#include <stdbool.h>
#include <stddef.h>

#include "brume.h"

#define VDB_PATH_READER_FILE "brume-openvdb-reader"

/* The path of `file` in the first place that holds it, into path[n]; false when none does,
 * the places looked in then listed, comma-separated, in looked[nl]. */
bool vdb_path_find(const char *file, char *path, size_t n, char *looked, size_t nl);

/* The path of brume-openvdb-reader into path[n], or a one-line refusal naming the places
 * looked in. */
brume_status vdb_path_reader(char *path, size_t n);

#endif
