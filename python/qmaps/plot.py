"""qmaps-plot FILE.h5 [-o DIR] [--format png|pdf|svg] [--dpi N] [--color-by WHAT] [--range auto]
                   [--style screen|paper] [--resonance-order N]

Draws the pictures of a qmaps run file (docs/hdf5-schema.md), one image per item and a summary:
  <stem>-histogram-<name>   every /histograms/<name>: 2D on a log colour scale, 1D as steps
  <stem>-section-<name>     every /sections/<name>: the points coloured by their orbit (orbit),
                            its initial invariant or its chaos indicator (by default MEGNO, else
                            an invariant that varies over the ensemble, else the orbit; MEGNO
                            and FLI on a log colour scale, MEGNO's class threshold marked), or
                            the section's density when the cap cut points or none were kept
  <stem>-drift              each invariant's drift histogram, machine epsilon marked
  <stem>-energy-momentum    /invariants/image, when the run has one
With [tunes] (/tunes):
  <stem>-frequency-map      each orbit's tunes (nu1, nu2) coloured by their diffusion log10 |dnu|
                            (orbits at the round-off floor in the lowest colour, counted), over
                            the tunes' extent, with the resonance lines m nu1 + n nu2 = k up to
                            |m| + |n| = --resonance-order (default 4; labelled, fainter as the
                            order rises); without per-orbit data the tunes' 2D histogram
  <stem>-diffusion-map      a grid's diffusion over its two coordinates, escaped orbits in grey
  <stem>-tune-footprint     nu2 against nu1 coloured by the initial amplitude, a grid's
                            neighbours joined into a mesh (of at most 60 lines a side)
  <stem>-tune-amplitude     a line's nu1 and nu2 against the coordinate that varies most on it
  <stem>-tune-diffusion     the diffusion's histogram, the round-off floor 2^-53 marked
  <stem>-summary            all of them in one image, two panels per row up to four, else three
The file of `qmaps integrability --out` (docs/integrability.md) gets one image instead,
<stem>-integrability: the degree sequences on a log scale with their fitted growth, each prime's
periods over lambda against R(x) = 1 - e^-x (1 + x), and the log heights.
A sweep's file (docs/sweeps.md) gets one image instead, <stem>-sweep: over the parameter plane
(or line), the chaotic fraction and the median MEGNO with [chaos], and the worst invariant drift,
with the known integrable cases (a second integral the map names there) and delta = 0 marked.
Each image is 6.4 x 4.8 in, each summary panel 5 x 4 in, at --dpi dots per inch (default 200).
--style paper fits a journal: an image is a column wide (3.4 in, 86 mm), a summary or a sweep a
page wide (7 in), each as tall as its content (a picture of fixed aspect fills its frame; one
taller than 1.4 columns makes the image narrower instead), leaving little of the canvas blank;
7 pt serif type (5 pt at least) with STIX mathematics, thinner lines; no text over the data:
notes under the frame, legends above the data, resonance lines labelled where no tune lies, a
sweep's known cases in a footer. Its PDF and PostScript embed their fonts (TrueType), its SVG
draws the glyphs as paths.
Labels use the physicist's symbols (q₁, p₂, α, I⁽ᴵⱽ⁾), the title gives a shell's energy E, and a
picture whose axes are both phase-space coordinates has equal aspect. Where a configured range
cut samples or points, the picture says how many; --range auto draws the data's own extent.
Exit codes as qmaps: 2 bad command line, 3 a file that cannot be read or written.
"""
import argparse
import math
import os
import pathlib
import re
import sys
import textwrap
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.collections  # noqa: E402
import matplotlib.colors  # noqa: E402
import matplotlib.legend  # noqa: E402
import matplotlib.lines  # noqa: E402
import matplotlib.patches  # noqa: E402
import matplotlib.path  # noqa: E402
import matplotlib.ticker  # noqa: E402
import matplotlib.text  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import runfile  # noqa: E402

# Per --style: the size of an image and of a summary panel (inches), the scale on the type sizes
# the pictures name (10 pt titles at 1) and the least size, and matplotlib's settings. The paper
# style's image is a column wide and its summary (and a sweep's panels) a page wide, each then
# sized to its content (fit_to_content); its vector files embed their fonts: TrueType in PDF and
# PostScript (fonttype 42, a /FontFile2 in the PDF), glyphs as paths in SVG.
STYLES = {
    "screen": {"image": (6.4, 4.8), "panel": (5.0, 4.0), "scale": 1.0, "rc": {}},
    "paper": {"image": (3.4, 2.7), "panel": (3.4, 2.7), "page": 7.0, "scale": 0.7, "least": 5.0,
              "rc": {"font.size": 7, "font.family": "serif",
                     "font.serif": ["STIXGeneral", "DejaVu Serif"], "mathtext.fontset": "stix",
                     "axes.linewidth": 0.6, "lines.linewidth": 0.8, "xtick.major.width": 0.6,
                     "ytick.major.width": 0.6, "xtick.major.size": 2.5, "ytick.major.size": 2.5,
                     "axes.titlepad": 3.0, "pdf.fonttype": 42, "ps.fonttype": 42,
                     "svg.fonttype": "path",
                     "figure.constrained_layout.w_pad": 0.02,
                     "figure.constrained_layout.h_pad": 0.02,
                     "figure.constrained_layout.hspace": 0.01}},
}
style = STYLES["screen"]


def paper():
    """Whether the paper style is in use: figures sized to their content, no text over data."""
    return style is STYLES["paper"]


def pt(size):
    """A type size of the screen style in the style in use (in the paper style 5 pt at least)."""
    return max(size * style["scale"], style.get("least", 0.0))


def scaled(size):
    """A mark's size (points) of the screen style in the style in use."""
    return size * style["scale"]


MAX_POINTS = 200_000  # section points or tunes drawn at most (a fixed random subset beyond)
EPSILON = np.finfo(np.float64).eps

# Datasets no picture needs, left unread (large runs hold 10^6 values in each).
UNUSED = ("final/*", "escape/*", "invariants/*/final", "invariants/*/max_abs_drift")


def count(n):
    """An integer count, short: 1000000 -> 10^6, 2500000 -> 2.5e6, 1234 -> 1234."""
    if n >= 100_000:
        exponent = int(math.floor(math.log10(n)))
        mantissa = n / 10 ** exponent
        return f"10$^{{{exponent}}}$" if mantissa == 1 else f"{mantissa:.3g}e{exponent}"
    return str(n)


COORDINATES = ("q1", "q2", "p1", "p2")
GREEK = {"alpha": r"\alpha", "beta": r"\beta", "gamma": r"\gamma", "delta": r"\delta",
         "lambda": r"\lambda", "nu": r"\nu"}
ROMAN = {"1": "I", "2": "II", "3": "III", "4": "IV"}


def symbol(name):
    r"""A coordinate, invariant or parameter as a physicist writes it, in matplotlib's mathtext:
    q1 -> $q_1$, I_case4 -> $I^{(\mathrm{IV})}$, I1 -> $I_1$, alpha -> $\alpha$, gamma11 ->
    $\gamma_{11}$; any other name as it is."""
    case = re.fullmatch(r"I_case(\d)", name)
    if case:
        return rf"$I^{{(\mathrm{{{ROMAN[case.group(1)]}}})}}$"
    parts = re.fullmatch(r"([A-Za-z]+?)_?(\d*)", name)
    if not parts or (len(parts.group(1)) > 1 and parts.group(1) not in GREEK):
        return name
    letter = GREEK.get(parts.group(1), parts.group(1))
    return f"${letter}_{{{parts.group(2)}}}$" if parts.group(2) else f"${letter}$"


def energy_of(run):
    """The energy E of the run's ensemble (a shell's), or None."""
    try:
        return tomllib.loads(run.attrs["config"]).get("ensemble", {}).get("energy")
    except (KeyError, tomllib.TOMLDecodeError):
        return None


def run_title(run, width):
    """The map, its parameters (those set: an unset optional one is NaN), the energy of a shell,
    orbits and steps, in lines of at most `width` characters (symbols count as one)."""
    params = ", ".join(f"{symbol(k)} = {v:g}" for k, v in run.params.items() if not math.isnan(v))
    energy = energy_of(run)
    at = f" at $E$ = {energy:g}" if energy is not None else ""
    return textwrap.fill(f"{run.attrs['map']} ({params}){at}: {count(run.attrs['orbits'])} orbits, "
                         f"{run.attrs['steps']} steps", width)


def outside_note(h):
    """What the configured range left out of a histogram, said where it cut samples."""
    cut = h.underflow + h.overflow
    text = f"underflow {h.underflow}, overflow {h.overflow} of {h.samples}"
    return f"the range cuts {cut} of {h.samples} samples: {text}" if cut else text


