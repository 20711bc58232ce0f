"""brume - a renderer for participating media (clouds, fog, haze, smoke, fire), in Python.

A thin layer over the C library libbrume (include/brume.h) through cffi, with numpy arrays
for images and densities. docs/python.md has a notebook-style walk-through.

    import brume, numpy as np
    rho = np.zeros((32, 32, 32), np.float32)          # indexed [z, y, x]
    rho[8:24, 8:24, 8:24] = 1.0
    scene = {"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0]},
             "lights": [{"type": "distant", "direction": [0, -1, -1], "irradiance": 3}],
             "media": [{"density": {"type": "array", "data": rho, "bounds": [[-1, -1, -1], [1, 1, 1]]},
                        "sigma_a": 0.1, "sigma_s": 4}]}
    img = brume.render(scene, width=128, height=96, spp=16)   # float32 (96, 128, 4), linear RGBA

A scene is a path to a scene file, a dict in the scene-file format (docs/scene-format.md),
or None for the built-in default scene. In a dict, a medium's density may be
{"type": "array", "data": ndarray, "bounds": [[xmin, ymin, zmin], [xmax, ymax, zmax]]}
(float32 values >= 0 indexed [z, y, x], optional "filter": "nearest" | "trilinear"). The
array is copied when the scene is made, so that changing it afterwards changes nothing;
"borrow": True uses a C-contiguous float32 array in place instead, without a copy, kept
alive until brume releases it: the caller then must not change it while the scene lives
(brume computed its majorants from the values it saw: a changed array renders a wrong
image, silently). Any other array is converted (copied) either way. Errors raise brume.Error with brume's
one-line message.
"""
import json
import os
import sys
import threading

import numpy as np

from ._lib import ffi, lib, has

__all__ = ["Error", "Scene", "render", "version", "AOVS"]

# AOV name -> bit (brume_aov), when the library has them
AOVS = {}
for _name, _sym in (("depth", "BRUME_AOV_DEPTH"), ("albedo", "BRUME_AOV_ALBEDO"), ("normal", "BRUME_AOV_NORMAL"),
                    ("variance", "BRUME_AOV_VARIANCE"), ("samples", "BRUME_AOV_SAMPLES")):
    if has(_sym):
        AOVS[_name] = getattr(lib, _sym)

_CANCELLED = getattr(lib, "BRUME_ERROR_CANCELLED") if has("BRUME_ERROR_CANCELLED") else None


class Error(Exception):
    """A failed call: .message is brume's one-line message, .status its brume_status."""

    def __init__(self, message, status=None):
        super().__init__(message)
        self.message = message
        self.status = status


class Cancelled(Error):
    """The progress callback asked to stop; .image holds the samples finished so far."""

    def __init__(self, message, status, image):
        super().__init__(message, status)
        self.image = image


def version():
    """libbrume's version, "MAJOR.MINOR.PATCH"."""
    return ffi.string(lib.brume_version()).decode()


class _Context:
    """A brume_context for one Scene (a context is not thread-safe)."""

    def __init__(self):
        self.ptr = lib.brume_context_new()
        if self.ptr == ffi.NULL:
            raise MemoryError("brume_context_new")

    def check(self, status):
        if status != 0:
            raise Error(ffi.string(lib.brume_context_last_error(self.ptr)).decode(errors="replace"), status)

    def close(self):
        if self.ptr is not None and self.ptr != ffi.NULL:
            lib.brume_context_release(self.ptr)
        self.ptr = None


# Borrowed numpy arrays, alive until brume calls the release callback (keyed by a counter,
# so that one array given to two scenes is held twice).
_borrowed = {}
_borrowed_lock = threading.Lock()
_borrowed_next = [1]


@ffi.callback("void(void *)")
def _release_array(user):
    with _borrowed_lock:
        _borrowed.pop(int(ffi.cast("uintptr_t", user)), None)


