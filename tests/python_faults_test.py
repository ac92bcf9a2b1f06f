"""The Python package under faults: Ctrl-C at any moment, runs in threads, and bad files and
arguments. Each ends in the documented exception (qmaps.ConfigError, qmaps.FileError,
KeyboardInterrupt), with the interpreter, its signal handlers and the temporary folders as
before. Run by pytest; CMake passes QMAPS_BINARY and puts the build tree's package first
(tests/small_run.py). Signals are sent to subprocesses, never to the test's own interpreter."""
import os
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

import small_run

import qmaps

PRESET = str(small_run.PRESET)
SMALL = {"ensemble": {"orbits": 300}, "run": {"steps": 20}}


def python(script, *args, timeout=120):
    """`script` run by a fresh interpreter with `args` (the preset first), its output as text."""
    return subprocess.run([sys.executable, "-c", script, PRESET, *map(str, args)],
                          capture_output=True, text=True, timeout=timeout)


LONG_ORBIT = """
import sys, time, qmaps
print("started", flush=True)
began = time.monotonic()
try:
    qmaps.orbit("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1}, (0.1, 0.2, 0.0, 0.1),
                steps=10**11, every=10**11, chaos=sys.argv[2] == "chaos", frame=False)
    print("finished")
except KeyboardInterrupt as e:
    print(f"KeyboardInterrupt after {time.monotonic() - began:.3f} s: {e}")
"""


