"""qmaps-plot FILE.h5 [-o DIR] [--format png|pdf|svg] [--dpi N] [--color-by WHAT] [--range auto]
                   [--style screen|paper] [--resonance-order N]

Draws the pictures of a qmaps run file (docs/hdf5-schema.md), one image per item and a summary:
  <stem>-histogram-<name>   every /histograms/<name>: 2D on a log colour scale, 1D as steps
  <stem>-section-<name>     every /sections/<name>: the points coloured by their orbit (orbit),
                            its initial invariant or its chaos indicator (by default MEGNO, else
                            an invariant that varies over the ensemble, else the orbit), or the
                            section's density when the cap cut points or none were kept
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
Each image is 6.4 x 4.8 in, each summary panel 5 x 4 in, at --dpi dots per inch (default 200);
--style paper fits a journal's column: images 3.4 x 2.7 in (86 mm wide), 7 pt serif type with
STIX mathematics, thinner lines; its summary panels are as wide, two or three to a page's width.
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
import matplotlib.patches  # noqa: E402
import matplotlib.ticker  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import runfile  # noqa: E402

# Per --style: the size of an image and of a summary panel (inches), the scale on the type sizes
# the pictures name (10 pt titles at 1), and matplotlib's settings.
STYLES = {
    "screen": {"image": (6.4, 4.8), "panel": (5.0, 4.0), "scale": 1.0, "rc": {}},
    "paper": {"image": (3.4, 2.7), "panel": (3.4, 2.7), "scale": 0.7,
              "rc": {"font.size": 7, "font.family": "serif",
                     "font.serif": ["STIXGeneral", "DejaVu Serif"], "mathtext.fontset": "stix",
                     "axes.linewidth": 0.6, "lines.linewidth": 0.8, "xtick.major.width": 0.6,
                     "ytick.major.width": 0.6, "xtick.major.size": 2.5, "ytick.major.size": 2.5}},
}
style = STYLES["screen"]


def pt(size):
    """A type size of the screen style in the style in use."""
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
    """A coordinate, invariant or parameter as a physicist writes it, in matplotlib's mathtext:
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
    """A small note in the lower left corner, left out of the layout."""
    ax.text(0.01, 0.01, text, transform=ax.transAxes, fontsize=pt(7), va="bottom", ha="left",
            bbox=dict(facecolor="white", alpha=0.8, edgecolor="none", pad=1.5),
            in_layout=False)


