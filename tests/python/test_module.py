"""The Python module against the CLI (issue 24): the same render bit for bit, the options'
checks and messages, the arrays' shapes, the files written only when asked for, clpt.diff's
figures as clpt-diff's, and Ctrl-C stopping a render.

Run by ctest (Python.Module) with PYTHONPATH at the built module and CLPT_BINARY,
CLPT_DIFF_BINARY and CLPT_SCENE set; also runnable by hand the same way.
"""
import json
import os
import signal
import subprocess
import tempfile
import threading
import time
import unittest

import numpy as np

import clpt

CLPT = os.environ["CLPT_BINARY"]
CLPT_DIFF = os.environ["CLPT_DIFF_BINARY"]
SCENE = os.environ["CLPT_SCENE"]  # the bundled Cornell box


def run_cli(*args):
    return subprocess.run([CLPT, *args], capture_output=True, text=True, timeout=300)


class Module(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.path = lambda name: os.path.join(self.dir.name, name)

    def tearDown(self):
        self.dir.cleanup()

    def test_same_image_as_the_cli_bit_for_bit(self):
        # pt with its variance layer and a filter; ao. (Integrators that splat, bdpt say, add
        # with float atomics in no fixed order: their images are not bit-reproducible at all.)
        for integrator, extra in (("pt", {"sampler": "sobol", "variance": True, "filter": "gaussian"}),
                                  ("ao", {"max_depth": 4})):
            with self.subTest(integrator=integrator):
                args = ["--integrator", integrator, "--spp", "8", "--resolution", "24x16", "--seed", "7",
                        "--device", "pocl", "-q", "-o", self.path(integrator + ".exr")]
                for k, v in extra.items():
                    args += ["--" + k.replace("_", "-")] + ([] if v is True else [str(v)])
                cli = run_cli(SCENE, *args)
                self.assertEqual(cli.returncode, 0, cli.stderr)
                r = clpt.render(SCENE, integrator=integrator, spp=8, resolution=(24, 16), seed=7,
                                device="pocl", quiet=True, **extra)
                self.assertEqual(r.image.shape, (16, 24, 3))
                self.assertEqual(r.image.dtype, np.float32)
                self.assertEqual(r.spp, 8)
                f = clpt.read_image(self.path(integrator + ".exr"))
                self.assertTrue(np.array_equal(r.image, f["image"]), "the module's image is the CLI's")
                self.assertGreater(float(r.image.mean()), 0.01)
                self.assertEqual(f["metadata"]["clpt:spp"], 8)
                if integrator == "pt":
                    self.assertTrue(np.array_equal(r.layers["variance"], f["layers"]["variance"]))
                    self.assertTrue(np.array_equal(r.variance, r.layers["variance"]))
                else:
                    self.assertEqual(r.layers, {}, "no layer unless asked for")
        bdpt = clpt.render(SCENE, integrator="bdpt", spp=2, resolution=(8, 8), quiet=True)
        self.assertIsNone(bdpt.variance, "bdpt splats light paths: no per-pixel variance")

    def test_aov_layers_and_pfm_files(self):
        r = clpt.render(SCENE, spp=4, resolution=(16, 12), aov="albedo,normal,depth,material-id", quiet=True,
                        output=self.path("a.exr"), aov_pfm=True)
        self.assertEqual(r.layers["Albedo"].shape, (12, 16, 3))
        self.assertEqual(r.layers["Normal"].shape, (12, 16, 3))
        self.assertEqual(r.layers["Depth"].shape, (12, 16), "one-channel layers are 2-D")
        self.assertEqual(r.layers["IndexMA"].shape, (12, 16))
        self.assertTrue(np.all(r.layers["Depth"] > 0.0))
        f = clpt.read_image(self.path("a.exr"))
        self.assertTrue(np.array_equal(f["layers"]["Depth"], r.layers["Depth"]))
        self.assertTrue(np.array_equal(f["layers"]["Normal"], r.layers["Normal"]))
        for name in ("color", "albedo", "normal"):
            self.assertTrue(os.path.isfile(self.path(f"a.{name}.pfm")), name)
        with open(self.path("a.albedo.pfm"), "rb") as pfm:  # PF, 16 x 12, little-endian, rows bottom up
            self.assertEqual(pfm.readline(), b"PF\n")
            self.assertEqual(pfm.readline(), b"16 12\n")
            self.assertEqual(pfm.readline(), b"-1.0\n")
            rows = np.frombuffer(pfm.read(), dtype="<f4").reshape(12, 16, 3)
        self.assertTrue(np.array_equal(rows[::-1], r.layers["Albedo"]))

    def test_stats_are_the_clis_document(self):
        cli = run_cli(SCENE, "--spp", "2", "--resolution", "16x16", "--device", "pocl", "-q",
                      "-o", self.path("a.exr"), "--stats", self.path("a.json"))
        self.assertEqual(cli.returncode, 0, cli.stderr)
        with open(self.path("a.json")) as f:
            cli_stats = json.load(f)
        r = clpt.render(SCENE, spp=2, resolution=(16, 16), device="pocl", quiet=True)
        self.assertEqual(set(r.stats), set(cli_stats))
        self.assertEqual(r.stats["spp"], 2)
        self.assertEqual(r.stats["resolution"], [16, 16])
        self.assertEqual(r.metadata["clpt:integrator"], "pt")

    def test_files_only_when_asked_for(self):
        cwd = os.getcwd()
        os.chdir(self.dir.name)
        try:
            clpt.render(SCENE, spp=1, resolution=(8, 8), quiet=True)
            self.assertEqual(os.listdir("."), [], "no output= : nothing written")
            r = clpt.render(SCENE, spp=1, resolution=(8, 8), quiet=True, output="x.png", view="agx",
                            stats="s.json")
            self.assertEqual(sorted(os.listdir(".")), ["s.json", "x.png"])
            self.assertEqual(r.metadata["clpt:view"], "agx")
        finally:
            os.chdir(cwd)

    def test_bad_options_raise_the_clis_errors(self):
        cases = [({"max_depth": -1}, ["--max-depth=-1"]),
                 ({"resolution": (0, 3)}, ["--resolution=0x3"]),
                 ({"integrator": "nope"}, ["--integrator=nope"]),
                 ({"bdpt_strategy": (1, 1), "integrator": "bdpt"}, ["--bdpt-strategy=1,1", "--integrator=bdpt"]),
                 ({"limit": {"triangles": 3}}, ["--limit=triangles=3"])]
        for kwargs, argv in cases:
            with self.subTest(kwargs=kwargs):
                cli = run_cli(SCENE, *argv, "-o", self.path("never.exr"))
                self.assertNotEqual(cli.returncode, 0)
                with self.assertRaises(clpt.Error) as e:
                    clpt.render(SCENE, quiet=True, **kwargs)
                self.assertEqual(e.exception.exit_code, cli.returncode)
                first_line = str(e.exception).splitlines()[0]
                self.assertIn(first_line, cli.stderr)
        with self.assertRaises(clpt.Error) as e:
            clpt.render(os.path.join(self.dir.name, "missing.gltf"))
        self.assertEqual(e.exception.exit_code, 2)
        self.assertIn("missing.gltf", str(e.exception))
        with self.assertRaises(clpt.Error) as e:
            clpt.render(SCENE, save_every=1)
        self.assertIn("--save-every", str(e.exception))
        self.assertFalse(os.path.exists(self.path("never.exr")))

    def test_diff_matches_clpt_diff(self):
        for name, seed in (("a", 1), ("b", 2)):
            cli = run_cli(SCENE, "--spp", "16", "--resolution", "16x16", "--seed", str(seed), "--variance",
                          "-q", "-o", self.path(name + ".exr"))
            self.assertEqual(cli.returncode, 0, cli.stderr)
        tool = subprocess.run([CLPT_DIFF, "--json", self.path("a.exr"), self.path("b.exr")],
                              capture_output=True, text=True, timeout=60)
        self.assertEqual(tool.returncode, 0, tool.stderr)
        expected = json.loads(tool.stdout)
        got = clpt.diff(self.path("a.exr"), self.path("b.exr"))
        for key in ("relmse", "mse", "smape", "max_abs_diff", "compared"):
            self.assertEqual(got[key], expected[key], key)
        self.assertEqual(got["z_test"]["passed"], expected["z_test"]["passed"])
        self.assertGreater(got["relmse"], 0.0)
        a = clpt.read_image(self.path("a.exr"))["image"]
        self.assertEqual(clpt.diff(a, a)["relmse"], 0.0)
        self.assertAlmostEqual(clpt.diff(a, a + 1.0)["max_abs_diff"], 1.0, places=5)
        with self.assertRaises(clpt.Error):
            clpt.diff(a, a[:8])  # sizes differ
        with self.assertRaises(clpt.Error):
            clpt.diff(a, np.zeros((16, 16)))  # not RGB

    def test_ctrl_c_stops_the_render_and_saves(self):
        # SIGINT from another thread while a 120-second render runs: the render stops after the
        # pass in flight, writes what it has, and KeyboardInterrupt reaches the caller.
        timer = threading.Timer(1.5, lambda: os.kill(os.getpid(), signal.SIGINT))
        timer.start()
        start = time.monotonic()
        try:
            with self.assertRaises(KeyboardInterrupt):
                clpt.render(SCENE, time=120, resolution=(16, 16), quiet=True, output=self.path("i.exr"))
        finally:
            timer.cancel()
        self.assertLess(time.monotonic() - start, 60.0, "the interrupt ended the render")
        saved = clpt.read_image(self.path("i.exr"))
        self.assertGreater(saved["metadata"]["clpt:spp"], 0)

    def test_devices(self):
        devices = clpt.devices()
        self.assertTrue(any("pocl" in d["platform"].lower() or "portable" in d["platform"].lower()
                            for d in devices), devices)
        for d in devices:
            self.assertRegex(d["device"], r"^\d+:\d+$")


if __name__ == "__main__":
    unittest.main(verbosity=2)
