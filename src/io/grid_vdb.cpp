// grid_vdb.cpp - OpenVDB reading (straight to NanoVDB), listing and writing behind a C
// interface (grid_vdb.h). The only C++ in brume: libopenvdb and NanoVDB's builders are C++
// APIs. Built as the module libbrume-openvdb.so, which exports one symbol, its table
// (brume_openvdb_module); grid_vdb_load.c opens it on first use. Every exception stops at
// this file's boundary and becomes a one-line message through the host's error function.
// grid_io.c runs the readers in a child process under resource limits (grid_sandbox.c).
#include "io/grid_vdb.h"

#include <cmath>
#include <dlfcn.h>
#include <link.h>
#include <unistd.h>
#include <mutex>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/io/Stream.h>
#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>

namespace {

gridvdb_err_fn host_err; // the host's err_vset, from brume_openvdb_module

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
brume_status err_set(brume_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    host_err(status, fmt, ap);
    va_end(ap);
    return status;
}

void init_once()
{
    static bool done = false;
    if (!done) {
        openvdb::initialize();
        done = true;
    }
}

// Grids of a file, trees loaded.
struct source {
    openvdb::GridPtrVecPtr grids;
};

// The whole file in memory, read through an istringstream that throws at a short read:
// OpenVDB trusts the counts it reads, and at the end of the bytes a failed stream would
// otherwise let it loop over billions of tiles (found by fuzzing); an exception ends it.
void open_source(source &s, const char *path, const void *bytes, size_t size, const char *name)
{
    std::string data;
    if (path) {
        std::ifstream f(path, std::ios::in | std::ios::binary);
        if (!f)
            throw std::runtime_error("cannot open the file");
        data.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    } else {
        data.assign(static_cast<const char *>(bytes), size);
    }
    if (data.size() < 8 || std::memcmp(data.data(), " BDV\0\0\0\0", 8) != 0)
        throw std::runtime_error("not an OpenVDB file (wrong magic number)");
    std::istringstream is(std::move(data), std::ios::in | std::ios::binary);
    is.exceptions(std::ios::failbit | std::ios::badbit | std::ios::eofbit);
    try {
        openvdb::io::Stream stream(is, /*delayLoad=*/false);
        s.grids = stream.getGrids();
    } catch (const std::ios_base::failure &) {
        throw std::runtime_error("truncated or malformed OpenVDB file (read past its end)");
    }
    if (!s.grids)
        throw std::runtime_error("truncated OpenVDB file");
    (void)name;
}

// The grid with its tree.
openvdb::GridBase::Ptr load_grid(source &, const openvdb::GridBase::Ptr &g) { return g; }

std::string names_of(const openvdb::GridPtrVecPtr &grids)
{
    std::string out;
    for (const auto &g : *grids) {
        if (!out.empty())
            out += ", ";
        out += "\"" + g->getName() + "\" (" + g->valueType() + ")";
    }
    return out.empty() ? "none" : out;
}

bool is_float(const openvdb::GridBase::Ptr &g) { return g->isType<openvdb::FloatGrid>(); }
bool is_vec3(const openvdb::GridBase::Ptr &g) { return g->isType<openvdb::Vec3SGrid>(); }

// The grid chosen by name, or by the default rule; throws with the message to report.
openvdb::GridBase::Ptr pick(const openvdb::GridPtrVecPtr &grids, const char *grid, int vec3)
{
    if (grid && grid[0]) {
        for (const auto &g : *grids)
            if (g->getName() == grid) {
                if (!is_float(g) && !(vec3 && is_vec3(g)))
                    throw std::runtime_error("grid \"" + std::string(grid) + "\" holds " + g->valueType() +
                                             " values; " + (vec3 ? "a float or vec3s" : "a float") +
                                             " grid is needed");
                return g;
            }
        throw std::runtime_error("no grid named \"" + std::string(grid) + "\"; grids: " + names_of(grids));
    }
    openvdb::GridBase::Ptr only;
    int nfloat = 0;
    for (const auto &g : *grids) {
        if (g->getName() == "density" && is_float(g))
            return g;
        if (is_float(g)) {
            only = g;
            nfloat++;
        }
    }
    if (nfloat == 1)
        return only;
    if (nfloat == 0)
        throw std::runtime_error("no float grid; grids: " + names_of(grids));
    throw std::runtime_error("several float grids and none named \"density\": pick one with \"grid\" (--grid); grids: " +
                             names_of(grids));
}

template <typename GridT> void check_transform(const GridT &g)
{
    if (!g.transform().isLinear())
        throw std::runtime_error("grid \"" + g.getName() + "\" has a non-linear (frustum) transform");
}

// The grid as NanoVDB: float and vec3s grids only (what brume reads; the converter's other
// value types would instantiate a dozen more templates for nothing). Null handle otherwise.
nanovdb::GridHandle<nanovdb::HostBuffer> to_nano(const openvdb::GridBase::Ptr &g)
{
    if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g))
        return nanovdb::openToNanoVDB(*f);
    if (auto v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(g))
        return nanovdb::openToNanoVDB(*v);
    return nanovdb::GridHandle<nanovdb::HostBuffer>();
}

