"""qmaps-plot --style paper on the gallery's presets, run small: every figure (each picture, the
summary, a sweep's plane) is checked as drawn, from its artists' extents on the canvas.

Blank canvas: the fraction of the canvas's area that no element covers. The elements are each
panel, the rectangle of an Axes' frame with its tick labels and axis labels, joined with those of
its colour bars; each legend's frame; and each text drawn, where a line heading or footing a
panel (its title, a note under it) takes the panel's width and a heading or footing of the
figure (its title, a footer) the canvas's, being that row of it. What is left is what a reader
sees as empty: margins, the space beside a picture of fixed aspect narrower than its slot, the
gaps between panels and an empty cell of a grid. Empty space inside a frame is the data's.
At most BLANK of the canvas may be blank.

Text over data: a text drawn (its outline, turned with the text) whose outline covers a data
mark of an Axes: a scatter point (with its radius), an occupied cell of an image or mesh, a
curve, a filled step histogram or a marker; reference lines (gid "reference": machine epsilon,
the round-off floor, the resonance lines) are not data. A legend's frame counts as one text.
Text over text: two outlines that overlap (more than half a pixel each way, the entries of one
legend apart). Clipped: a text cut by the canvas's edge or by its clip box. None of these may
occur.

Colour bars: one that shows MEGNO or FLI has a logarithmic norm (LogNorm) or a norm by classes
(BoundaryNorm). Vector output: a PDF embeds its fonts' programs (/FontFile2 or /FontFile3, no
Type 3 font); an SVG draws its glyphs as paths (no <text>).

A few figures made to fail check the checks. QMAPS_PAPER_PRESETS=all (or a comma-separated list
of preset names) runs every preset instead of the representative subset PRESETS, which covers
every kind of figure: densities 2D and 1D, sections of points and of density, a section coloured
by MEGNO and by FLI, the drift, the energy-momentum image, the tunes' frequency map, diffusion map,
footprint and diffusion histogram, summaries of 2 to 5 panels, a sweep's plane and the evidence
of `qmaps integrability`."""
import contextlib
import io
import math
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import tomllib
import unittest

import matplotlib

matplotlib.use("Agg")
import matplotlib.collections  # noqa: E402
import matplotlib.colors  # noqa: E402
import matplotlib.path  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.text  # noqa: E402
import matplotlib.transforms  # noqa: E402
import numpy as np  # noqa: E402

import small_run  # noqa: E402
from qmaps import plot  # noqa: E402

Bbox = matplotlib.transforms.Bbox
BLANK = 0.10
PRESET_DIR = small_run.SOURCE_DIR / "ensembles" / "presets"
# The representative subset: suris (2D density, capped section, drift, energy-momentum: a 2 x 2
# summary), case3 (a 1D density: 5 panels), chaos-flow (a tall section coloured by MEGNO, and by
# FLI), tunes-suris (the tunes' four pictures) and scan-b4a (a sweep's plane with median MEGNO).
PRESETS = ["suris", "case3", "chaos-flow", "tunes-suris", "scan-b4a"]


def preset_size(preset):
    """--set options that run `preset` small, as tools/gallery does but smaller: a sweep with 8
    orbits a point, the tori and chaos sections over 20000 steps, the tunes over 2 x 256 steps,
    any other preset with 2000 orbits (a grid: its points) and 200 steps."""
    config = tomllib.loads(preset.read_text())
    if "sweep" in config:
        return ["--set", "ensemble.orbits=8", "--set", "run.steps=200"]
    if preset.stem.startswith("tunes-"):
        return ["--set", "run.steps=512", "--set", "tunes.window=256"]
    if preset.stem.startswith(("tori-", "chaos-")):
        return ["--set", "run.steps=20000"]
    sized = "orbits" in config.get("ensemble", {})
    return ["--set", "run.steps=200"] + (["--set", "ensemble.orbits=2000"] if sized else [])


def chosen_presets():
    names = os.environ.get("QMAPS_PAPER_PRESETS", "")
    if names == "all":
        return sorted(p.stem for p in PRESET_DIR.glob("*.toml"))
    return names.split(",") if names else PRESETS


# --- What is drawn -----------------------------------------------------------------------------

