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

Images are brume.Image: a numpy float32 array (height, width, 4) of linear RGBA that a
notebook shows (_repr_png_, through libbrume's PNG encoder) and brume.write() saves as .exr,
.png or .pfm. Ctrl-C during a render raises brume.Interrupted, a KeyboardInterrupt whose
.image holds the samples finished. The animation time of a scene is frame_time= (seconds);
a render's time budget is the setting time_budget= (seconds): a bare time= is refused.
"""
import inspect
import json
import math
import operator
import os
import sys
import threading
import time
from typing import Any, Callable, Dict, List, Mapping, NamedTuple, Optional, Tuple, Union

import numpy as np

from ._lib import ffi, lib, has

__all__ = ["Error", "ArgumentError", "Cancelled", "Interrupted", "Image", "Progress", "Scene", "render", "write", "version", "options",
           "AOVS"]

SceneSource = Union[None, str, bytes, "os.PathLike[str]", Mapping[str, Any]]
ProgressFn = Callable[..., Optional[bool]]  # fn(progress: Progress) or fn(done: int, total: int)


class Progress(NamedTuple):
    """A render's figures as the progress line and the live view show them (the library's
    brume_render_progress, docs/render-jobs.md "Progress")."""
    done: int          # pixel samples taken
    total: int         # pixel samples in all: exact for a fixed count, else an estimate >= done
    spp_min: int       # samples per pixel over the pixels
    spp_max: int
    spp_mean: float
    noise: float       # largest relative standard error over the pixels with signal (last pass)
    converged: float   # fraction of pixels adaptive sampling has stopped
    elapsed: float     # seconds spent rendering, a light pass included
    eta: float         # seconds left, an estimate, smoothed; negative: not known yet
    finished: bool     # nothing left to do under the settings
    fraction: float    # of the work done, [0, 1], 1 only when finished, never going back; negative: not known
    stopped: str = ""  # why the passes ended: "spp", "noise", "time", "cancelled"; "" while work is left


# brume_stop_reason -> Progress.stopped
_STOPPED = {getattr(lib, "BRUME_STOP_" + n.upper(), None): n for n in ("spp", "noise", "time", "cancelled")}


def _job_figures(job) -> Progress:
    """The figures of a render job (brume_render_job_progress); safe during a pass."""
    p = ffi.new("brume_render_progress *")
    lib.brume_render_job_progress(job, p)
    fields = [getattr(p, name) for name in Progress._fields[:-1]]
    stopped = _STOPPED.get(p.stopped, "") if has("BRUME_STOP_NONE") else ""
    return Progress(*fields, stopped=stopped)


def _takes_figures(fn) -> bool:
    """Whether a progress callback takes one argument (a Progress) rather than the two of
    earlier versions (done, total), which are still called so."""
    try:
        sig = inspect.signature(fn)
    except (TypeError, ValueError):
        return False
    try:
        sig.bind(None, None)
        return False
    except TypeError:
        pass
    try:
        sig.bind(None)
        return True
    except TypeError:
        return False

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


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT) stopped a render: .image holds the samples finished so far (the image,
    or (image, layers) when AOVs were asked for; None when nothing was rendered yet)."""

    def __init__(self, image=None):
        super().__init__("brume: render interrupted")
        self.image = image


class KeywordError(Error, TypeError):
    """An unknown or ambiguous keyword argument; the message lists the valid ones."""


class ArgumentError(Error, TypeError):
    """A value brume cannot take: of a type the field does not hold, beyond the range of its C
    type, or one a scene file cannot hold (NaN, a set, a key that is not a string); the
    message names the field. A brume.Error, and a TypeError as Python's own would have been."""


# cJSON refuses arrays and objects nested deeper than 1000 as a syntax error: refused here
# first, by name, well within it
_MAX_NESTING = 200


