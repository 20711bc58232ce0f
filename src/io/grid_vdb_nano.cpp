// grid_vdb_nano.cpp - OpenVDB grids to NanoVDB (float and vec3s: what brume reads; the
// converter's other value types would instantiate a dozen more templates for nothing), and
// NanoVDB grids to a .nvdb file. Float grids here, vec3s grids in grid_vdb_nano_vec3.cpp: the
// converter's templates for each value type take as long to compile as the rest of the
// module, so each has a file of its own.
#include "io/grid_vdb_module.hpp"

#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>

namespace brume_vdb {

nano_handle to_nano(const openvdb::GridBase::Ptr &g)
{
    if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g))
        return nanovdb::openToNanoVDB(*f);
    if (auto v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(g))
        return to_nano_vec3(*v);
    return nano_handle();
}

void write_nano(const char *path, std::vector<nano_handle> &handles)
{
    nanovdb::io::writeGrids<nanovdb::HostBuffer, std::vector>(std::string(path), handles);
}

} // namespace brume_vdb