def drawn_texts(fig):
    """Draws the figure (laying it out, rendering nothing); returns the text artists that drew
    (visible, not empty)."""
    drawn = []
    draw = matplotlib.text.Text.draw

    def recorded(self, renderer):
        draw(self, renderer)
        if self.get_visible() and self.get_text().strip():
            drawn.append(self)

    matplotlib.text.Text.draw = recorded
    try:
        fig.draw_without_rendering()
    finally:
        matplotlib.text.Text.draw = draw
    return drawn


class Outline:
    """A text's outline on the canvas: a rectangle w x h about `centre`, turned by `angle`."""

    def __init__(self, centre, angle, w, h):
        self.centre, self.angle, self.w, self.h = np.asarray(centre, float), angle, w, h
        self.along = np.array([math.cos(angle), math.sin(angle)])
        self.across = np.array([-math.sin(angle), math.cos(angle)])

    @classmethod
    def of_box(cls, box):
        return cls(((box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2), 0.0, box.width, box.height)

    def corners(self, inset=0.0):
        w, h = self.w / 2 - inset, self.h / 2 - inset
        return np.array([self.centre + u * self.along + v * self.across
                         for u, v in ((-w, -h), (w, -h), (w, h), (-w, h))])

    def path(self, inset=0.0):
        return matplotlib.path.Path(self.corners(inset), closed=True)

    def box(self):
        c = self.corners()
        return Bbox([c.min(axis=0), c.max(axis=0)])

    def covers_points(self, xy, radii):
        d = np.asarray(xy) - self.centre
        u, v = d @ self.along, d @ self.across
        return (np.abs(u) < self.w / 2 + radii) & (np.abs(v) < self.h / 2 + radii)

    def overlaps(self, other, tolerance=0.5):
        if self.angle == other.angle == 0:
            a, b = self.box(), other.box()
            return (min(a.x1, b.x1) - max(a.x0, b.x0) > tolerance and
                    min(a.y1, b.y1) - max(a.y0, b.y0) > tolerance)
        return self.path(tolerance / 2).intersects_path(other.path(tolerance / 2), filled=True)

    def within(self, box, tolerance=0.5):
        c = self.corners()
        return bool((c >= np.array(box.p0) - tolerance).all() and
                    (c <= np.array(box.p1) + tolerance).all())


def text_outline(text, renderer):
    """The outline of a drawn text: its box (with its bbox patch) if upright or at a right angle,
    else its unturned size turned by its rotation about the centre of its extent."""
    box = text.get_window_extent(renderer)
    patch = text.get_bbox_patch()
    if patch is not None:
        box = Bbox.union([box, patch.get_window_extent(renderer)])
    angle = math.radians(text.get_rotation())
    if patch is not None or abs(math.sin(2 * angle)) < 1e-9:
        return Outline.of_box(box)
    upright = matplotlib.text.Text(0, 0, text.get_text(), fontproperties=text.get_fontproperties())
    upright.set_figure(text.figure)
    size = upright.get_window_extent(renderer)
    return Outline(((box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2), angle, size.width, size.height)


def is_colorbar(ax):
    return hasattr(ax, "_colorbar")


def covers_data(ax, outline):
    """Whether the outline covers any data mark drawn in `ax` (within its frame)."""
    box = Bbox.intersection(outline.box(), ax.bbox)
    if box is None or box.width <= 0.5 or box.height <= 0.5:
        return False
    shape = outline.path(0.5)
    px = ax.figure.dpi / 72

    def cells_covered(corners, shown):
        """corners (ny+1, nx+1, 2) on the canvas of cells (ny, nx), those `shown`."""
        quads = np.stack([corners[:-1, :-1], corners[1:, :-1], corners[1:, 1:], corners[:-1, 1:]],
                         axis=2)
        low, high = quads.min(axis=2), quads.max(axis=2)
        near = shown & (low[..., 0] < box.x1) & (high[..., 0] > box.x0) & \
            (low[..., 1] < box.y1) & (high[..., 1] > box.y0)
        return any(matplotlib.path.Path(quads[i, j], closed=True).intersects_path(shape, True)
                   for i, j in zip(*np.nonzero(near)))

    for c in ax.collections:
        if not c.get_visible():
            continue
        if isinstance(c, matplotlib.collections.QuadMesh):
            corners = c.get_coordinates()
            xy = c.get_transform().transform(corners.reshape(-1, 2)).reshape(corners.shape)
            values = np.ma.asarray(c.get_array()).reshape(np.array(corners.shape[:2]) - 1)
            shown = ~np.ma.getmaskarray(values) | (c.get_cmap().get_bad()[3] > 0)
            if cells_covered(xy, shown):
                return True
        elif isinstance(c, matplotlib.collections.PathCollection):
            offsets = c.get_offset_transform().transform(np.asarray(c.get_offsets()))
            radii = np.broadcast_to(np.sqrt(c.get_sizes()) / 2 * px, (len(offsets),))
            if outline.covers_points(offsets, radii).any():
                return True
        else:
            transform = c.get_transform()
            for p in c.get_paths():
                p = transform.transform_path(p)
                if p.intersects_path(shape, False) or shape.contains_points(p.vertices).any():
                    return True
    for image in ax.get_images():
        x0, x1, y0, y1 = image.get_extent()
        values = np.ma.asarray(image.get_array())
        ny, nx = values.shape[:2]
        gx, gy = np.meshgrid(np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1))
        corners = ax.transData.transform(np.column_stack([gx.ravel(), gy.ravel()]))
        shown = ~np.ma.getmaskarray(values)
        if image.origin == "upper":
            shown = shown[::-1]
        if cells_covered(corners.reshape(ny + 1, nx + 1, 2), shown):
            return True
    for patch in ax.patches:
        p = patch.get_transform().transform_path(patch.get_path())
        if p.intersects_path(shape, filled=patch.get_fill()) or \
                shape.contains_points(p.vertices).any():
            return True
    for line in ax.lines:
        if line.get_gid() == "reference" or not line.get_visible():
            continue
        p = line.get_transform().transform_path(line.get_path())
        if line.get_linestyle() not in ("None", "", " ") and len(p.vertices) > 1 and \
                (p.intersects_path(shape, False) or shape.contains_points(p.vertices).any()):
            return True
        if line.get_marker() not in ("None", "", " ", None):
            r = np.full(len(p.vertices), line.get_markersize() / 2 * px)
            if outline.covers_points(p.vertices, r).any():
                return True
    return False


def panel_boxes(fig, renderer):
    """{Axes: its panel}: the frame with its tick labels and axis labels, and its colour bars'."""
    blocks = {}
    for ax in fig.axes:
        if ax.get_visible():
            axes = (a.get_tightbbox(renderer) for a in (ax.xaxis, ax.yaxis))
            boxes = [ax.bbox] + [b for b in axes if b is not None and b.width > 0 and b.height > 0]
            blocks[ax] = Bbox.union(boxes)
    panels = dict(blocks)
    for ax, box in blocks.items():
        parent = ax._colorbar.mappable.axes if is_colorbar(ax) else None
        if parent in panels:
            panels[parent] = Bbox.union([panels[parent], box])
    return panels


def row_of(text, box, fig, panels):
    """The row a heading or footing line takes: a figure's spans the canvas, an Axes' title or a
    text of its above or below its frame spans its panel; any other text its own box."""
    if text.get_rotation() != 0:
        return box
    if text in fig.texts or text in (getattr(fig, "_suptitle", None),
                                     getattr(fig, "_supxlabel", None)):
        return Bbox([[fig.bbox.x0, box.y0], [fig.bbox.x1, box.y1]])
    for ax, panel in panels.items():
        if text is ax.title or text in ax.texts:
            if box.y0 >= ax.bbox.y1 - 0.5 or box.y1 <= ax.bbox.y0 + 0.5:
                return Bbox([[min(panel.x0, box.x0), box.y0], [max(panel.x1, box.x1), box.y1]])
    return box


def describe(artist):
    return repr(artist.get_text()[:60]) if isinstance(artist, matplotlib.text.Text) else \
        type(artist).__name__


def layout(fig):
    """{blank: the blank fraction, faults: [text over data, text over text, clipped, each said],
    bars: [(label, norm)] of the colour bars, covered: the canvas's covered pixels, bottom row
    first} of the figure as drawn."""
    texts = drawn_texts(fig)
    renderer = fig.canvas.get_renderer()
    width, height = int(round(fig.bbox.width)), int(round(fig.bbox.height))
    covered = np.zeros((height, width), bool)

    def cover(box):
        part = Bbox.intersection(box, fig.bbox)
        if part is not None:
            covered[int(round(part.y0)):int(round(part.y1)),
                    int(round(part.x0)):int(round(part.x1))] = True

    panels = panel_boxes(fig, renderer)
    for box in panels.values():
        cover(box)
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend()] + list(fig.legends)
    labels, faults = [], []  # labels: (artist, outline, its legend)
    for text in texts:
        outline = text_outline(text, renderer)
        inside = Bbox.intersection(outline.box(), fig.bbox)
        clip = text.get_clip_box() if text.get_clip_on() else None
        if clip is not None:
            inside = inside and Bbox.intersection(inside, clip)
        if inside is None or inside.width <= 0 or inside.height <= 0:
            continue  # drawn wholly outside its clip box: not seen
        if not outline.within(fig.bbox) or (clip is not None and not outline.within(clip)):
            faults.append(f"clipped: {describe(text)}")
        legend = next((lg for lg in legends if text in lg.get_texts()), None)
        labels.append((text, outline, legend))
        cover(row_of(text, outline.box(), fig, panels))
    for legend in legends:
        box = legend.get_window_extent(renderer)
        cover(box)
        labels.append((legend, Outline.of_box(box), legend))
    for i, (a, outline_a, legend_a) in enumerate(labels):
        for b, outline_b, legend_b in labels[i + 1:]:
            if (legend_a is None or legend_a is not legend_b) and outline_a.overlaps(outline_b):
                faults.append(f"text over text: {describe(a)} and {describe(b)}")
    for a, outline, legend in labels:
        if legend is not None and a is not legend:
            continue  # a legend's entries: its frame stands for them
        if any(covers_data(ax, outline) for ax in fig.axes if not is_colorbar(ax)):
            faults.append(f"text over data: {describe(a)}")
    bars = [(ax.get_ylabel() or ax.get_xlabel(), ax._colorbar.norm)
            for ax in fig.axes if is_colorbar(ax)]
    return {"blank": 1 - covered.mean(), "faults": faults, "bars": bars, "covered": covered}


