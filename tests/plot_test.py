"""qmaps-plot (qmaps.plot) on a small run with every kind of observer: it writes the predictable names at
the documented pixel sizes (6.4 x 4.8 in, summary panels 5 x 4 in, at --dpi), every image has
content, each panel draws what the file holds (log colour scale, points coloured by their orbit's
invariant or chaos indicator, density when capped, machine epsilon), and bad input is a clear error that writes
nothing. The tunes' pictures (frequency map with its resonance lines, diffusion over a grid,
footprint, tunes along a line, diffusion histogram) are drawn from grid and line runs given a
/tunes group as the schema lays it out, with escaped orbits, a degree of freedom without
oscillation and orbits at the round-off floor, and from one written without per-orbit data."""
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
import unittest.mock

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


def axes_with(test, run, kind, color_by="H", **options):
    """A fresh Axes with the picture `kind` of `run` drawn on it by plot.items(run, color_by,
    **options)."""
    fig = plt.figure()
    test.addCleanup(plt.close, fig)
    ax = fig.add_subplot()
    dict(plot.items(run, color_by, **options))[kind](ax)
    return ax


def assert_drawn(test, path):
    """The image at `path` has ink and more colours than text alone: a colour map or curves."""
    pixels = matplotlib.image.imread(path)
    ink = (pixels[..., :3] < 0.9).any(axis=2).mean()
    test.assertGreater(ink, 0.02, "mostly blank")
    colours = len(np.unique(pixels.reshape(-1, pixels.shape[2]), axis=0))
    test.assertGreater(colours, 50, "no colour map or curve drawn")
    return pixels


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
        return axes_with(self, run or self.loaded, kind)

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
                pixels = assert_drawn(self, out / name)
                expected = (200 * rows, 250 * columns) if "summary" in name else (240, 320)
                self.assertEqual(pixels.shape[:2], expected)

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
        # A journal column's width, 3.4 in (86 mm) at 200 dpi; a height fitted to what it draws.
        self.assertEqual(pixels.shape[1], 680)
        self.assertLessEqual(pixels.shape[0], 680)
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
                ([self.path, "--resonance-order", "-1"], 2,
                 "--resonance-order -1: must be 0 (no lines) to 20"),
                ([self.path, "--resonance-order", "21"], 2,
                 "--resonance-order 21: must be 0 (no lines) to 20"),
                ([self.path, "--resonance-order", "two"], 2,
                 "argument --resonance-order: invalid int value: 'two'"),
                ([self.path, "--color-by", "K"], 2, "--color-by K: not orbit, and the run's "
                                                    "invariants are H, I1, I2; its chaos "
                                                    "indicators fli, gali_2, gali_4, lyapunov")):
            with self.subTest(message=message):
                got, stdout, stderr = run_main(*args, "-o", out)
                self.assertEqual(got, status, stderr)
                self.assertIn(message, stderr)
                self.assertEqual(stdout, "")
                self.assertFalse(out.exists() and any(out.iterdir()))


# Grid and line ensembles (the grid's outer coordinate p1, its inner q1; the line's q1 varies
# most), nothing observed but the invariants; their /tunes are written by write_tunes.
TUNE_MAP = """
[map]
name = "suris"
A = 0.7
B = 0.3
alpha = 0.9
h = 0.1
"""
GRID = TUNE_MAP + """
[ensemble]
kind = "grid"
axes = ["p1", "q1"]
points = [7, 6]
q1 = [-0.4, 0.4]
p1 = [-0.3, 0.3]
q2 = 0.1
p2 = 0.2
"""
LINE = TUNE_MAP + """
[ensemble]
kind = "line"
orbits = 15
from = [0.0, 0.0, 0.0, 0.1]
to = [0.5, 0.0, 0.0, 0.2]
"""
FLOOR = math.log10(2.0 ** -53)
THRESHOLD = -6.0
BINS = 16