def note(ax, text):
    """A small note in the lower left corner, left out of the layout; in the paper style under
    the x axis' label, centred on the frame, in the layout (it covers no data)."""
    if paper():
        ax.annotate(text, (0.5, 0), xycoords=("axes fraction", ax.xaxis.label), xytext=(0, -1),
                    textcoords="offset points", fontsize=pt(7), va="top", ha="center",
                    gid="note")
        return
    ax.text(0.01, 0.01, text, transform=ax.transAxes, fontsize=pt(7), va="bottom", ha="left",
            bbox=dict(facecolor="white", alpha=0.8, edgecolor="none", pad=1.5),
            in_layout=False)


def after_layout(ax, place):
    """Runs place(): at once, or in the paper style once the figure has its final size and layout
    (place() needs where the data lie on the canvas; it says whether it changed what the layout
    depends on, such as a note's text or an axis' limits)."""
    if paper():
        ax.figure.__dict__.setdefault("qmaps_after_layout", []).append(place)
    else:
        place()


def legend_clear_of_data(ax, **options):
    """A legend in an upper corner; in the paper style in the corner that needs less room, the y
    axis raised until the data lie below it."""
    legend = ax.legend(fontsize=pt(7), loc="upper right", **options)
    if paper():
        after_layout(ax, lambda: raise_above_data(ax, legend))
    return legend


def data_top(ax, x0, x1):
    """The highest y of the data lines and steps drawn between x0 and x1 (data units): of their
    points there and of the segments that cross there; None if none."""
    tops = []
    for artist in ax.patches + [line for line in ax.lines if line.get_gid() != "reference"]:
        xy = artist.get_xydata() if isinstance(artist, matplotlib.lines.Line2D) else \
            artist.get_patch_transform().transform(artist.get_path().vertices)
        xy = xy[np.isfinite(xy).all(axis=1)]
        inside = (xy[:, 0] >= x0) & (xy[:, 0] <= x1)
        left, right = np.minimum(xy[:-1, 0], xy[1:, 0]), np.maximum(xy[:-1, 0], xy[1:, 0])
        across = (left <= x1) & (right >= x0)
        tops += list(xy[inside, 1]) + list(np.maximum(xy[:-1, 1], xy[1:, 1])[across])
    return max(tops) if tops else None


def move_legend(legend, loc):
    if hasattr(legend, "set_loc"):
        legend.set_loc(loc)
    else:  # matplotlib before 3.8
        legend._loc = matplotlib.legend.Legend.codes[loc]


def raise_above_data(ax, legend, gap=4.0):
    """Puts the legend in the upper corner that needs the least headroom, and raises the top of
    the y axis so that the data under the legend's span lie below it, `gap` points apart (text
    measures a little differently at another dpi); whether it raised it."""
    renderer = ax.figure.canvas.get_renderer()
    log = ax.get_yscale() == "log"
    scale, unscale = (np.log10, lambda v: 10 ** v) if log else (float, float)
    bottom, top = (scale(v) for v in ax.get_ylim())
    best = None
    for loc in ("upper right", "upper left"):
        move_legend(legend, loc)
        box = legend.get_window_extent(renderer)
        span = box.transformed(ax.transData.inverted())
        high = data_top(ax, span.x0, span.x1)
        needed = top
        if high is not None and (high > 0 or not log):
            room = box.transformed(ax.transAxes.inverted()).y0 - \
                gap * ax.figure.dpi / 72 / ax.bbox.height  # the data's share of the height
            needed = max(top, bottom + (scale(high) - bottom) / room)
        if best is None or needed < best[1]:
            best = (loc, needed)
    move_legend(legend, best[0])
    if best[1] <= top + 1e-9 * (top - bottom):
        return False
    ax.set_ylim(top=unscale(best[1]))
    return True


def tick_label(value, _):
    return f"{value:g}" if value < 1e5 else f"$10^{{{round(math.log10(value))}}}$"


def colorbar(ax, mappable, **options):
    """The colour bar of `mappable` beside `ax`; in the paper style closer to it."""
    return ax.figure.colorbar(mappable, ax=ax, **({"pad": 0.03} if paper() else {}), **options)


def draw_2d(ax, counts, x_edges, y_edges, label, equal=False, auto=False):
    """Counts (nx, ny), x first, on a log colour scale; empty bins left white. `equal`: one unit
    as long on both axes (both are phase-space coordinates); `auto`: the axes span the occupied
    bins only."""
    ax.set_facecolor("white")
    extent = (x_edges[0], x_edges[-1], y_edges[0], y_edges[-1])
    if counts.max() <= 0:
        ax.set_xlim(extent[:2])
        ax.set_ylim(extent[2:])
        ax.text(0.5, 0.5, "no samples", transform=ax.transAxes, ha="center", va="center")
        return
    image = ax.imshow(np.ma.masked_equal(counts.T, 0), origin="lower", extent=extent,
                      aspect="equal" if equal else "auto", interpolation="nearest",
                      cmap="viridis",
                      norm=matplotlib.colors.LogNorm(vmin=1, vmax=max(counts.max(), 2)))
    if auto:
        xs, ys = np.nonzero(counts)
        ax.set_xlim(x_edges[xs.min()], x_edges[xs.max() + 1])
        ax.set_ylim(y_edges[ys.min()], y_edges[ys.max() + 1])
    bar = colorbar(ax, image, label=label)
    bar.ax.yaxis.set_major_locator(matplotlib.ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
    bar.ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(tick_label))
    bar.ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())


def megno_scale(values, threshold, what="MEGNO"):
    """The colour scale of MEGNO values (`what`: their name): (norm, ticks, the value marked,
    label).

    MEGNO ⟨Y⟩ tends to 2 on a quasi-periodic orbit (to 0 on a stable periodic one) and grows as
    λn/2 on a chaotic one. A linear scale spends its colours on the most chaotic orbits and gives
    the regular and the weakly chaotic ones the same colour (2 and 40 in one band). This scale is
    logarithmic from 1 to at least four times the threshold of the classes: each doubling of ⟨Y⟩
    is the same step in colour, so the regular orbits (2) stand apart from the weakly chaotic (3
    to 10) and those from the strongly chaotic (40 and more); the stable periodic orbits (below 1)
    share the lowest colour, and the threshold above which the run calls an orbit chaotic (its
    /chaos/class) is drawn across the bar, so that the colours read as the classes do."""
    finite = values[np.isfinite(values)]
    top = max(finite.max() if finite.size else 0.0, 4 * threshold)
    norm = matplotlib.colors.LogNorm(1.0, top, clip=True)
    decades = [m * 10 ** e for e in range(int(math.log10(top)) + 1) for m in (1, 2, 5)]
    ticks = sorted({1.0, 2.0, threshold} | {t for t in decades if 1.5 * threshold <= t <= top})
    return norm, ticks, threshold, rf"{what} $\langle Y\rangle$ (log; chaotic above {threshold:g})"


def fli_scale(values, steps):
    """The colour scale of FLI values (max_k ln |w_k|): (norm, ticks, the value marked, label).
    The FLI grows as ln n on a regular orbit and as λn on a chaotic one, so the scale is
    logarithmic over the values, with ln n of the run's n steps (the regular orbits' level) drawn
    across the bar."""
    positive = values[np.isfinite(values) & (values > 0)]
    regular = math.log(max(steps, 2))
    low = min(positive.min(), regular) if positive.size else regular / 10
    high = max(positive.max() if positive.size else 0.0, 10 * low)
    norm = matplotlib.colors.LogNorm(low, high, clip=True)
    powers = range(math.floor(math.log10(low)), math.ceil(math.log10(high)) + 1)
    ticks = [m * 10.0 ** e for e in powers for m in (1, 2, 5) if low <= m * 10.0 ** e <= high]
    return norm, ticks, regular, f"FLI (log; regular near ln $n$ = {regular:.3g})"


def scaled_colorbar(ax, mappable, scale, values):
    """The colour bar of `mappable` on `scale` (megno_scale's or fli_scale's): its ticks, its
    marked value across it, an arrow where values lie below the scale."""
    _, ticks, marked, label = scale
    below = bool((values[np.isfinite(values)] < mappable.norm.vmin).any())
    bar = colorbar(ax, mappable, label=label, extend="min" if below else "neither")
    bar.ax.yaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
    bar.ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    bar.ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    if mappable.norm.vmin <= marked <= mappable.norm.vmax:
        bar.ax.axhline(marked, color="black", linewidth=plt.rcParams["axes.linewidth"])
    return bar


def both_coordinates(*names):
    return all(n in COORDINATES for n in names)


def subset(points):
    """The indices of the points drawn: all, or beyond MAX_POINTS a fixed random subset, the same
    on every call."""
    if points <= MAX_POINTS:
        return slice(None)
    return np.sort(np.random.default_rng(0).choice(points, MAX_POINTS, replace=False))


def fit(ax, x, y, margin, least, within=(-math.inf, math.inf)):
    """Axes over the data's extent, `margin` of it wider on each side (`least` where it has none),
    and never beyond `within`."""
    for limit, v in ((ax.set_xlim, x), (ax.set_ylim, y)):
        pad = margin * (v.max() - v.min()) or least
        limit(max(v.min() - pad, within[0]), min(v.max() + pad, within[1]))