def measured(path, out_dir, color_by=None, dpi=72):
    """{figure's name: layout()} of every figure qmaps.plot draws of the run at `path` in the
    paper style, measured at the `dpi` it would be saved at (and not saved)."""
    found = {}
    save = plot.save

    def measuring(fig, where, dpi):
        fig.set_dpi(dpi)
        found[pathlib.Path(where).stem] = layout(fig)
        plt.close(fig)

    plot.save = measuring
    try:
        with contextlib.redirect_stdout(io.StringIO()):  # the paths it would have written
            plot.plot(path, out_dir, "png", dpi, color_by, False, "paper")
    finally:
        plot.save = save
    return found


def run_preset(name, directory):
    preset = PRESET_DIR / f"{name}.toml"
    out = pathlib.Path(directory) / f"{name}.h5"
    subprocess.run([str(small_run.BINARY), "run", str(preset), *preset_size(preset),
                    "--out", str(out), "--quiet"], check=True, capture_output=True)
    return out


class PaperStyleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        cls.runs, cls.figures = {}, {}
        for name in chosen_presets():
            cls.runs[name] = run_preset(name, cls.dir)
            cls.figures.update(measured(cls.runs[name], cls.dir / "png"))
        # The evidence of `qmaps integrability --out`, over few steps and orbits.
        evidence = cls.dir / "evidence.h5"
        subprocess.run([str(small_run.BINARY), "integrability", "--map", "suris", "--set", "A=0.7",
                        "--set", "B=0.3", "--set", "alpha=0.9", "--set", "h=0.1", "--steps", "12",
                        "--orbits", "200", "--height-steps", "12", "--out", str(evidence)],
                       check=True, capture_output=True)
        cls.figures.update(measured(evidence, cls.dir / "integrability"))
        if "chaos-flow" in cls.runs:
            cls.figures.update({f"{k} (fli)": v for k, v in measured(
                cls.runs["chaos-flow"], cls.dir / "fli", color_by="fli").items()})

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_every_kind_of_figure_is_drawn(self):
        if os.environ.get("QMAPS_PAPER_PRESETS"):
            self.skipTest("presets chosen by QMAPS_PAPER_PRESETS")
        kinds = {name.split("-", 1)[1].split(" ")[0] for name in self.figures}
        for kind in ("histogram-q1q2", "histogram-t", "section-q1up", "drift", "energy-momentum",
                     "frequency-map", "diffusion-map", "tune-footprint", "tune-diffusion",
                     "summary", "b4a-sweep", "integrability"):
            self.assertTrue(any(k.endswith(kind) for k in kinds), kind)

    def test_blank_canvas_is_at_most_a_tenth(self):
        self.assertEqual({name: round(figure["blank"], 3) for name, figure in self.figures.items()
                          if figure["blank"] > BLANK}, {})

    def test_no_text_over_data_or_text_and_none_clipped(self):
        self.assertEqual({name: figure["faults"] for name, figure in self.figures.items()
                          if figure["faults"]}, {})

    def test_megno_and_fli_colour_bars_are_logarithmic_or_by_class(self):
        seen = set()
        for name, figure in sorted(self.figures.items()):
            for label, norm in figure["bars"]:
                shows = re.match(r"(median )?(MEGNO|FLI)\b", label)  # not "chaotic fraction"
                if shows:
                    seen.add(shows.group(2))
                    with self.subTest(figure=name, bar=label):
                        self.assertIsInstance(norm, (matplotlib.colors.LogNorm,
                                                     matplotlib.colors.BoundaryNorm))
        if "chaos-flow" in self.runs:
            self.assertEqual(seen, {"MEGNO", "FLI"})

    def test_vector_output_embeds_its_fonts(self):
        run = self.runs.get("chaos-flow") or next(iter(self.runs.values()))
        with contextlib.redirect_stdout(io.StringIO()):
            written = plot.plot(run, self.dir / "vector", "pdf", 72, None, False, "paper")
            written += plot.plot(run, self.dir / "vector", "svg", 72, None, False, "paper")
        for path in written:
            with self.subTest(file=path.name):
                data = path.read_bytes()
                if path.suffix == ".pdf":
                    self.assertTrue(b"/FontFile2" in data or b"/FontFile3" in data)
                    self.assertNotIn(b"/Type3", data)
                else:
                    self.assertNotIn(b"<text", data)

    def test_the_checks_catch_each_fault(self):
        """A figure with a wide margin, a text over scatter points, two texts on each other and a
        text cut by the canvas's edge: each is found."""
        fig = plt.figure(figsize=(4, 3), dpi=72)
        self.addCleanup(plt.close, fig)
        ax = fig.add_axes([0.3, 0.2, 0.4, 0.6])
        ax.scatter([0.5], [0.5], s=20)
        ax.set(xlim=(0, 1), ylim=(0, 1))
        ax.text(0.5, 0.5, "over the point", ha="center", va="center")
        ax.text(0.1, 0.9, "first")
        ax.text(0.1, 0.9, "second")
        fig.text(0.95, 0.5, "off the edge")
        found = layout(fig)
        self.assertGreater(found["blank"], 0.3)
        said = "\n".join(found["faults"])
        self.assertIn("text over data: 'over the point'", said)
        self.assertIn("text over text: 'first' and 'second'", said)
        self.assertIn("clipped: 'off the edge'", said)
        turned = plt.figure(figsize=(4, 3), dpi=72)  # a turned label over points: its outline
        self.addCleanup(plt.close, turned)
        ax = turned.add_axes([0.1, 0.1, 0.8, 0.8])
        ax.set(xlim=(0, 1), ylim=(0, 1))
        ax.scatter([0.2, 0.8], [0.8, 0.2], s=4)  # in the corners of its box, off its outline
        ax.text(0.5, 0.5, "a label turned by 45 degrees", rotation=45, ha="center", va="center")
        self.assertEqual(layout(turned)["faults"], [])
        ax.scatter([0.5], [0.5], s=4)
        self.assertEqual(len(layout(turned)["faults"]), 1)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
