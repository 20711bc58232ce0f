// grid_vdb_write_vec3.cpp - the sparse writer's vec3s grids (grid_vdb_write.cpp has the
// writer and its float grids): a tree's accessor templates for one value type take longer to
// compile than the rest of the writer, so each value type has its file.
#include "io/grid_vdb_module.hpp"

#include <memory>

namespace brume_vdb {

namespace {

// A vec3s grid of the sparse writer, with its accessor.
struct vec3_grid : writer_grid {
    openvdb::Vec3SGrid::Ptr g = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    openvdb::Vec3SGrid::Accessor acc = g->getAccessor();
    vec3_grid() { grid = g; }
    void set(int i, int j, int k, const float *v) override
    {
        acc.setValueOn(openvdb::Coord(i, j, k), openvdb::Vec3s(v[0], v[1], v[2]));
    }
};

} // namespace

std::unique_ptr<writer_grid> writer_grid_vec3() { return std::unique_ptr<writer_grid>(new vec3_grid); }

} // namespace brume_vdb