def _array_density(ctx, spec, where):
    """A brume_density from {"type": "array", "data": ndarray, "bounds": ...}."""
    allowed = {"type", "data", "bounds", "filter", "borrow", "comment"}
    unknown = set(spec) - allowed
    if unknown:
        raise Error("%s: unknown key '%s' (known here: data, bounds, filter, borrow)" % (where, sorted(unknown)[0]))
    borrow = spec.get("borrow", False)
    if not isinstance(borrow, bool):
        raise Error("%s.borrow: expected true or false" % where)
    if "data" not in spec or "bounds" not in spec:
        raise Error("%s: an array density needs \"data\" (ndarray [z, y, x]) and \"bounds\"" % where)
    data = np.asarray(spec["data"])
    if data.ndim != 3:
        raise Error("%s.data: expected a 3-d array indexed [z, y, x], got %d dimensions" % (where, data.ndim))
    if data.dtype != np.float32 or not data.flags["C_CONTIGUOUS"]:
        data = np.ascontiguousarray(data, dtype=np.float32)  # a copy: the caller's array is not float32 [z][y][x]
    elif not borrow:
        data = data.copy()  # the scene's own: the caller's later changes cannot reach it
    try:
        b = np.asarray(spec["bounds"], dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        b = np.zeros(0)
    if b.size != 6:
        raise Error("%s.bounds: expected [[xmin, ymin, zmin], [xmax, ymax, zmax]]" % where)
    filt = spec.get("filter", "trilinear")
    if filt not in ("nearest", "trilinear"):
        raise Error("%s.filter: unknown filter '%s' (known: nearest, trilinear)" % (where, filt))
    nz, ny, nx = data.shape
    out = ffi.new("brume_density **")
    with _borrowed_lock:
        key = _borrowed_next[0]
        _borrowed_next[0] += 1
        _borrowed[key] = data
    st = lib.brume_density_new_array(ctx.ptr, ffi.cast("const float *", data.ctypes.data), nx, ny, nz,
                                     ffi.new("double[6]", list(b)),
                                     lib.BRUME_GRID_NEAREST if filt == "nearest" else lib.BRUME_GRID_TRILINEAR,
                                     _release_array, ffi.cast("void *", key), out)
    if st != 0:
        with _borrowed_lock:
            _borrowed.pop(key, None)  # not kept: brume calls no release on failure
        msg = ffi.string(lib.brume_context_last_error(ctx.ptr)).decode(errors="replace")
        raise Error("%s: %s" % (where, msg), st)
    return out[0]


def _json_default(o):
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.bool_):
        return bool(o)
    raise TypeError("not JSON: %r" % type(o))