def _plain(value, where, active=()):
    """value in JSON's types (dicts with string keys, lists, strings, finite numbers, bools,
    None), numpy arrays and scalars converted; anything a scene file cannot hold raises
    ArgumentError naming `where`, the field's path. `active`: the ids of the containers
    enclosing value (a container inside itself is refused)."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, str) and "\0" in value:
        raise ArgumentError("%s: contains a NUL character (the scene reader's strings end there)" % where)
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, int):
        try:
            float(value)
        except OverflowError:
            raise ArgumentError("%s: %d is too large for a number brume reads (a double)" % (where, value)) from None
        return int(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ArgumentError("%s: %r: a scene holds finite numbers only" % (where, value))
        return float(value)
    if isinstance(value, np.ndarray):
        return _plain(value.tolist(), where, active)  # a 0-d array is a number
    if not isinstance(value, (Mapping, list, tuple)):
        raise ArgumentError("%s: a %s is not a value of the scene format (numbers, strings, bools, None, lists, "
                            "dicts, numpy arrays)" % (where, type(value).__name__))
    if id(value) in active:
        raise ArgumentError("%s: contains itself" % where)
    if len(active) >= _MAX_NESTING:
        raise ArgumentError("%s: nested more than %d deep" % (where, _MAX_NESTING))
    active = active + (id(value),)
    if isinstance(value, Mapping):
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise ArgumentError("%s: the key %r is not a string" % (where, k))
            out[k] = _plain(v, "%s.%s" % (where, k) if where != "<dict>" else "<dict>: " + k, active)
        return out
    return [_plain(v, "%s[%d]" % (where, i), active) for i, v in enumerate(value)]


def _c_string(value, where):
    """A str, bytes or path as the bytes of a C string; NUL inside would cut it short."""
    try:
        b = os.fsencode(value)
    except TypeError:
        raise ArgumentError("%s: expected a string, got %s" % (where, type(value).__name__)) from None
    if b"\0" in b:
        raise ArgumentError("%s: contains a NUL character" % where)
    return b


def _number(value, where):
    """value as a float: a real number, finite."""
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ArgumentError("%s: expected a number, got %r" % (where, value)) from None
    if not math.isfinite(v):
        raise ArgumentError("%s: %r is not finite" % (where, value))
    return v


def _c_int(value, where, lo, hi):
    """value as a whole number in [lo, hi]."""
    try:
        v = operator.index(value)
    except TypeError:
        raise ArgumentError("%s: expected a whole number, got %r" % (where, value)) from None
    if not lo <= v <= hi:
        raise ArgumentError("%s: %d outside [%d, %d]" % (where, v, lo, hi))
    return v


def _refuse_time(kwargs):
    if "time" in kwargs:
        raise KeywordError("time: ambiguous; say frame_time= for the scene's animation time (seconds) or "
                           "time_budget= for how long to render (seconds)")


def version() -> str:
    """libbrume's version, "MAJOR.MINOR.PATCH"."""
    return ffi.string(lib.brume_version()).decode()


def options() -> "List[Dict[str, str]]":
    """The rendering methods' options, as the library's own tables give them (brume_option_get):
    one dict per "METHOD.KEY" that Scene(options=...) and render(options=...) take, with its
    "key", "kind" (number, integer, enum, bool, color, path), "values" (what a value is),
    "default_value" and "doc"."""
    out = []
    o = ffi.new("brume_option *")
    for i in range(lib.brume_option_count()):
        if lib.brume_option_get(ffi.NULL, i, o) != 0:
            raise Error("brume_option_get(%d) failed" % i)
        out.append({f: ffi.string(lib.brume_option_kind_name(o.kind) if f == "kind" else getattr(o, f)).decode()
                    for f in ("key", "kind", "values", "default_value", "doc")})
    return out


class _Context:
    """A brume_context for one Scene (a context is not thread-safe)."""

    def __init__(self):
        self.ptr = lib.brume_context_new()
        if self.ptr == ffi.NULL:
            raise Error("brume_context_new: out of memory")

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
    try:
        data = np.asarray(spec["data"])
        if data.ndim != 3:
            raise Error("%s.data: expected a 3-d array indexed [z, y, x], got %d dimensions" % (where, data.ndim))
        converted = data.dtype != np.float32 or not data.flags["C_CONTIGUOUS"]
        if converted:
            data = np.ascontiguousarray(data, dtype=np.float32)  # a copy: the caller's array is not float32 [z][y][x]
    except (TypeError, ValueError, OverflowError) as e:
        raise ArgumentError("%s.data: expected an array of numbers (%s)" % (where, e)) from None
    if not converted and not borrow:
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


