"""A qmaps run file (docs/hdf5-schema.md), opened lazily under the schema's names.

    import qmaps
    with qmaps.load("suris.h5") as run:
        run.attrs["map"], run.params["h"], run["invariants/H/initial"]
        frame = run.to_pandas()           # one row per orbit

Everything the file holds is there, whatever its name (a newer writer's extra attributes and
datasets too): attributes become str, int or float, groups `Group`s, and a dataset is read into a
numpy array the first time it is asked for (`run.dataset(path)` gives the h5py dataset, to read
a slice). docs/python.md documents it.
"""
import collections.abc
import dataclasses
import fnmatch
import os
import shutil
import stat

import h5py
import numpy as np

from .errors import FileError

SCHEMA_VERSION = 1  # the version docs/hdf5-schema.md describes


def _decode(value):
    """An HDF5 attribute as str, int, float or (for an array) a numpy array."""
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8")
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    return value


def _check_replaceable(path):
    """Refuses (FileError) a `path` that exists but is not a regular file: a device, FIFO, folder
    or link is never replaced by a saved file (`Run.save('/dev/null')`)."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return
    except OSError as e:
        raise FileError(f"cannot write '{path}': {e.strerror or e}") from e
    if not stat.S_ISREG(mode):
        kind = ("a directory" if stat.S_ISDIR(mode) else "a FIFO" if stat.S_ISFIFO(mode) else
                "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else
                "a symbolic link" if stat.S_ISLNK(mode) else "not a regular file")
        raise FileError(f"cannot write '{path}': it is {kind}; save() replaces only a regular file")

class Datasets(collections.abc.MutableMapping):
    """A group's datasets by name, each read from the file into a numpy array the first time it
    is asked for, and kept. An array assigned to a name replaces the file's in memory."""

    def __init__(self, h5group, names):
        self._group = h5group
        self._names = list(names)
        self._read = {}

    def __getitem__(self, name):
        if name not in self._read:
            if name not in self._names:
                raise KeyError(name)
            try:
                self._read[name] = self._group[name][()]
            except OSError as e:  # a truncated or damaged file
                raise FileError(f"{self._group.file.filename}: {self._group.name.rstrip('/')}/"
                                f"{name} cannot be read: {_reason(e)}") from e
        return self._read[name]

    def __setitem__(self, name, value):
        if name not in self._names:
            self._names.append(name)
        self._read[name] = value

    def __delitem__(self, name):
        self._names.remove(name)
        self._read.pop(name, None)

    def __iter__(self):
        return iter(self._names)

    def __len__(self):
        return len(self._names)

    def h5(self, name):
        """The h5py dataset, whose slices read only what they ask for."""
        if name not in self._names or name not in self._group:
            raise KeyError(name)
        return self._group[name]


@dataclasses.dataclass
class Group:
    """An HDF5 group of a run file: its path, attributes, datasets (each read when first asked
    for) and subgroups, each by name.

    Attributes:
        path: the group's path in the file, as "/invariants/H".
        attrs: its attributes by name, each a str, int or float (an array stays a numpy array).
        datasets: its datasets by name, each read into a numpy array (the file's dtype and
            shape) when first asked for and then kept; an array assigned to a name replaces it
            in memory.
        groups: its subgroups by name, each a Group.

    Example::

        h = run["invariants/H"]                  # a Group
        drift = h.datasets["max_abs_drift"] / abs(h.datasets["initial"])
        print(h.path, list(h.datasets), h.attrs)
    """
    path: str
    attrs: dict = dataclasses.field(default_factory=dict)
    datasets: dict = dataclasses.field(default_factory=dict)
    groups: dict = dataclasses.field(default_factory=dict)

    def __getitem__(self, path):
        """The dataset (a numpy array) or group at `path` below this group.

        Args:
            path: names joined by "/", as "invariants/H/initial".

        Raises:
            KeyError: there is none.

        Example::

            initial = run["invariants/H/initial"]
        """
        node = self
        parts = [p for p in path.split("/") if p]
        for k, part in enumerate(parts):
            if part in node.groups:
                node = node.groups[part]
            elif part in node.datasets and k == len(parts) - 1:
                return node.datasets[part]
            else:
                raise KeyError(f"{path}: no {part!r} in {node.path}")
        return node

    def __contains__(self, path):
        """Whether there is a dataset or group at `path` below this group.

        Example::

            if "chaos/megno" in run:
                megno = run["chaos/megno"]
        """
        try:
            self[path]
        except KeyError:
            return False
        return True

    def get(self, path, default=None):
        """The dataset or group at `path` below this group, or `default` when there is none.

        Args:
            path: names joined by "/", as "chaos/megno".
            default: what to return when there is nothing at `path`.

        Example::

            megno = run.get("chaos/megno")       # None for a run without [chaos]
        """
        return self[path] if path in self else default


