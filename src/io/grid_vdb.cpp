// grid_vdb.cpp - OpenVDB reading/writing and NanoVDB writing behind a C interface
// (grid_vdb.h). The only C++ in brume: libopenvdb and NanoVDB's builders are C++ APIs.
// Every exception stops at this file's boundary and becomes a one-line err_set message.
#include "io/grid_vdb.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include <openvdb/openvdb.h>
#include <openvdb/io/Stream.h>
#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>

extern "C" {
#include "core/error.h"
}

namespace {

void init_once()
{
    static bool done = false;
    if (!done) {
        openvdb::initialize();
        done = true;
    }
}

// The float grid named "density", else the first float grid; null if none.
openvdb::FloatGrid::Ptr pick_float_grid(const openvdb::GridPtrVecPtr &grids)
{
    openvdb::FloatGrid::Ptr first;
    for (const auto &g : *grids) {
        auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g);
        if (!f)
            continue;
        if (f->getName() == "density")
            return f;
        if (!first)
            first = f;
    }
    return first;
}

// OpenVDB's affine matrices act on row vectors (p' = p M); ours on columns.
void to_affine(const openvdb::math::Mat4d &m, const openvdb::Coord &lo, double out[12])
{
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++)
            out[4 * r + c] = m(c, r);
        // voxel space u = index - lo + 1/2: translate by (lo - 1/2) first
        out[4 * r + 3] = m(3, r) + m(0, r) * (lo.x() - 0.5) + m(1, r) * (lo.y() - 0.5) + m(2, r) * (lo.z() - 0.5);
    }
}

} // namespace

extern "C" brume_status gridvdb_read(const void *bytes, size_t size, const char *name, size_t max_memory,
                                     gridvdb_dense *out)
{
    std::memset(out, 0, sizeof *out);
    try {
        init_once();
        // magic: int64 0x56444220 little-endian
        if (size < 8 || std::memcmp(bytes, " BDV\0\0\0\0", 8) != 0)
            return err_set(BRUME_ERROR_PARSE, "%s: not an OpenVDB file (wrong magic number)", name);
        std::istringstream is(std::string(static_cast<const char *>(bytes), size), std::ios::in | std::ios::binary);
        openvdb::io::Stream stream(is, /*delayLoad=*/false);
        openvdb::GridPtrVecPtr grids = stream.getGrids();
        // OpenVDB does not always notice a short read; the stream does
        if (!is || !grids)
            return err_set(BRUME_ERROR_PARSE, "%s: truncated OpenVDB file", name);
        openvdb::FloatGrid::Ptr g = pick_float_grid(grids);
        if (!g)
            return err_set(BRUME_ERROR_UNSUPPORTED, "%s: no float grid in the file", name);
        const openvdb::math::Transform &xf = g->transform();
        if (!xf.isLinear())
            return err_set(BRUME_ERROR_UNSUPPORTED, "%s: grid \"%s\" has a non-linear (frustum) transform", name,
                           g->getName().c_str());
        openvdb::CoordBBox bb = g->evalActiveVoxelBoundingBox();
        if (bb.empty())
            return err_set(BRUME_ERROR_PARSE, "%s: grid \"%s\" has no active voxels", name, g->getName().c_str());
        openvdb::Coord dim = bb.dim();
        double count = (double)dim.x() * dim.y() * dim.z();
        if (count * sizeof(float) > (double)max_memory)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %d x %d x %d voxels exceed the memory limit of %zu bytes",
                           name, dim.x(), dim.y(), dim.z(), max_memory);
        float *data = static_cast<float *>(std::malloc((size_t)count * sizeof(float)));
        if (!data)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for %.0f voxels", name, count);
        auto acc = g->getConstAccessor();
        size_t o = 0;
        for (int k = bb.min().z(); k <= bb.max().z(); k++)
            for (int j = bb.min().y(); j <= bb.max().y(); j++)
                for (int i = bb.min().x(); i <= bb.max().x(); i++)
                    data[o++] = acc.getValue(openvdb::Coord(i, j, k));
        out->n[0] = dim.x();
        out->n[1] = dim.y();
        out->n[2] = dim.z();
        out->data = data;
        out->active = (unsigned long long)g->activeVoxelCount();
        to_affine(xf.baseMap()->getAffineMap()->getMat4(), bb.min(), out->voxel_to_world);
        return BRUME_OK;
    } catch (const std::exception &e) {
        return err_set(BRUME_ERROR_PARSE, "%s: OpenVDB: %s", name, e.what());
    } catch (...) {
        return err_set(BRUME_ERROR_PARSE, "%s: OpenVDB: unknown error", name);
    }
}

extern "C" brume_status gridvdb_write_dense(const char *path, int nanovdb, const int n[3], const float *data,
                                            const double v2w[12])
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
        if (!nanovdb) {
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
            openvdb::io::File f(path);
            f.write({g});
            f.close();
            return BRUME_OK;
        }
        nanovdb::GridBuilder<float> builder(0.0f, nanovdb::GridClass::FogVolume);
        auto acc = builder.getAccessor();
        size_t o = 0;
        for (int k = 0; k < n[2]; k++)
            for (int j = 0; j < n[1]; j++)
                for (int i = 0; i < n[0]; i++, o++)
                    if (keep(i, j, k, data[o]))
                        acc.setValue(nanovdb::Coord(i, j, k), data[o]);
        double mat[3][3], inv[3][3];
        openvdb::math::Mat3d m3 = m.getMat3(), i3 = m3.inverse();
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                mat[r][c] = m3(r, c); // row-vector convention, as Map::set expects
                inv[r][c] = i3(r, c);
            }
        nanovdb::Map map;
        map.set(mat, inv, nanovdb::Vec3d(m(3, 0), m(3, 1), m(3, 2)), 1.0);
        auto handle = builder.getHandle<>(map, "density");
        nanovdb::io::writeGrid(std::string(path), handle);
        return BRUME_OK;
    } catch (const std::exception &e) {
        return err_set(BRUME_ERROR_IO, "%s: %s", path, e.what());
    }
}

extern "C" brume_status gridvdb_vdb_to_nvdb(const char *in, const char *out)
{
    try {
        init_once();
        openvdb::io::File f(in);
        f.open(false);
        openvdb::FloatGrid::Ptr g = pick_float_grid(f.getGrids());
        f.close();
        if (!g)
            return err_set(BRUME_ERROR_UNSUPPORTED, "%s: no float grid in the file", in);
        auto handle = nanovdb::openToNanoVDB(*g);
        nanovdb::io::writeGrid(std::string(out), handle);
        return BRUME_OK;
    } catch (const std::exception &e) {
        return err_set(BRUME_ERROR_PARSE, "%s: %s", in, e.what());
    }
}
