"""The tunes ([tunes]: /tunes/nu1, nu2 over steps 1..N, nu1_second, nu2_second over N+1..2N, and
diffusion) of Suris' map against exact references (tests/tune_references.py):

a) α = 0, where the map is linear: ν1 = arccos(1 − Ah²)/(2π), ν2 = arccos(1 − Bh²)/(2π);
b) the invariant plane q2 = p2 = 0, where the map is McMillan's: ν1 = Danilov's rotation number
   of the orbit's level curve, folded to [0, 1/2]; within the tolerance at N = 2048, and the
   error falling as a power of N: for the Hann window of order p = 2, as N⁻⁶ (the fitted slope of
   log max error against log N over N = 256 .. 2048 must be below a bound).

Each orbit's reference is computed from its two-step state as the engine starts it: the same
configuration without [tunes], run for 0 steps, leaves it in /final/state (q1_n, q1_n+1); it must
also be the start rule applied to /initial (tune_references.suris_start).

The orbits are `line` ensembles ([ensemble] kind = "line", from = [q1, q2, p1, p2], to = [...],
orbits; the other kinds are box, grid, shell and file, docs/cli.md). The references' own
validation (tune_references.SelfTest: direct iteration, elliptic integrals) runs here too.

Run as /usr/bin/python3 -B tests/tunes_test.py, with QMAPS_BINARY and QMAPS_SOURCE_DIR as CMake
sets them (by hand: build/qmaps and this checkout).
"""
import math
import os
import pathlib
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

import small_run
import tune_references as ref
from tune_references import SelfTest as ReferencesSelfTest  # noqa: F401 (run with these tests)

# Tolerances, each against an exact reference (never between two runs of the engine).
LINEAR_TUNE_VS_EXACT = 1e-10        # |ν − arccos(1 − Ah²)/2π| at N = 2048, default order
MCMILLAN_TUNE_VS_DANILOV = 1e-10    # |ν1 − fold(τ/T)| at N = 2048, order 2
MCMILLAN_ERROR_SLOPE_BELOW = -4.0   # d log(max error)/d log N at order 2 (theory: −6)
RESOLVED_ERROR_ABOVE = 1e-12        # the smallest N's max error must exceed this, or the slope
                                    # is round-off's and the amplitudes must change

LINEAR = {"A": 0.5, "B": 0.8, "alpha": 0.0, "h": 0.1}
LINEAR_LINE = {"orbits": 9, "from": [0.1, 0.05, 0.0, 0.0], "to": [0.5, 0.4, 0.2, -0.1]}
PLANE = {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1}  # the suris preset's map
# q1 from 0.1 to 1.5 on q2 = p2 = 0, p1 = 0 (bounded for α > 0): tunes 0.019 .. 0.043, whose
# errors at N = 256 are 1e-9 .. 2e-7, well above round-off.
PLANE_LINE = {"orbits": 16, "from": [0.1, 0.0, 0.0, 0.0], "to": [1.5, 0.0, 0.0, 0.0]}
WINDOW = 2048
WINDOWS = [256, 512, 1024, 2048]
# The flow's orbits (tunes-flow.toml's grid on its section) classed by diffusion and by MEGNO
FLOW_GRID, FLOW_STEPS = 16, 32768
CLASSES_AGREE_AT_LEAST = 0.9


def toml_value(value):
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return repr(float(value)) if isinstance(value, float) else str(value)


def config_text(params, line, steps, tunes=None):
    """A Suris run of the `line` ensemble for `steps` steps; with `tunes` ({window, order?}) its
    [tunes] table."""
    def table(name, entries):
        return f"[{name}]\n" + "".join(f"{key} = {toml_value(value)}\n"
                                       for key, value in entries.items()) + "\n"
    text = table("map", {"name": "suris", **params})
    text += table("ensemble", {"kind": "line", "start": "taylor", **line})
    text += table("run", {"steps": steps})
    if tunes is not None:
        text += table("tunes", {**tunes, "bins": 100})
    return text


