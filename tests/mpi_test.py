"""MPI runs under mpirun: a run split over N = 1, 2 and 3 ranks (through the qmaps binary, which
hands over to qmaps-mpi, and through qmaps-mpi itself), over an orbit count neither 2 nor 3
divides, with every kind of observer, trajectories across ranks and escaping orbits, equals the
single process's run, dataset for dataset and byte for byte, and records its ranks, threads and
hosts; so does a gzip-compressed run and one without per-orbit datasets; a run interrupted under
2 ranks resumes under 3, and one interrupted under 3 resumes without mpirun, into the same file,
as does one stopped by SIGTERM or SIGINT sent to mpirun (4 times on a loaded machine, each stop
resumed by the next), which rank 0 names as mpirun's SIGTERM;
a bad configuration or an unwritable output given to the last rank alone, or ranks given
different configurations, end every rank with the message and nothing written; --shard is refused
over several ranks. Skipped where qmaps-mpi (beside the qmaps binary) or mpirun is missing."""
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import h5py

import small_run

BINARY = small_run.BINARY
MPI_BINARY = BINARY.parent / "qmaps-mpi"
MPIRUN = shutil.which("mpirun")
# The tests run as root, 3 ranks of one thread on 2 cores, maybe in a container that forbids the
# single-copy transfers between processes.
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1",
           "OMPI_MCA_btl_vader_single_copy_mechanism": "none"}
TIMEOUT = 300  # seconds, per process
INTERRUPT = {"QMAPS_SIGNAL_AT_STEP": "60:INT"}
# The delays after start-up of the SIGTERMs and SIGINTs sent in turn to mpirun, each to a run
# resumed from the last checkpoint: each signal early and late.
DELAYS = (0.2, 1.7, 0.7, 2.2)
TRAJECTORIES = small_run.fixture("trajectory-across.toml")


def argv(out, *extra, config="c.toml", steps=120, binary=BINARY):
    """A small run of `config` into `out`: 1001 orbits (some escape), one thread a process."""
    return [binary, "run", config, "--set", "ensemble.orbits=1001", "--set", f"run.steps={steps}",
            "--set", "run.escape_bound=0.6", "--threads", "1", "--quiet", "--out", out, *extra]