@dataclasses.dataclass
class Histogram:
    """A histogram of the file (a density, a section's density, a drift histogram, the
    energy-momentum image or a chaos indicator's), in one form.

    Attributes:
        counts: the counts, int64 of shape (nx,) or (nx, ny), x first.
        edges: the bins' edges, ``[x_edges]`` or ``[x_edges, y_edges]``.
        axes: the coordinate or invariant of each axis, the group's x (and y) attributes.
        underflow: the samples below the range.
        overflow: the samples above it.
        samples: all the samples, in range or not.

    Example::

        h = run.histogram("q1q2")
        assert h.samples == h.counts.sum() + h.underflow + h.overflow
    """
    counts: np.ndarray  # int64, (nx,) or (nx, ny), x first
    edges: list  # x_edges (and y_edges)
    axes: list  # the coordinate or invariant of each axis
    underflow: int
    overflow: int
    samples: int

    @classmethod
    def of(cls, group, counts="counts"):
        """The histogram stored in `group`.

        Args:
            group: the Group that holds it, as ``run["histograms/q1q2"]``.
            counts: the name of its counts' dataset: "counts", or "density" for a section.

        Example::

            density = qmaps.Histogram.of(run["sections/q1up"], "density")
        """
        data = group.datasets[counts]
        names = ["x", "y"][:data.ndim]
        return cls(data, [group.datasets[n + "_edges"] for n in names],
                   [group.attrs[n] for n in names], group.attrs["underflow"],
                   group.attrs["overflow"], group.attrs["samples"])


# The groups whose rows are not orbits: the sections' points and the trajectories' rows. Every
# other (N_o,) dataset, but a histogram's, is per-orbit data (a measurement's columns too).
NOT_PER_ORBIT = ("sections", "trajectories")


