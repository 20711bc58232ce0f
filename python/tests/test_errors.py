"""test_errors.py - every failure of the Python package is a brume.Error naming the field
(ctest python.errors, docs/python.md "Errors"): values a scene file cannot hold, integers
beyond C's fields, wrong types, NUL characters; never Python's KeyError, OverflowError or a
"JSON syntax error" the user never wrote."""
import os
import tempfile
import unittest

import numpy as np

import brume


def scene(**media):
    m = {"sigma_a": 0.1, "sigma_s": 1.0, "density": {"type": "constant", "value": 1,
                                                      "bounds": [[-1, -1, -1], [1, 1, 1]]}}
    m.update(media)
    return {"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0]},
            "lights": [{"type": "distant", "direction": [0, -1, -1], "irradiance": 3}],
            "media": [m], "render": {"width": 8, "height": 6, "spp": 1}}


class ErrorsTest(unittest.TestCase):
    def refused(self, fn, *fragments):
        """fn() raises a brume.Error (nothing else) whose message holds each fragment, on one line."""
        try:
            fn()
        except brume.Error as e:
            msg = str(e)
            for f in fragments:
                self.assertIn(f, msg)
            self.assertNotIn("\n", msg)
            self.assertNotIn("JSON syntax error", msg)
            return e
        except Exception as e:  # the point: nothing but brume.Error
            self.fail("%s raised %s: %s, not brume.Error" % (fragments, type(e).__name__, e))
        self.fail("%s: nothing raised" % (fragments,))

    def test_values_a_scene_cannot_hold(self):
        self.refused(lambda: brume.Scene(scene(sigma_s=float("nan"))), "<dict>: media[0].sigma_s", "nan",
                     "finite numbers only")
        self.refused(lambda: brume.Scene(scene(sigma_s=np.float32("inf"))), "media[0].sigma_s", "inf")
        self.refused(lambda: brume.Scene(scene(sigma_s={1, 2})), "media[0].sigma_s", "a set is not a value")
        self.refused(lambda: brume.Scene(scene(sigma_s=object())), "media[0].sigma_s", "object")
        self.refused(lambda: brume.Scene(scene(sigma_s=10 ** 400)), "media[0].sigma_s", "too large")
        self.refused(lambda: brume.Scene(scene(comment="a\0b")), "<dict>: media[0].comment", "NUL")
        bad_key = scene()
        bad_key["camera"][3] = 1
        self.refused(lambda: brume.Scene(bad_key), "<dict>: camera", "the key 3 is not a string")
        loop = scene()
        loop["media"][0]["self"] = loop["media"]
        self.refused(lambda: brume.Scene(loop), "media[0].self", "contains itself")
        deep = scene()
        nest = []
        for _ in range(2000):
            nest = [nest]
        deep["comment"] = nest
        self.refused(lambda: brume.Scene(deep), "<dict>: comment", "nested more than 200 deep")
        # numpy values where the format has numbers are taken, as before
        ok = scene(sigma_s=np.float64(2.0), sigma_a=np.array(0.1))
        ok["camera"]["position"] = np.array([0, 0, 4])
        brume.Scene(ok).close()

    def test_settings_beyond_their_c_fields(self):
        self.refused(lambda: brume.Scene(None, width=2 ** 40), "width: 1099511627776 is not a whole number in [")
        self.refused(lambda: brume.Scene(None, width="wide"), "width: 'wide' is not a whole number")
        self.refused(lambda: brume.Scene(None, seed=-1), "seed: -1 is not a whole number in [0, ")
        self.refused(lambda: brume.Scene(None, filter_width="2"), "filter_width: '2' is not a number")
        self.refused(lambda: brume.Scene(None, time_budget=float("nan")), "time_budget: nan is not finite")
        self.refused(lambda: brume.Scene(None, frame_time="soon"), "frame_time: expected a number")
        self.refused(lambda: brume.Scene(None, filter=["box"]), "filter: unknown value ['box']")
        self.refused(lambda: brume.Scene(None, aovs="depth"), "aovs: expected a list of layer names")
        self.refused(lambda: brume.Scene(None, aovs=[["depth"]]), "aovs: unknown layer")
        self.refused(lambda: brume.Scene(None, progress=5), "progress: expected True, False, None or a function")
        self.refused(lambda: brume.Scene(None, options=["blasi.r"]), "options: expected a dict")
        self.refused(lambda: brume.Scene(None, options={1: 2}), "options: the key 1 is not")
        self.refused(lambda: brume.Scene(None, options={"path.split": [1]}), "options: path.split: expected a number")
        self.refused(lambda: brume.Scene(None, options={"path.split\0x": 1}), "NUL")
        self.refused(lambda: brume.Scene(12), "scene: expected a path, a dict or None, got int")
        self.refused(lambda: brume.Scene("scene\0.json"), "scene: contains a NUL character")

    @unittest.skipUnless(brume._lib.has("brume_render_begin"), "this libbrume has no render jobs")
    def test_progressive_pass_counts(self):
        with brume.Scene(scene()) as s:
            s.begin()
            self.refused(lambda: s.add(2 ** 40), "add: spp: 1099511627776 outside [1, 2147483647]")
            self.refused(lambda: s.add("2"), "add: spp: expected a whole number")
            self.refused(lambda: s.add(0), "add: spp: 0 outside")
            s.add(1)
            self.assertEqual(s.samples, 1)

    def test_images_written(self):
        tmp = tempfile.mkdtemp(dir=os.environ.get("BRUME_TMP"))
        path = os.path.join(tmp, "x.png")
        img = np.zeros((4, 4, 4), np.float32)
        self.refused(lambda: brume.write(np.full((4, 4, 4), "grey"), path), "image: expected an array of numbers")
        self.refused(lambda: brume.write(img, path, exposure="bright"), "exposure: expected a number")
        self.refused(lambda: brume.write(img, 42), "path: expected a string")
        self.refused(lambda: brume.write(img, path + "\0.png"), "path: contains a NUL character")
        self.refused(lambda: brume.write(img, path, tonemap=["filmic"]), "tonemap: unknown value")
        self.refused(lambda: brume.Scene(scene(density={"type": "array", "data": [["a"]] * 2,
                                                        "bounds": [[0, 0, 0], [1, 1, 1]]})),
                     "media[0].density.data")
        self.assertFalse(os.path.exists(path))
        os.rmdir(tmp)


if __name__ == "__main__":
    unittest.main()
