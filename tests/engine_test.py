"""The Python package's engine (qmaps.run, qmaps.orbit, qmaps.maps) against the qmaps program:
the same files byte for byte, the same errors, the GIL released, Ctrl-C a clean stop. Run by
pytest; CMake passes QMAPS_BINARY and puts the build tree's package first (tests/small_run.py)."""
import gc
import os
import pathlib
import subprocess
import sys
import textwrap
import threading
import time
import tomllib

import h5py
import numpy as np
import pytest

import small_run

import qmaps

ROOT = small_run.SOURCE_DIR
SETS = {"ensemble": {"orbits": 501}, "run": {"steps": 120, "escape_bound": 0.6}}
CLI_SETS = ["--set", "ensemble.orbits=501", "--set", "run.steps=120", "--set",
            "run.escape_bound=0.6", "--quiet"]


datasets = small_run.datasets


def assert_same_datasets(mine, theirs):
    a, b = datasets(mine), datasets(theirs)
    assert sorted(a) == sorted(b)
    for path, value in b.items():
        assert a[path].dtype == value.dtype, path
        assert a[path].shape == value.shape, path
        assert a[path].tobytes() == value.tobytes(), path


@pytest.fixture(scope="module")
def configs(tmp_path_factory):
    """Two maps' configurations with every observer kind: Suris with a 1D and a 2D density, two
    sections (capped and linear), the image, the chaos indicators (spectrum too), the tunes and a
    trajectory; the leapfrog flow with its sections of mode exact."""
    folder = tmp_path_factory.mktemp("configs")
    out = {}
    for name, preset, extra in (("suris", small_run.PRESET,
                                 small_run.EXTRA_OBSERVERS + small_run.TUNES),
                                ("leapfrog", small_run.FLOW_PRESET, small_run.FLOW_OBSERVERS)):
        path = folder / f"{name}.toml"
        path.write_text(preset.read_text() + extra)
        out[name] = path
    return out


def cli(folder, *args, env=None):
    return small_run.qmaps(folder, *args, env=env)


@pytest.mark.parametrize("name", ["suris", "leapfrog"])
def test_run_writes_the_file_qmaps_run_writes(configs, tmp_path, name):
    """Every dataset byte for byte, from the config as a path, as TOML text and as a dict."""
    path = configs[name]
    r = cli(tmp_path, "run", path, *CLI_SETS, "--out", tmp_path / "cli.h5")
    assert r.returncode == 0, r.stderr
    text = path.read_text()
    for given in (path, str(path), text, tomllib.loads(text)):
        with qmaps.run(given, **SETS) as run:
            assert run.attrs["orbits"] == 501
            assert "particle-steps/s" in run.log
            run.save(tmp_path / "python.h5")
        assert_same_datasets(tmp_path / "python.h5", tmp_path / "cli.h5")


def test_run_gives_numpy_arrays_of_every_observer_kind(configs):
    with qmaps.run(configs["suris"], **SETS) as run:
        assert isinstance(run["initial/q1"], np.ndarray) and run["initial/q1"].shape == (501,)
        h = run.histogram("q1q2")
        assert h.counts.ndim == 2 and h.counts.dtype == np.int64
        assert [len(e) for e in h.edges] == [n + 1 for n in h.counts.shape]
        assert run["sections/q2both/x"].dtype == np.float64
        assert len(run["sections/q2both/orbit"]) == len(run["sections/q2both/x"]) > 0
        assert np.isfinite(run["chaos/megno"]).any()
        tunes = run.tunes()
        assert tunes["nu1"].shape == (501,) and tunes["class"].dtype == np.uint8
        bounded = run["escape/step"] < 0
        assert np.all((tunes["nu1"][bounded] > 0) & (tunes["nu1"][bounded] < 0.5))
        assert "tunes/frequency_map" in run.histograms()
        assert run.to_pandas().shape[0] == 501
        assert run.params["h"] > 0


def test_arrays_outlive_the_run_and_its_file_goes_with_it(configs):
    run = qmaps.run(configs["suris"], **SETS)
    q1, counts = run["final/q1"], run.histogram("q1q2").counts
    kept = q1.copy(), counts.copy()
    file = pathlib.Path(run.file)
    assert file.is_file()
    del run
    gc.collect()
    assert not file.exists() and not file.parent.exists()
    assert q1.tobytes() == kept[0].tobytes() and counts.tobytes() == kept[1].tobytes()