def write_tunes(path, varying, per_orbit=True):
    """Adds /tunes to the run at `path` as the engine writes it (docs/hdf5-schema.md), for orbits
    starting at `varying` (the two coordinates that vary over the ensemble): nu1 rises with the
    first, nu2 falls with the second (crossing nu1 = nu2), the diffusion log10 |dnu| rises from
    -14 to -4 with the squared amplitude; the orbits of the least amplitude change by nothing (the
    floor), those beyond 0.21 escape, and orbit 1's second degree of freedom does not oscillate
    (nu2 NaN, its diffusion that of nu1)."""
    squares = varying[0] ** 2 + varying[1] ** 2
    nu = np.column_stack([0.2 + 0.25 * varying[0] ** 2 + 0.05 * varying[1] ** 2,
                          0.26 - 0.05 * varying[0] ** 2 - 0.6 * varying[1] ** 2])
    change = np.where(squares == squares.min(), 0.0, 10.0 ** (-14 + 40 * squares))
    second = nu + np.column_stack([change, np.zeros_like(change)])
    nu[1, 1] = second[1, 1] = np.nan
    escaped = squares > 0.21
    nu[escaped] = second[escaped] = np.nan
    size = np.sqrt(np.nansum((second - nu) ** 2, axis=1))
    round_off = (size < 2.0 ** -53) & ~escaped
    with np.errstate(divide="ignore"):
        diffusion = np.where(round_off, FLOOR, np.log10(size))
    diffusion[escaped] = np.nan
    classes = np.where(escaped, 2, diffusion > THRESHOLD).astype(np.uint8)
    counts = {c: np.int64((classes == k).sum())
              for k, c in enumerate(("regular", "chaotic", "escaped", "no_tune"))}
    with h5py.File(path, "a") as f:
        t = f.create_group("tunes")
        t.attrs.update(window=np.int64(64), order=np.int64(1), bins=np.int64(BINS),
                       signal="q1, q2", folding="[0, 1/2]", diffusion_floor=FLOOR,
                       diffusion_threshold=THRESHOLD, round_off=np.int64(round_off.sum()),
                       chaotic_fraction=counts["chaotic"] / (counts["regular"] + counts["chaotic"]),
                       class_codes="0 regular, 1 chaotic, 2 escaped, 3 no tune", **counts)
        if per_orbit:
            for j in (0, 1):
                t[f"nu{j + 1}"], t[f"nu{j + 1}_second"] = nu[:, j], second[:, j]
            t["diffusion"], t["class"] = diffusion, classes
        for name, values in (("nu1", nu[:, 0]), ("nu2", nu[:, 1]), ("diffusion", diffusion)):
            values = values[np.isfinite(values)]
            g = t.create_group(f"histograms/{name}")
            g["x_edges"] = np.linspace(values.min(), values.max(), BINS + 1)
            g["counts"] = np.histogram(values, g["x_edges"][:])[0].astype(np.int64)
            g.attrs.update(x=name, underflow=np.int64(0), overflow=np.int64(0),
                           samples=np.int64(values.size),
                           **dict(zip(("q1", "median", "q3"), np.percentile(values, [25, 50, 75]))))
        both = np.isfinite(nu).all(axis=1)
        g = t.create_group("frequency_map")
        g["x_edges"] = g["y_edges"] = np.linspace(0.0, 0.5, BINS + 1)
        g["counts"] = np.histogram2d(nu[both, 0], nu[both, 1],
                                     [g["x_edges"][:]] * 2)[0].astype(np.int64)
        g.attrs.update(x="nu1", y="nu2", underflow=np.int64(0), overflow=np.int64(0),
                       samples=np.int64(both.sum()))


def varying(path):
    """The initial values of the coordinates that vary over the run's orbits."""
    with h5py.File(path, "r") as f:
        columns = [f["initial/" + c][:] for c in ("q1", "q2", "p1", "p2")]
    return [c for c in columns if np.ptp(c) > 0]


