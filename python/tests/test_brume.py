"""test_brume.py - the Python package over the build tree's libbrume (ctest python.package):
a dict scene with a numpy density renders byte for byte as the same values read from a raw
file, shapes and types, zero-copy borrowing and its release, errors carrying brume's
message, repeated renders, options, and (when the library has them) progress,
cancellation, progressive passes and AOVs; Ctrl-C during a render, keywords, settings read
back, writing images and the notebook's PNG."""
import gc
import json
import os
import signal
import tempfile
import threading
import time
import unittest

import numpy as np

import brume
from brume._lib import has

BOUNDS = [[-1.0, -0.8, -0.6], [1.2, 0.8, 0.6]]


def cloud(nz=8, ny=10, nx=12):
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    r = np.sqrt((i - (nx - 1) / 2) ** 2 + (j - (ny - 1) / 2) ** 2 + 2.0 * (k - (nz - 1) / 2) ** 2)
    v = np.where(r < 5.0, (5.0 - r) * (1.0 + 0.3 * np.sin(i + 2.0 * j + 3.0 * k)), 0.0)
    return v.astype(np.float32)


def scene_with(density):
    return {"render": {"width": 32, "height": 24, "spp": 4},
            "camera": {"position": [0.3, 0.5, 4], "look_at": [0, 0, 0]},
            "lights": [{"type": "distant", "direction": [-1, -1, -1], "irradiance": 3}],
            "media": [{"sigma_a": 0.3, "sigma_s": 2, "density": density}]}


class PackageTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(dir=os.environ.get("BRUME_TMP"))

    def tearDown(self):
        for f in os.listdir(self.tmp):
            os.remove(os.path.join(self.tmp, f))
        os.rmdir(self.tmp)

    def test_dict_with_numpy_density_equals_raw_file(self):
        rho = cloud()
        raw = os.path.join(self.tmp, "cloud.raw")
        rho.tofile(raw)  # float32, x fastest: what a [z, y, x] C array is in memory
        nz, ny, nx = rho.shape
        path = os.path.join(self.tmp, "cloud.json")
        with open(path, "w") as f:
            json.dump(scene_with({"type": "grid", "file": raw, "format": "raw", "dims": [nx, ny, nz],
                                  "bounds": BOUNDS, "filter": "trilinear"}), f)
        want = brume.render(path)
        got = brume.render(scene_with({"type": "array", "data": rho, "bounds": BOUNDS}))
        self.assertEqual(got.shape, (24, 32, 4))
        self.assertEqual(got.dtype, np.float32)
        self.assertGreater(float(want[..., 3].max()), 0.1)  # the cloud is in the picture
        self.assertEqual(want.tobytes(), got.tobytes())
        # a non-contiguous view (same values) is copied, and renders the same
        fortran = np.asfortranarray(rho)
        self.assertFalse(fortran.flags["C_CONTIGUOUS"])
        got2 = brume.render(scene_with({"type": "array", "data": fortran, "bounds": BOUNDS}))
        self.assertEqual(want.tobytes(), got2.tobytes())
        # settings given to render override the file's
        small = brume.render(path, width=8, height=6, spp=1)
        self.assertEqual(small.shape, (6, 8, 4))

    def test_zero_copy_borrow_and_release(self):
        rho = cloud()
        s = brume.Scene(scene_with({"type": "array", "data": rho, "bounds": BOUNDS, "borrow": True}))
        held = [a for a in brume._borrowed.values() if a is rho]
        self.assertEqual(len(held), 1)  # the caller's own array, not a copy
        img = s.render()
        s.close()
        self.assertFalse(any(a is rho for a in brume._borrowed.values()))  # released with the scene
        self.assertEqual(img.shape, (24, 32, 4))
        # an array given to a scene that fails later is not kept either
        with self.assertRaises(brume.Error):
            brume.Scene(dict(scene_with({"type": "array", "data": rho, "bounds": BOUNDS, "borrow": True}), camera={}))
        gc.collect()
        self.assertFalse(any(a is rho for a in brume._borrowed.values()))

    def test_array_copied_unless_borrowed(self):
        # a borrowed array changed after Scene() would render an inconsistent image
        # silently; by default the scene holds its own copy, so a change reaches nothing
        rho = cloud()
        want = brume.render(scene_with({"type": "array", "data": rho.copy(), "bounds": BOUNDS}), spp=2)
        with brume.Scene(scene_with({"type": "array", "data": rho, "bounds": BOUNDS})) as s:
            self.assertFalse(any(a is rho for a in brume._borrowed.values()))
            rho[:] = 0.0  # the caller's array emptied: the scene keeps the cloud
            got = s.render(spp=2)
        self.assertEqual(want.tobytes(), got.tobytes())
        with self.assertRaises(brume.Error) as e:
            brume.Scene(scene_with({"type": "array", "data": rho, "bounds": BOUNDS, "borrow": "yes"}))
        self.assertIn("borrow", str(e.exception))

    def test_errors_carry_brumes_message(self):
        bad = scene_with({"type": "constant", "value": 1})
        bad["camera"]["fov"] = 400
        with self.assertRaises(brume.Error) as e:
            brume.render(bad)
        self.assertIn("camera.fov: 400 outside [0.001, 179]", e.exception.message)
        self.assertNotIn("\n", e.exception.message)
        rho = cloud()
        rho[1, 2, 3] = np.nan
        with self.assertRaises(brume.Error) as e:
            brume.render(scene_with({"type": "array", "data": rho, "bounds": BOUNDS}))
        self.assertIn("media[0].density", str(e.exception))
        self.assertIn("brume_density_new_array: data", str(e.exception))
        self.assertIn("nan", str(e.exception))
        with self.assertRaises(brume.Error) as e:
            brume.render(scene_with({"type": "array", "data": np.zeros((4, 4), np.float32), "bounds": BOUNDS}))
        self.assertIn("expected a 3-d array", str(e.exception))
        with self.assertRaises(brume.Error) as e:
            brume.render(scene_with({"type": "array", "data": cloud(), "bounds": [[1, 0, 0], [0, 1, 1]]}))
        self.assertIn("min < max", str(e.exception))
        missing = os.path.join(self.tmp, "missing.json")
        with self.assertRaises(brume.Error) as e:
            brume.render(missing)
        self.assertIn(missing, str(e.exception))
        with self.assertRaises(brume.Error) as e:
            brume.render(scene_with({"type": "constant"}), options={"blasi.rays": 3})
        self.assertIn("blasi.rays: unknown key", str(e.exception))

    @unittest.skipUnless(has("brume_scene_ignored"), "this libbrume has no --lenient")
    def test_lenient_pbrt_lists_what_it_skipped(self):
        path = os.path.join(self.tmp, "cone.pbrt")
        with open(path, "w") as f:
            f.write('LookAt 0 0 -5  0 0 0  0 1 0\nCamera "perspective"\nWorldBegin\n'
                    'Shape "cone"\nShape "sphere" "float radius" [1]\n')
        with self.assertRaises(brume.Error) as e:
            brume.Scene(path)
        self.assertIn("cone.pbrt:4: Shape \"cone\"", e.exception.message)
        scene = brume.Scene(path, lenient=True)
        self.assertEqual(len(scene.ignored), 1)
        self.assertIn("cone.pbrt:4: Shape \"cone\"", scene.ignored[0])
        self.assertEqual(brume.Scene(scene_with({"type": "constant", "value": 1})).ignored, [])

    @unittest.skipUnless(has("brume_option_get"), "this libbrume does not list its options")
    def test_options_listed_by_the_library_are_taken(self):
        opts = brume.options()
        keys = [o["key"] for o in opts]
        for k in ("path.sun_lobe", "path.split", "blasi.light_rays", "blasi.gather", "stam.voxelize.resolution"):
            self.assertIn(k, keys)
        self.assertEqual(len(keys), len(set(keys)))
        by_key = {o["key"]: o for o in opts}
        self.assertEqual(by_key["path.split"]["values"], "a whole number in [1, 8]")
        self.assertEqual(by_key["blasi.gather"]["kind"], "enum")
        # every option whose default is a value (not words for a computed one) takes it back
        def settable(o):
            v = o["default_value"]
            return v != "" and (o["kind"] in ("enum", "bool") or not v[0].isalpha())
        given = {k: o["default_value"] for k, o in by_key.items() if settable(o)}
        self.assertGreater(len(given), 20)
        s = brume.Scene(scene_with({"type": "constant", "value": 1}), options=given)
        s.close()

    def test_scene_renders_again_and_takes_options(self):
        s = brume.Scene(scene_with({"type": "array", "data": cloud(), "bounds": BOUNDS}), spp=2,
                        method="blasi", options={"blasi.light_rays": 2000, "blasi.variant": "physical"})
        a, b = s.render(), s.render()
        self.assertEqual(a.tobytes(), b.tobytes())
        self.assertEqual(s.settings["method"], "blasi")
        self.assertEqual(s.settings["spp"], 2)
        with self.assertRaises(brume.Error):
            s.render(spp=3)  # committed: frozen
        s.close()
        default = brume.render(None, width=12, height=8, spp=1)
        self.assertEqual(default.shape, (8, 12, 4))

    @unittest.skipUnless(has("brume_progress_fn"), "this libbrume has no progress callback")
    def test_progress_and_cancel(self):
        calls = []

        def progress(done, total):
            calls.append((done, total))
            return True

        brume.render(scene_with({"type": "constant", "value": 0.5}), progress=progress)
        self.assertTrue(calls)
        self.assertTrue(all(0 <= d <= t for d, t in calls))
        self.assertEqual(calls[-1][0], calls[-1][1])
        with self.assertRaises(brume.Cancelled) as e:
            brume.render(scene_with({"type": "constant", "value": 0.5}), progress=lambda d, t: d == 0)
        self.assertEqual(e.exception.image.shape, (24, 32, 4))
        brume.render(scene_with({"type": "constant", "value": 0.5}), width=8, height=6, progress=True)

        # an exception raised by the callback comes back as itself, not brume.Cancelled
        class Mine(Exception):
            pass

        def broken(done, total):
            raise Mine("from the callback")

        with self.assertRaises(Mine):
            brume.render(scene_with({"type": "constant", "value": 0.5}), progress=broken)
        if has("brume_render_begin"):
            with brume.Scene(scene_with({"type": "constant", "value": 0.5})) as s:
                s.begin(spp=2, progress=broken)
                with self.assertRaises(Mine):
                    s.add(2)
        # and the next render of a scene is not troubled by the last one's exception
        with brume.Scene(scene_with({"type": "constant", "value": 0.5})) as s:
            with self.assertRaises(Mine):
                s.render(progress=broken)

    @unittest.skipUnless(has("brume_render_progress"), "this libbrume has no progress figures")
    def test_progress_callback_gets_the_figures(self):
        """A callback fn(p) gets the progress line's figures (samples, noise,
        elapsed, ETA), sane as the render goes and the image's at the end."""
        scene = scene_with({"type": "array", "data": cloud(), "bounds": BOUNDS})
        scene["render"].update(width=48, height=40, spp=6)  # 3 x 3 tiles
        seen = []
        img, layers = brume.render(scene, aovs=["samples"], progress=lambda p: seen.append(p))
        self.assertGreaterEqual(len(seen), 2)  # a tile's (the first is always shown) and the end's
        self.assertTrue(all(isinstance(p, brume.Progress) for p in seen))
        for a, b in zip(seen, seen[1:]):
            self.assertLessEqual(a.elapsed, b.elapsed)
            self.assertLessEqual(a.done, b.done)
        self.assertLess(seen[0].elapsed, seen[-1].elapsed)
        for p in seen[:-1]:  # during the render: a fixed count's exact total, below 100 %
            self.assertFalse(p.finished)
            self.assertEqual(p.total, 48 * 40 * 6)
            self.assertTrue(0 <= p.fraction < 1 and p.eta >= 0, p)
            self.assertTrue(0 <= p.spp_min <= p.spp_mean <= p.spp_max <= 6, p)
        end = seen[-1]
        self.assertTrue(end.finished)
        self.assertEqual((end.done, end.total, end.eta, end.fraction), (48 * 40 * 6, 48 * 40 * 6, 0.0, 1.0))
        # the samples per pixel are the image's own (its "samples" layer)
        self.assertEqual((end.spp_min, end.spp_max), (int(layers["samples"].min()), int(layers["samples"].max())))
        self.assertEqual(end.spp_mean, float(layers["samples"].mean()))
        # a relative standard error of a mean of n >= 2 non-negative samples lies in [0, 1] (1:
        # one sample of the n carries it all, as at the cloud's thin edge); something is noisy
        self.assertTrue(0 < end.noise <= 1, end)
        # the same render as without figures, bit for bit (they come from a render job)
        self.assertEqual(img.tobytes(), brume.render(scene).tobytes())
        # a progressive job's callback too: its last figures are the job's after each call
        with brume.Scene(scene) as s:
            seen.clear()
            s.begin(spp=6, progress=lambda p: seen.append(p))
            s.add(2)
            self.assertEqual((seen[-1].spp_max, seen[-1].done), (2, 48 * 40 * 2))
            s.run()
            self.assertTrue(seen[-1].finished)
            self.assertEqual(seen[-1]._asdict(), s.progress)
            self.assertEqual(s.samples, seen[-1].spp_max)
        # under a time budget the ETA never exceeds the time left
        seen.clear()
        brume.render(scene, spp=1 << 16, time_budget=0.5, progress=lambda p: seen.append(p))
        self.assertTrue(all(p.eta <= 0.5 - p.elapsed + 0.05 for p in seen[:-1] if p.eta >= 0), seen)
        self.assertTrue(seen[-1].finished)
        # returning False cancels, as the two-argument form does
        with self.assertRaises(brume.Cancelled) as e:
            brume.render(scene, progress=lambda p: False)
        self.assertEqual(e.exception.image.shape, (40, 48, 4))

    @unittest.skipUnless(has("brume_render_begin"), "this libbrume has no render jobs")
    def test_progressive_passes_equal_one_render(self):
        scene = scene_with({"type": "array", "data": cloud(), "bounds": BOUNDS})
        one = brume.render(scene, spp=4)
        with brume.Scene(scene) as s:
            s.begin(spp=4)
            s.add(2)
            half = s.image()
            s.add(2)
            self.assertEqual(s.samples, 4)
            self.assertEqual(s.image().tobytes(), one.tobytes())
            self.assertEqual(half.shape, one.shape)

    @unittest.skipUnless("depth" in brume.AOVS and "albedo" in brume.AOVS, "this libbrume has no AOVs")
    def test_aovs_as_arrays(self):
        # a matte wall 3 units in front of the camera: depth 3 on every pixel, albedo its own
        scene = {"render": {"width": 16, "height": 12, "spp": 2},
                 "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 30},
                 "lights": [{"type": "distant", "direction": [0, 0, -1], "irradiance": 1}],
                 "surfaces": [{"type": "quad", "corner": [-5, -5, 0], "edge_u": [10, 0, 0], "edge_v": [0, 10, 0],
                               "material": {"albedo": [0.2, 0.4, 0.6]}}]}
        rgba, aovs = brume.render(scene, aovs=["depth", "albedo"])
        self.assertEqual(rgba.shape, (12, 16, 4))
        self.assertEqual(aovs["depth"].shape, (12, 16))
        self.assertEqual(aovs["albedo"].shape, (12, 16, 3))
        centre = aovs["depth"][6, 8]
        self.assertAlmostEqual(float(centre), 3.0, delta=0.05)
        np.testing.assert_allclose(aovs["albedo"][6, 8], [0.2, 0.4, 0.6], atol=1e-6)

    @unittest.skipUnless("depth" in brume.AOVS, "this libbrume has no AOVs")
    def test_depth_is_inf_where_nothing_was_hit(self):
        # a wall filling the left half of the image only: the right half hits nothing
        scene = {"render": {"width": 16, "height": 12, "spp": 2},
                 "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 30},
                 "lights": [{"type": "distant", "direction": [0, 0, -1], "irradiance": 1}],
                 "surfaces": [{"type": "quad", "corner": [-5, -5, 0], "edge_u": [4.9, 0, 0], "edge_v": [0, 10, 0],
                               "material": {"albedo": [0.5, 0.5, 0.5]}}]}
        _, aovs = brume.render(scene, aovs=["depth"])
        self.assertTrue(np.isinf(aovs["depth"][6, 15]) and aovs["depth"][6, 15] > 0)
        self.assertAlmostEqual(float(aovs["depth"][6, 0]), 3.0, delta=0.2)

    def test_keywords_cannot_be_mistaken(self):
        with self.assertRaises(TypeError) as e:
            brume.render(None, time=1)
        self.assertIn("frame_time", str(e.exception))
        self.assertIn("time_budget", str(e.exception))
        with self.assertRaises(brume.Error) as e:
            brume.Scene(None, time=1)
        self.assertIn("frame_time", str(e.exception))
        with self.assertRaises(TypeError) as e:
            brume.render(None, noise=0.1)
        self.assertIn("noise_target", str(e.exception))  # the valid names are listed
        self.assertIn("'noise'", str(e.exception))
        with self.assertRaises(brume.Error) as e:
            brume.render(None, filter="tent")
        self.assertIn("box, gaussian", str(e.exception))
        # the animation time is frame_time: a blob field drifting at 1 unit/s moves
        path = os.path.join(os.environ["BRUME_SOURCE_DIR"], "scenes", "anim-stam-drift.json")
        a = brume.render(path, frame_time=0.0, width=16, height=12, spp=1)
        b = brume.render(path, frame_time=1.0, width=16, height=12, spp=1)
        self.assertNotEqual(a.tobytes(), b.tobytes())

    def test_settings_read_back_as_set(self):
        with brume.Scene(None, filter="box", width=20, height=10, method="single") as s:
            got = s.settings
            self.assertEqual(got["filter"], "box")
            self.assertEqual((got["width"], got["height"], got["method"]), (20, 10, "single"))
        with brume.Scene(None, filter="gaussian") as s:
            self.assertEqual(s.settings["filter"], "gaussian")
        if has("brume_sensor_name"):
            with brume.Scene(None, sensor="nikon_d850") as s:
                self.assertEqual(s.settings["sensor"], "nikon_d850")
            with self.assertRaises(brume.KeywordError):
                brume.Scene(None, sensor="nikon_d9000")
        if "depth" in brume.AOVS:
            with brume.Scene(None, aovs=["depth"]) as s:
                self.assertEqual(s.settings["aovs"], ["depth"])

    def test_write_and_notebook_png(self):
        img = brume.render(None, width=24, height=16, spp=1)
        self.assertIsInstance(img, brume.Image)
        png = img._repr_png_()
        self.assertEqual(png[:8], b"\x89PNG\r\n\x1a\n")
        exr, pngf = os.path.join(self.tmp, "x.exr"), os.path.join(self.tmp, "x.png")
        brume.write(img, exr)
        brume.write(img, pngf)
        with open(exr, "rb") as f:
            self.assertEqual(f.read(4), b"\x76\x2f\x31\x01")  # OpenEXR's magic number
        with open(pngf, "rb") as f:
            self.assertEqual(f.read(), png)  # the notebook's PNG is the file's, byte for byte
        with self.assertRaises(brume.Error) as e:
            brume.write(np.zeros((4, 4)), exr)
        self.assertIn("(height, width, 4)", str(e.exception))
        with self.assertRaises(brume.Error) as e:
            brume.write(img, os.path.join(self.tmp, "x.bmp"))
        self.assertIn("x.bmp", str(e.exception))

    @unittest.skipUnless(has("brume_progress_fn"), "this libbrume has no progress callback")
    @unittest.skipUnless(signal.getsignal(signal.SIGINT) is signal.default_int_handler, "SIGINT is not Python's")
    def test_ctrl_c_stops_a_render_within_a_second(self):
        # a render that would take minutes; SIGINT after 1 s, as Ctrl-C or a notebook's interrupt
        scene = scene_with({"type": "constant", "value": 0.5})
        for progress in (None, lambda done, total: True):
            sent = []

            def interrupt():
                time.sleep(1.0)
                sent.append(time.monotonic())
                os.kill(os.getpid(), signal.SIGINT)

            threading.Thread(target=interrupt, daemon=True).start()
            with self.assertRaises(KeyboardInterrupt) as e:
                brume.render(scene, width=256, height=256, spp=1 << 20, progress=progress)
            waited = time.monotonic() - sent[0]
            self.assertLess(waited, 1.0, "progress=%r" % (progress,))
            self.assertIsInstance(e.exception, brume.Interrupted)
            part = e.exception.image
            self.assertEqual(part.shape, (256, 256, 4))
            self.assertGreater(float(part[..., 3].max()), 0.0)  # the tiles finished are kept


if __name__ == "__main__":
    unittest.main()
