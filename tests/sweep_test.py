"""Sweeps through the qmaps binary: every point's run in /sweep/runs/<k> equals, dataset for
dataset and byte for byte, the same point run alone on the scalar reference path, for every ISA
this machine runs and 1, 2 and 3 threads; /sweep's summaries agree with the points' own records;
a shell ensemble lies on each point's own energy surface; bad sweeps (a degenerate point, a
parameter the map lacks, a checkpoint) are refused before anything runs, with nothing written;
an interrupted sweep leaves no file."""
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

import small_run

BASE = small_run.fixture("flow-shell-chaos.toml")

AXES = """
[[sweep]]
parameter = "beta/alpha"
values = [1, 8]

[[sweep]]
parameter = "delta/alpha"
from = 2
to = 6
points = 2
"""

POINTS = [(1, 2), (1, 6), (8, 2), (8, 6)]  # (β/α, δ/α), the first axis slowest
REQUIRED = [i for i in os.environ.get("QMAPS_REQUIRE_ISAS", "").replace(";", ",").split(",") if i]


run = small_run.qmaps


def datasets(group):
    """Every dataset under `group`, by its path relative to it."""
    out = {}
    group.visititems(lambda name, item: out.__setitem__(name, item) if isinstance(item, h5py.Dataset) else None)
    return out