def _progress_bar(description="brume", log_seconds=10.0):
    """A progress callback drawing the library's figures (samples per pixel, noise, elapsed,
    ETA, the fraction done): tqdm's bar (notebook-aware) when installed, else a text bar
    redrawn in place on a terminal, else (stderr a file or a pipe) a line every log_seconds,
    as `brume render` logs. libbrume itself prints nothing."""
    try:
        from tqdm.auto import tqdm
    except ImportError:
        tqdm = None
    tty = sys.stderr.isatty()
    state = {"t_last": time.monotonic()}

    def figures(p):
        what = "%.1f spp" % p.spp_mean
        if p.noise > 0:
            what += ", noise %.2f%%" % (100 * p.noise)
        eta = "done" if p.finished else "ETA not known yet" if p.eta < 0 else "ETA %.1f s" % p.eta
        return "%s, %.1f s elapsed, %s" % (what, p.elapsed, eta)

    def update(p):
        if tqdm is not None:
            bar = state.get("bar")
            if bar is None:
                bar = state["bar"] = tqdm(total=1000, desc=description, bar_format="{l_bar}{bar}|{postfix}")
            bar.n = 1000 if p.finished else int(1000 * max(p.fraction, 0.0))
            bar.set_postfix_str(figures(p), refresh=True)
            if p.finished:
                bar.close()
                state.pop("bar")
        elif not tty:
            now = time.monotonic()
            if p.finished or now - state["t_last"] < log_seconds:
                return True
            state["t_last"] = now
            pct = "  ?%" if p.fraction < 0 else "%3d%%" % int(100 * p.fraction)
            sys.stderr.write("%s %s: %s\n" % (description, pct, figures(p)))
            sys.stderr.flush()
        else:
            width = 30
            frac = 1.0 if p.finished else p.fraction
            filled = int(width * max(frac, 0.0))
            pct = "  ?%" if frac < 0 else "%3d%%" % int(100 * frac)
            sys.stderr.write("\r%s [%s%s] %s  %s   " % (description, "#" * filled, "." * (width - filled), pct,
                                                     figures(p)))
            if p.finished:
                sys.stderr.write("\n")
            sys.stderr.flush()
        return True

    return update


# brume_render_settings fields a caller sets by name (the callback fields are progress=),
# the enumerations by name, and the keywords that are not fields
_SETTINGS = tuple(n for n, _ in ffi.typeof("brume_render_settings").fields if n not in ("progress_fn", "progress_user"))
_ENUMS = {"filter": {"box": lib.BRUME_FILTER_BOX, "gaussian": lib.BRUME_FILTER_GAUSSIAN}}
if has("BRUME_SAMPLER_SOBOL"):
    _ENUMS["sampler"] = {"independent": lib.BRUME_SAMPLER_INDEPENDENT, "sobol": lib.BRUME_SAMPLER_SOBOL}
if has("brume_sensor_name"):  # the film's sensors by name: "cie1931" and pbrt-v4's cameras
    _ENUMS["sensor"] = {}
    while lib.brume_sensor_name(len(_ENUMS["sensor"])) != ffi.NULL:
        _ENUMS["sensor"][ffi.string(lib.brume_sensor_name(len(_ENUMS["sensor"]))).decode()] = len(_ENUMS["sensor"])
_EXTRA = ("options", "frame_time")
_SETTING_TYPES = dict(ffi.typeof("brume_render_settings").fields)


def _field_words(key):
    """What a render setting's C field holds, in words, for a refusal."""
    t = _SETTING_TYPES[key].type
    if t.cname in ("float", "double"):
        return "a number"
    if t.cname in ("_Bool", "bool"):
        return "True or False"
    bits = 8 * ffi.sizeof(t)
    if t.cname.startswith(("uint", "unsigned", "size_t")):
        return "a whole number in [0, %d]" % (2 ** bits - 1)
    return "a whole number in [%d, %d]" % (-2 ** (bits - 1), 2 ** (bits - 1) - 1)


