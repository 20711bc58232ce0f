// grid_vdb_module.hpp - what the C++ files of the OpenVDB module share: the host's error
// function, a file's grids in memory, the grid chosen by name, the conversion to NanoVDB and
// the writers' entry points. The module is five files so that no one of them instantiates
// all of OpenVDB's and NanoVDB's templates: grid_vdb.cpp reads and lists, grid_vdb_nano.cpp
// and grid_vdb_nano_vec3.cpp convert to NanoVDB, grid_vdb_write.cpp and grid_vdb_write_vec3.cpp
// write (docs/grids.md, "The OpenVDB module").
#ifndef BRUME_IO_GRID_VDB_MODULE_HPP
#define BRUME_IO_GRID_VDB_MODULE_HPP

#include "io/grid_vdb.h"

#include <memory>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <nanovdb/util/GridHandle.h>
#include <nanovdb/util/HostBuffer.h>

namespace brume_vdb {

using nano_handle = nanovdb::GridHandle<nanovdb::HostBuffer>;

extern gridvdb_err_fn host_err; // the host's err_vset, from brume_openvdb_module

// Reports through the host's error function; returns status.
#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
brume_status err_set(brume_status status, const char *fmt, ...);

// openvdb::initialize(), once.
void init_once();

// Grids of a file, trees loaded.
struct source {
    openvdb::GridPtrVecPtr grids;
};

// Reads a whole .vdb (from path, or from bytes when path is NULL) into s; throws with the
// message to report.
void open_source(source &s, const char *path, const void *bytes, size_t size);

// "\"name\" (type), ..." for messages, or "none".
std::string names_of(const openvdb::GridPtrVecPtr &grids);

bool is_float(const openvdb::GridBase::Ptr &g);
bool is_vec3(const openvdb::GridBase::Ptr &g);

// The grid chosen by name, or by the default rule; throws with the message to report.
openvdb::GridBase::Ptr pick(const openvdb::GridPtrVecPtr &grids, const char *grid, int vec3);

// The grid as NanoVDB: float and vec3s grids only; a null handle otherwise (grid_vdb_nano.cpp).
nano_handle to_nano(const openvdb::GridBase::Ptr &g);

// A vec3s grid as NanoVDB (grid_vdb_nano_vec3.cpp).
nano_handle to_nano_vec3(const openvdb::Vec3SGrid &g);

// One grid of the sparse writer with its accessor: float grids in grid_vdb_write.cpp, vec3s
// grids in grid_vdb_write_vec3.cpp. set() may throw std::bad_alloc.
struct writer_grid {
    openvdb::GridBase::Ptr grid;
    virtual ~writer_grid() = default;
    virtual void set(int i, int j, int k, const float *v) = 0;
};
std::unique_ptr<writer_grid> writer_grid_vec3();

// Writes the handles to one .nvdb file; throws on failure (grid_vdb_nano.cpp).
void write_nano(const char *path, std::vector<nano_handle> &handles);

// The writers of the module's table (grid_vdb_write.cpp): see grid_vdb.h.
brume_status mod_write_dense(const char *path, int nanovdb, const int n[3], const float *data, const double v2w[12]);
gridvdb_writer *mod_writer_new(void);
int mod_writer_add(gridvdb_writer *w, const char *grid_name, int vec3, double voxel_size, const double origin[3]);
void mod_writer_set(gridvdb_writer *w, int g, int i, int j, int k, const float *v);
unsigned long long mod_writer_active(const gridvdb_writer *w, int g);
brume_status mod_writer_save(gridvdb_writer *w, const char *path, int nanovdb);
void mod_writer_free(gridvdb_writer *w);

} // namespace brume_vdb

#endif