@dataclasses.dataclass
class Run(Group):
    """The root group of a run file, a Group, as ``qmaps.load`` and ``qmaps.run`` return it,
    with the parameters and invariant names at hand. It keeps the file open until ``close()`` (or the end
    of a ``with`` block).

    Attributes:
        file: the file's path.
        log: for a run of ``qmaps.run``, the summary lines ``qmaps run`` prints; else empty.

    Example::

        with qmaps.load("suris.h5") as run:
            print(run.attrs["map"], run.params, run.invariants)
            x = run["sections/q1up/x"]
    """
    file: str = ""
    h5file: object = None
    owned: str = ""  # a folder removed with the file on close() (a run of qmaps.run)
    log: str = ""  # the engine's summary lines (a run of qmaps.run)

    @property
    def params(self):
        """The map's parameters as a dict, ``{"A": 0.7, ..., "h": 0.1}``, read from the
        ``param.<name>`` attributes.

        Example::

            h = run.params["h"]
        """
        return {k[len("param."):]: v for k, v in self.attrs.items() if k.startswith("param.")}

    @property
    def invariants(self):
        """The names of the map's invariants, as ``["H", "I1", "I2"]``, the groups of
        /invariants (without the energy-momentum image).

        Example::

            for name in run.invariants:
                print(name, run["invariants/" + name].datasets["max_abs_drift"].max())
        """
        return [n for n in self.groups["invariants"].groups if n != "image"]

    def histogram(self, name):
        """The Histogram of /histograms/<name>: counts, edges, axes, under- and overflow.

        Args:
            name: the histogram's name in the configuration's ``[[histogram]]``.

        Example::

            h = run.histogram("q1q2")
            print(h.axes, h.counts.shape)
        """
        return Histogram.of(self["histograms/" + name])

    def histograms(self):
        """Every histogram of the file, whichever observer wrote it, as a dict of Histograms by
        its group's path: "histograms/q1q2", "invariants/H/drift_histogram", "sections/q1up",
        "chaos/histograms/megno", ... A section's is its density of crossings.

        Example::

            for path, h in run.histograms().items():
                print(path, h.axes, h.samples)
        """
        found = {}

        def visit(group):
            for counts in ("counts", "density"):
                if counts in group.datasets and "x_edges" in group.datasets:
                    found[group.path.strip("/")] = Histogram.of(group, counts)
            for child in group.groups.values():
                visit(child)
        visit(self)
        return found

    def tunes(self):
        """Each orbit's tunes (docs/tunes.md) as a dict of arrays of shape (orbits,) by name:
        "nu1", "nu2", "nu1_second", "nu2_second", "diffusion" (log10 of the tunes' change) and
        "class", NaN where an orbit has no tune.

        Raises:
            KeyError: the run has no ``[tunes]``.
            FileError: the run was written without per-orbit data.

        Example::

            tunes = run.tunes()
            chaotic = tunes["class"] == 1        # 0 regular, 1 chaotic, 2 escaped, 3 no tune
        """
        group = self["tunes"]
        names = ("nu1", "nu2", "nu1_second", "nu2_second", "diffusion", "class")
        if not all(n in group.datasets for n in names):
            raise FileError(f"{self.file}: no per-orbit tunes (the run was written with "
                            "[output] per_orbit = false); its histograms are in histograms()")
        return {n: group.datasets[n] for n in names}

    def dataset(self, path):
        """The h5py dataset at `path`, whose slices read only what they select.

        Args:
            path: the dataset's path, as "sections/q1up/x".

        Raises:
            KeyError: there is no such dataset.

        Example::

            first = run.dataset("sections/q1up/x")[:1000]
        """
        group, _, name = path.strip("/").rpartition("/")
        node = self[group] if group else self
        return node.datasets.h5(name)

    def per_orbit(self):
        """Every per-orbit dataset as a dict ``{column: array of shape (orbits,)}``: those of
        /initial, /final with its raw state, /escape, /invariants, /chaos and every
        measurement's columns (all but the sections' points, the trajectories' rows and the
        histograms), each named by its path with "." for "/": "initial.q1",
        "invariants.H.max_abs_drift", "escape.step".

        Raises:
            FileError: the file has none (a run written with ``per_orbit = false``).

        Example::

            columns = run.per_orbit()
            alive = columns["escape.step"] < 0
        """
        orbits = self.attrs["orbits"]
        columns = {}

        def visit(group, prefix):
            if "samples" in group.attrs:  # a histogram
                return
            for name in group.datasets:
                if group.datasets.h5(name).shape == (orbits,):
                    columns[prefix + name] = group.datasets[name]
            for name, child in group.groups.items():
                visit(child, prefix + name + ".")

        for name, group in self.groups.items():
            if name not in NOT_PER_ORBIT:
                visit(group, name + ".")
        if not columns:
            raise FileError(f"{self.file}: no per-orbit datasets (the run was written with "
                                 "[output] per_orbit = false)")
        return columns

    def to_pandas(self):
        """The per-orbit data as a pandas DataFrame, one row per orbit (index "orbit"), one
        column per dataset of ``per_orbit()``. Needs pandas (Debian: python3-pandas).

        Raises:
            ImportError: pandas is not installed.
            FileError: the file has no per-orbit data.

        Example::

            frame = run.to_pandas()
            print(frame["invariants.H.max_abs_drift"].describe())
        """
        pandas = _import("pandas", "python3-pandas")
        frame = pandas.DataFrame(self.per_orbit())
        frame.index.name = "orbit"
        return frame

    def to_xarray(self):
        """The per-orbit data as an xarray Dataset over the dimension "orbit", with the file's
        root attributes. Needs xarray (Debian: python3-xarray).

        Raises:
            ImportError: xarray is not installed.
            FileError: the file has no per-orbit data.

        Example::

            data = run.to_xarray()
            mean_q1 = data["initial.q1"].where(data["escape.step"] < 0).mean().item()
        """
        xarray = _import("xarray", "python3-xarray")
        variables = {name: ("orbit", values) for name, values in self.per_orbit().items()}
        attrs = {k: v for k, v in self.attrs.items() if isinstance(v, (str, int, float))}
        return xarray.Dataset(variables, coords={"orbit": np.arange(self.attrs["orbits"])},
                              attrs=attrs)

    def save(self, path):
        """Writes the file, as it is, to `path`: under a temporary name first (created anew,
        never through a link), renamed when complete, so that `path` is never a partial file.

        Args:
            path: where to write it (a str or os.PathLike); a regular file there is replaced.

        Raises:
            FileError: `path` exists but is not a regular file (a folder, device, FIFO or
                link), cannot be written, or the run's own file is gone (a run of
                ``qmaps.run`` that was closed).

        Example::

            with qmaps.run("ensembles/presets/suris.toml", ensemble={"orbits": 1000}) as run:
                run.save("suris-small.h5")
        """
        path = os.fspath(path)
        if not os.path.isfile(self.file):
            raise FileError(f"cannot save to '{path}': the run's file '{self.file}' is gone" +
                            (" (the run was closed, which removes it: save() before close())"
                             if self.h5file is None else ""))
        _check_replaceable(path)
        temporary = f"{path}.tmp-{os.getpid()}"
        made = False
        try:
            # Created anew, never through a link planted under the temporary's name.
            fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW |
                         os.O_CLOEXEC, 0o644)
            made = True
            with os.fdopen(fd, "wb") as out, open(self.file, "rb") as source:
                shutil.copyfileobj(source, out)
            _check_replaceable(path)  # what the name holds now
            os.replace(temporary, path)
        except (OSError, FileError) as e:
            if made and os.path.lexists(temporary):
                os.remove(temporary)
            if isinstance(e, FileError):
                raise
            raise FileError(f"cannot write '{path}': {e.strerror or e}") from e

    def close(self):
        """Closes the file: datasets not read by then can no longer be; arrays already read stay
        valid. A run of ``qmaps.run`` removes its file then (``save()`` it first to keep it).

        Example::

            run = qmaps.load("suris.h5")
            x = run["sections/q1up/x"]
            run.close()                          # x stays valid
        """
        if self.h5file is not None:
            self.h5file.close()
            self.h5file = None
        if self.owned:
            shutil.rmtree(self.owned, ignore_errors=True)
            self.owned = ""

    def __del__(self):
        try:
            self.close()
        except Exception:  # at the interpreter's exit h5py may be gone before us
            pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _import(module, package):
    try:
        return __import__(module)
    except ImportError as e:
        raise ImportError(f"{module} is needed for this (Debian: apt-get install {package})") from e