def test_initial_arrays_equal_the_same_points_from_a_file(configs, tmp_path):
    """The points as numpy arrays (each form) run as the file ensemble of the same points does."""
    first = tmp_path / "first.h5"
    assert cli(tmp_path, "run", configs["suris"], *CLI_SETS, "--out", first).returncode == 0
    points = {k: h5py.File(first)["initial"][k][()] for k in ("q1", "q2", "p1", "p2")}
    text = configs["suris"].read_text()
    config = tomllib.loads(text)
    from_file = dict(config, ensemble={"kind": "file", "path": str(first), "group": "initial"})
    expected = qmaps.run(from_file, run=SETS["run"])
    del config["ensemble"]
    stacked = np.stack([points[k] for k in ("q1", "q2", "p1", "p2")], axis=1)
    structured = np.zeros(501, dtype=[(k, "f8") for k in ("q1", "q2", "p1", "p2")])
    for k in points:
        structured[k] = points[k]
    for initial in (points, stacked, tuple(points[k] for k in ("q1", "q2", "p1", "p2")),
                    structured):
        with qmaps.run(config, initial=initial, run=SETS["run"]) as run:
            assert run.attrs["ensemble"] == "points"
            assert_same_datasets(run.file, expected.file)
    expected.close()


def bad_inputs(folder, good):
    """(what, the configuration's text, --set assignments) that qmaps run refuses."""
    text = good.read_text()
    return [
        ("unknown key", text + "\n[run]\nstepz = 3\n" if "[run]" not in text else
         text.replace("[run]", "[run]\nstepz = 3", 1), []),
        ("bad steps", text, ["run.steps=-5"]),
        ("unknown map", text.replace('name = "suris"', 'name = "nosuch"', 1), []),
        ("bad parameter", text, ["map.h=-1"]),
        ("bad orbits", text, ["ensemble.orbits=0"]),
        ("unknown kind", text, ["ensemble.kind=blob"]),
        ("bad section", text, ["section[0].direction=sideways"]),
        ("bad TOML", text + "\n[run\n", []),
        ("missing ensemble file", text, ["ensemble.kind=file", f"ensemble.path={folder}/none.h5"]),
        ("bad compression", text, ["output.compression=zip"]),
        ("too many orbits", text, ["ensemble.orbits=100000000000000"]),
    ]


def test_bad_input_raises_the_cli_message(configs, tmp_path):
    """Each bad input: the exception the exit code documents, with the message qmaps run prints
    after 'qmaps: error: '; nothing is left behind."""
    kinds = {2: qmaps.ConfigError, 3: qmaps.FileError}
    for what, text, sets in bad_inputs(tmp_path, configs["suris"]):
        path = tmp_path / "bad.toml"
        path.write_text(text)
        args = [a for s in sets for a in ("--set", s)]
        r = cli(tmp_path, "run", path, *args, "--quiet")
        assert r.returncode in kinds, (what, r.returncode, r.stderr)
        message = r.stderr.strip().splitlines()[0].removeprefix("qmaps: error: ")
        with pytest.raises(kinds[r.returncode]) as caught:
            qmaps.run(path, sets=sets, tmpdir=tmp_path)
        assert str(caught.value) == message, what
        assert isinstance(caught.value, qmaps.Error)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]
    missing = tmp_path / "missing.toml"
    r = cli(tmp_path, "run", missing, "--quiet")
    with pytest.raises(qmaps.FileError) as caught:
        qmaps.run(missing)
    assert r.returncode == 3 and str(caught.value) == r.stderr.strip().removeprefix("qmaps: error: ")


def test_bad_arguments_raise_clear_errors(configs):
    for initial in (np.zeros((3, 5)), {"q1": [0.0], "q2": [0.0], "p1": [0.0]},
                    ([0.0, 1.0], [0.0], [0.0], [0.0]), np.array([[0.1, 0.0, np.nan, 0.0]])):
        with pytest.raises(qmaps.ConfigError):
            qmaps.run({"map": {"name": "suris"}}, initial=initial)
    with pytest.raises(qmaps.ConfigError, match=r"leave out \[ensemble\]"):
        qmaps.run(configs["suris"], initial=np.zeros((2, 4)))
    with pytest.raises(qmaps.ConfigError, match="config: a dict, TOML text or a path, not int"):
        qmaps.run(42)
    with pytest.raises(qmaps.ConfigError, match="run=5: a dict of keys"):
        qmaps.run(configs["suris"], run=5)


def test_the_gil_is_released_while_stepping(configs):
    """A second Python thread counts while the run steps: far more than it could if the run
    held the interpreter."""
    count, running = [0], threading.Event()

    def counter():
        running.wait()
        while running.is_set():
            count[0] += 1
    worker = threading.Thread(target=counter)
    worker.start()
    running.set()
    began = time.perf_counter()
    run = qmaps.run(configs["suris"], ensemble={"orbits": 5000}, run={"steps": 2000}, threads=1)
    took = time.perf_counter() - began
    seen = count[0]
    running.clear()
    worker.join()
    run.close()
    print(f"counted {seen} in {took:.2f} s of run")
    assert took > 0.2 and seen > 10000