def launch(command, directory, env=None):
    """`command` run in `directory` with `env` added, its output captured as text; past TIMEOUT
    its whole process group (mpirun's ranks too) is killed."""
    with subprocess.Popen(list(map(str, command)), cwd=directory, text=True,
                          env={**os.environ, **(env or {})}, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, start_new_session=True) as p:
        try:
            out, err = p.communicate(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            raise
    return subprocess.CompletedProcess(command, p.returncode, out, err)


def mpirun(directory, *programs, env=None):
    """mpirun over `programs`, each (ranks, argv), joined by ':' when several (MPMD); `env` is
    added to mpirun's environment and exported to the ranks with -x."""
    command = [MPIRUN, "--oversubscribe"]
    for name, value in (env or {}).items():
        command += ["-x", f"{name}={value}"]
    for i, (ranks, args) in enumerate(programs):
        command += ([":"] if i else []) + ["-np", ranks, *args]
    return launch(command, directory, {**MPI_ENV, **(env or {})})


def datasets(group):
    out = {}
    group.visititems(lambda name, item: out.__setitem__(name, item)
                     if isinstance(item, h5py.Dataset) else None)
    return out


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


class Mpi(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        found = launch([MPIRUN, "--version"], ".").stdout.splitlines()[:1] if MPIRUN else []
        print(f"mpirun: {found[0] if found else 'not on PATH'}; qmaps-mpi: "
              f"{'found' if MPI_BINARY.is_file() else 'missing'} beside {BINARY.name}",
              file=sys.stderr)
        missing = [what for what, there in (("mpirun on PATH", MPIRUN),
                                            ("qmaps-mpi beside the qmaps binary",
                                             MPI_BINARY.is_file())) if not there]
        if missing:
            raise unittest.SkipTest("no " + " and no ".join(missing))
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        cls.config = small_run.PRESET.read_text() + small_run.EXTRA_OBSERVERS + small_run.TUNES + TRAJECTORIES
        (cls.dir / "c.toml").write_text(cls.config)
        r = launch(argv("single.h5"), cls.dir)
        assert r.returncode == 0, r.stderr
        with h5py.File(cls.dir / "single.h5") as f:
            assert f.attrs["escaped"] > 0

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def fresh(self):
        d = pathlib.Path(tempfile.mkdtemp(dir=self.dir))
        (d / "c.toml").write_text(self.config)
        return d

    def assert_same_datasets(self, mine, single):
        with h5py.File(mine) as m, h5py.File(single) as s:
            ours, theirs = datasets(m), datasets(s)
            self.assertEqual(sorted(ours), sorted(theirs))
            for path, item in theirs.items():
                self.assertEqual(ours[path].dtype, item.dtype, path)
                self.assertEqual(ours[path][()].tobytes(), item[()].tobytes(), path)
            for name in ("orbits", "escaped", "rejected", "steps", "seed"):
                self.assertEqual(m.attrs[name], s.attrs[name], name)

    def assert_nothing_written(self, directory, *outputs):
        for out in outputs:
            self.assertFalse((directory / out).exists(), out)
        self.assertEqual([p.name for p in directory.rglob("*.tmp-*")], [])

    def test_every_rank_count_writes_the_single_process_file(self):
        for ranks, binary in ((1, BINARY), (2, BINARY), (3, BINARY), (3, MPI_BINARY)):
            with self.subTest(ranks=ranks, program=binary.name):
                out = f"{binary.name}-{ranks}.h5"
                r = mpirun(self.dir, (ranks, argv(out, binary=binary)))
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assert_same_datasets(self.dir / out, self.dir / "single.h5")
                with h5py.File(self.dir / out) as f:
                    self.assertEqual(f.attrs["ranks"], ranks)
                    self.assertEqual(f.attrs["threads"], 1)
                    hosts = text(f.attrs["hosts"]).splitlines()
                    self.assertEqual(len(hosts), ranks, hosts)
                    self.assertTrue(all(h.strip() for h in hosts), hosts)

    def same_as_alone(self, setting, ranks=2):
        """A run with `setting` under mpirun and alone: the same datasets; the MPI file's path."""
        d = self.fresh()
        r = launch(argv("single.h5", "--set", setting), d)
        self.assertEqual(r.returncode, 0, r.stderr)
        r = mpirun(d, (ranks, argv("mpi.h5", "--set", setting)))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assert_same_datasets(d / "mpi.h5", d / "single.h5")
        return d / "mpi.h5"

    def test_gzip_compressed_ranks_write_the_same_datasets(self):
        with h5py.File(self.same_as_alone("output.compression=gzip")) as f:
            self.assertIn("gzip", {item.compression for item in datasets(f).values()})

    def test_ranks_without_per_orbit_datasets_write_the_same_datasets(self):
        with h5py.File(self.same_as_alone("output.per_orbit=false")) as f, \
                h5py.File(self.dir / "single.h5") as whole:
            self.assertLess(len(datasets(f)), len(datasets(whole)))

    def test_an_interrupted_run_resumes_under_other_ranks_or_alone(self):
        for first, then in ((2, 3), (3, None)):
            with self.subTest(interrupted_on=first, resumed_on=then or "no mpirun"):
                d = self.fresh()
                r = mpirun(d, (first, argv("out.h5")), env=INTERRUPT)
                self.assertEqual(r.returncode, 5, r.stderr)
                self.assertTrue((d / "out.h5.ckpt").is_file())
                self.assert_nothing_written(d, "out.h5")
                resume = [BINARY, "run", "--resume", "out.h5.ckpt", "--threads", "1", "--quiet"]
                r = mpirun(d, (then, resume)) if then else launch(resume, d)
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertFalse((d / "out.h5.ckpt").exists())
                self.assert_same_datasets(d / "out.h5", self.dir / "single.h5")
                if then:
                    with h5py.File(d / "out.h5") as f:
                        self.assertEqual(f.attrs["ranks"], then)

    def test_a_signal_to_mpirun_checkpoints_every_rank(self):
        """SIGTERM sent to mpirun itself, as a batch system ends a job, or SIGINT (Ctrl-C): mpirun
        sends the ranks SIGTERM for either 1 s later and SIGKILLs them 1 s after that, and rank 0
        names the SIGTERM as mpirun's, not the signal mpirun had. Sent once per DELAYS,
        alternately, to a run on a machine loaded by a busy process per core, each time resuming
        the previous checkpoint: every time, the ranks stop within their grace and write
        one checkpoint further on. mpirun's own status is then OpenMPI's (not 0; the ranks exit
        with 5). The last checkpoint equals the one the run never stopped writes at the same
        step."""
        d = self.fresh()
        (d / "p.toml").write_text(small_run.PRESET.read_text())
        run = [BINARY, "run", "p.toml", "--set", "ensemble.orbits=2000", "--set",
               "run.steps=100000000", "--quiet"]
        resume = [BINARY, "run", "--resume", "out.h5.ckpt", "--quiet"]
        busy = [subprocess.Popen([sys.executable, "-c", "while True: pass"])
                for _ in range(os.cpu_count() or 1)]
        step = 0
        try:
            for trial, delay in enumerate(DELAYS):
                command = [MPIRUN, "--oversubscribe", "-np", "2",
                           *(resume if trial else [*run, "--out", "out.h5"]), "--threads", "1"]
                with subprocess.Popen(list(map(str, command)), cwd=d, text=True,
                                      env={**os.environ, **MPI_ENV}, stderr=subprocess.PIPE,
                                      start_new_session=True) as p:
                    # Once the ranks have made the output's temporary, they answer a signal with
                    # a checkpoint (before, during MPI's start-up, it would only end them).
                    for _ in range(600):
                        if list(d.glob("out.h5.tmp-*")) or p.poll() is not None:
                            break
                        time.sleep(0.1)
                    time.sleep(delay)
                    sent = (signal.SIGTERM, signal.SIGINT)[trial % 2]
                    p.send_signal(sent)
                    _, err = p.communicate(timeout=TIMEOUT)
                with self.subTest(trial=trial, delay=delay, signal=sent.name):
                    self.assertNotEqual(p.returncode, 0, err)
                    # The checkpoint is the proof. Rank 0's line about it reaches mpirun's
                    # stderr only while mpirun still forwards the ranks' output, which OpenMPI
                    # does not promise once it is ending the job: where mpirun said anything,
                    # it says that.
                    if err:
                        self.assertIn("qmaps: SIGTERM from mpirun (which sends it for a SIGINT or a "
                                      "SIGTERM) at step ", err)
                        self.assertIn("checkpoint written to out.h5.ckpt", err)
                    self.assert_nothing_written(d, "out.h5")
                    with h5py.File(d / "out.h5.ckpt") as f:
                        reached = int(f["final/state"].attrs["step"])
                    self.assertGreater(reached, step,
                                       f"no checkpoint further on; mpirun said {err!r}")
                    step = reached
        finally:
            for b in busy:
                b.kill()
                b.wait()
        r = launch([*run, "--threads", "2", "--out", "alone.h5"], d,
                   {"QMAPS_SIGNAL_AT_STEP": f"{step}:TERM"})
        self.assertEqual(r.returncode, 5, r.stderr)
        self.assert_same_datasets(d / "out.h5.ckpt", d / "alone.h5.ckpt")

    def test_a_bad_configuration_on_the_last_rank_ends_every_rank(self):
        bad = {"speed": ("[run]\n", "[run]\nspeed = 3\n"),  # an unknown key
               "stride": ("stride = 10\n", "stride = -5\n")}  # a bad value (no --set hides it)
        for key, (old, new) in bad.items():
            with self.subTest(key=key):
                d = self.fresh()
                (d / "bad.toml").write_text(self.config.replace(old, new, 1))
                self.assertNotEqual((d / "bad.toml").read_text(), self.config)
                r = mpirun(d, (2, argv("out.h5")), (1, argv("out.h5", config="bad.toml")))
                self.assertEqual(r.returncode, 2, r.stderr)
                self.assertIn("bad.toml", r.stderr)
                self.assertIn(key, r.stderr)
                self.assert_nothing_written(d, "out.h5")

    def test_an_unwritable_output_on_the_last_rank_ends_every_rank(self):
        d = self.fresh()
        r = mpirun(d, (2, argv("out.h5")), (1, argv("missing/out.h5")))
        self.assertIn(r.returncode, (2, 3), r.stderr)
        self.assertIn("missing/out.h5", r.stderr)
        self.assert_nothing_written(d, "out.h5", "missing/out.h5")

    def test_ranks_given_different_configurations_are_refused(self):
        d = self.fresh()
        r = mpirun(d, (1, argv("out.h5")), (1, argv("out.h5", steps=100)))
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("differ", r.stderr.lower())
        self.assert_nothing_written(d, "out.h5")

    def test_shard_is_refused_over_several_ranks(self):
        d = self.fresh()
        r = mpirun(d, (2, argv("out.h5", "--shard", "1/2")))
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--shard", r.stderr)
        self.assert_nothing_written(d, "out.h5")


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