unsigned long long nano_size(const openvdb::GridBase::Ptr &g) { return (unsigned long long)to_nano(g).size(); }

} // namespace

static brume_status mod_list(const char *path, const void *bytes, size_t size, const char *name,
                             gridvdb_info **out, int *count)
{
    *out = nullptr;
    *count = 0;
    try {
        init_once();
        source s;
        open_source(s, path, bytes, size, name);
        std::vector<gridvdb_info> infos;
        for (const auto &meta : *s.grids) {
            openvdb::GridBase::Ptr g = load_grid(s, meta);
            gridvdb_info in;
            std::memset(&in, 0, sizeof in);
            std::snprintf(in.name, sizeof in.name, "%s", g->getName().c_str());
            std::snprintf(in.type, sizeof in.type, "%s", g->valueType().c_str());
            std::snprintf(in.cls, sizeof in.cls, "%s",
                          openvdb::GridBase::gridClassToString(g->getGridClass()).c_str());
            openvdb::CoordBBox bb = g->evalActiveVoxelBoundingBox();
            for (int a = 0; a < 3; a++) {
                in.bbmin[a] = bb.min()[a];
                in.bbmax[a] = bb.max()[a];
            }
            in.active = (unsigned long long)g->activeVoxelCount();
            in.vmin = INFINITY;
            in.vmax = -INFINITY;
            if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g)) {
                for (auto it = f->cbeginValueOn(); it; ++it) {
                    in.vmin = std::fmin(in.vmin, (double)*it);
                    in.vmax = std::fmax(in.vmax, (double)*it);
                }
            } else if (auto v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(g)) {
                for (auto it = v->cbeginValueOn(); it; ++it)
                    for (int c = 0; c < 3; c++) {
                        in.vmin = std::fmin(in.vmin, (double)(*it)[c]);
                        in.vmax = std::fmax(in.vmax, (double)(*it)[c]);
                    }
            }
            if (!(in.vmin <= in.vmax))
                in.vmin = in.vmax = 0.0;
            in.nano_bytes = g->transform().isLinear() ? nano_size(g) : 0;
            infos.push_back(in);
        }
        *out = static_cast<gridvdb_info *>(std::malloc(infos.size() * sizeof(gridvdb_info) + 1));
        if (!*out)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        if (!infos.empty())
            std::memcpy(*out, infos.data(), infos.size() * sizeof(gridvdb_info));
        *count = (int)infos.size();
        return BRUME_OK;
    } catch (const std::bad_alloc &) {
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: OpenVDB: out of memory", name);
    } catch (const std::exception &e) {
        return err_set(BRUME_ERROR_PARSE, "%s: OpenVDB: %s", name, e.what());
    } catch (...) {
        return err_set(BRUME_ERROR_PARSE, "%s: OpenVDB: unknown error", name);
    }
}