def test_progress_is_reported_up_to_the_last_step(configs):
    seen = []
    qmaps.run(configs["suris"], progress=lambda step, total: seen.append((step, total)),
              **SETS).close()
    assert seen and seen[-1] == (120, 120)
    assert [s for s, _ in seen] == sorted(s for s, _ in seen)


def test_progress_bar_and_a_failing_callback(configs, tmp_path, capfd):
    """progress=True draws a bar (tqdm) on stderr; a callback that raises ends the run with its
    exception and nothing left behind."""
    qmaps.run(configs["suris"], progress=True, **SETS).close()
    assert "120/120" in capfd.readouterr().err

    def fail(step, total):
        raise ArithmeticError(f"stop at {step}")
    with pytest.raises(ArithmeticError, match="stop at"):
        qmaps.run(configs["suris"], progress=fail, tmpdir=tmp_path, **SETS)
    assert not list(tmp_path.iterdir())


INTERRUPTED = """
import os, signal, sys, threading, qmaps
config, folder, how = sys.argv[1], sys.argv[2], sys.argv[3]
if how == "signal":  # Ctrl-C from outside, while it steps (the run lasts far longer than 5 s:
    # about 150 s; under load, importing and drawing the orbits have taken more than 1 s)
    threading.Timer(5.0, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
try:
    qmaps.run(config, ensemble={"orbits": 20000}, run={"steps": 100000}, threads=1,
              tmpdir=folder)
    print("finished")
except KeyboardInterrupt as e:
    print("interrupted:", e)
print("left:", os.listdir(folder))
run = qmaps.run(config, ensemble={"orbits": 100}, run={"steps": 64})  # still usable
print("after:", run.attrs["orbits"])
"""


