"""setup.py - the build step pyproject.toml cannot say: the package's _cdef.h (the C
declarations of brume.h, by gen_cdef.py) and _config.py (where libbrume.so.1 is), and, when
no libbrume is found, libbrume built from this repository with CMake into the package.

libbrume is, in order: the file BRUME_LIBRARY names; the install pkg-config finds
(`pkg-config --variable=libdir brume`); a build of the repository around this folder
(cmake, target brume_shared and the OpenVDB module, into build/libbrume)."""
import os
import shutil
import subprocess
import sys

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
SONAME = "libbrume.so.1"


def pkg_config(var):
    try:
        out = subprocess.run(["pkg-config", "--variable=" + var, "brume"], capture_output=True, text=True)
    except OSError:
        return None
    return out.stdout.strip() if out.returncode == 0 and out.stdout.strip() else None


def build_libbrume(dest):
    """Builds libbrume (and its OpenVDB module when OpenVDB is there) from the repository;
    returns the files to put in the package."""
    if not os.path.exists(os.path.join(REPO, "CMakeLists.txt")):
        raise SystemExit("brume: no libbrume found (set BRUME_LIBRARY to libbrume.so.1, or PKG_CONFIG_PATH to "
                         "PREFIX/lib/pkgconfig of an install) and no brume repository around %s to build it" % HERE)
    build = os.path.join(HERE, "build", "libbrume")
    print("brume: no libbrume installed; building it in %s" % build, file=sys.stderr)
    subprocess.run(["cmake", "-S", REPO, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DBRUME_FUZZ_TESTS=OFF",
                    "-DBRUME_MPI=OFF"], check=True, stdout=subprocess.DEVNULL)
    targets = ["brume_shared"]
    if os.path.exists(os.path.join(build, "CMakeFiles", "brume_openvdb.dir")):
        targets += ["brume_openvdb", "brume_openvdb_reader"]
    subprocess.run(["cmake", "--build", build, "-j", str(os.cpu_count() or 2), "--target"] + targets, check=True)
    files = [os.path.join(build, SONAME)]
    module = os.path.join(build, "libbrume-openvdb.so")
    if os.path.exists(module):
        # found beside libbrume.so.1 (src/io/grid_vdb_load.c), with the program that runs it
        files += [module, os.path.join(build, "brume-openvdb-reader")]
    return files


class BuildPy(build_py):
    def run(self):
        super().run()
        pkg = os.path.join(self.build_lib, "brume")
        os.makedirs(pkg, exist_ok=True)
        header = os.path.join(REPO, "include", "brume.h")
        library = os.environ.get("BRUME_LIBRARY")
        if not library:
            libdir = pkg_config("libdir")
            if libdir and os.path.exists(os.path.join(libdir, SONAME)):
                library = os.path.join(libdir, SONAME)
                header = os.path.join(pkg_config("includedir") or "", "brume.h")
        if library:
            library = os.path.abspath(library)
            print("brume: using %s" % library, file=sys.stderr)
        else:
            for f in build_libbrume(pkg):
                shutil.copy2(f, pkg)  # copy2 follows the symlink: the library itself
            library = SONAME  # relative to the package
        if not os.path.exists(header):
            raise SystemExit("brume: no brume.h (looked for %s)" % header)
        subprocess.run([sys.executable, os.path.join(HERE, "gen_cdef.py"), header, os.path.join(pkg, "_cdef.h")],
                       check=True)
        with open(os.path.join(pkg, "_config.py"), "w") as f:
            f.write("LIBRARY = %r\n" % library)


setup(cmdclass={"build_py": BuildPy})