static brume_status mod_to_nano(const char *path, const void *bytes, size_t size, const char *name,
                                const char *grid, int vec3, gridvdb_sink sink, void *user)
{
    try {
        init_once();
        source s;
        open_source(s, path, bytes, size, name);
        openvdb::GridBase::Ptr g;
        try {
            g = load_grid(s, pick(s.grids, grid, vec3));
        } catch (const std::runtime_error &e) {
            return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s", name, e.what());
        }
        if (!g->transform().isLinear())
            return err_set(BRUME_ERROR_UNSUPPORTED, "%s: grid \"%s\" has a non-linear (frustum) transform", name,
                           g->getName().c_str());
        if (g->activeVoxelCount() == 0)
            return err_set(BRUME_ERROR_PARSE, "%s: grid \"%s\" has no active voxels", name, g->getName().c_str());
        nanovdb::GridHandle<nanovdb::HostBuffer> h = to_nano(g);
        if (sink(user, h.data(), h.size()) != 0)
            return err_set(BRUME_ERROR_IO, "%s: could not hand the NanoVDB grid back", name);
        return BRUME_OK;
    } catch (const std::bad_alloc &) {
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: OpenVDB: out of memory", name);
    } catch (const std::exception &e) {
        return err_set(BRUME_ERROR_PARSE, "%s: OpenVDB: %s", name, e.what());
    } catch (...) {
        return err_set(BRUME_ERROR_PARSE, "%s: OpenVDB: unknown error", name);
    }
}

static brume_status mod_vdb_to_nvdb(const char *in, const char *out, const char *grid)
{
    try {
        init_once();
        source s;
        open_source(s, in, nullptr, 0, in);
        std::vector<nanovdb::GridHandle<nanovdb::HostBuffer>> handles;
        if (grid && grid[0]) {
            openvdb::GridBase::Ptr g;
            for (const auto &m : *s.grids)
                if (m->getName() == grid)
                    g = load_grid(s, m);
            if (!g)
                return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: no grid named \"%s\"; grids: %s", in, grid,
                               names_of(s.grids).c_str());
            if (!is_float(g) && !is_vec3(g))
                return err_set(BRUME_ERROR_UNSUPPORTED, "%s: grid \"%s\" holds %s values; brume converts float and vec3s grids",
                               in, grid, g->valueType().c_str());
            handles.push_back(to_nano(g));
        } else {
            for (const auto &m : *s.grids) {
                openvdb::GridBase::Ptr g = load_grid(s, m);
                if (g->transform().isLinear() && (is_float(g) || is_vec3(g)))
                    handles.push_back(to_nano(g));
            }
            if (handles.empty())
                return err_set(BRUME_ERROR_UNSUPPORTED, "%s: no float or vec3s grid to convert; grids: %s", in,
                               names_of(s.grids).c_str());
        }
        nanovdb::io::writeGrids<nanovdb::HostBuffer, std::vector>(std::string(out), handles);
        return BRUME_OK;
    } catch (const std::exception &e) {
        return err_set(BRUME_ERROR_PARSE, "%s: %s", in, e.what());
    } catch (...) {
        return err_set(BRUME_ERROR_PARSE, "%s: OpenVDB: unknown error", in);
    }
}

/* The process the libraries were loaded in: only there do log4cplus's pool threads exist. A
 * process forked from it has the pool's bookkeeping without its threads, and stopping that
 * pool would wait for them for ever; it has no other thread of log4cplus's either, so its
 * forks are safe as they are. */
static const pid_t load_pid = getpid();

static void mod_before_fork(void)
{
    if (getpid() != load_pid)
        return;
    static std::once_flag once;
    std::call_once(once, [] {
        /* log4cplus::shutdownThreadPool(), looked up among this object's dependencies (OpenVDB
         * brings log4cplus without its headers): the module is opened with RTLD_LOCAL, so
         * its libraries are not in the global scope; linked into a program, they are */
        Dl_info info;
        struct link_map *self = nullptr;
        if (!dladdr1(reinterpret_cast<void *>(&brume_openvdb_module), &info, reinterpret_cast<void **>(&self),
                     RTLD_DL_LINKMAP) ||
            !self)
            return;
        void *h = dlopen(self->l_name && self->l_name[0] ? self->l_name : nullptr, RTLD_LAZY | RTLD_NOLOAD);
        void *f = h ? dlsym(h, "_ZN9log4cplus18shutdownThreadPoolEv") : nullptr;
        if (f) {
            try {
                reinterpret_cast<void (*)()>(f)();
            } catch (...) {
            }
        }
        if (h)
            dlclose(h);
    });
}

