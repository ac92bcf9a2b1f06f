"""The engine in process: run(), orbit() and maps(), the qmaps program's run, orbit and list
commands with numpy arrays in and out (docs/python.md)."""
import operator
import collections.abc
import os
import shutil
import sys
import tempfile
import warnings

import numpy as np

from . import runfile, toml_text
from .errors import ConfigError, FileError

try:
    from . import _engine
except ImportError as missing:  # the package's pure-Python parts (load, plot) work without it
    _engine = None
    _missing = missing


def _the_engine():
    if _engine is None:
        raise ImportError("qmaps._engine is not built: configure with the Python module "
                          "(docs/python.md)") from _missing
    return _engine


def _config_source(config):
    """(path, text, the name messages give it) of a configuration given as a dict, TOML text or a
    path."""
    if isinstance(config, dict):
        return "", toml_text.dumps(config), "<dict>"
    if isinstance(config, os.PathLike):
        return os.fspath(config), "", ""
    if isinstance(config, str):
        if "\n" in config or "=" in config:
            return "", config, "<text>"
        return config, "", ""
    raise ConfigError(f"config: a dict, TOML text or a path, not {type(config).__name__}")


def _column(name, values):
    try:
        return np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise ConfigError(f"initial conditions: {name} must be numbers") from None


def _points(initial):
    """The (orbits, 4) float64 array (q1, q2, p1, p2) of `initial`: a dict or structured array
    with fields q1, q2, p1, p2, four arrays, or an array of shape (orbits, 4)."""
    names = ("q1", "q2", "p1", "p2")
    if isinstance(initial, dict) or getattr(getattr(initial, "dtype", None), "names", None):
        missing = [n for n in names if n not in (initial.keys() if isinstance(initial, dict)
                                                 else initial.dtype.names)]
        if missing:
            raise ConfigError(f"initial conditions: no {', '.join(missing)}")
        columns = [_column(n, initial[n]) for n in names]
    elif isinstance(initial, (list, tuple)) and len(initial) == 4 and np.ndim(initial[0]) == 1:
        columns = [_column(n, c) for n, c in zip(names, initial)]
    else:
        try:
            array = np.asarray(initial, dtype=np.float64)
        except (TypeError, ValueError):
            raise ConfigError(f"initial conditions: numbers of shape (orbits, 4), not "
                              f"{type(initial).__name__}") from None
        if array.ndim != 2 or array.shape[1] != 4:
            raise ConfigError(f"initial conditions: expected shape (orbits, 4), got {array.shape}")
        return np.ascontiguousarray(array)
    if len({c.shape for c in columns}) != 1 or columns[0].ndim != 1:
        raise ConfigError("initial conditions: q1, q2, p1 and p2 must be 1-D arrays of one length, "
                          f"got shapes {[c.shape for c in columns]}")
    return np.ascontiguousarray(np.stack(columns, axis=1))


def _integer(name, value, low, high, rule):
    """`value` as an int in [low, high] (numpy integers too), or a ConfigError naming the
    argument and the rule."""
    try:
        number = operator.index(value)
    except TypeError:
        raise ConfigError(f"{name}={value!r}: must be {rule}") from None
    if isinstance(value, bool) or not low <= number <= high:
        raise ConfigError(f"{name}={value!r}: must be {rule}")
    return number


def _number(name, value):
    """`value` as a float (numpy numbers and 0-d arrays too), or a ConfigError naming it."""
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"{name}={value!r}: must be a number") from None


def _flag(name, value):
    """`value` as a bool (numpy bools and 0-d arrays too), or a ConfigError naming it."""
    try:
        return bool(value)
    except (TypeError, ValueError):
        raise ConfigError(f"{name}={value!r}: must be True or False") from None


def _path(name, value):
    """`value` as a path (str, bytes or os.PathLike), or a ConfigError naming the argument."""
    try:
        return os.fspath(value)
    except TypeError:
        raise ConfigError(f"{name}={value!r}: must be a path (str or os.PathLike), not "
                          f"{type(value).__name__}") from None


def _orbit_arguments(params, ic):
    """The map's parameters as a dict and the initial condition as text, or a ConfigError naming
    the argument and the rule."""
    if params is not None and not isinstance(params, dict):
        raise ConfigError(f"params={params!r}: must be a dict {{name: value}}, not "
                          f"{type(params).__name__}")
    if isinstance(ic, str):
        return params or {}, ic
    try:
        values = [float(x) for x in np.asarray(ic, dtype=object).reshape(-1)]
    except (TypeError, ValueError):
        values = None
    if values is None or np.ndim(ic) != 1 or len(values) != 4:
        raise ConfigError(f"ic={ic!r}: must be four numbers (q1, q2, p1, p2)")
    return params or {}, ",".join(repr(x) for x in values)