def draw_steps(ax, h):
    """A 1D histogram as filled steps."""
    ax.stairs(h.counts, h.edges[0], fill=True, alpha=0.4)
    ax.stairs(h.counts, h.edges[0])


def draw_histogram(ax, run, name, auto=False):
    h = runfile.Histogram.of(run["histograms/" + name])
    if h.counts.ndim == 2:
        draw_2d(ax, h.counts, h.edges[0], h.edges[1], "samples per bin (log)",
                equal=both_coordinates(*h.axes), auto=auto)
        ax.set_ylabel(symbol(h.axes[1]))
    else:
        draw_steps(ax, h)
        ax.set_ylabel("samples per bin")
        ax.set_ylim(bottom=0)
        if auto and h.counts.any():
            occupied = np.nonzero(h.counts)[0]
            ax.set_xlim(h.edges[0][occupied[0]], h.edges[0][occupied[-1] + 1])
    ax.set_xlabel(symbol(h.axes[0]))
    stride = run["histograms/" + name].attrs.get("stride", run.attrs["stride"])
    ax.set_title(f"density {name}, every {stride} steps", fontsize=pt(10))
    note(ax, outside_note(h))


def section_title(g, name):
    a = g.attrs
    return f"section {name}: {symbol(a['plane'])} = {a['value']:g} ({a['direction']}, {a['mode']})"


def draw_section(ax, run, name, color_by, auto=False):
    g = run["sections/" + name]
    points = len(g.datasets["x"])
    capped = g.attrs["crossings"] > points
    if points and not capped:
        orbit = g.datasets["orbit"]
        keep = subset(points)
        cmap, scale = "viridis", None
        if color_by == "orbit":  # one colour per orbit, cycling through 20
            value, label, cmap = orbit[keep] % 20, "orbit (mod 20)", "tab20"
        elif color_by in run.invariants:
            value = run[f"invariants/{color_by}/initial"][orbit[keep]]
            label = f"{symbol(color_by)} of the orbit (initial)"
        else:  # a chaos indicator; the GALIs by their logarithm, MEGNO and FLI on a log scale
            value = run[f"chaos/{color_by}"][orbit[keep]]
            label = f"{color_by} of the orbit"
            if color_by.startswith("gali"):
                value = np.log10(value)
                label = f"log10 {label}"
            elif color_by == "megno":
                scale = megno_scale(value, run["chaos"].attrs.get("megno_threshold", 3.0))
            elif color_by == "fli":
                scale = fli_scale(value, run.attrs["steps"])
        x, y = g.datasets["x"], g.datasets["y"]
        dots = ax.scatter(x[keep], y[keep], c=value, s=scaled(1.0) ** 2, linewidths=0, cmap=cmap,
                          norm=scale[0] if scale else None, rasterized=True)
        if scale:
            scaled_colorbar(ax, dots, scale, value)
        else:
            colorbar(ax, dots, label=label)
        x_edges, y_edges = g.datasets["x_edges"], g.datasets["y_edges"]
        shown = f"{min(points, MAX_POINTS)} of {points} points" if points > MAX_POINTS else \
            f"{points} points"
        if auto:  # the data's own extent, 2% wider
            fit(ax, x, y, 0.02, 0.5)
        else:
            ax.set_xlim(x_edges[0], x_edges[-1])
            ax.set_ylim(y_edges[0], y_edges[-1])
            cut = int(((x < x_edges[0]) | (x > x_edges[-1]) | (y < y_edges[0])
                       | (y > y_edges[-1])).sum())
            if cut:
                shown += f", {cut} outside the configured range (--range auto shows them)"
        if both_coordinates(g.attrs["x"], g.attrs["y"]):
            ax.set_aspect("equal", adjustable="datalim" if auto else "box")
        note(ax, f"{shown} ({g.attrs['crossings']} crossings)")
    else:
        h = runfile.Histogram.of(g, "density")
        draw_2d(ax, h.counts, h.edges[0], h.edges[1], "crossings per bin (log)",
                equal=both_coordinates(g.attrs["x"], g.attrs["y"]), auto=auto)
        why = f"{points} points kept, at most {g.attrs['cap']} per orbit" if points else \
            "no points kept"
        note(ax, f"density of all crossings ({why})\n{outside_note(h)}")
    ax.set_xlabel(symbol(g.attrs["x"]))
    ax.set_ylabel(symbol(g.attrs["y"]))
    ax.set_title(section_title(g, name), fontsize=pt(10))


def draw_drift(ax, run):
    shown = [math.log10(EPSILON)]  # the x range: machine epsilon and every occupied bin
    for name in run.invariants:
        g = run[f"invariants/{name}/drift_histogram"]
        h = runfile.Histogram.of(g)
        occupied = np.nonzero(h.counts)[0]
        if occupied.size:
            shown += [h.edges[0][occupied[0]], h.edges[0][occupied[-1] + 1]]
        ax.stairs(h.counts, h.edges[0], label=f"{symbol(name)}: zero {g.attrs['zero']}, "
                                              f"under {h.underflow}, over {h.overflow}")
    ax.axvline(math.log10(EPSILON), color="black", linestyle="--", linewidth=1,
               label=r"machine $\varepsilon$ = 2$^{-52}$", gid="reference")
    if any(run[f"invariants/{n}/drift_histogram/counts"].any() for n in run.invariants):
        ax.set_yscale("log")
    else:
        ax.set_ylim(0, 1)
        ax.text(0.5, 0.5, "no drift other than 0", transform=ax.transAxes, ha="center")
    ax.set_xlim(max(min(shown) - 1, h.edges[0][0]), min(max(shown) + 1, h.edges[0][-1]))
    ax.set_xlabel(r"log$_{10}$ max$_n$ |I$_n$ − I$_0$| / |I$_0$| (absolute where I$_0$ = 0)")
    ax.set_ylabel("orbits per bin")
    ax.set_title("invariant drift", fontsize=pt(10))
    legend_clear_of_data(ax)


def draw_image(ax, run):
    h = runfile.Histogram.of(run["invariants/image"])
    draw_2d(ax, h.counts, h.edges[0], h.edges[1], "orbits per bin (log)")
    ax.set_xlabel(f"{symbol(h.axes[0])} (initial)")
    ax.set_ylabel(f"{symbol(h.axes[1])} (initial)")
    ax.set_title("energy–momentum image", fontsize=pt(10))
    note(ax, outside_note(h))


# The tunes of [tunes] (/tunes): each orbit's two tunes over steps 1..N and N+1..2N, in cycles per
# step within [0, 1/2], and their diffusion log10 |Δν|.
RESONANCE_ORDER = 4  # the resonance lines drawn by default: |m| + |n| up to this
MAX_RESONANCE_ORDER = 20
DIFFUSION = r"log$_{10}$ |$\Delta\nu$|"
ESCAPED = "0.8"  # the colour of the orbits without tunes (escaped) over the initial points
MESH_LINES = 60  # a footprint's mesh joins every k-th point of a larger grid, as many lines at most


def initial(run, name):
    return run["initial/" + name]


def varying(run):
    """The coordinates whose initial values differ over the ensemble."""
    return [c for c in COORDINATES if np.ptp(initial(run, c)) > 0]


def lattice(run):
    """A grid's two coordinates, the outer one of the orbits' order first, and the values of
    each, from the initial points; None unless the run is a grid over two varying coordinates."""
    names = varying(run)
    if run.attrs["ensemble"] != "grid" or len(names) != 2:
        return None
    values = [np.unique(initial(run, c)) for c in names]
    if len(values[0]) * len(values[1]) != len(initial(run, names[0])):  # a shard of it
        return None
    first = initial(run, names[0]).reshape(len(values[0]), -1)
    if not (first == first[:, :1]).all():  # the second coordinate is the outer one
        names, values = names[::-1], values[::-1]
    return names, values


def amplitude(run):
    """Each orbit's initial distance from the origin over the coordinates that vary, its label."""
    names = varying(run) or list(COORDINATES)
    squares = " + ".join(symbol(c).strip("$") + "^2" for c in names)
    return np.sqrt(sum(initial(run, c) ** 2 for c in names)), f"amplitude $\\sqrt{{{squares}}}$"


def dot(points):
    """The area of a tune's dot among `points`: 4 pt wide for a few hundred, 1 pt for 10^5."""
    return scaled(min(4.0, max(1.0, 300 / math.sqrt(max(points, 1))))) ** 2


def tunes_note(tunes, drawn, coloured=False):
    """The orbits drawn and escaped; where colours show the diffusion, those at its floor."""
    a = tunes.attrs
    floor = f",\n{a['round_off']} at the round-off floor (lowest colour)" \
        if coloured and a["round_off"] else ""
    return f"{drawn} orbits; {a['escaped']} escaped (no tunes){floor}"