@pytest.mark.parametrize("chaos", ["plain", "chaos"])
def test_orbit_stops_within_a_second_of_ctrl_c(chaos):
    """10^11 steps would take hours; SIGINT 0.5 s in stops them with KeyboardInterrupt."""
    p = subprocess.Popen([sys.executable, "-c", LONG_ORBIT, PRESET, chaos],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.stdout.readline() == "started\n"
    time.sleep(0.5)
    sent = time.monotonic()
    p.send_signal(2)
    try:
        out, err = p.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        p.kill()
        p.communicate()
        pytest.fail("qmaps.orbit still running 20 s after SIGINT")
    took = time.monotonic() - sent
    print(f"qmaps.orbit ({chaos}): stopped {took:.3f} s after SIGINT; {out.strip()}")
    assert p.returncode == 0 and out.startswith("KeyboardInterrupt after"), (out, err)
    assert "SIGINT while stepping the orbit at step" in out
    assert took < 2


def test_orbit_in_chunks_equals_orbit_at_once():
    """The long orbit's chunks (a look for a signal between them) change no bit."""
    params = {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1}
    for chaos in (False, True):
        whole = qmaps.orbit("suris", params, (0.1, 0.2, 0.0, 0.1), steps=300_000,
                            every=300_000, chaos=chaos, frame=False)
        parts = qmaps.orbit("suris", params, (0.1, 0.2, 0.0, 0.1), steps=300_000,
                            every=1000, chaos=chaos, frame=False)
        assert whole[-1].tobytes() == parts[-1].tobytes()


OVERLAPPING = """
import os, signal, sys, threading, time, qmaps
config = sys.argv[1]
before = signal.getsignal(signal.SIGINT)
first_segment = threading.Event()

def long_run():
    qmaps.run(config, ensemble={"orbits": 50000}, run={"steps": 400}, threads=1,
              progress=lambda step, total: first_segment.set()).close()

def short_run():
    first_segment.wait()
    qmaps.run(config, ensemble={"orbits": 300}, run={"steps": 20}, threads=1).close()

threads = [threading.Thread(target=long_run), threading.Thread(target=short_run)]
for t in threads:
    t.start()
for t in threads:
    t.join()
print("same handler:", signal.getsignal(signal.SIGINT) is before, flush=True)
for attempt in (1, 2):
    try:
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(3)
        print(f"SIGINT {attempt} swallowed", flush=True)
    except KeyboardInterrupt:
        print(f"SIGINT {attempt}: KeyboardInterrupt", flush=True)
"""


def test_overlapping_runs_in_threads_leave_the_handlers_as_they_were():
    r = python(OVERLAPPING)
    assert r.returncode == 0, (r.returncode, r.stdout, r.stderr)
    assert r.stdout.splitlines() == ["same handler: True", "SIGINT 1: KeyboardInterrupt",
                                     "SIGINT 2: KeyboardInterrupt"], r.stdout


WHILE_WRITTEN = """
import os, signal, sys, qmaps
config, folder = sys.argv[1], sys.argv[2]

def at_the_end(step, total):  # after the last step: the file is written next
    if step == total:
        os.kill(os.getpid(), signal.SIGINT)

try:
    run = qmaps.run(config, ensemble={"orbits": 300}, run={"steps": 20}, progress=at_the_end,
                    tmpdir=folder)
    print("returned a run")
except KeyboardInterrupt as e:
    print("KeyboardInterrupt:", e)
print("left:", os.listdir(folder))
run = qmaps.run(config, ensemble={"orbits": 100}, run={"steps": 10})  # still usable
print("after:", run.attrs["orbits"])
"""


def test_ctrl_c_while_the_file_is_written_raises_keyboard_interrupt(tmp_path):
    r = python(WHILE_WRITTEN, tmp_path)
    assert r.returncode == 0, (r.returncode, r.stdout, r.stderr)
    assert r.stdout.splitlines() == [
        "KeyboardInterrupt: qmaps: SIGINT while the run's file was written: stopped, nothing kept",
        "left: []", "after: 100"], r.stdout


FULL_DISK = """
import os, resource, signal, sys
import h5py, numpy as np, qmaps
config, folder = sys.argv[1], sys.argv[2]
tables = {"ensemble": {"orbits": 20000}, "run": {"steps": 20}}
with qmaps.run(config, **tables) as run:
    run.save(os.path.join(folder, "whole.h5"))
size = os.path.getsize(os.path.join(folder, "whole.h5"))
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails with EFBIG
# The limit cuts the initial points, the datasets after the run, or only the last metadata
# that HDF5 writes when the file is closed.
for cut in ("start", "half", "close"):
    limit = {"start": 200_000, "half": size // 2, "close": size - 1}[cut]
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
    work = os.path.join(folder, cut)
    os.mkdir(work)
    try:
        qmaps.run(config, tmpdir=work, **tables)
        print(cut, "returned a run")
    except qmaps.FileError as e:
        print(cut, "FileError" if "File too large" in str(e) else e)
    print(cut, "left:", os.listdir(work))
resource.setrlimit(resource.RLIMIT_FSIZE, (resource.RLIM_INFINITY,) * 2)
with h5py.File(os.path.join(folder, "other.h5"), "w") as f:  # HDF5 still sound
    f["x"] = np.arange(10)
run = qmaps.run(config, ensemble={"orbits": 100}, run={"steps": 10})
print("after:", run.attrs["orbits"])
"""


def test_a_full_disk_raises_file_error_and_the_interpreter_ends_cleanly(tmp_path):
    """A write refused by the file system (here a file-size limit, as a full disk), at the start,
    after the run or only in the close's last metadata: FileError naming the reason, never a
    damaged file returned, the run's folder removed, and HDF5 left sound, so that other files
    are written and the interpreter ends with status 0 (HDF5 1.10 kept a file whose close
    failed over freed memory, and its exit handler ended the interpreter with SIGSEGV)."""
    r = python(FULL_DISK, tmp_path)
    assert r.returncode == 0, (r.returncode, r.stdout, r.stderr)
    assert r.stdout.splitlines() == [
        line for cut in ("start", "half", "close") for line in
        (f"{cut} FileError", f"{cut} left: []")] + ["after: 100"], r.stdout


IN_A_THREAD = """
import sys, threading, qmaps
config, folder = sys.argv[1], sys.argv[2]

def run(name):
    with qmaps.run(config, ensemble={"orbits": 300}, run={"steps": 20}, threads=1) as r:
        r.save(f"{folder}/{name}.h5")
thread = threading.Thread(target=run, args=("thread",))
thread.start()
thread.join()
run("main")
"""


def test_a_run_in_another_thread_writes_no_noise_and_the_same_file(tmp_path):
    r = python(IN_A_THREAD, tmp_path)
    assert r.returncode == 0, (r.returncode, r.stderr)
    assert r.stderr == ""
    with h5py.File(tmp_path / "thread.h5") as a, h5py.File(tmp_path / "main.h5") as b:
        names = []
        b.visititems(lambda name, item: names.append(name)
                     if isinstance(item, h5py.Dataset) else None)
        assert names
        for name in names:
            assert a[name][()].tobytes() == b[name][()].tobytes(), name


@pytest.fixture(scope="module")
def a_run(tmp_path_factory):
    """A small run's file."""
    path = tmp_path_factory.mktemp("run") / "small.h5"
    with qmaps.run(PRESET, **SMALL) as run:
        run.save(path)
    return path


def read_everything(path):
    with qmaps.load(path) as run:
        def visit(group):
            for name in group.datasets:
                group.datasets[name]
            for child in group.groups.values():
                visit(child)
        visit(run)


def test_a_truncated_file_raises_file_error(a_run, tmp_path):
    data = a_run.read_bytes()
    for length in (0, 7, 100, 2048, len(data) // 3, len(data) // 2, len(data) - 100):
        cut = tmp_path / f"cut-{length}.h5"
        cut.write_bytes(data[:length])
        with pytest.raises(qmaps.FileError, match=str(cut)):
            read_everything(cut)


def test_a_file_that_cannot_be_read_raises_file_error():
    with pytest.raises(qmaps.FileError, match="/proc/self/mem: cannot be read as HDF5: "
                                               "Input/output error"):
        qmaps.load("/proc/self/mem")


def test_a_folder_or_a_fifo_is_named_as_what_it_is(tmp_path):
    with pytest.raises(qmaps.FileError, match=f"{tmp_path}: a folder, not a file"):
        qmaps.load(tmp_path)
    fifo = tmp_path / "fifo.h5"
    os.mkfifo(fifo)
    with pytest.raises(qmaps.FileError, match=f"{fifo}: not a regular file"):
        qmaps.load(fifo)
    with pytest.raises(qmaps.FileError, match="none.h5: no such file"):
        qmaps.load(tmp_path / "none.h5")


def test_a_link_that_leads_nowhere_raises_file_error(a_run, tmp_path):
    for kind, link in (("external", h5py.ExternalLink("gone.h5", "/g")),
                       ("soft", h5py.SoftLink("/nothing"))):
        path = tmp_path / f"{kind}.h5"
        path.write_bytes(a_run.read_bytes())
        with h5py.File(path, "a") as f:
            f["invariants/lost"] = link
        with pytest.raises(qmaps.FileError,
                           match=f"{path}: /invariants/lost is a link to .* leads to nothing"):
            qmaps.load(path)


def test_tmpdir_missing_not_a_folder_or_not_writable_raises_file_error(tmp_path):
    a_file = tmp_path / "file"
    a_file.write_text("")
    for tmpdir, why in ((tmp_path / "none", "no such folder"), (a_file, "not a folder"),
                        ("/sys", None)):
        with pytest.raises(qmaps.FileError, match=f"tmpdir '{tmpdir}': {why or ''}") as caught:
            qmaps.run(PRESET, tmpdir=tmpdir, **SMALL)
        print(caught.value)
    if os.geteuid() != 0:
        locked = tmp_path / "locked"
        locked.mkdir(mode=0o500)
        with pytest.raises(qmaps.FileError, match="Permission denied"):
            qmaps.run(PRESET, tmpdir=locked, **SMALL)


def test_numpy_numbers_are_numbers():
    """0-d arrays and numpy scalars are taken as the numbers they hold."""
    with qmaps.run(PRESET, map={"h": np.array(0.1), "A": np.float32(0.5)},
                   ensemble={"orbits": np.int64(300)}, run={"steps": np.array(20)}) as run:
        assert run.attrs["param.h"] == 0.1 and run.attrs["param.A"] == float(np.float32(0.5))
        assert run.attrs["orbits"] == 300 and run.attrs["steps"] == 20
    with qmaps.run({"map": {"name": "suris", "A": 0.7, "B": 0.3, "alpha": np.array(0.9),
                            "h": np.float64(0.1)}, "run": {"steps": np.int32(5)}},
                   initial=np.zeros((3, 4)) + 0.1) as run:
        assert run.attrs["param.alpha"] == 0.9 and run.attrs["steps"] == 5


def test_an_integer_beyond_64_bits_names_the_key_and_the_rule():
    for given in ({"ensemble": {"orbits": 2**63}}, {"ensemble": {"orbits": -2**63 - 1}}):
        with pytest.raises(qmaps.ConfigError, match=r"ensemble.orbits = -?\d+: an integer must "
                                                    r"lie in TOML's 64 bits"):
            qmaps.run(PRESET, **given)
    config = {"map": {"name": "suris"}, "run": {"steps": 2**64}}
    with pytest.raises(qmaps.ConfigError, match=r"run.steps = 18446744073709551616: an integer"):
        qmaps.run(config)
    with pytest.raises(qmaps.ConfigError, match=r"run.steps = None: a configuration value must"):
        qmaps.run(PRESET, run={"steps": None})


def test_save_after_close_names_the_missing_source(tmp_path):
    run = qmaps.run(PRESET, **SMALL)
    source = run.file
    run.close()
    target = tmp_path / "kept.h5"
    with pytest.raises(qmaps.FileError) as caught:
        run.save(target)
    message = str(caught.value)
    print(message)
    assert source in message and "closed" in message and "save() before close()" in message
    assert not target.exists()


def test_save_never_replaces_a_device_fifo_folder_or_link(tmp_path):
    run = qmaps.run(PRESET, **SMALL)
    fifo, folder, link, target = (tmp_path / n for n in ("fifo.h5", "dir.h5", "link.h5", "t.h5"))
    os.mkfifo(fifo)
    folder.mkdir()
    target.write_bytes(b"precious")
    link.symlink_to(target)
    for path, kind in ((fifo, "a FIFO"), (folder, "a directory"), (link, "a symbolic link")):
        with pytest.raises(qmaps.FileError, match=f"'{path}': it is {kind}"):
            run.save(path)
    if os.geteuid() == 0:  # as root a replaced /dev/full would be the machine's
        before = os.stat("/dev/full")
        with pytest.raises(qmaps.FileError, match="it is a device"):
            run.save("/dev/full")
        assert os.stat("/dev/full").st_rdev == before.st_rdev
    # A link planted under the temporary's name is not written through.
    (tmp_path / f"new.h5.tmp-{os.getpid()}").symlink_to(target)
    with pytest.raises(qmaps.FileError, match="cannot write"):
        run.save(tmp_path / "new.h5")
    assert target.read_bytes() == b"precious" and fifo.is_fifo() and link.is_symlink()
    run.close()


def test_threads_follow_the_rule_of_threads_option(tmp_path):
    r = small_run.qmaps(tmp_path, "run", PRESET, "--threads", "-1")
    assert r.returncode != 0 and "--threads" in r.stderr
    for threads in (-1, 2**31, 1.5, "2", True):
        with pytest.raises(qmaps.ConfigError, match=r"threads=.*: must be an integer >= 1, as "
                                                    r"--threads \(or 0, the default"):
            qmaps.run(PRESET, threads=threads, tmpdir=tmp_path, **SMALL)
    assert not os.listdir(tmp_path)
    with qmaps.run(PRESET, threads=np.int64(1), **SMALL) as run:
        assert run.attrs["threads"] == 1


def test_orbit_arguments_name_themselves():
    params = {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1}
    for given, message in (({"steps": 2**63}, "steps=9223372036854775808: must be an integer"),
                           ({"steps": 1.5}, "steps=1.5: must be an integer >= 0"),
                           ({"every": 0}, "every=0: must be an integer >= 1")):
        with pytest.raises(qmaps.ConfigError, match=message):
            qmaps.orbit("suris", params, (0.1, 0, 0, 0), **given)
