"""qmaps-plot (qmaps.plot) on a small run with every kind of observer: it writes the predictable names at
the documented pixel sizes (6.4 x 4.8 in, summary panels 5 x 4 in, at --dpi), every image has
content, each panel draws what the file holds (log colour scale, points coloured by their orbit's
invariant or chaos indicator, density when capped, machine epsilon), and bad input is a clear error that writes
nothing."""
import contextlib
import io
import math
import pathlib
import shutil
import subprocess
import sys
import tempfile
import tomllib
import unittest

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.colors  # noqa: E402
import matplotlib.image  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import small_run  # noqa: E402
import qmaps  # noqa: E402
from qmaps import plot  # noqa: E402

SCRIPT = small_run.TOOLS / "qmaps-plot"

KINDS = ["histogram-p1", "histogram-q1q2", "section-q1up", "section-q2both", "drift",
         "energy-momentum"]


def run_script(*args, cwd):
    """The script as a command, as users run it."""
    return subprocess.run([sys.executable, "-B", str(SCRIPT), *map(str, args)], cwd=cwd,
                          capture_output=True, text=True)


def run_main(*args):
    """The script's main() in this process (quicker): (exit status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            status = plot.main(list(map(str, args)))
        except SystemExit as e:
            status = e.code
    return status, out.getvalue(), err.getvalue()


class PlotTool(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        cls.path = small_run.small_run(cls.dir, orbits=1000, steps=200, name="run.h5")
        cls.loaded = qmaps.load(cls.path)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def axes_of(self, kind, run=None):
        """A fresh Axes with the picture `kind` of `run` (default the small run) drawn on it."""
        fig = plt.figure()
        self.addCleanup(plt.close, fig)
        ax = fig.add_subplot()
        dict(plot.items(run or self.loaded, "H"))[kind](ax)
        return ax

    def test_writes_every_picture_at_its_size(self):
        out = self.dir / "png"
        r = run_script(self.path, "-o", out, "--dpi", 50, cwd=self.dir)
        self.assertEqual(r.returncode, 0, r.stderr)
        names = [f"run-{k}.png" for k in KINDS] + ["run-summary.png"]
        self.assertEqual(r.stdout.split(), [str(out / n) for n in names])
        self.assertEqual(sorted(p.name for p in out.iterdir()), sorted(names))
        columns, rows = plot.summary_grid(len(KINDS))
        self.assertEqual((columns, rows), (3, 2))
        self.assertEqual(plot.summary_grid(4), (2, 2))
        self.assertEqual(plot.summary_grid(1), (1, 1))
        for name in names:
            with self.subTest(image=name):
                pixels = matplotlib.image.imread(out / name)
                expected = (200 * rows, 250 * columns) if "summary" in name else (240, 320)
                self.assertEqual(pixels.shape[:2], expected)
                ink = (pixels[..., :3] < 0.9).any(axis=2).mean()
                self.assertGreater(ink, 0.02, "mostly blank")
                colours = len(np.unique(pixels.reshape(-1, pixels.shape[2]), axis=0))
                self.assertGreater(colours, 50, "no colour map or curve drawn")

    def test_pdf_of_a_run_without_observers(self):
        bare = self.dir / "bare.h5"
        shutil.copyfile(self.path, bare)
        with h5py.File(bare, "a") as f:
            for path in ("histograms", "sections", "invariants/image"):
                del f[path]
        out = self.dir / "pdf"
        status, stdout, err = run_main(bare, "-o", out, "--format", "pdf")
        self.assertEqual(status, 0, err)
        self.assertEqual(stdout.split(),
                         [str(out / "bare-drift.pdf"), str(out / "bare-summary.pdf")])
        for p in out.iterdir():
            self.assertEqual(p.read_bytes()[:5], b"%PDF-", p.name)

    def test_two_dimensional_histogram_on_log_scale(self):
        ax = self.axes_of("histogram-q1q2")
        image = ax.get_images()[0]
        counts = self.loaded["histograms/q1q2/counts"]
        self.assertIsInstance(image.norm, matplotlib.colors.LogNorm)
        np.testing.assert_array_equal(image.get_array().filled(0), counts.T)
        self.assertEqual((ax.get_xlabel(), ax.get_ylabel()), ("$q_{1}$", "$q_{2}$"))
        self.assertEqual(tuple(image.get_extent()), (-1.0, 1.0, -1.0, 1.0))
        self.assertEqual(ax.get_aspect(), 1.0, "both axes are coordinates: equal aspect")

    def test_one_dimensional_histogram_as_steps(self):
        ax = self.axes_of("histogram-p1")
        steps = ax.patches[-1]
        np.testing.assert_array_equal(steps.get_data().values, self.loaded["histograms/p1/counts"])
        self.assertEqual(ax.get_xlabel(), "$p_{1}$")
        attrs = self.loaded["histograms/p1"].attrs
        notes = " ".join(t.get_text() for t in ax.texts)
        self.assertIn(f"underflow {attrs['underflow']}, overflow {attrs['overflow']}", notes)

    def test_section_points_coloured_by_their_orbit_invariant(self):
        g = self.loaded["sections/q2both"]
        self.assertEqual(g.attrs["crossings"], len(g.datasets["x"]), "not capped")
        ax = self.axes_of("section-q2both")
        dots = ax.collections[0]
        np.testing.assert_array_equal(dots.get_offsets(),
                                      np.column_stack([g.datasets["x"], g.datasets["y"]]))
        np.testing.assert_array_equal(dots.get_array(),
                                      self.loaded["invariants/H/initial"][g.datasets["orbit"]])
        self.assertEqual((ax.get_xlabel(), ax.get_ylabel()), ("$q_{1}$", "$p_{1}$"))
        self.assertEqual(ax.get_aspect(), 1.0, "both axes are coordinates: equal aspect")

    def test_section_points_coloured_by_a_chaos_indicator(self):
        g = self.loaded["sections/q2both"]
        for name, values in (("megno", self.loaded["chaos/megno"]),
                             ("gali_2", np.log10(self.loaded["chaos/gali_2"]))):
            with self.subTest(indicator=name):
                fig = plt.figure()
                self.addCleanup(plt.close, fig)
                ax = fig.add_subplot()
                dict(plot.items(self.loaded, name))["section-q2both"](ax)
                np.testing.assert_array_equal(ax.collections[0].get_array(),
                                              values[g.datasets["orbit"]])

    def test_section_points_coloured_by_orbit(self):
        g = self.loaded["sections/q2both"]
        fig = plt.figure()
        self.addCleanup(plt.close, fig)
        ax = fig.add_subplot()
        dict(plot.items(self.loaded, "orbit"))["section-q2both"](ax)
        np.testing.assert_array_equal(ax.collections[0].get_array(), g.datasets["orbit"] % 20)

    def test_range_auto_spans_the_data_and_a_cut_range_says_so(self):
        g = self.loaded["sections/q2both"]
        x, y = g.datasets["x"], g.datasets["y"]
        fig = plt.figure()
        self.addCleanup(plt.close, fig)
        ax = fig.add_subplot()
        dict(plot.items(self.loaded, "H", auto=True))["section-q2both"](ax)
        low, high = ax.get_xlim()
        self.assertLessEqual(low, x.min())
        self.assertGreaterEqual(high, x.max())
        self.assertLess(high - low, 1.1 * (x.max() - x.min()) + 1e-12)
        h = self.axes_of("histogram-q1q2")  # the configured range
        self.assertEqual(h.get_xlim(), (-1.0, 1.0))
        fig = plt.figure()
        self.addCleanup(plt.close, fig)
        ax = fig.add_subplot()
        dict(plot.items(self.loaded, "H", auto=True))["histogram-q1q2"](ax)
        counts = self.loaded["histograms/q1q2/counts"]
        edges = self.loaded["histograms/q1q2/x_edges"]
        occupied = np.nonzero(counts.any(axis=1))[0]
        self.assertEqual(ax.get_xlim(), (edges[occupied[0]], edges[occupied[-1] + 1]))
        # A range that cuts points: the picture says how many.
        cut = qmaps.load(self.path)
        section = cut["sections/q2both"]
        section.datasets["x_edges"] = np.linspace(-0.1, 0.1, 65)
        fig = plt.figure()
        self.addCleanup(plt.close, fig)
        ax = fig.add_subplot()
        dict(plot.items(cut, "H"))["section-q2both"](ax)
        outside = int(((x < -0.1) | (x > 0.1)).sum())
        self.assertGreater(outside, 0)
        self.assertTrue(any(f"{outside} outside the configured range" in t.get_text()
                            for t in ax.texts))

    def test_symbols_for_coordinates_invariants_and_parameters(self):
        for name, written in (("q1", "$q_{1}$"), ("p2", "$p_{2}$"), ("H", "$H$"), ("I1", "$I_{1}$"),
                              ("I_case4", r"$I^{(\mathrm{IV})}$"), ("alpha", r"$\alpha$"),
                              ("gamma11", r"$\gamma_{11}$"), ("megno", "megno"), ("K+", "K+")):
            self.assertEqual(plot.symbol(name), written)
        title = plot.run_title(self.loaded, 200)
        self.assertIn(r"$\alpha$ = 0.9", title)

    def test_svg_at_the_default_dpi(self):
        out = self.dir / "svg"
        status, stdout, err = run_main(self.path, "-o", out, "--format", "svg")
        self.assertEqual(status, 0, err)
        self.assertEqual(len(stdout.split()), len(KINDS) + 1)
        for p in out.iterdir():
            self.assertIn(b"<svg", p.read_bytes()[:400], p.name)
        png = self.dir / "png200"
        status, _, err = run_main(self.path, "-o", png)
        self.assertEqual(status, 0, err)
        pixels = matplotlib.image.imread(png / "run-drift.png")
        self.assertEqual(pixels.shape[:2], (960, 1280))  # 4.8 x 6.4 in at 200 dpi

    def test_paper_style_fits_a_journal_column(self):
        out = self.dir / "paper"
        status, stdout, err = run_main(self.path, "-o", out, "--style", "paper")
        self.assertEqual(status, 0, err)
        pixels = matplotlib.image.imread(out / "run-section-q2both.png")
        self.assertEqual(pixels.shape[:2], (540, 680))  # 2.7 x 3.4 in (86 mm) at 200 dpi
        status, _, err = run_main(self.path, "-o", out, "--style", "paper", "--format", "pdf")
        self.assertEqual(status, 0, err)
        self.assertEqual((out / "run-summary.pdf").read_bytes()[:5], b"%PDF-")
        # Its type: 7 pt serif, 10 pt titles scaled to 7 pt; the screen style after it unchanged.
        with matplotlib.rc_context(plot.STYLES["paper"]["rc"]):
            plot.style = plot.STYLES["paper"]
            try:
                ax = self.axes_of("section-q2both")
                self.assertEqual(ax.title.get_fontsize(), 7.0)
                self.assertEqual(ax.xaxis.get_label().get_fontfamily(), ["serif"])
            finally:
                plot.style = plot.STYLES["screen"]
        self.assertEqual(self.axes_of("section-q2both").title.get_fontsize(), 10.0)

    def test_every_presets_section_figure_shows_several_orbits_in_several_colours(self):
        """Each preset's sections, run small (the tori and chaos presets at their own orbits),
        drawn as the tool draws them by default: points of more than one orbit, coloured with more
        than one value, or, capped, a density of more than one count."""
        presets = sorted((small_run.SOURCE_DIR / "ensembles" / "presets").glob("*.toml"))
        checked = 0
        for preset in presets:
            config = tomllib.loads(preset.read_text())
            if "section" not in config or "sweep" in config:
                continue
            with self.subTest(preset=preset.stem):
                sets = ["--set", "run.steps=3000"]
                if "orbits" in config.get("ensemble", {}) and not preset.stem.startswith(
                        ("tori", "chaos")):
                    sets += ["--set", "ensemble.orbits=300", "--set", "run.steps=300"]
                out = self.dir / f"{preset.stem}.h5"
                small_run.qmaps(self.dir, "run", preset, *sets, "--set", "output.per_orbit=true",
                                "--out", out, "--quiet").check_returncode()
                run = qmaps.load(out)
                colour = plot.default_colouring(run)
                for name in run["sections"].groups:
                    g = run["sections/" + name]
                    self.assertGreater(len(np.unique(g.datasets["orbit"])), 1, name)
                    fig = plt.figure()
                    self.addCleanup(plt.close, fig)
                    ax = fig.add_subplot()
                    dict(plot.items(run, colour))["section-" + name](ax)
                    if g.attrs["crossings"] > len(g.datasets["x"]):  # capped: the density
                        shown = ax.images[0].get_array().compressed()
                    else:
                        shown = ax.collections[0].get_array()
                    self.assertGreater(len(np.unique(shown)), 1, f"{name} coloured by {colour}")
                    checked += 1
        self.assertGreaterEqual(checked, 10)

    def test_capped_section_shows_its_density(self):
        g = self.loaded["sections/q1up"]
        self.assertGreater(g.attrs["crossings"], len(g.datasets["x"]), "capped")
        ax = self.axes_of("section-q1up")
        self.assertEqual(len(ax.collections), 0)
        image = ax.get_images()[0]
        self.assertIsInstance(image.norm, matplotlib.colors.LogNorm)
        np.testing.assert_array_equal(image.get_array().filled(0), g.datasets["density"].T)

    def test_run_without_steps_draws_empty_panels_as_such(self):
        path = small_run.small_run(self.dir, orbits=50, steps=0, name="still.h5")
        still = qmaps.load(path)
        self.assertEqual(len(still["sections/q2both/x"]), 0)
        for kind, says in (("section-q2both", "no points kept"), ("section-q2both", "no samples"),
                           ("drift", "no drift other than 0")):
            with self.subTest(kind=kind, says=says):
                ax = self.axes_of(kind, still)
                self.assertTrue(any(says in text.get_text() for text in ax.texts))
                self.assertEqual(len(ax.get_images()), 0)

    def test_drift_histograms_with_machine_epsilon(self):
        ax = self.axes_of("drift")
        self.assertEqual(len(ax.patches), 3)
        for steps, name in zip(ax.patches, ["H", "I1", "I2"]):
            np.testing.assert_array_equal(
                steps.get_data().values, self.loaded[f"invariants/{name}/drift_histogram/counts"])
        epsilon = [line.get_xdata()[0] for line in ax.lines]
        self.assertEqual(epsilon, [math.log10(2.0 ** -52)])
        self.assertEqual(ax.get_yscale(), "log")

    def test_energy_momentum_image(self):
        ax = self.axes_of("energy-momentum")
        image = ax.get_images()[0]
        np.testing.assert_array_equal(image.get_array().filled(0),
                                      self.loaded["invariants/image/counts"].T)
        self.assertEqual((ax.get_xlabel(), ax.get_ylabel()), ("$H$ (initial)", "$I_{1}$ (initial)"))

    def test_bad_input_is_a_clear_error_and_writes_nothing(self):
        text = self.dir / "text.h5"
        text.write_text("not hdf5\n")
        foreign = self.dir / "foreign.h5"
        with h5py.File(foreign, "w") as f:
            f.attrs["x"] = 1
        out = self.dir / "none"
        for args, status, message in (
                ([self.dir / "missing.h5"], 3, "missing.h5: no such file"),
                ([text], 3, "text.h5: not an HDF5 file"),
                ([foreign], 3, "foreign.h5: not a qmaps run"),
                ([self.path, "--format", "gif"], 2, "argument --format: invalid choice: 'gif'"),
                ([self.path, "--color-by", "K"], 2, "--color-by K: not orbit, and the run's "
                                                    "invariants are H, I1, I2; its chaos "
                                                    "indicators fli, gali_2, gali_4, lyapunov")):
            with self.subTest(message=message):
                got, stdout, stderr = run_main(*args, "-o", out)
                self.assertEqual(got, status, stderr)
                self.assertIn(message, stderr)
                self.assertEqual(stdout, "")
                self.assertFalse(out.exists() and any(out.iterdir()))


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