def resonances(order, box):
    """(m, n, k) of each resonance line m ν1 + n ν2 = k with 1 <= |m| + |n| <= order through the
    inside of box ((x0, x1), (y0, y1)), each line once (gcd(m, n, k) = 1, the first nonzero of
    m, n positive), lowest order first."""
    corners = [(x, y) for x in box[0] for y in box[1]]
    found = []
    for o in range(1, order + 1):
        for m in range(o + 1):
            for n in sorted({o - m, m - o} - ({-o} if m == 0 else set())):
                values = [m * x + n * y for x, y in corners]
                found += [(m, n, k) for k in range(math.floor(min(values)) + 1,
                                                   math.ceil(max(values)))
                          if math.gcd(m, n, k) == 1]
    return found


def crossing(m, n, k, box):
    """The two ends of the line m x + n y = k within the box, the left one first."""
    (x0, x1), (y0, y1) = box
    ends = [(x, (k - m * x) / n) for x in (x0, x1) if n] + \
           [((k - n * y) / m, y) for y in (y0, y1) if m]
    ends = sorted((x, y) for x, y in ends if x0 <= x <= x1 and y0 <= y <= y1)
    return ends[0], ends[-1]


def resonance_label(m, n, k):
    """(2, -1, 0) -> $2\\nu_1-\\nu_2=0$."""
    terms = "".join(("-" if c < 0 else "+" if j and m else "") +
                    (str(abs(c)) if abs(c) != 1 else "") + rf"\nu_{j + 1}"
                    for j, c in enumerate((m, n)) if c)
    return f"${terms}={k}$"


def draw_resonances(ax, order):
    """The resonance lines up to `order` across the Axes' box, each labelled along itself, lighter
    and thinner as the order rises; the labels at staggered places along their lines, in the paper
    style where they cover no tune (place_resonance_labels)."""
    box = (ax.get_xlim(), ax.get_ylim())
    width = plt.rcParams["lines.linewidth"]
    labels = []
    for i, (m, n, k) in enumerate(resonances(order, box)):
        rise = (abs(m) + abs(n) - 1) / max(order - 1, 1)  # 0 for the first order, 1 for the last
        shade = str(round(0.2 + 0.5 * rise, 3))
        (xa, ya), (xb, yb) = crossing(m, n, k, box)
        ax.plot([xa, xb], [ya, yb], color=shade, linewidth=width * (0.8 - 0.5 * rise), zorder=0.5,
                gid="reference")
        if paper():
            labels.append((resonance_label(m, n, k), ((xa, ya), (xb, yb)), shade))
            continue
        at = 0.2 + 0.6 * (i * 0.618 % 1)
        ax.text(xa + at * (xb - xa), ya + at * (yb - ya), resonance_label(m, n, k), color=shade,
                fontsize=pt(6), ha="center", va="bottom", zorder=3, clip_on=True,
                rotation=math.degrees(math.atan2(yb - ya, xb - xa)),
                transform_rotates_text=True, rotation_mode="anchor")
    if labels:
        after_layout(ax, lambda: place_resonance_labels(ax, labels))


def data_points(ax):
    """The canvas positions of the marks drawn in `ax` (scatter points, the occupied cells of an
    image) and the radius of each, in pixels."""
    xy, radii = [np.empty((0, 2))], [np.empty(0)]
    for c in ax.collections:
        if isinstance(c, matplotlib.collections.PathCollection) and len(c.get_offsets()):
            xy.append(c.get_offset_transform().transform(np.asarray(c.get_offsets())))
            radii.append(np.broadcast_to(np.sqrt(c.get_sizes()) / 2 * ax.figure.dpi / 72,
                                         len(xy[-1])))
    for image in ax.get_images():
        x0, x1, y0, y1 = image.get_extent()
        occupied = ~np.ma.getmaskarray(np.ma.asarray(image.get_array()))
        rows, columns = np.nonzero(occupied)
        dx, dy = (x1 - x0) / occupied.shape[1], (y1 - y0) / occupied.shape[0]
        xy.append(ax.transData.transform(np.column_stack([x0 + (columns + 0.5) * dx,
                                                          y0 + (rows + 0.5) * dy])))
        cell = np.abs(np.diff(ax.transData.transform([[x0, y0], [x0 + dx, y0 + dy]]), axis=0))
        radii.append(np.full(len(rows), np.hypot(*cell[0]) / 2))
    return np.concatenate(xy), np.concatenate(radii)


def place_resonance_labels(ax, labels):
    """The paper style's labels [(text, the line's two ends, shade)] of the resonance lines, each
    along its line (above or below it) at the first place, from its middle out, where it lies
    within the frame and covers no tune and no other label; a line with no such place is left
    unlabelled, which the note counts. Again from the start on each call; whether the note
    changed."""
    renderer = ax.figure.canvas.get_renderer()
    for text in ax.__dict__.get("qmaps_resonance_labels", []):
        text.remove()
    ax.qmaps_resonance_labels = []
    points, radii = data_points(ax)
    frame = ax.bbox
    margin = ax.figure.dpi / 72  # 1 pt
    placed = []  # the corners of each label placed
    for label, ends, shade in labels:
        (xa, ya), (xb, yb) = ax.transData.transform(ends)
        angle = math.atan2(yb - ya, xb - xa)
        along, across = np.array([math.cos(angle), math.sin(angle)]), \
            np.array([-math.sin(angle), math.cos(angle)])
        text = ax.text(0, 0, label, color=shade, fontsize=pt(6), ha="center", zorder=3,
                       in_layout=False)  # within the frame: none of the layout's business
        extent = text.get_window_extent(renderer)
        w, h = extent.width, extent.height
        spot = None
        for t in (0.5, 0.35, 0.65, 0.2, 0.8, 0.1, 0.9):
            centre = np.array([xa + t * (xb - xa), ya + t * (yb - ya)])
            for side in (1, -1):  # above the line, below it
                # The label's box with a margin: text measures a little differently at another
                # dpi.
                low, high = sorted((0.0, side * h))
                low, high, half = low - margin, high + margin, w / 2 + margin
                corners = np.array([centre + u * along + v * across
                                    for u, v in ((-half, low), (half, low), (half, high),
                                                 (-half, high))])
                if not ((corners >= frame.p0).all() and (corners <= frame.p1).all()):
                    continue
                u, v = (points - centre) @ along, (points - centre) @ across
                if ((np.abs(u) <= half + radii) & (v >= low - radii) & (v <= high + radii)).any():
                    continue
                outline = matplotlib.path.Path(corners, closed=True)
                if any(outline.intersects_path(other, filled=True) for other in placed):
                    continue
                spot = (centre, side)
                break
            if spot:
                break
        if spot is None:
            text.remove()
            continue
        text.set_position(ax.transData.inverted().transform(spot[0]))
        text.set(rotation=math.degrees(angle), rotation_mode="anchor",
                 va="bottom" if spot[1] > 0 else "top")
        placed.append(outline)
        ax.qmaps_resonance_labels.append(text)
    changed = False
    for note_text in (t for t in ax.texts if t.get_gid() == "note"):
        # Worded alike whatever the count, so that a new count moves little.
        base = note_text.__dict__.setdefault("qmaps_base", note_text.__dict__.get(
            "qmaps_raw", note_text.get_text()))
        said = f"{base}; {len(placed)} of {len(labels)} resonance lines labelled, " \
               "where no tune lies"
        changed |= said != note_text.__dict__.get("qmaps_raw")
        note_text.qmaps_raw = said
        wrap_text(note_text, text_width(ax), renderer)
    return changed


def fit_tunes(ax, nu1, nu2):
    """Axes over the tunes' extent, 5% wider, within [0, 1/2]; all of it, saying so, without
    tunes."""
    if nu1.size:
        fit(ax, nu1, nu2, 0.05, 0.01, within=(0.0, 0.5))
    else:
        ax.set_xlim(0.0, 0.5)
        ax.set_ylim(0.0, 0.5)
        ax.text(0.5, 0.5, "no tunes", transform=ax.transAxes, ha="center", va="center")


def tune_axes(ax):
    ax.set_xlabel(f"{symbol('nu1')} (cycles per step)")
    ax.set_ylabel(f"{symbol('nu2')} (cycles per step)")


def draw_frequency_map(ax, run, order):
    """Each orbit's tunes coloured by their diffusion, the most diffusive on top, over the tunes'
    extent; without per-orbit data the 2D histogram of the tunes."""
    tunes = run["tunes"]
    if "nu1" in tunes.datasets:
        nu1, nu2, diffusion = (tunes.datasets[n] for n in ("nu1", "nu2", "diffusion"))
        drawn = np.flatnonzero(np.isfinite(nu1) & np.isfinite(nu2))
        drawn = drawn[subset(drawn.size)]
        drawn = drawn[np.argsort(diffusion[drawn], kind="stable")]
        if drawn.size:
            dots = ax.scatter(nu1[drawn], nu2[drawn], c=diffusion[drawn], cmap="plasma",
                              s=dot(drawn.size), linewidths=0, rasterized=True)
            colorbar(ax, dots, label=DIFFUSION)
        fit_tunes(ax, nu1[drawn], nu2[drawn])
        note(ax, tunes_note(tunes, f"{drawn.size} of {nu1.size}", coloured=True))
    else:
        h = runfile.Histogram.of(tunes["frequency_map"])
        draw_2d(ax, h.counts, h.edges[0], h.edges[1], "orbits per bin (log)", auto=True)
        note(ax, f"{tunes_note(tunes, h.counts.sum())}\n{outside_note(h)}")
    draw_resonances(ax, order)
    tune_axes(ax)
    ax.set_title(f"frequency map, {tunes.attrs['window']} steps a window" +
                 (f", resonances to order {order}" if order else ""), fontsize=pt(10))