class _RunState:
    """What a scene's renders share with its progress callback: the user's callback and the
    stop flag that Ctrl-C sets. The callback refers to this object, not to the Scene."""

    FIGURES_INTERVAL = 0.1  # seconds between two calls of a callback that takes figures

    def __init__(self):
        self.progress = None   # as given: a callable, True or None
        self.user_fn = None    # what is called: the callable, or the bar of progress=True
        self.figures = False   # user_fn takes a Progress (else done, total)
        self.job = None        # the render job whose figures it gets (None: none yet)
        self.t_last = 0.0
        self.stop = threading.Event()
        self.error = None      # what the user's callback raised during a render (re-raised as itself)

    def set_user_fn(self, fn):
        self.user_fn = fn
        self.figures = fn is not None and has("brume_render_progress") and _takes_figures(fn)

    def callback(self):
        state = self

        def on_error(exc_type, exc_value, tb):
            # the render stops; Scene._raise_callback_error raises this exception itself,
            # not brume.Cancelled
            if state.error is None:
                state.error = exc_value
            return False

        @ffi.callback("bool(void *, uint64_t, uint64_t)", onerror=on_error)
        def cb(user, done, total):
            if state.stop.is_set():
                return False
            fn = state.user_fn
            if fn is None:
                return True
            if not state.figures:
                go_on = fn(int(done), int(total))
            else:
                # the figures cost a pass over the pixels: ten times a second at most, and
                # always at the last tile of a fixed count (a light pass, before the job
                # exists, has no figures yet)
                now = time.monotonic()
                job = state.job
                if job is None or (now - state.t_last < state.FIGURES_INTERVAL and done < total):
                    return True
                state.t_last = now
                go_on = fn(_job_figures(job))
            return go_on is None or bool(go_on)

        return cb

    def final(self):
        """After a call that rendered and succeeded: a callback that takes figures gets those
        of the end (finished when nothing is left to do), so its last figures are the image's."""
        if self.figures and self.job is not None:
            self.user_fn(_job_figures(self.job))

    def call(self, c_call):
        """Runs c_call (a libbrume call that renders) so that Ctrl-C can stop it: from the main
        thread the call runs in a helper thread while this one waits, wakes for signals and, on
        KeyboardInterrupt, sets the stop flag; the progress callback then cancels the render,
        which ends after the tiles in flight. The caller raises Interrupted afterwards."""
        self.stop.clear()
        self.error = None
        if threading.current_thread() is not threading.main_thread():
            return c_call()  # signals reach the main thread only: nothing to wait for here
        box = {}
        # a lock the helper releases when the call returns; Thread.join is not used: a join
        # interrupted by KeyboardInterrupt can leave the thread marked stopped while it runs
        finished = threading.Lock()
        finished.acquire()

        def target():
            try:
                box["status"] = c_call()
            except BaseException as e:  # raised again in the caller's thread
                box["error"] = e
            finally:
                finished.release()

        threading.Thread(target=target, name="brume-render", daemon=True).start()
        while True:
            try:
                if finished.acquire(timeout=0.05):
                    break
            except KeyboardInterrupt:
                self.stop.set()  # and go on waiting: the scene must outlive the call
        if "error" in box:
            raise box["error"]
        return box["status"]