def _run_folder(tmpdir):
    """A new folder for the run's file, in `tmpdir` (None: the system's)."""
    if tmpdir is not None:
        tmpdir = os.fsdecode(_path("tmpdir", tmpdir))
        if "\0" in tmpdir:
            raise FileError(f"tmpdir {tmpdir!r}: a folder name cannot hold a NUL byte")
    try:
        return tempfile.mkdtemp(prefix="qmaps-run-", dir=tmpdir)
    except OSError as e:
        where = "the system's temporary folder" if tmpdir is None else f"tmpdir '{tmpdir}'"
        why = {FileNotFoundError: "no such folder",
               NotADirectoryError: "not a folder"}.get(type(e), e.strerror or str(e))
        raise FileError(f"{where}: {why}: the run's file is written into a writable "
                        "folder there") from e


def _progress_callback(progress):
    if progress is None or progress is False:
        return None, None
    if callable(progress):
        return progress, None
    try:
        import tqdm
        bar = tqdm.tqdm(unit="step", desc="qmaps")
    except ImportError:
        bar = None

    def show(step, total):
        if bar is not None:
            bar.total = total
            bar.update(step - bar.n)
        else:
            print(f"\rqmaps: step {step} of {total}", end="" if step < total else "\n",
                  file=sys.stderr, flush=True)

    return show, bar


class Spec:
    """A run read and checked, not yet run, as ``qmaps.spec`` returns it: every key of its
    configuration read once (an unknown one refused with its line) and the memory it needs
    checked. Its attributes say what it runs; ``run()`` runs it, once.

    Attributes:
        map: the map's name.
        params: the map's parameters, ``{name: value}``, defaults filled in.
        orbits: its orbits (a sweep's, over all its points).
        steps: its steps.
        stride: its sampling stride: every stride-th step is sampled.
        points: a sweep's points; 1 for a run.
        invariants: the names of the invariants it tracks (``["H", "I1", "I2"]``).
        measured: the optional per-orbit measurements it takes.

    Example::

        spec = qmaps.spec("ensembles/presets/suris.toml", ensemble={"orbits": 1000})
        print(spec.map, spec.orbits, spec.steps, spec.invariants)
        run = spec.run()
    """

    def __init__(self, engine, handle, folder, label):
        self._engine, self._handle, self._folder, self._label = engine, handle, folder, label
        for key, value in engine.describe(handle).items():
            setattr(self, key, value)

    def __repr__(self):
        return (f"qmaps.Spec({self.map}, {self.orbits} orbits x {self.steps} steps"
                + (f", {self.points} points" if self.points > 1 else "") + ")")

    def run(self, *, progress=None):
        """Runs it as ``qmaps run`` does and returns the run, a ``qmaps.Run`` opened lazily:
        per-orbit arrays, histograms, sections and indicators as numpy arrays, the provenance in
        ``.attrs``, and ``.save(path)`` to keep the file. A spec runs once. The GIL is released
        while the orbits step.

        Args:
            progress: a callable ``progress(step, total)``, called after each segment, or True
                for a bar (tqdm when installed, else a line on stderr).

        Raises:
            ConfigError: the spec has run already.
            FileError: the run's file cannot be written.
            KeyboardInterrupt: a signal (Ctrl-C) stopped the run; nothing is kept.

        Example::

            spec = qmaps.spec("ensembles/presets/suris.toml", ensemble={"orbits": 1000})
            with spec.run(progress=True) as run:
                print(run.log)
        """
        if self._folder is None:
            raise ConfigError(f"{self!r} has run: a spec runs once (read it again with qmaps.spec)")
        folder, self._folder = self._folder, None
        callback, bar = _progress_callback(progress)
        try:
            log = self._engine.run(self._handle, callback)
            loaded = runfile.load(os.path.join(folder, "run.h5"))
        except BaseException:
            shutil.rmtree(folder, ignore_errors=True)
            raise
        finally:
            if bar is not None:
                bar.close()
        loaded.owned, loaded.log = folder, log
        return loaded

    def __del__(self):
        if getattr(self, "_folder", None) is not None:
            shutil.rmtree(self._folder, ignore_errors=True)