def draw_diffusion_map(ax, run, grid):
    """The diffusion over a grid's two coordinates, the escaped orbits in their own colour."""
    (x, y), values = grid
    diffusion = run["tunes/diffusion"].reshape(len(values[0]), len(values[1]))
    mesh = ax.pcolormesh(cell_edges(values[0]), cell_edges(values[1]), diffusion.T,
                         cmap=matplotlib.colormaps["plasma"].with_extremes(bad=ESCAPED),
                         rasterized=True)
    colorbar(ax, mesh, label=DIFFUSION)
    missing, escaped = int(np.isnan(diffusion).sum()), run["tunes"].attrs["escaped"]
    key = ""
    if missing:  # the escaped orbits, and any whose signals are both 0
        label = f"escaped ({escaped})" if missing == escaped else \
            f"no tune ({missing}, {escaped} escaped)"
        if paper():  # the grid fills the axes: said in the note
            key = f"; in grey: {label}"
        else:
            ax.legend(handles=[matplotlib.patches.Patch(color=ESCAPED, label=label)],
                      fontsize=pt(7), loc="upper right")
    ax.set_xlabel(f"{symbol(x)} (initial)")
    ax.set_ylabel(f"{symbol(y)} (initial)")
    ax.set_aspect("equal")
    ax.set_title("diffusion of the tunes over the initial points", fontsize=pt(10))
    note(ax, tunes_note(run["tunes"], diffusion.size - missing, coloured=True) + key)


def draw_footprint(ax, run, grid):
    """ν2 against ν1 coloured by the initial amplitude: a grid's neighbours joined into a mesh."""
    nu1, nu2 = run["tunes/nu1"], run["tunes/nu2"]
    size, label = amplitude(run)
    drawn = np.isfinite(nu1) & np.isfinite(nu2)
    norm = matplotlib.colors.Normalize()
    norm.autoscale_None(size[drawn] if drawn.any() else size)
    if grid:
        shape = tuple(len(v) for v in grid[1])
        k = math.ceil(max(shape) / MESH_LINES)
        at = np.stack([nu1, nu2], axis=-1).reshape(*shape, 2)[::k, ::k]
        a = size.reshape(shape)[::k, ::k]
        ends = [(at[:-1], at[1:], a[:-1], a[1:]), (at[:, :-1], at[:, 1:], a[:, :-1], a[:, 1:])]
        segments = np.concatenate([np.stack([p, q], axis=-2).reshape(-1, 2, 2)
                                   for p, q, _, _ in ends])
        colour = np.concatenate([(u + v).ravel() / 2 for _, _, u, v in ends])
        joined = np.isfinite(segments).all(axis=(1, 2))
        ax.add_collection(matplotlib.collections.LineCollection(
            segments[joined], array=colour[joined], cmap="viridis", norm=norm,
            linewidths=0.6 * plt.rcParams["lines.linewidth"]))
    dots = ax.scatter(nu1[drawn], nu2[drawn], c=size[drawn], cmap="viridis", norm=norm,
                      s=dot(drawn.sum()), linewidths=0, rasterized=True)
    colorbar(ax, dots, label=label)
    fit_tunes(ax, nu1[drawn], nu2[drawn])
    tune_axes(ax)
    mesh = "" if not grid else ", neighbours of the grid joined" if k == 1 else \
        f", grid points {k} apart joined"
    ax.set_title("tune footprint" + mesh, fontsize=pt(10))
    note(ax, tunes_note(run["tunes"], f"{drawn.sum()} of {drawn.size}"))


def draw_tune_amplitude(ax, run):
    """A line's tunes against the coordinate that varies most along it."""
    name = max(varying(run), key=lambda c: np.ptp(initial(run, c)))
    for j in (1, 2):
        ax.plot(initial(run, name), run[f"tunes/nu{j}"], "o-", ms=scaled(3), label=symbol(f"nu{j}"))
    ax.set_xlabel(f"{symbol(name)} (initial)")
    ax.set_ylabel("tune (cycles per step)")
    legend_clear_of_data(ax)
    ax.set_title("tunes along the line", fontsize=pt(10))
    tunes = run["tunes"]
    note(ax, tunes_note(tunes, int(np.isfinite(tunes.datasets["nu1"]).sum())))


def draw_tune_diffusion(ax, run):
    """The histogram of the diffusion, the round-off floor marked."""
    tunes = run["tunes"]
    g = tunes["histograms/diffusion"]
    h = runfile.Histogram.of(g)
    draw_steps(ax, h)
    floor = tunes.attrs["diffusion_floor"]
    if h.edges[0][0] <= floor <= h.edges[0][-1]:
        ax.axvline(floor, color="black", linestyle="--", linewidth=1, gid="reference",
                   label=f"round-off floor 2$^{{-53}}$: {tunes.attrs['round_off']} orbits")
        legend_clear_of_data(ax)
    ax.set_xlabel(DIFFUSION)
    ax.set_ylabel("orbits per bin")
    ax.set_ylim(bottom=0)
    ax.set_title("diffusion of the tunes", fontsize=pt(10))
    note(ax, f"median {g.attrs['median']:.3g} (quartiles {g.attrs['q1']:.3g}, "
             f"{g.attrs['q3']:.3g}); {tunes.attrs['escaped']} escaped\n{outside_note(h)}")


def tune_items(run, order):
    """The pictures of /tunes: the frequency map; with per-orbit data, a grid's diffusion over its
    plane, the footprint and a line's tunes along it; the diffusion's histogram."""
    tunes = run["tunes"]
    out = [("frequency-map", lambda ax: draw_frequency_map(ax, run, order))]
    if "nu1" in tunes.datasets and "initial" in run.groups:
        grid = lattice(run)
        if grid:
            out.append(("diffusion-map", lambda ax: draw_diffusion_map(ax, run, grid)))
        out.append(("tune-footprint", lambda ax: draw_footprint(ax, run, grid)))
        if run.attrs["ensemble"] == "line" and varying(run):
            out.append(("tune-amplitude", lambda ax: draw_tune_amplitude(ax, run)))
    if "histograms/diffusion" in tunes:
        out.append(("tune-diffusion", lambda ax: draw_tune_diffusion(ax, run)))
    return out


def items(run, color_by, auto=False, resonance_order=RESONANCE_ORDER):
    """(output name, drawing function of an Axes) for every picture of the run, in order;
    `auto`: the densities and sections over their data's extent, not the configured ranges;
    `resonance_order`: the frequency map's resonance lines up to that order."""
    out = []
    for name in run.get("histograms", runfile.Group("/histograms")).groups:
        out.append((f"histogram-{name}", lambda ax, n=name: draw_histogram(ax, run, n, auto)))
    for name in run.get("sections", runfile.Group("/sections")).groups:
        out.append((f"section-{name}",
                    lambda ax, n=name: draw_section(ax, run, n, color_by, auto)))
    if run.invariants:  # (a map written as formulas may track none)
        out.append(("drift", lambda ax: draw_drift(ax, run)))
    if "invariants/image" in run:
        out.append(("energy-momentum", lambda ax: draw_image(ax, run)))
    if "tunes" in run.groups:
        out += tune_items(run, resonance_order)
    return out


def summary_grid(panels):
    """(columns, rows) of the summary: two columns up to four panels, else three."""
    columns = min(panels, 2 if panels <= 4 else 3)
    return columns, math.ceil(panels / columns)


# The paper style's layout (fit_to_content): the tallest image, in column widths (a page's height
# for a summary), and the height over width of a frame whose picture's aspect is free.
TALLEST = 1.4
PAGE_HEIGHT = 9.0
FREE_SHAPE = 0.75


def panel_rows(fig, columns, count):
    """`count` Axes of the figure in rows of `columns`, as lists per row. In the paper style each
    row has a grid of its own, so that a shorter last row spans the figure's width and each row's
    frames can take the widths their aspects need (fit_to_content)."""
    rows = math.ceil(count / columns)
    if not paper():
        axes = [fig.add_subplot(rows, columns, k + 1) for k in range(count)]
        return [axes[r * columns:(r + 1) * columns] for r in range(rows)]
    outer = fig.add_gridspec(rows, 1)
    inner = [outer[r].subgridspec(1, min(columns, count - r * columns)) for r in range(rows)]
    fig.qmaps_grids = (outer, inner)
    return [[fig.add_subplot(grid[0, k]) for k in range(grid.ncols)] for grid in inner]