class Scene:
    """A scene kept for repeated renders: a path to a scene file, a dict in the scene-file
    format, or None (the built-in default scene), loaded at `frame_time` seconds of its
    animation (time_budget= is the render setting that bounds a render's seconds).
    lenient=True reads a .pbrt file skipping each directive or parameter brume cannot honour
    instead of refusing it; Scene.ignored lists what was skipped.

    Scene.render(**settings) renders it; Scene.begin(**settings) starts a progressive
    render (then add(spp), image(), samples). Settings are brume_render_settings fields:
    width, height, spp, seed, threads, method, max_depth, fps, ...; options are the methods'
    "METHOD.KEY" options (path.sun_lobe, blasi.r, stam.eps, ...). A scene is committed (frozen) by its first
    render: settings and options can be given to the constructor or to that render only.
    """

    def __init__(self, scene: SceneSource = None, *, frame_time: float = 0.0,
                 options: Optional[Mapping[str, Any]] = None, lenient: bool = False, **settings: Any) -> None:
        self._ctx = _Context()
        self._ptr = None
        self._job = None
        self._committed = False
        self._run = _RunState()
        self._progress_cb = None
        self._aovs = False
        _refuse_time(settings)
        out = ffi.new("brume_scene **")
        if not isinstance(lenient, bool):
            raise ArgumentError("lenient: expected True or False, got %s" % type(lenient).__name__)
        opts = ffi.new("brume_load_options *", {"time": _number(frame_time, "frame_time"), "lenient": lenient})
        if scene is None:
            self._ctx.check(lib.brume_scene_load(self._ctx.ptr, ffi.NULL, opts, out))
            self._ptr = out[0]
        elif isinstance(scene, Mapping):
            self._from_dict(scene, opts, out)
        elif isinstance(scene, (str, bytes, os.PathLike)):
            path = ffi.new("char[]", _c_string(scene, "scene"))
            src = ffi.new("brume_source *", {"path": path})
            self._ctx.check(lib.brume_scene_load(self._ctx.ptr, src, opts, out))
            self._ptr = out[0]
        else:
            raise ArgumentError("scene: expected a path, a dict or None, got %s" % type(scene).__name__)
        self._configure(options, settings)

    def _from_dict(self, scene, opts, out):
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
        # the scene as the user gave it, checked here: anything JSON cannot hold would reach
        # the reader as a "JSON syntax error" the user never wrote
        text = json.dumps(_plain(doc, "<dict>"), allow_nan=False).encode()
        name, text = ffi.new("char[]", b"<dict>"), ffi.new("char[]", text)
        src = ffi.new("brume_source *", {"path": name, "text": text})
        self._ctx.check(lib.brume_scene_load(self._ctx.ptr, src, opts, out))
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
        if options is not None and not isinstance(options, Mapping):
            raise ArgumentError("options: expected a dict {\"METHOD.KEY\": value}, got %s" % type(options).__name__)
        for key, value in (options or {}).items():
            if not isinstance(key, str):
                raise ArgumentError("options: the key %r is not a \"METHOD.KEY\" string" % (key,))
            if isinstance(value, bool):
                value = "true" if value else "false"
            elif isinstance(value, (float, np.floating)):
                value = repr(_number(value, "options: " + key))  # every digit: str() would round
            elif not isinstance(value, (str, int, np.integer)):
                raise ArgumentError("options: %s: expected a number, a string or a bool, got %s"
                                    % (key, type(value).__name__))
            self._ctx.check(lib.brume_scene_set_option(self._ctx.ptr, self._ptr, _c_string(key, "options"),
                                                       _c_string(str(value), "options: " + key)))
        if settings:
            rs = ffi.new("brume_render_settings *")
            lib.brume_scene_settings(self._ptr, rs)
            for key, value in settings.items():
                self._set_field(rs, key, value)
            self._ctx.check(lib.brume_scene_set_settings(self._ctx.ptr, self._ptr, rs))

    def _set_field(self, rs, key, value):
        if key == "method":
            m = ffi.new("brume_method *")
            self._ctx.check(lib.brume_method_from_name(self._ctx.ptr, str(value).encode(), m))
            rs.method = m[0]
        elif key in _ENUMS:
            names = _ENUMS[key]
            if not isinstance(value, str) or value not in names:
                raise KeywordError("%s: unknown value %r (known: %s)" % (key, value, ", ".join(names)))
            setattr(rs, key, names[value])
        elif key == "aovs":
            mask = 0
            if not isinstance(value, (list, tuple)):
                raise ArgumentError("aovs: expected a list of layer names, got %s" % type(value).__name__)
            for name in value:
                if not isinstance(name, str) or name not in AOVS:
                    raise Error("aovs: unknown layer '%s' (known: %s)" % (name, ", ".join(AOVS) or "none in this build"))
                mask |= AOVS[name]
            rs.aovs = mask
        elif key == "progress":
            if value is not None and value is not False and not has("brume_progress_fn"):
                raise Error("progress: this libbrume has no progress callback")
            if not (value is None or isinstance(value, bool) or callable(value)):
                raise ArgumentError("progress: expected True, False, None or a function, got %s" % type(value).__name__)
            self._run.progress = value if callable(value) or value is True else None
            self._run.set_user_fn(_progress_bar() if value is True else self._run.progress)
        elif key in _SETTINGS:
            if isinstance(value, (float, np.floating)) and not math.isfinite(value):
                raise ArgumentError("%s: %r is not finite" % (key, value))
            try:
                setattr(rs, key, value)
            except (TypeError, ValueError, OverflowError):
                raise ArgumentError("%s: %r is not %s" % (key, value, _field_words(key))) from None
        else:
            raise KeywordError("unknown render setting '%s' (valid: %s)" % (key, ", ".join(sorted(set(_SETTINGS) | set(_EXTRA)))))

    def _commit(self, options, settings):
        _refuse_time(settings)
        if options or settings:
            self._configure(options, settings)
        if not self._committed:
            if has("brume_progress_fn"):
                # the progress callback is always there: it is how Ctrl-C stops a render
                self._progress_cb = self._run.callback()
                rs = ffi.new("brume_render_settings *")
                lib.brume_scene_settings(self._ptr, rs)
                rs.progress_fn = self._progress_cb
                rs.progress_user = ffi.NULL
                self._ctx.check(lib.brume_scene_set_settings(self._ctx.ptr, self._ptr, rs))
            self._ctx.check(lib.brume_scene_commit(self._ctx.ptr, self._ptr))
            self._committed = True

    @property
    def ignored(self) -> List[str]:
        """What the scene's source asked for and the scene leaves out: with lenient=True, each
        pbrt-v4 directive or parameter brume cannot honour, as "FILE:LINE: what" (docs/pbrt.md)."""
        return [ffi.string(lib.brume_scene_ignored(self._ptr, i)).decode()
                for i in range(lib.brume_scene_ignored_count(self._ptr))]

    @property
    def settings(self) -> Dict[str, Any]:
        """The render settings as a dict, in the form they are given: filter and sampler by
        name, aovs as a list of names, progress as given (None when none)."""
        rs = ffi.new("brume_render_settings *")
        lib.brume_scene_settings(self._ptr, rs)
        out: Dict[str, Any] = {}
        for name in _SETTINGS:
            v = getattr(rs, name)
            if name == "method":
                v = ffi.string(lib.brume_method_name(v)).decode()
            elif name in _ENUMS:
                v = next((k for k, e in _ENUMS[name].items() if e == v), v)
            elif name == "aovs":
                v = [k for k, bit in AOVS.items() if v & bit]
            out[name] = v
        if has("brume_progress_fn"):
            out["progress"] = self._run.progress
        return out

    def render(self, *, options: Optional[Mapping[str, Any]] = None, **settings: Any) -> "Union[Image, Tuple[Image, Dict[str, np.ndarray]]]":
        """Renders the scene: a brume.Image, float32 (height, width, 4) of linear RGBA. With
        aovs=[...] (names of AOVS) the result is (rgba, {name: array}). progress=True draws
        a bar with the figures; progress=fn(p) is called as the render goes with a
        brume.Progress (samples per pixel, noise, elapsed, ETA ...), ten times a second at
        most and once at the end, fn(done, total) of earlier versions after every tile,
        either returning False to cancel (brume.Cancelled then carries the partial image). Ctrl-C raises
        brume.Interrupted (a KeyboardInterrupt) with the partial image."""
        aovs = "aovs" in settings and settings["aovs"]
        self._commit(options, settings)
        out = ffi.new("brume_image **")
        if not (self._run.figures and has("brume_render_begin")):
            st = self._run.call(lambda: lib.brume_render(self._ctx.ptr, self._ptr, out))
            return self._finish(st, out[0], aovs)
        # a callback that takes figures reads them from a job: brume_render's own steps
        # (begin, run, the image), which give its image bit for bit
        job = ffi.new("brume_render_job **")
        progressive = self._run.job

        def c_call():
            st = lib.brume_render_begin(self._ctx.ptr, self._ptr, job)
            if st == 0:
                self._run.job = job[0]
                st = lib.brume_render_job_run(self._ctx.ptr, job[0])
            return st

        try:
            st = self._run.call(c_call)
            msg = ffi.string(lib.brume_context_last_error(self._ctx.ptr)).decode(errors="replace")
            if job[0] != ffi.NULL and (st == 0 or st == _CANCELLED):
                sti = lib.brume_render_job_image(self._ctx.ptr, job[0], out)
                st = sti if sti != 0 else st
                msg = msg if sti == 0 else None
            if st == 0 and not self._run.stop.is_set():
                self._run.final()
            return self._finish(st, out[0], aovs, msg)
        finally:
            self._run.job = progressive
            if job[0] != ffi.NULL:
                lib.brume_render_job_release(job[0])

    def _raise_callback_error(self, st):
        """After a render that stopped: the exception the progress callback raised, if any."""
        e, self._run.error = self._run.error, None
        if e is not None and _CANCELLED is not None and st == _CANCELLED:
            raise e

    def _finish(self, st, img, aovs, msg=None):
        """The result of a render: the image, or the exception its status says. msg: the
        render's message when the context's last one is no longer it (None: read it)."""
        interrupted = self._run.stop.is_set()
        if st != 0 and img != ffi.NULL and self._run.error is not None:
            lib.brume_image_release(img)
            img = ffi.NULL
        self._raise_callback_error(st)
        if st != 0:
            if msg is None:
                msg = ffi.string(lib.brume_context_last_error(self._ctx.ptr)).decode(errors="replace")
            if _CANCELLED is not None and st == _CANCELLED and img != ffi.NULL:
                result = _image_arrays(img, aovs)
                lib.brume_image_release(img)
                if interrupted:
                    raise Interrupted(result)
                raise Cancelled(msg, st, result)
            if img != ffi.NULL:
                lib.brume_image_release(img)
            if interrupted:
                raise Interrupted(None)
            raise Error(msg, st)
        result = _image_arrays(img, aovs)
        lib.brume_image_release(img)
        if interrupted:
            raise Interrupted(result)
        return result

    # ---- progressive rendering -------------------------------------------------------------
    def begin(self, *, options: Optional[Mapping[str, Any]] = None, **settings: Any) -> "Scene":
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
        self._job = self._run.job = out[0]
        return self

    def add(self, spp: int = 1) -> "Scene":
        """Adds a pass of spp samples per pixel to the job begun by begin()."""
        if self._job is None:
            raise Error("add: no render job (call begin() first)")
        spp = _c_int(spp, "add: spp", 1, 2 ** 31 - 1)
        st = self._run.call(lambda: lib.brume_render_job_add(self._ctx.ptr, self._job, spp))
        self._job_status(st)
        self._run.final()
        return self

    def _job_status(self, st):
        self._raise_callback_error(st)
        if self._run.stop.is_set():
            raise Interrupted(self.image())
        if st != 0:
            msg = ffi.string(lib.brume_context_last_error(self._ctx.ptr)).decode(errors="replace")
            if _CANCELLED is not None and st == _CANCELLED:
                raise Cancelled(msg, st, self.image())
            raise Error(msg, st)

    def run(self) -> "Scene":
        """Runs passes until the settings say stop (spp, time_budget or noise_target)."""
        if self._job is None:
            raise Error("run: no render job (call begin() first)")
        if not has("brume_render_job_run"):
            raise Error("run: this libbrume cannot run a job to its settings' end")
        st = self._run.call(lambda: lib.brume_render_job_run(self._ctx.ptr, self._job))
        self._job_status(st)
        self._run.final()
        return self

    @property
    def progress(self) -> Dict[str, Any]:
        """The job's figures (brume_render_progress) as a dict: done, total, spp_min, ...
        (the fields of brume.Progress, which a progress callback fn(progress) receives)."""
        if self._job is None or not has("brume_render_job_progress"):
            return {}
        return dict(_job_figures(self._job)._asdict())

    def image(self) -> "Union[Image, Tuple[Image, Dict[str, np.ndarray]]]":
        """The job's image so far (and its AOVs, as render returns them)."""
        if self._job is None:
            raise Error("image: no render job (call begin() first)")
        out = ffi.new("brume_image **")
        st = lib.brume_render_job_image(self._ctx.ptr, self._job, out)
        self._run.stop.clear()  # the partial image of an interrupted pass is what is asked for
        return self._finish(st, out[0], self._aovs)

    @property
    def samples(self) -> int:
        """Samples per pixel the job has so far."""
        return 0 if self._job is None else int(lib.brume_render_job_samples(self._job))

    def _release_job(self):
        if self._job is not None:
            lib.brume_render_job_release(self._job)
            self._job = self._run.job = None

    def close(self) -> None:
        """Releases the scene now (also done when it is garbage-collected)."""
        self._release_job()
        if self._ptr is not None:
            lib.brume_scene_release(self._ptr)  # releases borrowed arrays through the callback
            self._ptr = None
        self._ctx.close()

    def __enter__(self) -> "Scene":
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
    rgba = np.frombuffer(ffi.buffer(lib.brume_image_pixels(img), w * h * 16), dtype=np.float32)
    rgba = rgba.reshape(h, w, 4).copy().view(Image)
    if not aovs:
        return rgba
    layers = {}
    for i in range(lib.brume_image_layer_count(img)):
        name = ffi.string(lib.brume_image_layer_name(img, i)).decode()
        c = lib.brume_image_layer_channels(img, i)
        a = np.frombuffer(ffi.buffer(lib.brume_image_layer_pixels(img, i), w * h * c * 4), dtype=np.float32)
        layers[name] = a.reshape(h, w, c).copy() if c > 1 else a.reshape(h, w).copy()
        if name == "depth":
            # libbrume writes 0 where no sample hit anything; in Python that is +inf (no distance)
            layers[name][layers[name] == 0] = np.inf
    return rgba, layers


