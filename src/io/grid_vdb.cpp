// grid_vdb.cpp - OpenVDB reading (straight to NanoVDB) and listing, and the module's table,
// behind a C interface (grid_vdb.h). The module's other files convert to NanoVDB
// (grid_vdb_nano.cpp) and write (grid_vdb_write.cpp). The only C++ in brume: libopenvdb and NanoVDB's builders are C++
// APIs. Built as the module libbrume-openvdb.so, which exports one symbol, its table
// (brume_openvdb_module); grid_vdb_load.c opens it on first use. Every exception stops at
// this file's boundary and becomes a one-line message through the host's error function.
// grid_io.c runs the readers in a child process under resource limits (grid_sandbox.c).
#include "io/grid_vdb_module.hpp"

#include <cmath>
#include <dlfcn.h>
#include <link.h>
#include <unistd.h>
#include <mutex>
#include <cstdarg>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <openvdb/io/Stream.h>

namespace brume_vdb {

gridvdb_err_fn host_err;

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

// The whole file in memory, read through an istringstream that throws at a short read:
// OpenVDB trusts the counts it reads, and at the end of the bytes a failed stream would
// otherwise let it loop over billions of tiles (found by fuzzing); an exception ends it.
void open_source(source &s, const char *path, const void *bytes, size_t size)
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
}

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

} // namespace brume_vdb

using namespace brume_vdb;

static brume_status mod_list(const char *path, const void *bytes, size_t size, const char *name,
                             gridvdb_info **out, int *count)
{
    *out = nullptr;
    *count = 0;
    try {
        init_once();
        source s;
        open_source(s, path, bytes, size);
        std::vector<gridvdb_info> infos;
        for (const auto &meta : *s.grids) {
            openvdb::GridBase::Ptr g = meta;
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
            in.nano_bytes = g->transform().isLinear() ? (unsigned long long)to_nano(g).size() : 0;
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
        open_source(s, path, bytes, size);
        openvdb::GridBase::Ptr g;
        try {
            g = pick(s.grids, grid, vec3);
        } catch (const std::runtime_error &e) {
            return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s", name, e.what());
        }
        if (!g->transform().isLinear())
            return err_set(BRUME_ERROR_UNSUPPORTED, "%s: grid \"%s\" has a non-linear (frustum) transform", name,
                           g->getName().c_str());
        if (g->activeVoxelCount() == 0)
            return err_set(BRUME_ERROR_PARSE, "%s: grid \"%s\" has no active voxels", name, g->getName().c_str());
        nano_handle h = to_nano(g);
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
        open_source(s, in, nullptr, 0);
        std::vector<nano_handle> handles;
        if (grid && grid[0]) {
            openvdb::GridBase::Ptr g;
            for (const auto &m : *s.grids)
                if (m->getName() == grid)
                    g = m;
            if (!g)
                return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: no grid named \"%s\"; grids: %s", in, grid,
                               names_of(s.grids).c_str());
            if (!is_float(g) && !is_vec3(g))
                return err_set(BRUME_ERROR_UNSUPPORTED, "%s: grid \"%s\" holds %s values; brume converts float and vec3s grids",
                               in, grid, g->valueType().c_str());
            handles.push_back(to_nano(g));
        } else {
            for (const auto &m : *s.grids) {
                openvdb::GridBase::Ptr g = m;
                if (g->transform().isLinear() && (is_float(g) || is_vec3(g)))
                    handles.push_back(to_nano(g));
            }
            if (handles.empty())
                return err_set(BRUME_ERROR_UNSUPPORTED, "%s: no float or vec3s grid to convert; grids: %s", in,
                               names_of(s.grids).c_str());
        }
        write_nano(out, handles);
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
