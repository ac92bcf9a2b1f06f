"""qmaps: ensembles of orbits of the integrable maps of a quartic two-degree-of-freedom
Hamiltonian, in process (docs/python.md).

    import qmaps
    run = qmaps.run("ensembles/presets/suris.toml", ensemble={"orbits": 10000})
    h = run.histogram("q1q2")                 # counts and edges
    x = run["sections/q1up/x"]                # numpy arrays
    run.save("suris.h5")                      # the file qmaps run writes
    table = qmaps.orbit("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1},
                        (0.1, 0.2, 0.0, 0.1), steps=1000)
    earlier = qmaps.load("suris.h5")          # a file, opened lazily
    kick = qmaps.Map("standard", "phase", {"K": 0.9}, step="p1 = p1 - K*sin(q1); q1 = q1 + p1")
    run = qmaps.run({"map": kick, ...})       # a map written as formulas (docs/formulas.md)
    qmaps.integrability("suris", {...})       # is it integrable? (docs/integrability.md)

qmaps.plot draws a file's pictures (the qmaps-plot program); it is imported, with matplotlib, on
first use.
"""
from .engine import Spec, maps, orbit, run, spec
from .errors import ConfigError, Error, FileError, UnsupportedError
from .formula_map import Map
from .integrability import Integrability, integrability
from .runfile import Group, Histogram, Run, load

__all__ = ["run", "spec", "Spec", "orbit", "maps", "Map", "integrability", "Integrability", "load",
           "Run", "Group", "Histogram", "Error", "ConfigError",
           "FileError", "UnsupportedError"]


def __getattr__(name):
    """qmaps.plot, imported when first used, so that `import qmaps` does not import matplotlib."""
    if name == "plot":
        import importlib
        return importlib.import_module(".plot", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