class Image(np.ndarray):
    """A picture: a numpy float32 array (height, width, 4) of linear RGBA, rows top first, as
    render() returns it. A notebook shows it (_repr_png_: libbrume's PNG, sRGB, clamped);
    img.write(path) is brume.write(img, path)."""

    def __new__(cls, array: Any) -> "Image":
        return np.asarray(array, dtype=np.float32).view(cls)

    def _repr_png_(self) -> Optional[bytes]:
        if self.ndim != 3 or self.shape[2] not in (3, 4) or 0 in self.shape:
            return None
        return encode_png(self)

    def write(self, path: "Union[str, os.PathLike[str]]", *, exposure: float = 0.0, tonemap: str = "clamp") -> None:
        write(self, path, exposure=exposure, tonemap=tonemap)


def _to_brume_image(ctx, array):
    try:
        a = np.asarray(array)
        if a.ndim != 3 or a.shape[2] not in (3, 4):
            raise Error("image: expected an array (height, width, 4) of RGBA or (height, width, 3) of RGB, got "
                        "shape %s" % (a.shape,))
        h, w = a.shape[:2]
        rgba = np.ones((h, w, 4), np.float32)
        rgba[..., :a.shape[2]] = a
    except (TypeError, ValueError, OverflowError) as e:
        raise ArgumentError("image: expected an array of numbers (%s)" % e) from None
    _c_int(w, "image: width", 1, 2 ** 31 - 1)
    _c_int(h, "image: height", 1, 2 ** 31 - 1)
    out = ffi.new("brume_image **")
    ctx.check(lib.brume_image_new(ctx.ptr, w, h, out))
    ffi.memmove(lib.brume_image_pixels(out[0]), ffi.from_buffer(rgba), rgba.nbytes)
    return out[0]