def _reason(e):
    """An OSError of the system or of HDF5 in a few words."""
    return os.strerror(e.errno) if getattr(e, "errno", None) else str(e)


def _child(h5group, name, file):
    """The group or dataset `name` of `h5group`; a link that leads nowhere is a FileError."""
    child = h5group.get(name)
    if child is None:
        link = h5group.get(name, getlink=True)
        target = (f"'{link.filename}:{link.path}'" if isinstance(link, h5py.ExternalLink)
                  else f"'{getattr(link, 'path', '?')}'")
        raise FileError(f"{file}: {h5group.name.rstrip('/')}/{name} is a link to {target} "
                        "that leads to nothing: a run's groups and datasets must be there")
    return child


def _load_group(h5group, group, skip, file):
    for name, value in h5group.attrs.items():
        group.attrs[name] = _decode(value)
    names = []
    for name in h5group:
        child = _child(h5group, name, file)
        path = f"{group.path.rstrip('/')}/{name}"
        if isinstance(child, h5py.Group):
            group.groups[name] = _load_group(child, Group(path), skip, file)
        elif not any(fnmatch.fnmatchcase(path.lstrip("/"), pattern) for pattern in skip):
            names.append(name)
    group.datasets = Datasets(h5group, names)
    return group


def _regular_file(path):
    """Raises FileError unless `path` is a regular file (a FIFO would hang the reader)."""
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise FileError(f"{path}: no such file") from None
    except OSError as e:
        raise FileError(f"{path}: cannot be read: {_reason(e)}") from e
    if stat.S_ISDIR(mode):
        raise FileError(f"{path}: a folder, not a file: a run is an HDF5 file")
    if not stat.S_ISREG(mode):
        raise FileError(f"{path}: not a regular file (a FIFO, device or socket): a run is an "
                        "HDF5 file")


def load(path, skip=()):
    """The run in the file at `path` as a Run, opened lazily: attributes and the tree are read
    now, each dataset when first asked for. Every group, dataset and attribute the file holds is
    there, whatever its name, but for the datasets `skip` leaves out.

    Args:
        path: the run file (a str or os.PathLike).
        skip: fnmatch patterns on a dataset's path without the leading /, as ``"initial/*"``
            or ``"invariants/*/final"``: the datasets they match are left out.

    Raises:
        FileError: the file is missing, not a regular file, not HDF5, damaged, or not a qmaps
            run; `path` is not a path.

    Example::

        run = qmaps.load("suris.h5", skip=("initial/*", "final/*"))
        print(run.attrs["orbits"], run.params)
        run.close()
    """
    try:
        path = os.fspath(path)
    except TypeError:
        raise FileError(f"{path!r}: not a path (str or os.PathLike), but "
                        f"{type(path).__name__}") from None
    if "\0" in (path if isinstance(path, str) else path.decode(errors="replace")):
        raise FileError(f"{path!r}: a file name cannot hold a NUL byte")
    _regular_file(path)
    f = None
    try:
        if not h5py.is_hdf5(path):
            raise FileError(f"{path}: not an HDF5 file")
        f = h5py.File(path, "r")
        if "schema_version" not in f.attrs:
            raise FileError(f"{path}: not a qmaps run (no schema_version attribute)")
        return _load_group(f, Run("/", file=path, h5file=f), skip, path)
    except (FileError, OSError, KeyError) as e:
        if f is not None:
            f.close()
        if isinstance(e, FileError):
            raise
        raise FileError(f"{path}: cannot be read as HDF5: {_reason(e)}") from e