def frame_shape(ax):
    """The height over width that the frame of `ax` needs (its picture at a fixed aspect, such as
    two phase-space coordinates at equal aspect), or None where any will do."""
    if ax.get_aspect() == "auto" or ax.get_adjustable() != "box":
        return None
    return ax.get_aspect() * ax.get_data_ratio()


def wrap_text(text, width, renderer):
    """Sets the words of a text artist (as first given: kept as its qmaps_raw) in lines at most
    `width` pixels long (wide, or for an upright label such as a colour bar's, tall), each word
    measured once."""
    raw = text.__dict__.setdefault("qmaps_raw", text.get_text())
    if text.__dict__.get("qmaps_wrapped") == (raw, round(width)):
        return
    probe = matplotlib.text.Text(0, 0, "", fontproperties=text.get_fontproperties())
    probe.set_figure(text.figure)

    def length(words):
        probe.set_text(words)
        return probe.get_window_extent(renderer).width

    space = length("x x") - length("xx")
    lines = []
    for paragraph in raw.split("\n"):
        line, used = [], 0.0
        for word in paragraph.split(" "):
            size = length(word)
            if line and used + space + size > width:
                lines.append(" ".join(line))
                line, used = [], 0.0
            used += (space if line else 0.0) + size
            line.append(word)
        lines.append(" ".join(line))
    text.set_text("\n".join(lines))
    text.qmaps_wrapped = (raw, round(width))


def colour_bars(ax):
    return [bar for bar in ax.figure.axes
            if hasattr(bar, "_colorbar") and bar._colorbar.mappable.axes is ax]


NARROWEST_TEXT = 1.2  # inches: the width a panel's title, x label and note wrap to at least


def text_width(ax):
    """The width (pixels) the title, x label and note of `ax`, each centred on its frame, wrap
    to: the frame's, or NARROWEST_TEXT. (A text that juts out of its frame widens the frame's
    margins by as much; centred, it juts out half as far on each side, and the layout settles.)"""
    return max(ax.bbox.width, NARROWEST_TEXT * ax.figure.dpi)


def wrap_panel_texts(fig, rows, headings):
    """Titles, x axis' labels and notes wrapped to text_width, colour bars' labels to the bars'
    height, `headings` (the figure's own texts) to the figure's width."""
    renderer = fig.canvas.get_renderer()
    for text in headings:
        wrap_text(text, 0.98 * fig.bbox.width, renderer)
    for ax in (ax for row in rows for ax in row):
        width = text_width(ax)
        texts = [ax.title, ax.xaxis.label] + [t for t in ax.texts if t.get_gid() == "note"]
        for text in texts:
            if text.get_text():
                wrap_text(text, width, renderer)
        for bar in colour_bars(ax):
            if bar.yaxis.label.get_text():
                wrap_text(bar.yaxis.label, bar.bbox.height, renderer)


def row_extents(fig, rows):
    """The height of each row of panels with its decorations (titles, axis labels, notes, colour
    bars), inches."""
    renderer = fig.canvas.get_renderer()
    extents = []
    for row in rows:
        boxes = [a.get_tightbbox(renderer) for ax in row for a in [ax] + colour_bars(ax)]
        extents.append(max(b.y1 for b in boxes) - min(b.y0 for b in boxes))
    return [e / fig.dpi for e in extents]


def shown_tick_labels(axis):
    """The major tick labels an axis draws: those with text at ticks within its view."""
    low, high = sorted(axis.get_view_interval())
    slack = 1e-9 * (high - low)
    return [label for tick, label in zip(axis.get_major_ticks(), axis.get_ticklabels())
            if low - slack <= tick.get_loc() <= high + slack and label.get_text()]


def thin_ticks(ax, gap=2.0):
    """Fewer ticks on an axis whose tick labels (of a drawn figure) come closer than `gap` pixels,
    as on a narrow frame's x axis; whether it took any away."""
    renderer = ax.figure.canvas.get_renderer()
    thinned = False
    for axis, along in ((ax.xaxis, 0), (ax.yaxis, 1)):
        if not isinstance(axis.get_major_locator(), matplotlib.ticker.MaxNLocator):
            continue
        for bins in (5, 4, 3, 2):
            boxes = sorted((label.get_window_extent(renderer) for label in shown_tick_labels(axis)),
                           key=lambda b: b.p0[along])
            if all(b.p0[along] - a.p1[along] >= gap for a, b in zip(boxes, boxes[1:])):
                break
            ax.locator_params(axis="x" if along == 0 else "y", nbins=bins,
                              steps=[1, 2, 4, 5, 10])
            thinned = True
    return thinned


def fit_to_content(fig, rows, headings, width, tallest, free_shape=FREE_SHAPE):
    """The paper style's figure sized to its content, so that no canvas is left blank around a
    picture of fixed aspect: `width` wide, each row of panels (panel_rows) as tall as its frames
    need to fill the row at their aspects (a free aspect at `free_shape`), at most `tallest` in all;
    past that the free frames take the row's spare width, and a row of fixed aspects only (an
    image's) makes the figure narrower. Texts wrap (wrap_panel_texts; `headings`, the figure's
    own, to its width), crowded tick labels are thinned, and the placements that need the layout
    (after_layout) run once it holds. While it is sought the frames fill their slots (constrained layout measures
    the decorations of a frame shrunk to its aspect from the frame, not from its slot); they get
    their aspect back when their slots have it."""
    outer, inner = fig.qmaps_grids
    axes = [ax for row in rows for ax in row]
    shapes = [[frame_shape(ax) for ax in row] for row in rows]
    aspects = [(ax.get_aspect(), ax.get_adjustable()) for ax in axes]
    for ax in axes:
        ax.set_aspect("auto")
    size = (width, free_shape * width)
    for _ in range(12):
        fig.set_size_inches(size)
        wrap_panel_texts(fig, rows, headings)
        fig.draw_without_rendering()
        w, h = size
        frames = [[(w * ax.get_position().width, h * ax.get_position().height) for ax in row]
                  for row in rows]
        tall = [max(frame[1] for frame in row) for row in frames]
        wide = [[frame[0] for frame in row] for row in frames]
        decoration = h - sum(tall)
        heights = [sum(row) / sum(1 / (shape or free_shape) for shape in row_shapes)
                   for row, row_shapes in zip(wide, shapes)]
        squeeze = min(1.0, max(tallest - decoration, 0.2 * tallest) / sum(heights))
        heights = [squeeze * height for height in heights]
        widths, narrower = [], 0.0
        for row, row_shapes, height in zip(wide, shapes, heights):
            fixed = [height / shape for shape in row_shapes if shape]
            free = len(row) - len(fixed)
            spare = max(sum(row) - sum(fixed), 0.0)
            widths.append([height / shape if shape else max(spare / free, 0.2 * height)
                           for shape in row_shapes])
            if not free and len(rows) == 1:
                narrower = spare
        if narrower < 0.01 and all(abs(a - b) < 0.01 for a, b in zip(tall, heights)) and \
                all(abs(a - b) < 0.01 for x, y in zip(wide, widths) for a, b in zip(x, y)):
            break
        # A row's share of the height is that of its frames with their decorations (titles, axis
        # labels, notes); within a row the shares of the width are those of the frames alone.
        outer.set_height_ratios([height + extent - frame for height, extent, frame
                                 in zip(heights, row_extents(fig, rows), tall)])
        for grid, row in zip(inner, widths):
            grid.set_width_ratios(row)
        size = (w - narrower, sum(heights) + decoration)
        if len(rows) == 1 and narrower < 0.01 and \
                all(abs(a - b) < 0.01 for a, b in zip(wide[0], widths[0])):
            fig.set_size_inches(size)  # one row, as wide: its decorations keep their height
            break
    for ax, (aspect, adjustable) in zip(axes, aspects):
        # In its upper left corner: should the slot come out a little larger than the frame (at
        # another dpi), the frame keeps its place beside the tick labels on its left and under
        # its title, as constrained layout measured them.
        ax.set_aspect(aspect, adjustable=adjustable, anchor="NW")
    placed_on = None  # the frames the placements were made on
    for _ in range(4):  # a placement may lengthen a note or widen tick labels, moving the frames
        wrap_panel_texts(fig, rows, headings)
        fig.draw_without_rendering()
        if any([thin_ticks(ax) for ax in axes]):
            fig.draw_without_rendering()
        frames = [tuple(np.round(ax.bbox.bounds, 1)) for ax in axes]
        if frames == placed_on:
            break
        moved = [place() for place in fig.__dict__.get("qmaps_after_layout", [])]
        placed_on = frames
        if not any(moved):
            break


def save(fig, path, dpi):
    try:
        fig.savefig(path, dpi=dpi)
    except OSError as e:
        raise runfile.FileError(f"{path}: cannot write ({e.strerror})") from e
    finally:
        plt.close(fig)
    print(path)