def _write_options(exposure, tonemap):
    maps = {"clamp": lib.BRUME_TONEMAP_CLAMP, "filmic": lib.BRUME_TONEMAP_FILMIC}
    if not isinstance(tonemap, str) or tonemap not in maps:
        raise KeywordError("tonemap: unknown value %r (known: clamp, filmic)" % (tonemap,))
    opts = ffi.new("brume_write_options *")
    opts.exposure = _number(exposure, "exposure")
    opts.tonemap = maps[tonemap]
    return opts


def write(image: Any, path: "Union[str, os.PathLike[str]]", *, exposure: float = 0.0, tonemap: str = "clamp") -> None:
    """Writes an image (an array (height, width, 4) or (height, width, 3), linear) through
    libbrume's writers, by the extension: .exr (float RGBA), .png (8-bit sRGB after exposure
    in stops and tonemap "clamp" or "filmic"), .pfm. The write is atomic."""
    name = _c_string(path, "path")
    ctx = _Context()
    img = ffi.NULL
    try:
        img = _to_brume_image(ctx, image)
        ctx.check(lib.brume_image_write(ctx.ptr, img, name, _write_options(exposure, tonemap)))
    finally:
        lib.brume_image_release(img)
        ctx.close()


def encode_png(image: Any, *, exposure: float = 0.0, tonemap: str = "clamp") -> bytes:
    """The image as PNG bytes, as write() would write a .png."""
    ctx = _Context()
    img = ffi.NULL
    data = ffi.new("unsigned char **")
    size = ffi.new("size_t *")
    try:
        img = _to_brume_image(ctx, image)
        ctx.check(lib.brume_image_encode_png(ctx.ptr, img, _write_options(exposure, tonemap), data, size))
        try:
            return bytes(ffi.buffer(data[0], size[0]))
        finally:
            lib.free(data[0])
    finally:
        lib.brume_image_release(img)
        ctx.close()


def render(scene: SceneSource = None, *, frame_time: float = 0.0, options: Optional[Mapping[str, Any]] = None,
           **settings: Any) -> "Union[Image, Tuple[Image, Dict[str, np.ndarray]]]":
    """Renders scene (a path, a dict in the scene-file format, or None for the default scene)
    at frame_time seconds of its animation, with the given render settings (width, height,
    spp, seed, method, time_budget, noise_target, ...; aovs=[...]; progress=True,
    fn(progress) or fn(done, total)) and method options ({"blasi.r": 0.5}). Returns a brume.Image (height,
    width, 4) of linear RGBA, or (rgba, {aov: array}) with aovs. Ctrl-C raises
    brume.Interrupted (a KeyboardInterrupt) whose .image is the partial image."""
    _refuse_time(settings)
    with Scene(scene, frame_time=frame_time) as s:
        return s.render(options=options, **settings)