def spec(config, *, initial=None, threads=0, simd="auto", sets=(), tmpdir=None, **tables):
    """The run a configuration describes, read and checked as ``qmaps run`` reads it, not run: a
    ``qmaps.Spec``, whose attributes say what it runs and whose ``run()`` runs it.

    Args:
        config: a dict of tables, TOML text or the path of a TOML file.
        initial: the starting points instead of ``[ensemble]``: a dict or structured array with
            q1, q2, p1, p2, four arrays, or an array of shape (orbits, 4).
        threads: as ``--threads``: 1 to 1024, or 0 (the default) for every core.
        simd: as ``--simd``: "auto" (the default, the best this CPU has), "scalar", "sse2",
            "avx2" or "avx512".
        sets: ``"section.key=value"`` overrides, as ``--set``.
        tmpdir: the folder that holds the run's file until the run is closed (default: the
            system's temporary folder).
        **tables: keyword overrides by table, as ``run={"steps": 100}`` or
            ``ensemble={"orbits": 1000}``.

    Raises:
        ConfigError: a bad configuration or argument (the message names the key and its line).
        FileError: a file that cannot be read, or a ``tmpdir`` that cannot be written.
        UnsupportedError: ``simd`` names an instruction set this CPU or build lacks.

    Example::

        spec = qmaps.spec("ensembles/presets/suris.toml", run={"steps": 100},
                          ensemble={"orbits": 1000}, sets=["map.h=0.05"])
        print(spec)          # qmaps.Spec(suris, 1000 orbits x 100 steps)
    """
    engine = _the_engine()
    path, text, source = _config_source(config)
    if isinstance(sets, (str, bytes)) or not isinstance(sets, collections.abc.Iterable):
        raise ConfigError(f"sets={sets!r}: must be a list of \"section.key=value\" strings")
    try:
        overrides = list(sets)
    except TypeError:
        overrides = [None]
    if not all(isinstance(s, str) for s in overrides):
        raise ConfigError(f"sets={sets!r}: must be a list of \"section.key=value\" strings")
    if not isinstance(simd, str):
        raise ConfigError(f"simd={simd!r}: must be a path's name, as --simd (\"auto\", \"scalar\", "
                          "\"sse2\", \"avx2\", \"avx512\")")
    for table, values in tables.items():
        if not isinstance(values, dict):
            raise ConfigError(f"{table}={values!r}: a dict of keys, as {table}={{'key': value}}")
        overrides += [f"{table}.{k}={toml_text.value(v, f'{table}.{k}')}"
                      for k, v in values.items()]
    threads = _integer("threads", threads, 0, 2**31 - 1,
                       "an integer >= 1, as --threads (or 0, the default: every core)")
    points = None if initial is None else _points(initial)
    folder = _run_folder(tmpdir)
    label = f"qmaps.run({path or source})"
    try:
        handle = engine.read_spec(path, text, source, overrides, os.path.join(folder, "run.h5"),
                                  threads, simd, points, label)
    except BaseException:
        shutil.rmtree(folder, ignore_errors=True)
        raise
    return Spec(engine, handle, folder, label)


def run(config, *, initial=None, threads=0, simd="auto", progress=None, sets=(), tmpdir=None,
        **tables):
    """Runs a configuration as ``qmaps run`` does and returns the run, a ``qmaps.Run`` opened
    lazily: per-orbit arrays, histograms, sections and indicators as numpy arrays, the provenance
    in ``.attrs``, and ``.save(path)`` to keep the file. It is
    ``qmaps.spec(...).run(progress=...)``. The GIL is released while the orbits step.

    Args:
        config: a dict of tables, TOML text or the path of a TOML file.
        initial: the starting points instead of ``[ensemble]``: a dict or structured array with
            q1, q2, p1, p2, four arrays, or an array of shape (orbits, 4).
        threads: as ``--threads``: 1 to 1024, or 0 (the default) for every core.
        simd: as ``--simd``: "auto" (the default, the best this CPU has), "scalar", "sse2",
            "avx2" or "avx512".
        progress: a callable ``progress(step, total)``, called after each segment, or True for
            a bar (tqdm when installed, else a line on stderr).
        sets: ``"section.key=value"`` overrides, as ``--set``.
        tmpdir: the folder that holds the run's file until the run is closed (default: the
            system's temporary folder).
        **tables: keyword overrides by table, as ``run={"steps": 100}`` or
            ``ensemble={"orbits": 1000}``.

    Raises:
        ConfigError: a bad configuration or argument (the message names the key and its line).
        FileError: a file that cannot be read or written.
        UnsupportedError: ``simd`` names an instruction set this CPU or build lacks.
        KeyboardInterrupt: a signal (Ctrl-C) stopped the run; nothing is kept.

    Example::

        with qmaps.run("ensembles/presets/suris.toml", ensemble={"orbits": 1000},
                       run={"steps": 200}) as run:
            counts = run.histogram("q1q2").counts
            run.save("suris-small.h5")
    """
    return spec(config, initial=initial, threads=threads, simd=simd, sets=sets, tmpdir=tmpdir,
                **tables).run(progress=progress)