static brume_status mod_write_dense(const char *path, int nanovdb, const int n[3], const float *data,
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

// ---- the sparse writer ---------------------------------------------------------------------

struct gridvdb_writer {
    std::vector<openvdb::GridBase::Ptr> grids;
    std::vector<std::unique_ptr<openvdb::FloatGrid::Accessor>> facc;
    std::vector<std::unique_ptr<openvdb::Vec3SGrid::Accessor>> vacc;
};

static gridvdb_writer *mod_writer_new(void)
{
    try {
        init_once();
        return new gridvdb_writer;
    } catch (...) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "grid writer: out of memory");
        return nullptr;
    }
}

static int mod_writer_add(gridvdb_writer *w, const char *grid_name, int vec3, double voxel_size,
                          const double origin[3])
{
    try {
        openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(voxel_size);
        xf->postTranslate(openvdb::Vec3d(origin[0], origin[1], origin[2]));
        openvdb::GridBase::Ptr g;
        if (vec3) {
            auto v = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
            w->vacc.emplace_back(new openvdb::Vec3SGrid::Accessor(v->getAccessor()));
            w->facc.emplace_back(nullptr);
            g = v;
        } else {
            auto f = openvdb::FloatGrid::create(0.0f);
            w->facc.emplace_back(new openvdb::FloatGrid::Accessor(f->getAccessor()));
            w->vacc.emplace_back(nullptr);
            g = f;
        }
        g->setName(grid_name);
        g->setGridClass(openvdb::GRID_FOG_VOLUME);
        g->setTransform(xf);
        w->grids.push_back(g);
        return (int)w->grids.size() - 1;
    } catch (const std::exception &e) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "grid writer: %s", e.what());
        return -1;
    }
}

static void mod_writer_set(gridvdb_writer *w, int g, int i, int j, int k, const float *v)
{
    if (w->facc[(size_t)g])
        w->facc[(size_t)g]->setValueOn(openvdb::Coord(i, j, k), v[0]);
    else
        w->vacc[(size_t)g]->setValueOn(openvdb::Coord(i, j, k), openvdb::Vec3s(v[0], v[1], v[2]));
}

static unsigned long long mod_writer_active(const gridvdb_writer *w, int g)
{
    return (unsigned long long)w->grids[(size_t)g]->activeVoxelCount();
}

static brume_status mod_writer_save(gridvdb_writer *w, const char *path, int nanovdb)
{
    try {
        for (auto &g : w->grids)
            g->pruneGrid(0.0f); // constant 8^3 blocks become tiles
        if (!nanovdb) {
            openvdb::GridPtrVec v(w->grids.begin(), w->grids.end());
            openvdb::io::File f(path);
            f.write(v);
            f.close();
            return BRUME_OK;
        }
        std::vector<nanovdb::GridHandle<nanovdb::HostBuffer>> handles;
        for (auto &g : w->grids)
            handles.push_back(to_nano(g));
        nanovdb::io::writeGrids<nanovdb::HostBuffer, std::vector>(std::string(path), handles);
        return BRUME_OK;
    } catch (const std::exception &e) {
        return err_set(BRUME_ERROR_IO, "%s: %s", path, e.what());
    }
}

static void mod_writer_free(gridvdb_writer *w) { delete w; }

extern "C" const gridvdb_api *brume_openvdb_module(gridvdb_err_fn err)
{
    static const gridvdb_api api = {
        GRIDVDB_API_VERSION, sizeof(gridvdb_api), mod_list, mod_to_nano, mod_vdb_to_nvdb, mod_before_fork,
        mod_write_dense, mod_writer_new, mod_writer_add, mod_writer_set, mod_writer_active, mod_writer_save,
        mod_writer_free,
    };
    host_err = err;
    return &api;
}
