// grid_vdb_write.cpp - the OpenVDB module's writers: a dense grid as one "density" grid, and
// the sparse multi-grid writer of `brume gen fire|upres` (grid_vdb.h). Both build OpenVDB
// grids, written as .vdb by OpenVDB or converted to .nvdb by grid_vdb_nano.cpp's converter:
// one way to a NanoVDB grid, which keeps NanoVDB's own builder's templates out of the build.
#include "io/grid_vdb_module.hpp"

#include <memory>
#include <vector>

// The sparse writer: its grids, and whether setting a voxel failed (out of memory: the
// failure is reported when the grids are saved, since setting a voxel returns nothing).
struct gridvdb_writer {
    std::vector<std::unique_ptr<brume_vdb::writer_grid>> grids;
    bool failed = false;
};

namespace brume_vdb {

brume_status mod_write_dense(const char *path, int nanovdb, const int n[3], const float *data, const double v2w[12])
{
    try {
        init_once();
        // index (i, j, k) has its centre at voxel-space (i + 1/2, ...): index -> world map
        openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                m(c, r) = v2w[4 * r + c];
            m(3, r) = v2w[4 * r + 3] + 0.5 * (v2w[4 * r] + v2w[4 * r + 1] + v2w[4 * r + 2]);
        }
        auto keep = [&](int i, int j, int k, float v) {
            return v != 0.0f || (i == 0 && j == 0 && k == 0) || (i == n[0] - 1 && j == n[1] - 1 && k == n[2] - 1);
        };
        openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
        g->setName("density");
        g->setGridClass(openvdb::GRID_FOG_VOLUME);
        g->setTransform(openvdb::math::Transform::createLinearTransform(m));
        auto acc = g->getAccessor();
        size_t o = 0;
        for (int k = 0; k < n[2]; k++)
            for (int j = 0; j < n[1]; j++)
                for (int i = 0; i < n[0]; i++, o++)
                    if (keep(i, j, k, data[o]))
                        acc.setValueOn(openvdb::Coord(i, j, k), data[o]);
        if (nanovdb) {
            std::vector<nano_handle> handles;
            handles.push_back(to_nano(g));
            write_nano(path, handles);
        } else {
            openvdb::io::File f(path);
            f.write({g});
            f.close();
        }
        return BRUME_OK;
    } catch (const std::exception &e) {
        return err_set(BRUME_ERROR_IO, "%s: %s", path, e.what());
    }
}


namespace {

// A float grid of the sparse writer, with its accessor.
struct float_grid : writer_grid {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    openvdb::FloatGrid::Accessor acc = g->getAccessor();
    float_grid() { grid = g; }
    void set(int i, int j, int k, const float *v) override { acc.setValueOn(openvdb::Coord(i, j, k), v[0]); }
};

} // namespace

gridvdb_writer *mod_writer_new(void)
{
    try {
        init_once();
        return new gridvdb_writer;
    } catch (...) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "grid writer: out of memory");
        return nullptr;
    }
}

int mod_writer_add(gridvdb_writer *w, const char *grid_name, int vec3, double voxel_size, const double origin[3])
{
    try {
        openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(voxel_size);
        xf->postTranslate(openvdb::Vec3d(origin[0], origin[1], origin[2]));
        std::unique_ptr<writer_grid> wg = vec3 ? writer_grid_vec3() : std::unique_ptr<writer_grid>(new float_grid);
        wg->grid->setName(grid_name);
        wg->grid->setGridClass(openvdb::GRID_FOG_VOLUME);
        wg->grid->setTransform(xf);
        w->grids.push_back(std::move(wg));
        return (int)w->grids.size() - 1;
    } catch (const std::exception &e) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "grid writer: %s", e.what());
        return -1;
    }
}

void mod_writer_set(gridvdb_writer *w, int g, int i, int j, int k, const float *v)
{
    if (w->failed)
        return;
    try {
        w->grids[(size_t)g]->set(i, j, k, v);
    } catch (...) {
        w->failed = true; // out of memory: reported by mod_writer_save
    }
}

unsigned long long mod_writer_active(const gridvdb_writer *w, int g)
{
    return (unsigned long long)w->grids[(size_t)g]->grid->activeVoxelCount();
}

brume_status mod_writer_save(gridvdb_writer *w, const char *path, int nanovdb)
{
    if (w->failed)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory while setting the grids' voxels", path);
    try {
        openvdb::GridPtrVec v;
        for (auto &wg : w->grids) {
            wg->grid->pruneGrid(0.0f); // constant 8^3 blocks become tiles
            v.push_back(wg->grid);
        }
        if (!nanovdb) {
            openvdb::io::File f(path);
            f.write(v);
            f.close();
            return BRUME_OK;
        }
        std::vector<nano_handle> handles;
        for (auto &g : v)
            handles.push_back(to_nano(g));
        write_nano(path, handles);
        return BRUME_OK;
    } catch (const std::bad_alloc &) {
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    } catch (const std::exception &e) {
        return err_set(BRUME_ERROR_IO, "%s: %s", path, e.what());
    }
}

void mod_writer_free(gridvdb_writer *w) { delete w; }

} // namespace brume_vdb
