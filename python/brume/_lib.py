"""_lib.py - loads libbrume through cffi (ABI mode) with the declarations of its header.

The library is found from, in order: the environment variable BRUME_LIBRARY (a path),
the location recorded when the package was built or installed (_config.py), then the
system's search path (libbrume.so.1)."""
import os

import cffi

ffi = cffi.FFI()
_here = os.path.dirname(os.path.abspath(__file__))
with open(os.path.join(_here, "_cdef.h")) as _f:
    _cdef = _f.read()
ffi.cdef(_cdef)
ffi.cdef("void free(void *ptr);")  # for buffers libbrume allocates for the caller (brume_image_encode_png)


def _candidates():
    env = os.environ.get("BRUME_LIBRARY")
    if env:
        yield env
    try:
        from . import _config
        yield os.path.normpath(os.path.join(_here, _config.LIBRARY))
    except ImportError:
        pass
    yield "libbrume.so.1"


def _load():
    errors = []
    for path in _candidates():
        try:
            return ffi.dlopen(path)
        except OSError as e:
            errors.append("%s: %s" % (path, e))
    raise ImportError("brume: cannot load libbrume (" + "; ".join(errors) + ")")


lib = _load()


def has(name):
    """Whether the header this package was built from declares `name`."""
    import re
    return re.search(r"\b%s\b" % re.escape(name), _cdef) is not None