def run(directory, name, text, *sets):
    """Runs the configuration `text` (extra `--set` options `sets`); returns the file's path."""
    directory = pathlib.Path(directory)
    path, out = directory / f"{name}.toml", directory / f"{name}.h5"
    path.write_text(text)
    args = [str(small_run.BINARY.absolute()), "run", str(path), "--out", str(out), "--quiet"]
    for s in sets:
        args += ["--set", s]
    done = subprocess.run(args, capture_output=True, text=True, cwd=directory)
    if done.returncode != 0:
        raise AssertionError(f"qmaps run {path.name} failed ({done.returncode}):\n{text}\n"
                             f"{done.stderr}")
    return out


class InFolder(unittest.TestCase):
    """Tests that run in one scratch folder of their class."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()


class Tunes(InFolder):

    def starts(self, name, params, line):
        """Each orbit's two-step start (q1_0, q2_0, q1_1, q2_1), from a run of 0 steps."""
        path = run(self.dir, f"{name}-start", config_text(params, line, 0))
        with h5py.File(path, "r") as f:
            state = f["final/state"]
            self.assertEqual(state.attrs["step"], 0)
            starts = np.stack([state[c][()] for c in ("q1_n", "q2_n", "q1_n+1", "q2_n+1")], 1)
            initial = np.stack([f["initial"][c][()] for c in ("q1", "q2", "p1", "p2")], 1)
        for point, start in zip(initial, starts):
            self.assertEqual(ref.suris_start(*map(float, point), params["A"], params["B"],
                                             params["alpha"], params["h"]), tuple(start))
        return starts

    def tunes(self, name, params, line, window, order=None):
        """The /tunes columns of a run of `line` for 2 `window` steps (order: the default)."""
        tunes = {"window": window, **({"order": order} if order is not None else {})}
        path = run(self.dir, f"{name}-{window}", config_text(params, line, 2 * window, tunes))
        with h5py.File(path, "r") as f:
            columns = {name: f["tunes"][name][()] for name in
                       ("nu1", "nu2", "nu1_second", "nu2_second", "diffusion")}
            self.assertTrue(np.all(f["escape/step"][()] == -1), "no orbit escapes")
        for name, values in columns.items():
            self.assertEqual(values.dtype, np.float64, name)
            self.assertEqual(values.shape, (line["orbits"],), name)
        return columns

    def test_linear_tunes_against_arccos(self):
        nu1, nu2 = (float(nu) for nu in ref.suris_linear_tunes(LINEAR["A"], LINEAR["B"],
                                                               LINEAR["h"]))
        got = self.tunes("linear", LINEAR, LINEAR_LINE, WINDOW)
        for name, exact in (("nu1", nu1), ("nu2", nu2), ("nu1_second", nu1), ("nu2_second", nu2)):
            error = np.abs(got[name] - exact)
            print(f"linear {name}: exact {exact:.17f}, max |error| {error.max():.2e}")
            self.assertTrue(np.all(error <= LINEAR_TUNE_VS_EXACT), f"{name}: {got[name]} vs {exact}")
        # both windows within the tolerance of the same tune: |Δν| <= 2√2 tolerance
        self.assertTrue(np.all(got["diffusion"] <= math.log10(2 * math.sqrt(2) *
                                                              LINEAR_TUNE_VS_EXACT)))

    def danilov(self, starts):
        a, _, g = ref.suris_coefficients(PLANE["A"], PLANE["B"], PLANE["alpha"], PLANE["h"])
        for s in starts:
            self.assertEqual((s[1], s[3]), (0.0, 0.0), "the orbit starts on the plane q2 = p2 = 0")
        return np.array([float(ref.mcmillan_tune(s[0], s[2], a, g)) for s in starts])

    def test_mcmillan_plane_against_danilov(self):
        exact = self.danilov(self.starts("plane", PLANE, PLANE_LINE))
        errors = {}
        for window in WINDOWS:
            got = self.tunes("plane", PLANE, PLANE_LINE, window, order=2)
            errors[window] = np.abs(got["nu1"] - exact)
            self.assertTrue(np.all(np.isfinite(errors[window])), f"N = {window}: {got['nu1']}")
            if window == WINDOW:
                second = np.abs(got["nu1_second"] - exact)
                for name, error in (("nu1", errors[window]), ("nu1_second", second)):
                    self.assertTrue(np.all(error <= MCMILLAN_TUNE_VS_DANILOV),
                                    f"{name} at N = {window}: errors {error}")
                self.assertTrue(np.all(got["diffusion"] <= math.log10(
                    2 * MCMILLAN_TUNE_VS_DANILOV)))
        worst = np.array([errors[n].max() for n in WINDOWS])
        slope = np.polyfit(np.log(WINDOWS), np.log(worst), 1)[0]
        print(f"McMillan plane, tunes {exact.min():.4f} .. {exact.max():.4f} (Danilov), order 2:")
        print("     N   max |nu1 - Danilov|")
        for n, e in zip(WINDOWS, worst):
            print(f"  {n:4d}   {e:.3e}")
        print(f"  fitted slope {slope:.2f} (theory -6)")
        self.assertGreater(worst[0], RESOLVED_ERROR_ABOVE,
                           "the error at the smallest N is round-off: the slope is not measured")
        self.assertLess(slope, MCMILLAN_ERROR_SLOPE_BELOW)


