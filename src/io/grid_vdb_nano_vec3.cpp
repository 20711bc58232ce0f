// grid_vdb_nano_vec3.cpp - vec3s OpenVDB grids to NanoVDB (Vec3f): the converter's templates
// for that value type alone (grid_vdb_nano.cpp has the float grids and says why).
#include "io/grid_vdb_module.hpp"

#include <nanovdb/util/OpenToNanoVDB.h>

namespace brume_vdb {

nano_handle to_nano_vec3(const openvdb::Vec3SGrid &g) { return nanovdb::openToNanoVDB(g); }

} // namespace brume_vdb