@pytest.mark.parametrize("how", ["self", "signal"])
def test_ctrl_c_stops_cleanly_with_nothing_left(configs, tmp_path, how):
    env = {**os.environ, "QMAPS_SIGNAL_AT_STEP": "30:INT"} if how == "self" else os.environ
    folder = tmp_path / "runs"
    folder.mkdir()
    r = subprocess.run([sys.executable, "-c", INTERRUPTED, str(configs["suris"]), str(folder), how],
                       capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith("interrupted: qmaps: SIGINT at step"), r.stdout
    assert lines[1] == "left: []" and lines[2] == "after: 100", r.stdout
    assert not os.listdir(folder)


def test_orbit_equals_qmaps_orbit(tmp_path):
    params = {"A": 0.7, "B": 0.3, "alpha": 0.9, "beta": 0.9, "delta": 0.3, "h": 0.1}
    for chaos in (False, True):
        args = ["orbit", "--map", "leapfrog", *(a for k, v in params.items()
                                             for a in ("--set", f"{k}={v!r}")),
                "--ic", "0.1,0.2,0.05,0.1", "--steps", "300", "--every", "7"]
        r = cli(tmp_path, *args, *(["--chaos"] if chaos else []))
        assert r.returncode == 0, r.stderr
        header, *rows = r.stdout.splitlines()
        expected = np.array([[float(x) for x in row.split(",")] for row in rows])
        table = qmaps.orbit("leapfrog", params, (0.1, 0.2, 0.05, 0.1), steps=300, every=7,
                            chaos=chaos, frame=False)
        assert list(table.dtype.names) == header.split(",")
        got = np.stack([table[c].astype(np.float64) for c in table.dtype.names], axis=1)
        assert got.shape == expected.shape
        # The CSV's %.17g reads back exactly; NaN (n = 0 indicators) where the CSV has nan.
        assert np.array_equal(got, expected, equal_nan=True)
    frame = qmaps.orbit("leapfrog", params, (0.1, 0.2, 0.05, 0.1), steps=10)
    assert list(frame["n"]) == list(range(11))


def test_orbit_errors_and_escapes():
    with pytest.raises(qmaps.ConfigError, match="unknown map"):
        qmaps.orbit("nosuch", {}, (0, 0, 0, 0))
    with pytest.raises(qmaps.ConfigError, match="parameter 'A' is missing"):
        qmaps.orbit("suris", {}, (0.1, 0, 0, 0))
    with pytest.raises(qmaps.ConfigError, match="every=0: must be an integer >= 1"):
        qmaps.orbit("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1}, (0.1, 0, 0, 0), every=0)
    with pytest.raises(qmaps.ConfigError, match=r"rows of 10 columns need about .* GiB; .* is .* GiB; keep fewer rows"):
        qmaps.orbit("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1}, (0.1, 0, 0, 0),
                    steps=10**13)
    with pytest.warns(RuntimeWarning, match="escaped at step 3 "):
        t = qmaps.orbit("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1},
                        (0.3, 0.3, 0.5, 0.5), steps=1000, escape_bound=0.6, frame=False)
    assert len(t) == 3  # steps 0, 1, 2: it escapes at step 3, as qmaps orbit says


def test_orbit_of_a_million_steps_is_quick():
    params = {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1}
    began = time.perf_counter()
    t = qmaps.orbit("suris", params, (0.1, 0.2, 0.0, 0.1), steps=1_000_000, every=1000,
                    frame=False)
    took = time.perf_counter() - began
    print(f"qmaps.orbit: 1e6 steps, 1001 rows in {took:.3f} s")
    assert len(t) == 1001 and np.isfinite(t["H"]).all()


def test_maps_lists_every_map_as_qmaps_list(tmp_path):
    r = cli(tmp_path, "list")
    names = [line.split(":")[0] for line in r.stdout.splitlines() if not line.startswith(" ")]
    maps = qmaps.maps()
    assert list(maps) == names
    suris = maps["suris"]
    assert [p["name"] for p in suris["parameters"]] == ["A", "B", "alpha", "h"]
    assert all(p["meaning"] for m in maps.values() for p in m["parameters"])
    assert all(m["equations"] and m["invariants"] for m in maps.values())


def test_a_sweep_runs_from_python(tmp_path):
    config = tomllib.loads((ROOT / "ensembles/presets/scan-a-eq-b.toml").read_text())
    config["sweep"] = [{"parameter": "delta", "values": [0.0, 0.5]}]
    config["ensemble"]["orbits"] = 50
    config["run"]["steps"] = 50
    config.pop("output", None)
    path = tmp_path / "sweep.toml"
    with qmaps.run(config) as run:
        assert run["sweep/shape"].tolist() == [2]
        assert run["sweep/chaotic_fraction"].shape == (2,)


def test_a_spec_is_read_and_checked_before_it_runs_and_runs_once(configs, tmp_path):
    """qmaps.spec reads every key once: a bad one is refused with its line before anything runs
    (no folder left), the spec says what it runs, and its run is qmaps.run's, byte for byte."""
    spec = qmaps.spec(configs["suris"], tmpdir=tmp_path, **SETS)
    assert (spec.map, spec.orbits, spec.steps, spec.points) == ("suris", 501, 120, 1)
    assert spec.params["h"] > 0 and spec.invariants == ["H", "I1", "I2"]
    assert spec.measured == ["tunes"] and "501 orbits x 120 steps" in repr(spec)
    with spec.run() as run:
        run.save(tmp_path / "spec.h5")
    with pytest.raises(qmaps.ConfigError, match="a spec runs once"):
        spec.run()
    with qmaps.run(configs["suris"], **SETS) as run:
        run.save(tmp_path / "run.h5")
    assert_same_datasets(tmp_path / "spec.h5", tmp_path / "run.h5")
    before = sorted(p.name for p in tmp_path.iterdir())
    with pytest.raises(qmaps.ConfigError, match="stepz: unknown key"):
        qmaps.spec(configs["suris"], tmpdir=tmp_path, run={"stepz": 3})
    del spec
    gc.collect()
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    sweep = tomllib.loads((ROOT / "ensembles/presets/scan-a-eq-b.toml").read_text())
    sweep["sweep"] = [{"parameter": "delta", "values": [0.0, 0.5, 1.0]}]
    sweep["ensemble"]["orbits"] = 50
    assert qmaps.spec(sweep).points == 3


def test_pip_installs_into_a_venv(tmp_path):
    """pip install --no-build-isolation . into a venv that sees Debian's numpy and h5py, from
    this build folder (nothing is recompiled); the installed package runs."""
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(PIP_NO_INDEX="1", QMAPS_CMAKE_BUILD_DIR=str(small_run.BINARY.parent))
    r = subprocess.run([str(venv / "bin/pip"), "install", "--no-build-isolation", "--quiet",
                        str(ROOT)], capture_output=True, text=True, env=env, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    script = textwrap.dedent("""
        import qmaps
        suris = {"name": "suris", "A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1}
        run = qmaps.run({"map": suris}, initial=[[0.1, 0.2, 0.0, 0.1]], run={"steps": 10})
        print(qmaps.__file__, run.attrs["orbits"], run["final/q1"].shape)
    """)
    r = subprocess.run([str(venv / "bin/python"), "-c", script], capture_output=True, text=True,
                       env=env, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert str(venv) in r.stdout and r.stdout.split()[1:] == ["1", "(1,)"]
    assert (venv / "bin/qmaps-plot").is_file()