def tick_label(value, _):
    return f"{value:g}" if value < 1e5 else f"$10^{{{round(math.log10(value))}}}$"


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
    bar = ax.figure.colorbar(image, ax=ax, label=label)
    bar.ax.yaxis.set_major_locator(matplotlib.ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
    bar.ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(tick_label))
    bar.ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())


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
        cmap = "viridis"
        if color_by == "orbit":  # one colour per orbit, cycling through 20
            value, label, cmap = orbit[keep] % 20, "orbit (mod 20)", "tab20"
        elif color_by in run.invariants:
            value = run[f"invariants/{color_by}/initial"][orbit[keep]]
            label = f"{symbol(color_by)} of the orbit (initial)"
        else:  # a chaos indicator; the GALIs by their logarithm
            value = run[f"chaos/{color_by}"][orbit[keep]]
            label = f"{color_by} of the orbit"
            if color_by.startswith("gali"):
                value = np.log10(value)
                label = f"log10 {label}"
        x, y = g.datasets["x"], g.datasets["y"]
        dots = ax.scatter(x[keep], y[keep], c=value, s=pt(1.0) ** 2, linewidths=0, cmap=cmap,
                          rasterized=True)
        ax.figure.colorbar(dots, ax=ax, label=label)
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
               label=r"machine $\varepsilon$ = 2$^{-52}$")
    if any(run[f"invariants/{n}/drift_histogram/counts"].any() for n in run.invariants):
        ax.set_yscale("log")
    else:
        ax.set_ylim(0, 1)
        ax.text(0.5, 0.5, "no drift other than 0", transform=ax.transAxes, ha="center")
    ax.set_xlim(max(min(shown) - 1, h.edges[0][0]), min(max(shown) + 1, h.edges[0][-1]))
    ax.set_xlabel(r"log$_{10}$ max$_n$ |I$_n$ − I$_0$| / |I$_0$| (absolute where I$_0$ = 0)")
    ax.set_ylabel("orbits per bin")
    ax.set_title("invariant drift", fontsize=pt(10))
    ax.legend(fontsize=pt(7), loc="upper right")


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
    return pt(min(4.0, max(1.0, 300 / math.sqrt(max(points, 1))))) ** 2


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
    and thinner as the order rises; the labels at staggered places along their lines."""
    box = (ax.get_xlim(), ax.get_ylim())
    width = plt.rcParams["lines.linewidth"]
    for i, (m, n, k) in enumerate(resonances(order, box)):
        rise = (abs(m) + abs(n) - 1) / max(order - 1, 1)  # 0 for the first order, 1 for the last
        shade = str(round(0.2 + 0.5 * rise, 3))
        (xa, ya), (xb, yb) = crossing(m, n, k, box)
        ax.plot([xa, xb], [ya, yb], color=shade, linewidth=width * (0.8 - 0.5 * rise), zorder=0.5)
        at = 0.2 + 0.6 * (i * 0.618 % 1)
        ax.text(xa + at * (xb - xa), ya + at * (yb - ya), resonance_label(m, n, k), color=shade,
                fontsize=pt(6), ha="center", va="bottom", zorder=3, clip_on=True,
                rotation=math.degrees(math.atan2(yb - ya, xb - xa)),
                transform_rotates_text=True, rotation_mode="anchor")


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
            ax.figure.colorbar(dots, ax=ax, label=DIFFUSION)
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
    ax.figure.colorbar(mesh, ax=ax, label=DIFFUSION)
    missing, escaped = int(np.isnan(diffusion).sum()), run["tunes"].attrs["escaped"]
    if missing:  # the escaped orbits, and any whose signals are both 0
        label = f"escaped ({escaped})" if missing == escaped else \
            f"no tune ({missing}, {escaped} escaped)"
        ax.legend(handles=[matplotlib.patches.Patch(color=ESCAPED, label=label)],
                  fontsize=pt(7), loc="upper right")
    ax.set_xlabel(f"{symbol(x)} (initial)")
    ax.set_ylabel(f"{symbol(y)} (initial)")
    ax.set_aspect("equal")
    ax.set_title("diffusion of the tunes over the initial points", fontsize=pt(10))
    note(ax, tunes_note(run["tunes"], diffusion.size - missing, coloured=True))


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
    ax.figure.colorbar(dots, ax=ax, label=label)
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
        ax.plot(initial(run, name), run[f"tunes/nu{j}"], "o-", ms=pt(3), label=symbol(f"nu{j}"))
    ax.set_xlabel(f"{symbol(name)} (initial)")
    ax.set_ylabel("tune (cycles per step)")
    ax.legend(fontsize=pt(7), loc="upper right")
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
        ax.axvline(floor, color="black", linestyle="--", linewidth=1,
                   label=f"round-off floor 2$^{{-53}}$: {tunes.attrs['round_off']} orbits")
        ax.legend(fontsize=pt(7), loc="upper right")
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


def plot_sweep(run, out_dir, stem, fmt, dpi):
    """The maps of a sweep file over its parameter plane (or line): the chaotic fraction and the
    median MEGNO with [chaos], and the worst invariant drift, known cases marked."""
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
                          f"{run.attrs['steps']} steps", 110)
    fig = plt.figure(figsize=(style["panel"][0] * len(panels), style["panel"][1] + 0.6),
                     layout="constrained")
    fig.suptitle(title, fontsize=pt(9))
    for k, (name, label, norm, cmap) in enumerate(panels):
        ax = fig.add_subplot(1, len(panels), k + 1)
        data = np.asarray(sweep[name], dtype=float)
        if isinstance(norm, matplotlib.colors.LogNorm):
            data = np.where(data > 0, data, np.nan)
        if len(shape) == 2:
            mesh = ax.pcolormesh(cell_edges(values[0]), cell_edges(values[1]),
                                 data.reshape(shape).T, norm=norm, cmap=cmap)
            fig.colorbar(mesh, ax=ax, label=label)
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
            ax.plot(x, y, "*" if case else "o", ms=9 if case else 4, mfc="none" if not case else "white",
                    mec="cyan" if case else "white", mew=1.0)
            if case:
                ax.annotate(text, (x, y), xytext=(4, 4), textcoords="offset points", color="cyan",
                            fontsize=pt(8), fontweight="bold")
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
    """Writes every picture of the run at `path` into `out_dir` in the style named; returns the
    paths written."""
    global style
    if not 0 <= resonance_order <= MAX_RESONANCE_ORDER:
        raise ValueError(f"--resonance-order {resonance_order}: must be 0 (no lines) to "
                         f"{MAX_RESONANCE_ORDER}")
    style = STYLES[style_name]
    with matplotlib.rc_context(style["rc"]):
        return plot_in_style(path, out_dir, fmt, dpi, color_by, auto, resonance_order)


def draw_integrability(fig, result):
    """The three panels of an Integrability (qmaps.integrability, or its file)."""
    degrees, periods, heights = fig.subplots(1, 3)
    d = result.degrees
    for run in d["runs"]:
        degrees.semilogy(np.arange(len(run["degrees"])), np.maximum(run["degrees"], 1), marker=".",
                         linewidth=1, label=f"p = {run['prime']}, line {run['line']}")
    growth = d["growth"] + (f", log λ = {d['entropy']:.6g}" if d["growth"] == "exponential" else
                            f", n^{d['polynomial_degree']:.3g}" if d["growth"] == "polynomial" else "")
    degrees.set(xlabel="step n", ylabel="degree $d_n$", title=f"degree growth: {growth}")
    degrees.legend(fontsize=pt(7))
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
    periods.legend(fontsize=pt(7))
    h = result.heights
    heights.semilogy(np.arange(len(h["log_heights"])), np.maximum(h["log_heights"], 1e-3),
                     marker=".", linewidth=1)
    heights.set(xlabel="step n", ylabel="log height", title=f"height growth: {h['growth']}")
    fig.suptitle(f"{result.map}: {result.verdict} ({result.reason})", fontsize=pt(10))


def integrability(result, path=None, dpi=200):
    """The figure of an Integrability (or of the file `qmaps integrability --out` wrote), saved to
    `path` when one is given."""
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
    for name, draw in pictures:
        fig = plt.figure(figsize=style["image"], layout="constrained")
        fig.suptitle(run_title(run, 90 * style["image"][0] / 6.4 / style["scale"]), fontsize=pt(9))
        draw(fig.add_subplot())
        written.append(out_dir / f"{stem}-{name}.{fmt}")
        save(fig, written[-1], dpi)
    columns, rows = summary_grid(len(pictures))
    fig = plt.figure(figsize=(style["panel"][0] * columns, style["panel"][1] * rows),
                     layout="constrained")
    fig.suptitle(run_title(run, 12 * columns * style["panel"][0] / style["scale"]), fontsize=pt(11))
    for k, (_, draw) in enumerate(pictures):
        draw(fig.add_subplot(rows, columns, k + 1))
    written.append(out_dir / f"{stem}-summary.{fmt}")
    save(fig, written[-1], dpi)
    return written


def main(argv):
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
                        help="screen (default), or paper: a journal column's width and type")
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
