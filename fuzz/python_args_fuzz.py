"""A fuzz target for the Python package's argument checking: qmaps.run, qmaps.spec, qmaps.orbit
and qmaps.load called with arguments drawn from hostile values (wrong types, NaN and infinities,
huge and negative integers, numpy scalars and arrays, strings with NUL, nested containers, paths
of folders, FIFOs and devices). Every call must return or raise qmaps.ConfigError or
qmaps.FileError, within a bound of time: any other exception, a crash or a hang is a finding,
printed with the call that reproduces it.

    python3 fuzz/python_args_fuzz.py [SECONDS, default 20] [SEED, default 1]

Each call is small (a few orbits and steps), so that a call that is accepted ends at once."""
import math
import os
import pathlib
import random
import sys
import tempfile
import time

import numpy as np

import qmaps

HOSTILE = [None, True, False, 0, 1, -1, 2, 3, 2**31, 2**63, -2**63 - 1, 10**30, 0.5, -0.0,
           float("nan"), float("inf"), -float("inf"), 1e-320, 1e308, "", "x", "1", "a\0b",
           "suris", "scalar", b"bytes", [], [1], [1.0, 2.0], [[1]], {}, {"a": 1}, (1, 2, 3, 4),
           np.float64(0.1), np.int64(5), np.array(0.2), np.array([1.0, 2.0]), np.uint8(255),
           np.float32("nan"), object(), math.pi]


def draw(rng, folder):
    """A value, hostile most of the time, sometimes a path of the folder's hostile files."""
    if rng.random() < 0.1:
        return str(folder / rng.choice(["fifo", "dir", "missing.h5", "text.h5", "link"]))
    if rng.random() < 0.05:
        return "/dev/zero"
    return rng.choice(HOSTILE)


def calls(rng, folder):
    """One call's function and arguments, as text for the report and a callable."""
    v = lambda: draw(rng, folder)  # noqa: E731
    kind = rng.randrange(3)
    if kind == 0:
        steps = rng.choice([v(), 5])
        if isinstance(steps, int) and 1000 < steps < 2**63:  # valid, and long: kept small
            steps = 1000
        tables = {"ensemble": {"orbits": rng.choice([v(), 8])}, "run": {"steps": steps}}
        key = rng.choice(["threads", "simd", "sets", "tmpdir", "initial", "progress"])
        kwargs = {key: v(), **tables}
        if rng.random() < 0.3:
            tables.setdefault(rng.choice(["map", "ensemble", "run", "output", "chaos"]), {})[
                rng.choice(["h", "A", "orbits", "steps", "kind", "seed", "file", "x"])] = v()
        config = rng.choice([PRESET, PRESET, v(), {"map": v()}])
        if key != "progress" and rng.random() < 0.5:  # the spec, read, then run
            return (f"qmaps.spec({config!r}, **{kwargs!r}).run()",
                    lambda: qmaps.spec(config, **kwargs).run().close())
        return f"qmaps.run({config!r}, **{kwargs!r})", lambda: qmaps.run(config, **kwargs).close()
    if kind == 1:
        args = [rng.choice([v(), "suris"]), rng.choice([v(), {"h": v()}, None]),
                rng.choice([v(), (0.1, 0.2, 0.0, 0.1)]), rng.choice([v(), 10])]
        kwargs = {rng.choice(["every", "start", "escape_bound", "chaos", "energy", "frame"]): v()}
        return (f"qmaps.orbit(*{args!r}, **{kwargs!r})",
                lambda: qmaps.orbit(*args, **kwargs))
    path = v()
    return f"qmaps.load({path!r})", lambda: qmaps.load(path).close()


def main():
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 20.0
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    rng = random.Random(seed)
    with tempfile.TemporaryDirectory() as d:
        folder = pathlib.Path(d)
        os.mkfifo(folder / "fifo")
        (folder / "dir").mkdir()
        (folder / "text.h5").write_text("not HDF5\n")
        (folder / "link").symlink_to(folder / "nowhere")
        os.chdir(folder)
        began, count, accepted = time.monotonic(), 0, 0
        while time.monotonic() - began < seconds:
            text, call = calls(rng, folder)
            started = time.monotonic()
            try:
                call()
                accepted += 1
            except (qmaps.ConfigError, qmaps.FileError):
                pass
            except BaseException as e:  # noqa: B902: every other outcome is a finding
                print(f"finding: {text} raised {type(e).__name__}: {e}")
                return 1
            if time.monotonic() - started > 30:
                print(f"finding: {text} took {time.monotonic() - started:.1f} s")
                return 1
            count += 1
        print(f"qmaps python_args_fuzz: {count} calls in {seconds:g} s ({accepted} accepted), "
              "each returned or raised ConfigError or FileError")
    return 0


PRESET = str(pathlib.Path(os.environ.get("QMAPS_SOURCE_DIR", pathlib.Path(__file__).parent.parent))
             / "ensembles" / "presets" / "suris.toml")

if __name__ == "__main__":
    sys.exit(main())
