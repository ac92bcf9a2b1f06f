"""Loads a qmaps run file (docs/hdf5-schema.md) into numpy arrays, under the schema's names.

    import sys; sys.path.insert(0, "tools")
    import qmaps_h5
    run = qmaps_h5.load("suris.h5")
    run.attrs["map"], run.params["h"], run["invariants/H/initial"]

Everything the file holds is loaded, whatever its name (a newer writer's extra attributes and
datasets too): attributes become str, int or float, datasets numpy arrays, groups `Group`s.
docs/python.md documents it.
"""
import dataclasses
import fnmatch
import os

import h5py
import numpy as np

SCHEMA_VERSION = 1  # the version docs/hdf5-schema.md describes


class QmapsFileError(Exception):
    """A file that cannot be read as a qmaps run; the message names the file and why."""


def _decode(value):
    """An HDF5 attribute as str, int, float or (for an array) a numpy array."""
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8")
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    return value


@dataclasses.dataclass
class Group:
    """An HDF5 group: its path, attributes, datasets and subgroups, each by name."""
    path: str
    attrs: dict = dataclasses.field(default_factory=dict)
    datasets: dict = dataclasses.field(default_factory=dict)
    groups: dict = dataclasses.field(default_factory=dict)

    def __getitem__(self, path):
        """The dataset or group at `path` below this group ("invariants/H/initial")."""
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
        try:
            self[path]
        except KeyError:
            return False
        return True

    def get(self, path, default=None):
        return self[path] if path in self else default


@dataclasses.dataclass
class Histogram:
    """A histogram of the file (drift, image, density or section density), in one form."""
    counts: np.ndarray  # int64, (nx,) or (nx, ny), x first
    edges: list  # x_edges (and y_edges)
    axes: list  # the coordinate or invariant of each axis
    underflow: int
    overflow: int
    samples: int

    @classmethod
    def of(cls, group, counts="counts"):
        """The histogram stored in `group` (`counts="density"` for a section)."""
        data = group.datasets[counts]
        names = ["x", "y"][:data.ndim]
        return cls(data, [group.datasets[n + "_edges"] for n in names],
                   [group.attrs[n] for n in names], group.attrs["underflow"],
                   group.attrs["overflow"], group.attrs["samples"])


@dataclasses.dataclass
class Run(Group):
    """The root group of a run file, with the parameters and invariant names at hand."""
    file: str = ""

    @property
    def params(self):
        """The map's parameters, {"A": 0.7, ..., "h": 0.1}, from the `param.<name>` attributes."""
        return {k[len("param."):]: v for k, v in self.attrs.items() if k.startswith("param.")}

    @property
    def invariants(self):
        """The map's invariants ("H", "I1", ...), as in the file (not the energy-momentum image)."""
        return [n for n in self.groups["invariants"].groups if n != "image"]


def _load_group(h5group, group, skip):
    for name, value in h5group.attrs.items():
        group.attrs[name] = _decode(value)
    for name, child in h5group.items():
        path = child.name.lstrip("/")
        if isinstance(child, h5py.Group):
            group.groups[name] = _load_group(child, Group(child.name), skip)
        elif not any(fnmatch.fnmatchcase(path, pattern) for pattern in skip):
            group.datasets[name] = child[()]
    return group


def load(path, skip=()):
    """The run in the file at `path`. Datasets whose path (without the leading /) matches a
    pattern of `skip` (fnmatch: "initial/*", "invariants/*/final") are left out, to save memory
    on large runs. Raises QmapsFileError when the file is missing, not HDF5 or not a qmaps run."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise QmapsFileError(f"{path}: no such file")
    if not h5py.is_hdf5(path):
        raise QmapsFileError(f"{path}: not an HDF5 file")
    with h5py.File(path, "r") as f:
        if "schema_version" not in f.attrs:
            raise QmapsFileError(f"{path}: not a qmaps run (no schema_version attribute)")
        return _load_group(f, Run("/", file=path), skip)
