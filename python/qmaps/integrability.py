"""qmaps.integrability: whether a rational map is integrable, by three exact tests (degree growth,
orbits over finite fields, height growth), as `qmaps integrability` runs them
(docs/integrability.md).

    r = qmaps.integrability("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1})
    r.verdict                     # "integrable", "not integrable" or "undecided"
    r.degrees["sequence"]         # d_0 … d_n, and the fitted growth
    r.fields[101]["periods"]      # the periods of the orbits mod 101
    qmaps.plot.integrability(r)   # the evidence in three panels
"""
import os
import tempfile

import numpy as np

from . import toml_text
from .engine import _integer, _number, _path, _the_engine
from .errors import ConfigError


class Integrability:
    """The evidence of one map, as ``qmaps.integrability`` returns it: the verdict and the three
    tests, each a dict of its group's attributes in the file (docs/integrability.md) with its
    arrays. ``str()`` of it is the report.

    Args:
        path: the HDF5 file ``qmaps integrability --out`` (or ``out=``) wrote.
        text: the report, as ``qmaps integrability`` prints it.

    Attributes:
        map: the map's name.
        verdict: "integrable", "not integrable" or "undecided".
        reason: why, in a sentence.
        tests_agree: whether the three tests agree.
        coordinates: the names of the coordinates the map was evaluated over.
        evaluated_by: how the map was evaluated over exact numbers.
        degrees: degree growth: "sequence" (d_0 ... d_n), "runs" (one per prime and line, each
            with its "degrees"), "growth", "entropy", "generating_function", ...
        fields: orbits over finite fields, by prime: "periods", "ks_distance", "p_value",
            "level_kept", ...
        fields_says: the finite fields' verdict.
        heights: height growth: "log_heights", "growth", ...
        text: the report.

    Example::

        r = qmaps.Integrability("mcmillan-integrability.h5", "")
        print(r.verdict, r.degrees["growth"], sorted(r.fields))
    """

    def __init__(self, path, text):
        import h5py

        self.text = text
        with h5py.File(path, "r") as f:
            top = f["integrability"]
            attrs = {k: _plain(v) for k, v in top.attrs.items()}
            self.map = attrs["map"]
            self.evaluated_by = attrs["evaluated_by"]
            self.verdict = attrs["verdict"]
            self.reason = attrs["reason"]
            self.tests_agree = bool(attrs["tests_agree"])
            self.coordinates = attrs["coordinates"].split(",")
            g = top["degrees"]
            runs = [dict({k: _plain(v) for k, v in g[name].attrs.items()},
                         degrees=g[name]["degrees"][()])
                    for name in sorted((n for n in g if n.startswith("run")), key=lambda n: int(n[3:]))]
            self.degrees = dict({k: _plain(v) for k, v in g.attrs.items()}, runs=runs,
                                sequence=runs[0]["degrees"])
            g = top["finite_fields"]
            self.fields_says = _plain(g.attrs["says"])
            self.fields = {}
            for name in g:
                field = dict({k: _plain(v) for k, v in g[name].attrs.items()},
                             periods=g[name]["periods"][()])
                self.fields[field["prime"]] = field
            g = top["heights"]
            self.heights = dict({k: _plain(v) for k, v in g.attrs.items()},
                                log_heights=g["log_heights"][()])

    def __repr__(self):
        return f"<qmaps.Integrability {self.map}: {self.verdict} ({self.reason})>"

    def __str__(self):
        return self.text


def _plain(value):
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, np.generic):
        return value.item()
    return value


def _primes(name, primes):
    try:
        return [_integer(f"{name}[{i}]", p, 2, 2**64 - 1, "a prime") for i, p in enumerate(primes)]
    except TypeError:
        raise ConfigError(f"{name}={primes!r}: must be a sequence of primes") from None


def integrability(map, params=None, *, steps=30, degree_cap=20000, degree_primes=(), lines=2,
                  field_primes=(), orbits=1000, max_period=0, height_steps=40,
                  height_bits=2**20, seed=1, out=None):
    """Whether `map` is integrable, by ``qmaps integrability``'s three exact tests (degree
    growth, orbits over finite fields, height growth), in process: its verdict and evidence, an
    Integrability. The arguments after ``params`` are the command's options of the same names.

    Args:
        map: a built-in map's name, a ``qmaps.Map``, or a TOML file whose ``[map]`` is written
            as formulas.
        params: ``{name: value}`` of the map's parameters, each read exactly as the decimal
            written.
        steps: degree growth: its steps, 1 to 10000.
        degree_cap: degree growth: stop where a degree passes it, >= 16.
        degree_primes: degree growth: the primes p of F_p(t); empty for two primes near 2^61.
        lines: degree growth: random lines per prime, 1 to 16.
        field_primes: finite fields: the primes; empty for 1009, 4001, 10007 (a map of two
            coordinates) or 31, 61, 101 (four).
        orbits: finite fields: orbits per prime, 2 to 10^8.
        max_period: finite fields: an orbit not back by then is counted apart; 0 for
            64 p^(d/2).
        height_steps: height growth: its steps, 1 to 10000.
        height_bits: height growth: stop where a height passes this many bits.
        seed: the random lines, the points and the bootstrap.
        out: also keep the evidence in this HDF5 file (its schema is in
            docs/integrability.md).

    Raises:
        ConfigError: a bad argument (named), a number that is not prime, or a map that is not
            rational (saying why).

    Example::

        r = qmaps.integrability("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1})
        print(r.verdict, r.reason)
        print(r.degrees["sequence"], r.fields[31]["periods"][:10])
    """
    if isinstance(map, dict):  # a qmaps.Map, or a [map] table written as formulas
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "map.toml")
            with open(path, "w") as f:
                f.write(toml_text.dumps({"map": map}))
            return integrability(path, params, steps=steps, degree_cap=degree_cap,
                                 degree_primes=degree_primes, lines=lines,
                                 field_primes=field_primes, orbits=orbits, max_period=max_period,
                                 height_steps=height_steps, height_bits=height_bits, seed=seed,
                                 out=out)
    if params is not None and not isinstance(params, dict):
        raise ConfigError(f"params: a dict of the map's parameters, not {type(params).__name__}")
    sets = [f"{k}={toml_text.value(v, f'params[{k!r}]')}" for k, v in (params or {}).items()]
    arguments = dict(
        steps=_integer("steps", steps, 1, 10000, "an integer in 1 … 10000"),
        degree_cap=_integer("degree_cap", degree_cap, 16, 2**62, "an integer >= 16"),
        degree_primes=_primes("degree_primes", degree_primes),
        lines=_integer("lines", lines, 1, 16, "an integer in 1 … 16"),
        field_primes=_primes("field_primes", field_primes),
        orbits=_integer("orbits", orbits, 2, 10**8, "an integer in 2 … 10^8"),
        max_period=_integer("max_period", max_period, 0, 2**63 - 1, "an integer >= 0"),
        height_steps=_integer("height_steps", height_steps, 1, 10000, "an integer in 1 … 10000"),
        height_bits=_number("height_bits", height_bits),
        seed=_integer("seed", seed, 0, 2**64 - 1, "an integer >= 0"))
    engine = _the_engine()
    if out is not None:
        path = _path("out", out)
        text = engine.integrability(str(map), sets, out=path, **arguments)
        return Integrability(path, text)
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "integrability.h5")
        text = engine.integrability(str(map), sets, out=path, **arguments)
        text = text[: text.rfind("\nwritten to ")] + "\n"
        return Integrability(path, text)