def orbit(map, params=None, ic=(0.0, 0.0, 0.0, 0.0), steps=1000, every=1, *, start="taylor",
          escape_bound=1e8, chaos=False, energy=None, frame=None):
    """One orbit's table, as ``qmaps orbit`` prints it: ``n``, the phase point, the map's
    invariants, the continuous system's integrals (the ``_cont`` columns) and, with
    ``chaos=True``, the chaos indicators. An orbit that escapes ends its rows before the escape,
    with a RuntimeWarning that says when.

    Args:
        map: a built-in map's name, a ``qmaps.Map``, or a TOML file whose ``[map]`` is written
            as formulas.
        params: ``{name: value}`` of the map's parameters (``qmaps.maps()`` lists them).
        ic: the initial condition (q1, q2, p1, p2): four numbers, or the text "q1,q2,p1,p2".
        steps: the steps, >= 0.
        every: keep every every-th row, >= 1.
        start: the rule that turns the phase point into the map's two-step state, "taylor"
            (the default) or "euler".
        escape_bound: the orbit escapes when ``|q|`` exceeds it.
        chaos: also the chaos indicators' columns (lyapunov, fli, megno, ...).
        energy: put the initial condition on H_cont = energy: p2 is solved from q1, q2, p1,
            with the sign ``ic`` gives it.
        frame: True for a pandas DataFrame, False for a numpy structured array (``n`` int64,
            the rest float64); None (the default) for the DataFrame when pandas is installed,
            else the array.

    Raises:
        ConfigError: a bad map, parameter or argument.
        KeyboardInterrupt: a signal (Ctrl-C) stopped the orbit; no rows are returned.

    Example::

        table = qmaps.orbit("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1},
                            (0.0, 0.3, 0.4, 0.1), steps=10000, every=10, frame=False)
        error = abs(table["H_cont"] - table["H_cont"][0]).max()
    """
    engine = _the_engine()
    if isinstance(map, dict):  # a qmaps.Map, or a [map] table written as formulas
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "map.toml")
            with open(path, "w") as f:
                f.write(toml_text.dumps({"map": map}))
            return orbit(path, params, ic, steps, every, start=start, escape_bound=escape_bound,
                         chaos=chaos, energy=energy, frame=frame)
    params, ic_text = _orbit_arguments(params, ic)
    sets = [f"{k}={toml_text.value(v, f'params[{k!r}]')}" for k, v in params.items()]
    steps = _integer("steps", steps, 0, 2**63 - 1, "an integer >= 0")
    every = _integer("every", every, 1, 2**63 - 1, "an integer >= 1")
    columns, table, escaped = engine.orbit(str(map), sets, ic_text, steps, every,
                                           str(start), _number("escape_bound", escape_bound),
                                           _flag("chaos", chaos),
                                           None if energy is None else _number("energy", energy))
    if escaped:
        warnings.warn(f"qmaps.orbit: {escaped}", RuntimeWarning, stacklevel=2)
    if frame is None or frame:
        try:
            import pandas
        except ImportError:
            if frame:
                raise ImportError("frame=True needs pandas (Debian: python3-pandas)") from None
        else:
            result = pandas.DataFrame(table, columns=columns)
            result["n"] = result["n"].astype(np.int64)
            return result
    # One contiguous copy of the table into the records (n is column 0), then n as integers.
    rows = np.empty(table.shape[0], dtype=[(c, np.int64 if c == "n" else np.float64)
                                           for c in columns])
    rows.view(np.float64).reshape(table.shape)[:] = table
    rows["n"] = table[:, 0]
    return rows


def maps():
    """Every built-in map by name, in ``qmaps list``'s order, as it prints them: ``{name:
    {"name", "summary", "equations", "invariants", "parameters"}}``. Each parameter is a dict
    ``{"name", "meaning", "default", "required"}``, its default None where it has none.

    Example::

        for name, m in qmaps.maps().items():
            print(name, [p["name"] for p in m["parameters"] if p["required"]])
    """
    return {m["name"]: m for m in _the_engine().maps()}