def _progress_bar(description="brume"):
    """A progress callback drawing a bar: tqdm's (notebook-aware) when installed, else text."""
    try:
        from tqdm.auto import tqdm
    except ImportError:
        tqdm = None
    state = {}

    def update(done, total):
        if tqdm is not None:
            bar = state.get("bar")
            if bar is None:
                bar = state["bar"] = tqdm(total=total, desc=description, unit="samples")
            bar.total = total
            bar.n = done
            bar.refresh()
            if done >= total:
                bar.close()
        else:
            width = 40
            filled = width * done // total if total else width
            sys.stderr.write("\r%s [%s%s] %3d%%" % (description, "#" * filled, "." * (width - filled),
                                                    100 * done // total if total else 100))
            if done >= total:
                sys.stderr.write("\n")
            sys.stderr.flush()
        return True

    return update


class Scene:
    """A scene kept for repeated renders: a path to a scene file, a dict in the scene-file
    format, or None (the built-in default scene), loaded at `time` seconds.

    Scene.render(**settings) renders it; Scene.begin(**settings) starts a progressive
    render (then add(spp), image(), samples). Settings are brume_render_settings fields:
    width, height, spp, seed, threads, method, max_depth, fps, ...; options are the methods'
    "METHOD.KEY" options (path.sun_lobe, blasi.r, stam.eps, ...). A scene is committed (frozen) by its first
    render: settings and options can be given to the constructor or to that render only.
    """

    def __init__(self, scene=None, *, time=0.0, options=None, **settings):
        self._ctx = _Context()
        self._ptr = None
        self._job = None
        self._committed = False
        self._progress_cb = None
        self._callback_error = None  # what the progress callback raised during a render
        self._aovs = False
        out = ffi.new("brume_scene **")
        if scene is None:
            self._ctx.check(lib.brume_scene_new_default(self._ctx.ptr, out))
            self._ptr = out[0]
        elif isinstance(scene, dict):
            self._from_dict(scene, time, out)
        elif isinstance(scene, (str, bytes, os.PathLike)):
            self._ctx.check(lib.brume_scene_load_at(self._ctx.ptr, os.fsencode(scene), float(time), out))
            self._ptr = out[0]
        else:
            raise TypeError("scene: expected a path, a dict or None, got %s" % type(scene).__name__)
        self._configure(options, settings)

    def _from_dict(self, scene, time, out):
        doc = dict(scene)
        arrays = []
        media = doc.get("media")
        if isinstance(media, list):
            doc["media"] = media = list(media)
            for i, m in enumerate(media):
                d = m.get("density") if isinstance(m, dict) else None
                if isinstance(d, dict) and d.get("type") == "array":
                    arrays.append((i, d))
                    # the scene file holds a placeholder, replaced by the array below
                    m = dict(m)
                    try:
                        bounds = np.asarray(d.get("bounds"), dtype=np.float64).reshape(2, 3).tolist()
                    except (TypeError, ValueError):
                        raise Error("<dict>: media[%d].density.bounds: expected [[xmin, ymin, zmin], "
                                    "[xmax, ymax, zmax]]" % i) from None
                    m["density"] = {"type": "constant", "value": 0, "bounds": bounds}
                    media[i] = m
        text = json.dumps(doc, default=_json_default).encode()
        self._ctx.check(lib.brume_scene_from_json(self._ctx.ptr, text, b"<dict>", float(time), out))
        self._ptr = out[0]
        for i, d in arrays:
            rho = _array_density(self._ctx, d, "<dict>: media[%d].density" % i)
            st = lib.brume_scene_set_medium_density(self._ctx.ptr, self._ptr, i, rho)
            if st != 0:
                lib.brume_density_release(rho)
                self._ctx.check(st)

    def _configure(self, options, settings):
        if self._committed and (options or settings):
            raise Error("scene already rendered: settings and options are frozen (make a new brume.Scene)")
        for key, value in (options or {}).items():
            if isinstance(value, bool):
                value = "true" if value else "false"
            self._ctx.check(lib.brume_scene_set_option(self._ctx.ptr, self._ptr, key.encode(), str(value).encode()))
        if settings:
            rs = ffi.new("brume_render_settings *")
            lib.brume_scene_get_settings(self._ptr, rs)
            for key, value in settings.items():
                self._set_field(rs, key, value)
            self._ctx.check(lib.brume_scene_set_settings(self._ctx.ptr, self._ptr, rs))

    def _set_field(self, rs, key, value):
        if key == "method":
            raw = value.encode()
            if len(raw) >= 32:
                raise Error("method: '%s' is too long" % value)
            rs.method = raw
        elif key == "filter":
            rs.filter = {"box": lib.BRUME_FILTER_BOX, "gaussian": lib.BRUME_FILTER_GAUSSIAN}[value]
        elif key == "aovs":
            mask = 0
            for name in value:
                if name not in AOVS:
                    raise Error("aovs: unknown layer '%s' (known: %s)" % (name, ", ".join(AOVS) or "none in this build"))
                mask |= AOVS[name]
            rs.aovs = mask
        elif key == "progress":
            if value is True:
                value = _progress_bar()
            if value is None or value is False:
                self._progress_cb = None
                if has("brume_progress_fn"):
                    rs.progress_fn = ffi.NULL
                return
            if not has("brume_progress_fn"):
                raise Error("progress: this libbrume has no progress callback")
            user_fn = value

            def on_error(exc_type, exc_value, tb):
                # the render stops; _raise_callback_error raises this exception itself, not
                # brume.Cancelled
                if self._callback_error is None:
                    self._callback_error = exc_value
                return False

            @ffi.callback("bool(void *, uint64_t, uint64_t)", onerror=on_error)
            def cb(user, done, total):
                go_on = user_fn(int(done), int(total))
                return go_on is None or bool(go_on)

            self._progress_cb = cb  # kept alive as long as the scene may call it
            rs.progress_fn = cb
            rs.progress_user = ffi.NULL
        else:
            try:
                setattr(rs, key, value)
            except AttributeError:
                raise Error("unknown render setting '%s'" % key) from None

    def _commit(self, options, settings):
        if options or settings:
            self._configure(options, settings)
        if not self._committed:
            self._ctx.check(lib.brume_scene_commit(self._ctx.ptr, self._ptr))
            self._committed = True

    @property
    def settings(self):
        """The render settings as a dict."""
        rs = ffi.new("brume_render_settings *")
        lib.brume_scene_get_settings(self._ptr, rs)
        out = {}
        for name, _ in ffi.typeof("brume_render_settings").fields:
            v = getattr(rs, name)
            if name == "method":
                v = ffi.string(v).decode()
            elif isinstance(v, ffi.CData):
                continue
            out[name] = v
        return out

    def render(self, *, options=None, **settings):
        """Renders the scene: a float32 array (height, width, 4) of linear RGBA. With
        aovs=[...] (names of AOVS) the result is (rgba, {name: array}). progress=True draws
        a bar; progress=fn(done, total) is called as the render goes, returning False to
        cancel (brume.Cancelled then carries the partial image)."""
        aovs = "aovs" in settings and settings["aovs"]
        self._commit(options, settings)
        out = ffi.new("brume_image **")
        st = lib.brume_render(self._ctx.ptr, self._ptr, out)
        return self._finish(st, out[0], aovs)

    def _raise_callback_error(self, st):
        """After a render that stopped: the exception the progress callback raised, if any."""
        e, self._callback_error = self._callback_error, None
        if e is not None and _CANCELLED is not None and st == _CANCELLED:
            raise e

    def _finish(self, st, img, aovs):
        if st != 0 and img != ffi.NULL and self._callback_error is not None:
            lib.brume_image_release(img)
            img = ffi.NULL
        self._raise_callback_error(st)
        if st != 0:
            msg = ffi.string(lib.brume_context_last_error(self._ctx.ptr)).decode(errors="replace")
            if _CANCELLED is not None and st == _CANCELLED and img != ffi.NULL:
                result = _image_arrays(img, aovs)
                lib.brume_image_release(img)
                raise Cancelled(msg, st, result)
            if img != ffi.NULL:
                lib.brume_image_release(img)
            raise Error(msg, st)
        result = _image_arrays(img, aovs)
        lib.brume_image_release(img)
        return result

    # ---- progressive rendering -------------------------------------------------------------
    def begin(self, *, options=None, **settings):
        """Starts a progressive render (a render job): add(spp) passes, image() at any time.
        N passes of k samples equal one render of N x k samples, bit for bit."""
        if not has("brume_render_begin"):
            raise Error("progressive rendering: this libbrume has no render jobs")
        self._aovs = "aovs" in settings and settings["aovs"]
        self._commit(options, settings)
        self._release_job()
        out = ffi.new("brume_render_job **")
        st = lib.brume_render_begin(self._ctx.ptr, self._ptr, out)
        self._raise_callback_error(st)
        self._ctx.check(st)
        self._job = out[0]
        return self

    def add(self, spp=1):
        """Adds a pass of spp samples per pixel to the job begun by begin()."""
        if self._job is None:
            raise Error("add: no render job (call begin() first)")
        st = lib.brume_render_job_add(self._ctx.ptr, self._job, int(spp))
        self._raise_callback_error(st)
        if st != 0:
            msg = ffi.string(lib.brume_context_last_error(self._ctx.ptr)).decode(errors="replace")
            if _CANCELLED is not None and st == _CANCELLED:
                raise Cancelled(msg, st, self.image())
            raise Error(msg, st)
        return self

    def run(self):
        """Runs passes until the settings say stop (spp, time_budget or noise_target)."""
        if self._job is None:
            raise Error("run: no render job (call begin() first)")
        if not has("brume_render_job_run"):
            raise Error("run: this libbrume cannot run a job to its settings' end")
        st = lib.brume_render_job_run(self._ctx.ptr, self._job)
        self._raise_callback_error(st)
        if st != 0:
            msg = ffi.string(lib.brume_context_last_error(self._ctx.ptr)).decode(errors="replace")
            if _CANCELLED is not None and st == _CANCELLED:
                raise Cancelled(msg, st, self.image())
            raise Error(msg, st)
        return self

    @property
    def progress(self):
        """The job's figures (brume_render_progress) as a dict: done, total, spp_min, ..."""
        if self._job is None or not has("brume_render_job_progress"):
            return {}
        p = ffi.new("brume_render_progress *")
        lib.brume_render_job_progress(self._job, p)
        return {name: getattr(p, name) for name, _ in ffi.typeof("brume_render_progress").fields}

    def image(self):
        """The job's image so far (and its AOVs, as render returns them)."""
        if self._job is None:
            raise Error("image: no render job (call begin() first)")
        out = ffi.new("brume_image **")
        st = lib.brume_render_job_image(self._ctx.ptr, self._job, out)
        return self._finish(st, out[0], self._aovs)

    @property
    def samples(self):
        """Samples per pixel the job has so far."""
        return 0 if self._job is None else int(lib.brume_render_job_samples(self._job))

    def _release_job(self):
        if self._job is not None:
            lib.brume_render_job_release(self._job)
            self._job = None

    def close(self):
        """Releases the scene now (also done when it is garbage-collected)."""
        self._release_job()
        if self._ptr is not None:
            lib.brume_scene_release(self._ptr)  # releases borrowed arrays through the callback
            self._ptr = None
        self._ctx.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass


def _image_arrays(img, aovs):
    w, h = lib.brume_image_width(img), lib.brume_image_height(img)
    rgba = np.frombuffer(ffi.buffer(lib.brume_image_pixels_const(img), w * h * 16), dtype=np.float32)
    rgba = rgba.reshape(h, w, 4).copy()
    if not aovs:
        return rgba
    layers = {}
    for i in range(lib.brume_image_layer_count(img)):
        name = ffi.string(lib.brume_image_layer_name(img, i)).decode()
        c = lib.brume_image_layer_channels(img, i)
        a = np.frombuffer(ffi.buffer(lib.brume_image_layer_pixels(img, i), w * h * c * 4), dtype=np.float32)
        layers[name] = a.reshape(h, w, c).copy() if c > 1 else a.reshape(h, w).copy()
    return rgba, layers


def render(scene=None, *, time=0.0, options=None, **settings):
    """Renders scene (a path, a dict in the scene-file format, or None for the default scene)
    with the given render settings (width, height, spp, seed, method, ...; aovs=[...];
    progress=True or fn(done, total)) and method options ({"blasi.r": 0.5}). Returns a
    float32 array (height, width, 4) of linear RGBA, or (rgba, {aov: array}) with aovs."""
    with Scene(scene, time=time) as s:
        return s.render(options=options, **settings)