def indicators(run):
    """The chaos indicators the run holds per orbit (with [chaos] and per-orbit output)."""
    chaos = run.get("chaos")
    return [] if chaos is None else [n for n in chaos.datasets if n != "class"]


def axis_symbol(axis):
    """A sweep's axis as symbols: "beta_over_alpha" -> $\\beta$/$\\alpha$."""
    return "/".join(symbol(part) for part in axis.split("_over_"))


def sweep_marks(sweep):
    """{point: label} for the points a sweep file marks: those where the map names a second
    integral its other points lack (a known integrable case: "I_case4" -> "IV"), and, where the
    map has δ, those with δ = 0 (separable)."""
    runs = sweep.groups["runs"]
    names = {int(k): [n for n in g.groups["invariants"].groups if n != "image"]
             for k, g in runs.groups.items()}
    fewest = min(len(v) for v in names.values())
    marks = {}
    for k, invariants in names.items():
        if len(invariants) > fewest:
            case = invariants[-1]
            marks[k] = ROMAN.get(case.removeprefix("I_case"), case) if case.startswith("I_case") else case
    delta = sweep.groups["parameters"].datasets.get("delta")
    if delta is not None:
        for k in np.flatnonzero(delta == 0):
            marks.setdefault(int(k), "δ=0")
    return marks