def crossing_lines(order, box):
    """Every resonance line m x + n y = k of order |m| + |n| from 1 to `order` that passes
    through the inside of `box`, by brute force: (m, n, k) divided by their gcd, the first
    nonzero of m, n positive."""
    (x0, x1), (y0, y1) = box
    lines = set()
    for m in range(-order, order + 1):
        for n in range(-order, order + 1):
            if not 1 <= abs(m) + abs(n) <= order:
                continue
            values = [m * x + n * y for x in (x0, x1) for y in (y0, y1)]
            for k in range(-2 * order, 2 * order + 1):
                if min(values) < k < max(values):
                    g = math.gcd(m, n, k) * (1 if (m or n) > 0 else -1)
                    lines.add((m // g, n // g, k // g))
    return lines


class TunePictures(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        runs = {}
        for name, ensemble, output in (("grid", GRID, ""), ("line", LINE, ""),
                                       ("binned", GRID, "[output]\nper_orbit = false\n")):
            preset = cls.dir / f"{name}.toml"
            preset.write_text(ensemble)
            runs[name] = small_run.small_run(cls.dir, orbits=None, steps=20, name=f"{name}.h5",
                                             preset=preset, extra=output)
        for name in ("grid", "line"):
            write_tunes(runs[name], varying(runs[name]))
        write_tunes(runs["binned"], varying(runs["grid"]), per_orbit=False)
        cls.paths = runs
        cls.runs = {name: qmaps.load(path) for name, path in runs.items()}

    @classmethod
    def tearDownClass(cls):
        for run in cls.runs.values():
            run.close()
        cls.tmp.cleanup()

    def test_writes_the_tune_pictures_each_with_content(self):
        for name, kinds in (("grid", ["frequency-map", "diffusion-map", "tune-footprint",
                                      "tune-diffusion"]),
                            ("line", ["frequency-map", "tune-footprint", "tune-amplitude",
                                      "tune-diffusion"]),
                            ("binned", ["frequency-map", "tune-diffusion"])):
            with self.subTest(run=name):
                out = self.dir / f"{name}-png"
                status, stdout, err = run_main(self.paths[name], "-o", out, "--dpi", 50)
                self.assertEqual(status, 0, err)
                names = [f"{name}-{k}.png" for k in ["drift"] + kinds + ["summary"]]
                self.assertEqual(stdout.split(), [str(out / n) for n in names])
                for image in names[1:]:
                    with self.subTest(image=image):
                        pixels = assert_drawn(self, out / image)
                        if "summary" not in image:
                            self.assertEqual(pixels.shape[:2], (240, 320))
        out = self.dir / "paper-pdf"
        status, _, err = run_main(self.paths["grid"], "-o", out, "--style", "paper", "--format",
                                  "pdf", "--resonance-order", 6)
        self.assertEqual(status, 0, err)
        self.assertEqual((out / "grid-frequency-map.pdf").read_bytes()[:5], b"%PDF-")

    def test_frequency_map_coloured_by_diffusion_over_the_tunes_extent(self):
        run = self.runs["grid"]
        nu1, nu2, diffusion = (run["tunes/" + n] for n in ("nu1", "nu2", "diffusion"))
        ax = axes_with(self, run, "frequency-map")
        dots = ax.collections[0]
        both = np.isfinite(nu1) & np.isfinite(nu2)
        self.assertEqual((run["tunes"].attrs["escaped"], run["tunes"].attrs["round_off"]), (4, 2))
        self.assertEqual(both.sum(), len(nu1) - 5, "4 escaped, 1 without nu2")
        order = np.argsort(diffusion[both], kind="stable")  # the most diffusive on top
        np.testing.assert_array_equal(dots.get_offsets(),
                                      np.column_stack([nu1[both], nu2[both]])[order])
        np.testing.assert_array_equal(dots.get_array(), diffusion[both][order])
        self.assertEqual(dots.get_array().min(), FLOOR, "the floor's orbits drawn")
        self.assertEqual(ax.figure.axes[1].get_ylabel(), r"log$_{10}$ |$\Delta\nu$|")
        notes = " ".join(t.get_text() for t in ax.texts)
        self.assertIn(f"{both.sum()} of {len(nu1)} orbits; 4 escaped (no tunes),\n2 at the "
                      "round-off floor (lowest colour)", notes)
        for (low, high), v in ((ax.get_xlim(), nu1[both]), (ax.get_ylim(), nu2[both])):
            self.assertLess(low, v.min())
            self.assertGreater(high, v.max())
            self.assertLess(high - low, 1.2 * np.ptp(v))
        self.assertEqual((ax.get_xlabel(), ax.get_ylabel()),
                         (r"$\nu_{1}$ (cycles per step)", r"$\nu_{2}$ (cycles per step)"))

    def test_resonance_lines_labelled_where_they_cross_the_box(self):
        self.assertEqual(plot.resonance_label(2, -1, 0), r"$2\nu_1-\nu_2=0$")
        self.assertEqual(plot.resonance_label(0, 3, 1), r"$3\nu_2=1$")
        run = self.runs["grid"]
        for order in (2, 4):
            with self.subTest(order=order):
                ax = axes_with(self, run, "frequency-map", resonance_order=order)
                box = (ax.get_xlim(), ax.get_ylim())
                lines = crossing_lines(order, box)
                self.assertIn((1, -1, 0), lines)
                labels = [t.get_text() for t in ax.texts if r"\nu" in t.get_text()]
                self.assertEqual(sorted(labels),
                                 sorted(plot.resonance_label(*line) for line in lines))
                drawn = ax.lines
                self.assertEqual(len(drawn), len(lines))
                for line in drawn:  # within the box
                    x, y = line.get_data()
                    self.assertTrue(box[0][0] - 1e-12 <= min(x) <= max(x) <= box[0][1] + 1e-12)
                    self.assertTrue(box[1][0] - 1e-12 <= min(y) <= max(y) <= box[1][1] + 1e-12)
                widths = [line.get_linewidth() for line in drawn]  # lowest order first
                self.assertEqual(widths, sorted(widths, reverse=True))
        ax = axes_with(self, run, "frequency-map", resonance_order=0)
        self.assertEqual(len(ax.lines), 0)
        self.assertFalse(any(r"\nu" in t.get_text() for t in ax.texts))

    def test_diffusion_over_the_grid_with_escaped_orbits_in_their_colour(self):
        run = self.runs["grid"]
        ax = axes_with(self, run, "diffusion-map")
        mesh = ax.collections[0]
        diffusion = run["tunes/diffusion"].reshape(7, 6)  # p1 outer (7 points), q1 inner
        shown = mesh.get_array()
        np.testing.assert_array_equal(shown.filled(np.nan), diffusion.T.ravel())
        self.assertEqual(int(np.ma.getmaskarray(shown).sum()), 4)
        self.assertEqual(matplotlib.colors.to_hex(mesh.cmap.get_bad()),
                         matplotlib.colors.to_hex(plot.ESCAPED))
        self.assertEqual(ax.get_legend().get_texts()[0].get_text(), "escaped (4)")
        self.assertEqual((ax.get_xlabel(), ax.get_ylabel()),
                         ("$p_{1}$ (initial)", "$q_{1}$ (initial)"))
        np.testing.assert_allclose(ax.get_xlim(), (-0.35, 0.35))
        np.testing.assert_allclose(ax.get_ylim(), (-0.48, 0.48))
        self.assertEqual(ax.get_aspect(), 1.0)

    def test_footprint_a_mesh_over_the_grid_points_over_a_line(self):
        run = self.runs["grid"]
        ax = axes_with(self, run, "tune-footprint")
        mesh, dots = ax.collections
        nu = np.column_stack([run["tunes/nu1"], run["tunes/nu2"]]).reshape(7, 6, 2)
        size = np.sqrt(sum(c ** 2 for c in varying(self.paths["grid"]))).reshape(7, 6)
        pairs = [(nu[i, j], nu[i + di, j + dj], (size[i, j] + size[i + di, j + dj]) / 2)
                 for di, dj in ((1, 0), (0, 1)) for i in range(7 - di) for j in range(6 - dj)]
        pairs = [p for p in pairs if np.isfinite(p[0]).all() and np.isfinite(p[1]).all()]
        self.assertEqual(len(mesh.get_segments()), len(pairs))
        np.testing.assert_array_equal(np.array(mesh.get_segments()),
                                      np.array([[a, b] for a, b, _ in pairs]))
        np.testing.assert_allclose(mesh.get_array(), [c for _, _, c in pairs], rtol=1e-15)
        both = np.isfinite(nu).all(axis=2)
        np.testing.assert_array_equal(dots.get_array(), size[both])
        self.assertEqual(ax.figure.axes[1].get_ylabel(),
                         r"amplitude $\sqrt{q_{1}^2 + p_{1}^2}$")
        with unittest.mock.patch.object(plot, "MESH_LINES", 4):  # every 2nd point: 4 x 3 of them
            thinned = axes_with(self, run, "tune-footprint").collections[0]
        ends = np.isfinite(nu[::2, ::2]).all(axis=2)
        self.assertEqual(len(thinned.get_segments()),
                         (ends[:-1] & ends[1:]).sum() + (ends[:, :-1] & ends[:, 1:]).sum())
        line = axes_with(self, self.runs["line"], "tune-footprint")
        self.assertEqual(len(line.collections), 1, "points only")
        self.assertEqual(line.figure.axes[1].get_ylabel(),
                         r"amplitude $\sqrt{q_{1}^2 + p_{2}^2}$")

    def test_line_tunes_against_the_coordinate_that_varies_most(self):
        run = self.runs["line"]
        ax = axes_with(self, run, "tune-amplitude")
        self.assertEqual(len(ax.lines), 2)
        for line, name in zip(ax.lines, ("nu1", "nu2")):
            x, y = line.get_data()
            np.testing.assert_array_equal(x, run["initial/q1"])
            np.testing.assert_array_equal(y, run["tunes/" + name])
        self.assertEqual(np.isnan(ax.lines[0].get_ydata()).sum(), 3, "the escaped orbits")
        self.assertEqual(ax.get_xlabel(), "$q_{1}$ (initial)")
        self.assertEqual([t.get_text() for t in ax.get_legend().get_texts()],
                         [r"$\nu_{1}$", r"$\nu_{2}$"])

    def test_diffusion_histogram_with_the_floor(self):
        run = self.runs["grid"]
        ax = axes_with(self, run, "tune-diffusion")
        np.testing.assert_array_equal(ax.patches[-1].get_data().values,
                                      run["tunes/histograms/diffusion/counts"])
        self.assertEqual([line.get_xdata()[0] for line in ax.lines], [FLOOR])
        self.assertIn("2 orbits", ax.get_legend().get_texts()[0].get_text())
        self.assertEqual(ax.get_xlabel(), r"log$_{10}$ |$\Delta\nu$|")

    def test_every_orbit_escaped(self):
        path = self.dir / "escaped.h5"
        shutil.copyfile(self.paths["grid"], path)
        with h5py.File(path, "a") as f:
            for name in ("nu1", "nu2", "nu1_second", "nu2_second", "diffusion"):
                f["tunes/" + name][...] = np.nan
            f["tunes/class"][...] = 2
            f["tunes"].attrs.update(escaped=np.int64(42), regular=np.int64(0),
                                    chaotic=np.int64(0), round_off=np.int64(0))
        out = self.dir / "escaped"
        status, _, err = run_main(path, "-o", out, "--dpi", 50)
        self.assertEqual(status, 0, err)
        with qmaps.load(path) as run:
            for kind in ("frequency-map", "tune-footprint"):
                with self.subTest(kind=kind):
                    texts = [t.get_text() for t in axes_with(self, run, kind).texts]
                    self.assertIn("no tunes", texts)
                    self.assertIn("0 of 42 orbits; 42 escaped (no tunes)", texts)
            mesh = axes_with(self, run, "diffusion-map").collections[0]
            self.assertTrue(np.ma.getmaskarray(mesh.get_array()).all())

    def test_without_per_orbit_data_the_frequency_maps_histogram(self):
        run = self.runs["binned"]
        self.assertNotIn("tunes/nu1", run)
        ax = axes_with(self, run, "frequency-map", resonance_order=2)
        image = ax.get_images()[0]
        counts = run["tunes/frequency_map/counts"]
        self.assertIsInstance(image.norm, matplotlib.colors.LogNorm)
        np.testing.assert_array_equal(image.get_array().filled(0), counts.T)
        edges = run["tunes/frequency_map/x_edges"]
        occupied = np.nonzero(counts.any(axis=1))[0]
        self.assertEqual(ax.get_xlim(), (edges[occupied[0]], edges[occupied[-1] + 1]))
        labels = [t.get_text() for t in ax.texts if r"\nu" in t.get_text()]
        self.assertEqual(sorted(labels), sorted(plot.resonance_label(*line) for line in
                                                crossing_lines(2, (ax.get_xlim(), ax.get_ylim()))))
        self.assertNotIn("tune-footprint", dict(plot.items(run, "H")))


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
