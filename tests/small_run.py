"""A small run of the qmaps binary with every kind of observer, for the Python tests.

CMake passes the binary and the source tree as QMAPS_BINARY and QMAPS_SOURCE_DIR; run by hand,
they default to build/qmaps and this checkout. The package qmaps is the build tree's
(<binary's folder>/python, with its engine), for this process and the ones it starts.
"""
import os
import pathlib
import subprocess
import sys

SOURCE_DIR = pathlib.Path(os.environ.get("QMAPS_SOURCE_DIR", pathlib.Path(__file__).parent.parent))
BINARY = pathlib.Path(os.environ.get("QMAPS_BINARY", SOURCE_DIR / "build" / "qmaps"))
PRESET = SOURCE_DIR / "ensembles" / "presets" / "suris.toml"
TOOLS = SOURCE_DIR / "tools"
FIXTURES = pathlib.Path(__file__).parent / "fixtures"  # shared with the C++ tests and fuzzers
PACKAGE_DIR = BINARY.parent / "python"
if str(PACKAGE_DIR) not in os.environ.get("PYTHONPATH", "").split(os.pathsep):
    os.environ["PYTHONPATH"] = os.pathsep.join(
        p for p in (str(PACKAGE_DIR), os.environ.get("PYTHONPATH")) if p)
sys.path.insert(0, str(PACKAGE_DIR))


def fixture(name):
    """The text of the configuration tests/fixtures/`name` (tests/fixtures.hpp reads the same)."""
    return (FIXTURES / name).read_text()


def q2_section(name, mode):
    """A section of both directions across q2 = 0 that keeps every crossing, in `mode`."""
    return f"""
[[section]]
name = "{name}"
plane = "q2"
value = 0.0
direction = "both"
mode = "{mode}"
x = "q1"
y = "p1"
cap = 1000
x_range = [-1.0, 1.0]
y_range = [-1.0, 1.0]
bins = [64, 64]
"""


# Added to the preset (a 2D density, a section capped at 2 points per orbit, the image): a 1D
# density, a section that keeps every crossing, the chaos indicators and a trajectory.
EXTRA_OBSERVERS = """
[[histogram]]
name = "p1"
x = "p1"
x_range = [-1.0, 1.0]
bins = [50]
""" + q2_section("q2both", "linear") + """
[chaos]
spectrum = true

[[trajectory]]
name = "first"
first = 3
every = 50
"""

# The tunes over two windows of 32 steps (a run of at least 64 steps).
TUNES = """
[tunes]
window = 32
"""

# The flow's preset (its section of mode exact) with a second section of mode exact, in q2.
FLOW_PRESET = SOURCE_DIR / "ensembles" / "presets" / "leapfrog.toml"
FLOW_OBSERVERS = q2_section("q2exact", "exact")


def qmaps(directory, *args, env=None):
    """The binary run in `directory` with `args` (and `env` added to the environment), its
    output captured as text."""
    return subprocess.run([str(BINARY), *map(str, args)], capture_output=True, text=True,
                          cwd=directory, env={**os.environ, **(env or {})})


def datasets(path):
    """Every dataset of the file at `path`, by its path in the file, read whole."""
    import h5py  # here: the tests that never read a file run without it
    out = {}
    with h5py.File(path) as f:
        f.visititems(lambda name, item: out.__setitem__(name, item[()])
                     if isinstance(item, h5py.Dataset) else None)
    return out


def dataset_differences(a, b):
    """How the files a and b differ dataset by dataset (paths, types, bytes); [] if in nothing,
    and the number of datasets compared."""
    x, y = datasets(a), datasets(b)
    differences = [f"only in one file: {p}" for p in sorted(set(x) ^ set(y))]
    differences += [f"{p} differs" for p in sorted(set(x) & set(y))
                    if x[p].dtype != y[p].dtype or x[p].tobytes() != y[p].tobytes()]
    return differences, len(y)


def small_run(directory, orbits=2000, steps=200, name="small.h5", preset=PRESET,
              extra=EXTRA_OBSERVERS):
    """Runs the preset plus `extra` with `orbits` and `steps`; returns the file's path."""
    directory = pathlib.Path(directory)
    config = directory / "config.toml"
    config.write_text(preset.read_text() + extra)
    out = directory / name
    sets = ["--set", f"run.steps={steps}"]
    if orbits is not None:  # None: the preset's own (a grid's, one per point)
        sets += ["--set", f"ensemble.orbits={orbits}"]
    subprocess.run([str(BINARY), "run", str(config), *sets, "--out", str(out), "--quiet"],
                   check=True, capture_output=True, cwd=directory)
    return out


def every_layout(directory):
    """Small runs that together write everything the schema page documents: the preset with
    EXTRA_OBSERVERS and TUNES, a flow's with FLOW_OBSERVERS (mode exact), case2-staggered's and
    case3's raw states, and a map written as formulas (its formula.<key>). The first is the Suris
    run."""
    return [small_run(directory, orbits=300, steps=200, extra=EXTRA_OBSERVERS + TUNES),
            small_run(directory, orbits=300, steps=200, name="flow.h5", preset=FLOW_PRESET,
                      extra=FLOW_OBSERVERS),
            *(small_run(directory, orbits=None, steps=20, name=f"{p}.h5",
                        preset=PRESET.with_name(f"{p}.toml"), extra="")
              for p in ("case2-staggered", "case3")),
            small_run(directory, orbits=300, steps=20, name="formulas.h5",
                      preset=PRESET.with_name("suris-formulas.toml"), extra="")]