def qmaps(directory, *args, env=None):
    """The binary run in `directory`, its output captured as text."""
    return subprocess.run([str(small_run.BINARY.absolute()), *map(str, args)], capture_output=True,
                          text=True, cwd=directory, env={**os.environ, **(env or {})})


class TunesOfRuns(InFolder):
    """Bad [tunes] tables, orbits escaping within the windows, interruptions, and the diffusion's
    classes against MEGNO's on the non-integrable flow."""

    def test_a_bad_table_is_refused_naming_its_key_and_line(self):
        cases = [("window = 100", "tunes.window", "power of two"),
                 ("window = 16", "tunes.window", "power of two from 32"),
                 ("window = 2048", "tunes.window", "need 4096 steps"),
                 ("window = 64\norder = 9", "tunes.order", "1 to 8"),
                 ("window = 64\norder = 0", "tunes.order", "1 to 8"),
                 ("window = 64\norder = \"hann\"", "tunes.order", ""),
                 ("window = 64\nbins = 0", "tunes.bins", "1 to 4096"),
                 ("window = 64\ndiffusion_threshold = 1.0", "tunes.diffusion_threshold", "below 0"),
                 ("window = 64\nwindows = 2", "windows", "")]
        for table, key, words in cases:
            with self.subTest(table=table):
                text = config_text(PLANE, PLANE_LINE, 1000) + "[tunes]\n" + table + "\n"
                (self.dir / "bad.toml").write_text(text)
                r = qmaps(self.dir, "run", "bad.toml", "--out", "bad.h5", "--quiet")
                self.assertEqual(r.returncode, 2, r.stderr)
                line = text.splitlines().index(table.split("\n")[-1]) + 1
                self.assertIn(f"bad.toml:{line}", r.stderr)
                self.assertIn(key.split(".")[-1], r.stderr)
                self.assertIn(words, r.stderr)
                self.assertFalse((self.dir / "bad.h5").exists())
        for option, words in (("--tunes=100", "power of two"), ("--tunes=1024", "need 2048 steps")):
            r = qmaps(self.dir, "orbit", "--map", "suris", *(f"--set={k}={v}" for k, v in PLANE.items()),
                      "--ic", "0.1,0.1,0,0", "--steps", 1000, option)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn(words, r.stderr)

    def test_an_orbit_escaping_within_the_windows_has_nan_tunes_and_is_counted(self):
        # escape_bound 0.6: the line's outer orbits leave within the windows, the inner ones stay
        line = {"orbits": 12, "from": [0.05, 0.05, 0.0, 0.0], "to": [0.9, 0.9, 0.0, 0.0]}
        path = run(self.dir, "escapes", config_text(PLANE, line, 300, {"window": 128}),
                   "run.escape_bound=0.6")
        with h5py.File(path, "r") as f:
            step = f["escape/step"][()]
            inside = (step >= 0) & (step <= 256)
            self.assertGreater(inside.sum(), 0)
            self.assertGreater((step < 0).sum(), 0)
            for name in ("nu1", "nu2", "nu1_second", "nu2_second", "diffusion"):
                values = f["tunes"][name][()]
                self.assertTrue(np.all(np.isnan(values[inside])), name)
                self.assertTrue(np.all(np.isfinite(values[step < 0])), name)
            self.assertEqual(f["tunes"].attrs["escaped"], inside.sum())
            self.assertTrue(np.all(f["tunes/class"][()][inside] == 2))

    def test_an_interrupted_run_resumes_to_the_same_bytes(self):
        text = config_text(PLANE, PLANE_LINE, 400, {"window": 128})
        whole = run(self.dir, "whole", text)
        # a checkpoint every 50 steps and a signal at step 70, both inside the windows: answered
        # at their end (step 256), then resumed
        (self.dir / "cut.toml").write_text(text)
        r = qmaps(self.dir, "run", "cut.toml", "--out", "cut.h5", "--quiet", "--set",
                  "run.checkpoint_every=50", env={"QMAPS_SIGNAL_AT_STEP": "70:INT"})
        self.assertEqual(r.returncode, 5, r.stderr)
        with h5py.File(self.dir / "cut.h5.ckpt", "r") as f:
            self.assertEqual(f["final/state"].attrs["step"], 256)
        r = qmaps(self.dir, "run", "--resume", "cut.h5.ckpt", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(whole, "r") as a, h5py.File(self.dir / "cut.h5", "r") as b:
            for name in ("nu1", "nu2", "nu1_second", "nu2_second", "diffusion", "class"):
                self.assertEqual(a["tunes"][name][()].tobytes(), b["tunes"][name][()].tobytes(), name)
            for name in ("q1", "q2", "p1", "p2"):
                self.assertEqual(a["final"][name][()].tobytes(), b["final"][name][()].tobytes(), name)

    def test_diffusion_classes_agree_with_megno_on_the_non_integrable_flow(self):
        preset = small_run.SOURCE_DIR / "ensembles" / "presets" / "tunes-flow.toml"
        text = preset.read_text() + "\n[chaos]\n"
        path = self.dir / "flow.toml"
        path.write_text(text)
        r = qmaps(self.dir, "run", path, "--out", "flow.h5", "--quiet", "--set",
                  f"ensemble.points=[1, {FLOW_GRID}, {FLOW_GRID}]", "--set",
                  f"run.steps={FLOW_STEPS}")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(self.dir / "flow.h5", "r") as f:
            megno = f["chaos/class"][()]
            diffusion = f["tunes/class"][()]
            threshold = f["tunes"].attrs["diffusion_threshold"]
            megno_threshold = f["chaos"].attrs["megno_threshold"]
        both = (megno < 2) & (diffusion < 2)
        table = np.zeros((2, 2), int)
        for m, d in zip(megno[both], diffusion[both]):
            table[m, d] += 1
        agree = (table[0, 0] + table[1, 1]) / table.sum()
        print(f"flow, {both.sum()} bounded orbits, {FLOW_STEPS} steps: MEGNO class (threshold "
              f"{megno_threshold}) against diffusion class (threshold {threshold}, windows of "
              f"{FLOW_STEPS // 2} steps)")
        print("                  diffusion regular   diffusion chaotic")
        print(f"  MEGNO regular   {table[0, 0]:17d}   {table[0, 1]:17d}")
        print(f"  MEGNO chaotic   {table[1, 0]:17d}   {table[1, 1]:17d}")
        print(f"  agreement {agree:.3f}")
        self.assertGreater(table[0, 0], 0)
        self.assertGreater(table[1, 1], 0)
        self.assertGreaterEqual(agree, CLASSES_AGREE_AT_LEAST)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1] + ["-v"] + sys.argv[1:])