class Sweep(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        (cls.dir / "base.toml").write_text(BASE)
        (cls.dir / "sweep.toml").write_text(BASE + AXES)
        cls.isas = []
        for isa in ["sse2", "avx2", "avx512"]:
            r = run(cls.dir, "run", "sweep.toml", "--simd", isa, "--threads", "1", "--quiet",
                    "--out", f"sweep-{isa}-1.h5")
            if r.returncode == 4 and isa not in REQUIRED:
                continue  # not compiled, or not on this CPU
            assert r.returncode == 0, (isa, r.stderr)
            cls.isas.append(isa)
        print(f"[ ISAs run ] {' '.join(cls.isas)} (required: {','.join(REQUIRED)})")

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def alone(self, k):
        """Point k run alone, without [[sweep]], on the scalar path."""
        path = self.dir / f"alone-{k}.h5"
        if not path.exists():
            beta, delta = (0.5 * v for v in POINTS[k])
            r = run(self.dir, "run", "base.toml", "--simd", "scalar", "--quiet", "--set",
                    f"map.beta={beta!r}", "--set", f"map.delta={delta!r}", "--out", path.name)
            self.assertEqual(r.returncode, 0, r.stderr)
        return path

    def test_every_point_equals_its_run_alone_on_every_isa_and_thread_count(self):
        self.assertTrue(self.isas)
        for isa in self.isas:
            for threads in (1, 2, 3):
                name = f"sweep-{isa}-{threads}.h5"
                if threads > 1:
                    r = run(self.dir, "run", "sweep.toml", "--simd", isa, "--threads",
                            str(threads), "--quiet", "--out", name)
                    self.assertEqual(r.returncode, 0, r.stderr)
                with h5py.File(self.dir / name) as f:
                    runs = f["sweep/runs"]
                    self.assertEqual(sorted(runs), ["0", "1", "2", "3"])
                    for k in range(4):
                        with h5py.File(self.alone(k)) as g:
                            mine, theirs = datasets(runs[str(k)]), datasets(g)
                            self.assertEqual(sorted(mine), sorted(theirs), (isa, threads, k))
                            self.assertIn("sections/q1up/x", mine)
                            self.assertIn("chaos/megno", mine)
                            for path, d in theirs.items():
                                self.assertEqual(mine[path][()].tobytes(), d[()].tobytes(),
                                                 f"{isa}, {threads} threads, point {k}: {path}")
                            self.assertEqual(runs[str(k)].attrs["param.beta"], g.attrs["param.beta"])

    def test_the_summaries_agree_with_the_points_records(self):
        with h5py.File(self.dir / f"sweep-{self.isas[0]}-1.h5") as f:
            s = f["sweep"]
            self.assertEqual(s.attrs["axes"].decode(), "beta/alpha, delta/alpha")
            self.assertEqual(list(s["shape"][()]), [2, 2])
            self.assertEqual(list(s["axes/beta_over_alpha"][()]), [1.0, 8.0])
            self.assertEqual(list(s["axes/delta_over_alpha"][()]), [2.0, 6.0])
            self.assertEqual(list(s["parameters/beta"][()]), [0.5 * b for b, _ in POINTS])
            self.assertEqual(list(s["parameters/delta"][()]), [0.5 * d for _, d in POINTS])
            self.assertEqual(f.attrs["map"].decode(), "flow")
            for k in range(4):
                run_k = s[f"runs/{k}"]
                chaos = run_k["chaos"]
                self.assertEqual(s["orbits"][k], 37)
                self.assertEqual(s["escaped"][k], run_k.attrs["escaped"])
                self.assertEqual(s["regular"][k], chaos.attrs["regular"])
                self.assertEqual(s["chaotic"][k], chaos.attrs["chaotic"])
                self.assertEqual(s["chaotic_fraction"][k], chaos.attrs["chaotic_fraction"])
                self.assertEqual(s["median_megno"][k], chaos["histograms/megno"].attrs["median"])
                self.assertEqual(s["median_lyapunov"][k],
                                 chaos["histograms/lyapunov"].attrs["median"])
                bounded = run_k["escape/step"][()] < 0
                worst = 0.0
                for name in run_k["invariants"]:
                    g = run_k["invariants"][name]
                    scale = np.abs(g["initial"][()])
                    drift = g["max_abs_drift"][()]
                    rel = np.where(scale > 0, drift / np.where(scale > 0, scale, 1), drift)
                    worst = max(worst, rel[bounded].max())
                self.assertEqual(s["worst_drift"][k], worst)
                # Case I (1, 2) and case IV (8, 6) have a second integral; the others H alone.
                self.assertEqual(sorted(run_k["invariants"]),
                                 {0: ["H", "I_case1"], 3: ["H", "I_case4"]}.get(k, ["H"]))

    def test_a_shell_lies_on_each_points_own_energy_surface(self):
        # Tolerance against an independent reference: the shell's H = E, solved per point.
        with h5py.File(self.dir / f"sweep-{self.isas[0]}-1.h5") as f:
            for k in range(4):
                h = f[f"sweep/runs/{k}/invariants/H/initial"][()]
                np.testing.assert_allclose(h, 0.6, rtol=1e-13, atol=0)

    def test_the_plot_draws_the_parameter_plane(self):
        out = self.dir / "plots"
        r = subprocess.run([sys.executable, str(small_run.TOOLS / "qmaps-plot"),
                            str(self.dir / f"sweep-{self.isas[0]}-1.h5"), "-o", str(out)],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        image = out / f"sweep-{self.isas[0]}-1-sweep.png"
        self.assertEqual(r.stdout.split(), [str(image)])
        self.assertGreater(image.stat().st_size, 10000)

    def test_info_lists_every_point(self):
        r = run(self.dir, "info", f"sweep-{self.isas[0]}-1.h5")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("map:        flow, sweep of 4 points over beta/alpha, delta/alpha, 300 steps",
                      r.stdout)
        with h5py.File(self.dir / f"sweep-{self.isas[0]}-1.h5") as f:
            fraction = f["sweep/chaotic_fraction"][()]
        rows = [line.split() for line in r.stdout.splitlines()[3:]]
        self.assertEqual([row[:3] for row in rows], [[str(k), str(b), str(d)] for k, (b, d) in enumerate(POINTS)])
        self.assertEqual([float(row[5]) for row in rows], [float(f"{v:.3g}") for v in fraction])

    def refused(self, extra, *sets):
        d = pathlib.Path(tempfile.mkdtemp(dir=self.dir))
        (d / "c.toml").write_text(extra)
        r = run(d, "run", "c.toml", "--quiet", *sum((["--set", s] for s in sets), []))
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertEqual(sorted(os.listdir(d)), ["c.toml"])
        return r.stderr

    def test_bad_sweeps_are_refused_before_anything_runs(self):
        suris = re.sub(r'name = "flow".*?order = 6\n', 'name = "suris"\nA = 1.0\nB = 0.5\n'
                       'alpha = 0.9\nh = 0.1\n', BASE, flags=re.S)
        suris = suris.replace("[chaos]\n", "").replace('kind = "shell"', 'kind = "box"')
        suris = re.sub(r"energy = 0.6\n", "p2 = [-0.5, 0.5]\n", suris)
        err = self.refused(suris + '[[sweep]]\nparameter = "h"\nvalues = [0.1, 0.5, 1.0]\n')
        self.assertIn("[[sweep]] point 2 (h = 1): ", err)
        self.assertIn("1 - A h^2 = 0: the map degenerates", err)
        err = self.refused(BASE + '\n[[sweep]]\nparameter = "gamma"\nvalues = [1]\n')
        line = (BASE + "\n").count("\n") + 2
        self.assertIn(f"c.toml:{line}: [sweep[0]] parameter: flow has no parameter 'gamma'", err)
        err = self.refused(BASE + AXES, "run.checkpoint_every=10")
        self.assertIn("a sweep keeps no checkpoint", err)
        err = self.refused(BASE + AXES + "\n[ensemble2]\n")
        self.assertIn("ensemble2", err)

    def test_an_interrupted_sweep_leaves_nothing(self):
        d = pathlib.Path(tempfile.mkdtemp(dir=self.dir))
        (d / "c.toml").write_text(BASE + AXES)
        r = run(d, "run", "c.toml", "--quiet", env={"QMAPS_SIGNAL_AT_STEP": "100:INT"})
        self.assertEqual(r.returncode, 5, r.stderr)
        self.assertIn("SIGINT at step 100 of 300: a sweep keeps no checkpoint", r.stderr)
        self.assertEqual(sorted(os.listdir(d)), ["c.toml"])


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