def cell_edges(values):
    """Edges of cells centred on sorted `values` (a single value gets width 1)."""
    v = np.asarray(values, dtype=float)
    if v.size == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = (v[1:] + v[:-1]) / 2
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def marks_footer(marks, axes, values, shape):
    """The sweep's marked points in words: "stars: known integrable cases over (β/α, δ/α):
    I (1, 2), IV (8, 6); circles: δ = 0 (separable)"."""
    def where(p):
        at = (values[0][p // shape[1]], values[1][p % shape[1]]) if len(shape) == 2 else \
            (values[0][p],)
        return "(" + ", ".join(f"{v:g}" for v in at) + ")"

    cases = [f"{text} {where(p)}" for p, text in sorted(marks.items()) if text != "δ=0"]
    said = [f"stars: known integrable cases over ({', '.join(map(axis_symbol, axes))}): "
            f"{', '.join(cases)}"] if cases else []
    if "δ=0" in marks.values():
        said.append(r"circles: $\delta$ = 0 (separable)")
    return "; ".join(said)


def plot_sweep(run, out_dir, stem, fmt, dpi):
    """The maps of a sweep file over its parameter plane (or line): the chaotic fraction and the
    median MEGNO with [chaos] (on megno_scale's colours), and the worst invariant drift, known
    cases marked: beside their stars, or, in the paper style (where no label may cover the
    data), in a footer that lists them."""
    sweep = run["sweep"]
    shape = tuple(int(n) for n in sweep.datasets["shape"])
    axes = [sweep.attrs[f"axis{k}"] for k in range(len(shape))]
    values = [sweep[f"axes/{a}"] for a in axes]
    panels = []
    if "chaotic_fraction" in sweep.datasets:
        panels += [("chaotic_fraction", f"chaotic fraction (MEGNO > {sweep.attrs['megno_threshold']:g})",
                    matplotlib.colors.Normalize(0, 1), "magma"),
                   ("median_megno", "median MEGNO", matplotlib.colors.LogNorm(), "viridis")]
    panels.append(("worst_drift", "worst relative invariant drift", matplotlib.colors.LogNorm(),
                   "cividis"))
    marks = sweep_marks(sweep)
    first = sweep.groups["runs"].groups[sorted(sweep.groups["runs"].groups)[0]]
    swept = {a.split("_over_")[0] for a in axes}
    params = {k[len("param."):]: v for k, v in first.attrs.items() if k.startswith("param.")}
    fixed = ", ".join(f"{symbol(k)} = {v:g}" for k, v in params.items()
                      if k not in swept and not math.isnan(v))
    energy = f", $E$ = {energy_of(run):g}" if energy_of(run) is not None else ""
    title = textwrap.fill(f"{run.attrs['map']} ({fixed}): {sweep.attrs['points']} points × "
                          f"{int(sweep['orbits'][0])} orbits ({first.attrs['ensemble']}{energy}), "
                          f"{run.attrs['steps']} steps", 10 ** 6 if paper() else 110)
    fig = plt.figure(figsize=(style["panel"][0] * len(panels), style["panel"][1] + 0.6),
                     layout="constrained")
    headings = [fig.suptitle(title, fontsize=pt(9))]
    rows = panel_rows(fig, len(panels), len(panels))
    for ax, (name, label, norm, cmap) in zip(rows[0], panels):
        data = np.asarray(sweep[name], dtype=float)
        if isinstance(norm, matplotlib.colors.LogNorm):
            data = np.where(data > 0, data, np.nan)
        if len(shape) == 2:
            scale = megno_scale(data, sweep.attrs["megno_threshold"], "median MEGNO") \
                if name == "median_megno" else None
            mesh = ax.pcolormesh(cell_edges(values[0]), cell_edges(values[1]),
                                 data.reshape(shape).T, norm=scale[0] if scale else norm,
                                 cmap=cmap)
            if scale:
                scaled_colorbar(ax, mesh, scale, data)
            else:
                colorbar(ax, mesh, label=label)
            ax.set_ylabel(axis_symbol(axes[1]))
            at = lambda p: (values[0][p // shape[1]], values[1][p % shape[1]])  # noqa: E731
        else:
            ax.plot(values[0], data, "o-", ms=3)
            ax.set_ylabel(label)
            if isinstance(norm, matplotlib.colors.LogNorm):
                ax.set_yscale("log")
            at = lambda p: (values[0][p], data[p])  # noqa: E731
        ax.set_xlabel(axis_symbol(axes[0]))
        ax.set_title(label, fontsize=pt(9))
        for p, text in sorted(marks.items()):
            x, y = at(p)
            case = text != "δ=0"
            ax.plot(x, y, "*" if case else "o", ms=scaled(9) if case else scaled(4),
                    mfc="none" if not case else "white", mec="cyan" if case else "white",
                    mew=scaled(1.0))
            if case and not paper():
                ax.annotate(text, (x, y), xytext=(4, 4), textcoords="offset points", color="cyan",
                            fontsize=pt(8), fontweight="bold")
    if paper():
        if marks:
            headings.append(fig.supxlabel(marks_footer(marks, axes, values, shape),
                                          fontsize=pt(8)))
        fit_to_content(fig, rows, headings, style["page"], PAGE_HEIGHT,
                       free_shape=1.0 if len(shape) == 2 else FREE_SHAPE)
    written = out_dir / f"{stem}-sweep.{fmt}"
    save(fig, written, dpi)
    return [written]


def default_colouring(run):
    """What colours section points unless --color-by says: MEGNO where the run has the chaos
    indicators per orbit; else the energy–momentum image's x or the first invariant whose initial
    values spread over more than 1% of their size (on a shell, H does not); else the orbit."""
    if "chaos/megno" in run:
        return "megno"
    image = run.get("invariants/image")
    for name in ([image.attrs["x"]] if image is not None else []) + run.invariants:
        values = run.get(f"invariants/{name}/initial")
        if values is not None and values.size and \
                np.ptp(values) > 0.01 * max(np.abs(values).max(), np.finfo(float).tiny):
            return name
    return "orbit"


def is_integrability_file(path):
    import h5py

    try:
        with h5py.File(path, "r") as f:
            return "integrability" in f
    except OSError:
        return False  # runfile.load says why


def plot(path, out_dir, fmt="png", dpi=200, color_by=None, auto=False, style_name="screen",
         resonance_order=RESONANCE_ORDER):
    """Writes every picture of the run file at `path` into `out_dir`, as ``qmaps-plot`` does,
    and returns the paths written (pathlib.Path). A sweep's file gets its one sweep image, and
    the file of ``qmaps integrability --out`` its one integrability image.

    Args:
        path: the run file.
        out_dir: the folder to write into, made when missing.
        fmt: "png", "pdf" or "svg".
        dpi: dots per inch.
        color_by: what colours the section points: "orbit", an invariant or a chaos indicator
            (as "megno"); None for the default (MEGNO with the chaos indicators, else an
            invariant that varies over the ensemble, else the orbit).
        auto: draw the densities and sections over their data's extent, not the configured
            ranges (``--range auto``).
        style_name: "screen", or "paper" (a journal column's width and type).
        resonance_order: the frequency map's resonance lines, m nu1 + n nu2 = k with
            ``|m| + |n|`` up to it; 0 for none, at most 20.

    Raises:
        FileError: the file cannot be read, or `out_dir` cannot be made or written.
        ValueError: a `color_by` the run lacks, or a resonance order out of range.

    Example::

        written = qmaps.plot.plot("suris.h5", "plots", color_by="H", style_name="paper")
    """
    global style
    if not 0 <= resonance_order <= MAX_RESONANCE_ORDER:
        raise ValueError(f"--resonance-order {resonance_order}: must be 0 (no lines) to "
                         f"{MAX_RESONANCE_ORDER}")
    style = STYLES[style_name]
    with matplotlib.rc_context(style["rc"]):
        return plot_in_style(path, out_dir, fmt, dpi, color_by, auto, resonance_order)


def draw_integrability(fig, result):
    """Draws the three panels of an Integrability (of ``qmaps.integrability``, or read from its
    file) into `fig`: the degree growth, the orbits' periods over finite fields against R(x),
    and the height growth. In the paper style the figure is then sized to its content, a page
    wide.

    Args:
        fig: a matplotlib Figure, empty.
        result: the Integrability.

    Example::

        r = qmaps.integrability("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1})
        fig = matplotlib.pyplot.figure(figsize=(15, 4), layout="constrained")
        qmaps.plot.draw_integrability(fig, r)
    """
    rows = panel_rows(fig, 3, 3)
    degrees, periods, heights = rows[0]
    d = result.degrees
    for run in d["runs"]:
        degrees.semilogy(np.arange(len(run["degrees"])), np.maximum(run["degrees"], 1), marker=".",
                         linewidth=1, label=f"p = {run['prime']}, line {run['line']}")
    growth = d["growth"] + (f", log λ = {d['entropy']:.6g}" if d["growth"] == "exponential" else
                            f", n^{d['polynomial_degree']:.3g}" if d["growth"] == "polynomial" else "")
    degrees.set(xlabel="step n", ylabel="degree $d_n$", title=f"degree growth: {growth}")
    legend_clear_of_data(degrees)
    top = 0
    for prime, field in sorted(result.fields.items()):
        t = np.sort(np.asarray(field["periods"], dtype=float))
        if len(t) < 2:
            continue
        x = t / (t.mean() / 2)
        top = max(top, x[-1])
        periods.step(x, np.arange(1, len(x) + 1) / len(x), where="post", linewidth=1,
                     label=f"p = {prime}: D = {field['ks_distance']:.3f}")
    x = np.linspace(0, max(top, 1), 400)
    periods.plot(x, 1 - np.exp(-x) * (1 + x), "k--", linewidth=1.5, label="R(x)")
    periods.set(xlabel="period / λ,  λ = mean / 2", ylabel="fraction of points",
                title=f"orbits over finite fields: {result.fields_says}")
    legend_clear_of_data(periods)
    h = result.heights
    heights.semilogy(np.arange(len(h["log_heights"])), np.maximum(h["log_heights"], 1e-3),
                     marker=".", linewidth=1)
    heights.set(xlabel="step n", ylabel="log height", title=f"height growth: {h['growth']}")
    title = fig.suptitle(f"{result.map}: {result.verdict} ({result.reason})", fontsize=pt(10))
    if paper():
        fit_to_content(fig, rows, [title], style["page"], PAGE_HEIGHT)


def integrability(result, path=None, dpi=200):
    """The matplotlib figure of an Integrability's evidence, in three panels (as
    ``draw_integrability``), saved to `path` when one is given.

    Args:
        result: an Integrability, or the path of the file ``qmaps integrability --out`` wrote.
        path: the image to write (its suffix gives the format); None to write none.
        dpi: dots per inch.

    Example::

        r = qmaps.integrability("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1})
        fig = qmaps.plot.integrability(r, "evidence.png")
    """
    if not hasattr(result, "degrees"):
        from .integrability import Integrability
        result = Integrability(os.fspath(result), "")
    fig = plt.figure(figsize=(style["panel"][0] * 3, style["panel"][1]), layout="constrained")
    draw_integrability(fig, result)
    if path is not None:
        save(fig, pathlib.Path(path), dpi)
    return fig


def plot_in_style(path, out_dir, fmt, dpi, color_by, auto, resonance_order):
    if is_integrability_file(path):
        out_dir = pathlib.Path(out_dir)
        try:
            out_dir.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise runfile.FileError(f"{out_dir}: cannot create ({e.strerror})") from e
        written = out_dir / f"{pathlib.Path(path).stem}-integrability.{fmt}"
        integrability(path, written, dpi)
        return [written]
    run = runfile.load(path, skip=UNUSED + ("sweep/runs/*",))
    if "sweep" in run.groups:
        out_dir = pathlib.Path(out_dir)
        try:
            out_dir.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise runfile.FileError(f"{out_dir}: cannot create ({e.strerror})") from e
        return plot_sweep(run, out_dir, pathlib.Path(path).stem, fmt, dpi)
    if color_by is None:
        color_by = default_colouring(run)
    elif color_by not in ["orbit"] + run.invariants + indicators(run):
        raise ValueError(f"--color-by {color_by}: not orbit, and the run's invariants are "
                         f"{', '.join(run.invariants)}"
                         + (f"; its chaos indicators {', '.join(indicators(run))}"
                            if indicators(run) else ""))
    out_dir = pathlib.Path(out_dir)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise runfile.FileError(f"{out_dir}: cannot create ({e.strerror})") from e
    stem = pathlib.Path(path).stem
    written = []
    pictures = items(run, color_by, auto, resonance_order)
    unwrapped = 10 ** 6  # the paper style wraps the titles to the figure's final width
    for name, draw in pictures:
        fig = plt.figure(figsize=style["image"], layout="constrained")
        title = fig.suptitle(run_title(run, unwrapped if paper() else
                                       90 * style["image"][0] / 6.4 / style["scale"]),
                             fontsize=pt(9))
        panels = panel_rows(fig, 1, 1)
        draw(panels[0][0])
        if paper():
            fit_to_content(fig, panels, [title], style["image"][0], TALLEST * style["image"][0])
        written.append(out_dir / f"{stem}-{name}.{fmt}")
        save(fig, written[-1], dpi)
    columns, rows = summary_grid(len(pictures))
    fig = plt.figure(figsize=(style["panel"][0] * columns, style["panel"][1] * rows),
                     layout="constrained")
    title = fig.suptitle(run_title(run, unwrapped if paper() else
                                   12 * columns * style["panel"][0] / style["scale"]),
                         fontsize=pt(11))
    panels = panel_rows(fig, columns, len(pictures))
    for ax, (_, draw) in zip((ax for row in panels for ax in row), pictures):
        draw(ax)
    if paper():
        fit_to_content(fig, panels, [title],
                       style["page"] if columns > 1 else style["image"][0], PAGE_HEIGHT)
    written.append(out_dir / f"{stem}-summary.{fmt}")
    save(fig, written[-1], dpi)
    return written


def main(argv):
    """The ``qmaps-plot`` program: draws the pictures of a run file, as its command line
    (``qmaps-plot --help``) says, and returns its exit code: 0, 2 for a bad command line or
    argument, 3 for a file that cannot be read or written.

    Args:
        argv: the arguments after the program's name.

    Example::

        code = qmaps.plot.main(["suris.h5", "-o", "plots", "--format", "pdf"])
    """
    parser = argparse.ArgumentParser(
        prog="qmaps-plot", description=__doc__.split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("file", help="a qmaps run file (.h5)")
    parser.add_argument("-o", "--out-dir", default=".", help="the folder to write to (default .)")
    parser.add_argument("--format", choices=("png", "pdf", "svg"), default="png")
    parser.add_argument("--dpi", type=int, default=200, help="dots per inch (default 200)")
    parser.add_argument("--color-by", help="what colours section points: orbit, an invariant or "
                        "a chaos indicator (e.g. megno) of the orbit (default: megno with the "
                        "chaos indicators, else the energy-momentum image's x or the first "
                        "invariant that varies over the ensemble, else orbit)")
    parser.add_argument("--range", choices=("config", "auto"), default="config",
                        help="densities and sections over the configured ranges (default), or "
                        "over their data's extent")
    parser.add_argument("--style", choices=tuple(STYLES), default="screen",
                        help="screen (default), or paper: a journal's column (a summary: its "
                        "page) and type, sized to the content, no text over the data, fonts "
                        "embedded")
    parser.add_argument("--resonance-order", type=int, default=RESONANCE_ORDER, metavar="N",
                        help="the frequency map's resonance lines m ν1 + n ν2 = k with |m| + |n| "
                        f"up to N, 0 for none (default {RESONANCE_ORDER}, at most "
                        f"{MAX_RESONANCE_ORDER})")
    args = parser.parse_args(argv)
    if args.dpi <= 0:
        parser.error(f"--dpi {args.dpi}: must be positive")
    try:
        plot(args.file, args.out_dir, args.format, args.dpi, args.color_by, args.range == "auto",
             args.style, args.resonance_order)
    except runfile.FileError as e:
        print(f"qmaps-plot: {e}", file=sys.stderr)
        return 3
    except ValueError as e:
        print(f"qmaps-plot: {e}", file=sys.stderr)
        return 2
    return 0


def console():
    """The qmaps-plot program a pip install makes."""
    sys.exit(main(sys.argv[1:]))


if __name__ == "__main__":  # python3 -m qmaps.plot
    console()
