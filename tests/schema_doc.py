"""The objects docs/hdf5-schema.md lists, parsed from its tables, and how to match a file to them.

The page has tables per group: `## Root attributes` (name | type | meaning) and `## Groups and
datasets` for `/`, and a "### `/path`" heading for every other group (name | kind | shape, type |
meaning). A name or path part in angle brackets (`<I>`, `<name>`, `param.<name>`) stands for
any name; an exact name wins over a placeholder (`/invariants/image` is not an `<I>`).
"""
import dataclasses
import re

import numpy as np


@dataclasses.dataclass(frozen=True)
class Entry:
    group: str  # "/", "/final/state", "/invariants/<I>", ...
    name: str  # "q1", "param.<name>", "<I>"
    kind: str  # "attribute", "dataset" or "group"
    dtype: str  # "int64", "float64", "uint8", "string"; "" for a group
    shapes: tuple  # the allowed shapes, each a tuple of expressions ("N_o", "nx + 1", "72")


def _cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def _names(cell):
    return re.findall(r"`([^`]+)`", cell)


def _shapes(cell, count):
    """The shapes of a "shape, type" cell, one alternative list per name of its row."""
    shapes = [tuple(p.strip() for p in s.split(",") if p.strip())
              for s in re.findall(r"`\(([^`]*)\)`", cell)]
    if " or " in cell:  # "`(nx,)` or `(nx, ny)` int64": one name, either shape
        return [tuple(shapes)] * count
    if len(shapes) == count:  # "`(nx + 1,)`, `(ny + 1,)` float64": one shape per name
        return [(s,) for s in shapes]
    return [tuple(shapes)] * count


def _group_of(title):
    """The group a heading documents: "/" for the root's two sections, the path of a heading
    that names exactly one ("`/final/state`"), else None (a section with no table of a group)."""
    if title in ("Root attributes", "Groups and datasets"):
        return "/"
    paths = re.findall(r"`(/[^`]*)`", title)
    return paths[0] if len(paths) == 1 else None


def parse(path):
    """Every Entry of the page at `path`, in order."""
    entries, group, header = [], None, None
    with open(path, encoding="utf-8") as page:
        lines = page.read().splitlines()
    for line in lines:
        heading = re.match(r"^#+ (.*)$", line)
        if heading:
            group = _group_of(heading.group(1))
        if group is None or not line.startswith("|"):
            header = None  # a table ends where its lines end
            continue
        if header is None:
            header = _cells(line)
            continue
        if set(line) <= set("|- "):
            continue
        row = dict(zip(header, _cells(line)))
        names = _names(row["name"])
        kind = row.get("kind", "attribute")
        typed = row.get("shape, type", row.get("type", ""))
        dtype = next((t for t in ("int64", "float64", "uint8", "string") if t in typed), "")
        shapes = _shapes(typed, len(names)) if kind == "dataset" else [()] * len(names)
        entries.extend(Entry(group, name, kind, dtype, shape) for name, shape in zip(names, shapes))
    return entries


def _matches(documented, name):
    """Whether a documented name (possibly with <placeholders>) matches a concrete name."""
    parts = re.split(r"<[^>]+>", documented)
    return re.fullmatch("[^/]+".join(map(re.escape, parts)), name) is not None


def _best(candidates, name):
    """The exact candidate named `name`, else the first placeholder candidate matching it."""
    exact = [c for c in candidates if c == name]
    return exact[0] if exact else next(
        (c for c in candidates if "<" in c and _matches(c, name)), None)


def _join(group, name):
    return group.rstrip("/") + "/" + name


class Schema:
    """The entries of the page, matched against a file's concrete groups and names."""

    def __init__(self, path):
        self.entries = parse(path)

    def group(self, concrete):
        """The documented group ("/invariants/<I>") a file's group ("/invariants/H") is, or None."""
        documented = "/"
        for part in [p for p in concrete.split("/") if p]:
            subgroups = [e.name for e in self.entries
                         if e.group == documented and e.kind == "group"]
            name = _best(subgroups, part)
            if name is None:
                return None
            documented = _join(documented, name)
        return documented

    def entry(self, concrete_group, name, kind):
        """The Entry documenting `name` (an attribute, dataset or group) of a file's group."""
        group = self.group(concrete_group)
        here = [e for e in self.entries if e.group == group and e.kind == kind]
        best = _best([e.name for e in here], name)
        return next((e for e in here if e.name == best), None)


def dtype_name(value):
    """The schema's type name of an h5py dataset or attribute value."""
    if isinstance(value, (bytes, np.bytes_, str)):
        return "string"
    dtype = value.dtype
    if dtype.kind == "S":
        return "string"
    return {("i", 8): "int64", ("f", 8): "float64", ("u", 1): "uint8"}.get(
        (dtype.kind, dtype.itemsize), str(dtype))


def shape_matches(shape, alternatives, sizes):
    """Whether `shape` is one of `alternatives` once N_o, N_p, nx, ny take `sizes`' values."""
    def size(term):  # "nx + 1" with nx from `sizes`
        return eval(term, {"__builtins__": {}}, sizes)
    for alternative in alternatives:
        if len(alternative) == len(shape) and all(
                size(term) == n for term, n in zip(alternative, shape)):
            return True
    return False
