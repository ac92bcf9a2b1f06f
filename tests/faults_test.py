"""Faults while a run writes: a file-size limit (as a full disk) fails the write of the output or
of a checkpoint with exit 3 and a message naming the file and the reason, and leaves neither the
file nor its temporary; SIGHUP
(a dropped session) stops the run with a checkpoint as SIGTERM does, and the run resumes; an
ensemble beyond the address-space limit is refused before it is allocated; an output name too
long for its derived names is refused before the run; temporaries no writer holds are removed;
a second run to an output being written is refused and leaves the first run's files alone; a
signal while the initial conditions are drawn or enumerated ends the process by that signal,
with a message and nothing left; a shell grid too large for memory is refused before it is
enumerated."""
import os
import signal
import time
import pathlib
import resource
import subprocess
import sys
import tempfile
import unittest

import small_run


def run(directory, *args, env=None, fsize=None, address_space=None):
    def limit():
        if fsize is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
        if address_space is not None:
            resource.setrlimit(resource.RLIMIT_AS, (address_space, address_space))
    return subprocess.run([str(small_run.BINARY), *args], capture_output=True, text=True,
                          cwd=directory, env={**os.environ, **(env or {})}, preexec_fn=limit)


class Faults(unittest.TestCase):
    def config(self, directory, orbits, steps):
        config = pathlib.Path(directory) / "config.toml"
        config.write_text(small_run.PRESET.read_text())
        return ["run", str(config), "--set", f"ensemble.orbits={orbits}", "--set",
                f"run.steps={steps}", "--out", "out.h5", "--quiet"]

    def test_file_size_limit_fails_cleanly_and_leaves_nothing(self):
        with tempfile.TemporaryDirectory() as d:
            r = run(d, *self.config(d, 20000, 20), fsize=1 << 20)
            self.assertEqual(r.returncode, 3, r.stderr)
            self.assertIn("cannot write 'out.h5'", r.stderr)
            self.assertIn("File too large", r.stderr)
            self.assertEqual(sorted(p.name for p in pathlib.Path(d).iterdir()), ["config.toml"])

    def test_file_size_limit_on_a_checkpoint_fails_cleanly_and_leaves_nothing(self):
        with tempfile.TemporaryDirectory() as d:
            args = self.config(d, 20000, 40) + ["--set", "run.checkpoint_every=10"]
            r = run(d, *args, fsize=1 << 20)
            self.assertEqual(r.returncode, 3, r.stderr)
            self.assertIn("cannot write 'out.h5.ckpt'", r.stderr)
            self.assertIn("File too large", r.stderr)
            self.assertEqual(sorted(p.name for p in pathlib.Path(d).iterdir()), ["config.toml"])

    def test_sighup_checkpoints_like_sigterm_and_the_run_resumes(self):
        with tempfile.TemporaryDirectory() as d:
            args = self.config(d, 2000, 300) + ["--set", "run.checkpoint_every=100"]
            r = run(d, *args, env={"QMAPS_SIGNAL_AT_STEP": "100:HUP"})
            self.assertEqual(r.returncode, 5, r.stderr)
            self.assertIn("SIGHUP at step 100 of 300", r.stderr)
            names = sorted(p.name for p in pathlib.Path(d).iterdir())
            self.assertEqual(names, ["config.toml", "out.h5.ckpt"])
            r = run(d, "run", "--resume", "out.h5.ckpt", "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertTrue((pathlib.Path(d) / "out.h5").is_file())
            self.assertFalse((pathlib.Path(d) / "out.h5.ckpt").exists())


    @unittest.skipIf("ASAN_OPTIONS" in os.environ,
                     "AddressSanitizer reserves terabytes of address space at start")
    def test_an_ensemble_beyond_the_address_space_limit_is_refused_before_any_work(self):
        with tempfile.TemporaryDirectory() as d:
            # 10^8 Suris orbits need about 8.3 GiB; the limit is 2 GiB.
            r = run(d, *self.config(d, 100_000_000, 10), address_space=2 << 30)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("orbits need about", r.stderr)
            self.assertIn("the address-space limit (ulimit -v) of 2 GiB, less the ", r.stderr)
            self.assertEqual(sorted(p.name for p in pathlib.Path(d).iterdir()), ["config.toml"])


    def test_an_output_name_whose_checkpoint_name_is_too_long_is_refused_before_the_run(self):
        with tempfile.TemporaryDirectory() as d:
            args = self.config(d, 100, 10)
            args[args.index("out.h5")] = "o" * 240 + ".h5"  # legal, but not with ".ckpt.tmp-<pid>"
            r = run(d, *args)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("has 243 bytes; its checkpoint's temporary needs", r.stderr)
            self.assertEqual(sorted(p.name for p in pathlib.Path(d).iterdir()), ["config.toml"])

    def test_temporaries_of_dead_processes_are_removed_by_the_next_run(self):
        with tempfile.TemporaryDirectory() as d:
            dead = subprocess.Popen(["true"])
            dead.wait()
            stale = [f"out.h5.tmp-{dead.pid}", f"out.h5.ckpt.tmp-{dead.pid}"]
            # A live process's, with no lock held on the output: no writer's, so removed too
            # (tests/file_safety_test.py: a locked output's temporaries are kept).
            alive = f"out.h5.tmp-{os.getpid()}"
            for name in stale + [alive]:
                (pathlib.Path(d) / name).write_bytes(b"partial")
            args = self.config(d, 200, 20) + ["--set", "run.checkpoint_every=10"]
            r = run(d, *args)
            self.assertEqual(r.returncode, 0, r.stderr)
            names = sorted(p.name for p in pathlib.Path(d).iterdir())
            self.assertEqual(names, ["config.toml", "out.h5"])

    def test_a_second_run_to_an_output_being_written_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            lock = pathlib.Path(d) / "out.h5.lock"
            first = subprocess.Popen([str(small_run.BINARY), *self.config(d, 20000, 1000000)],
                                     cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True)
            try:
                for _ in range(600):  # the lock is taken once the ensemble is drawn
                    if lock.exists() and lock.read_text() == str(first.pid):
                        break
                    time.sleep(0.05)
                self.assertEqual(lock.read_text(), str(first.pid))
                time.sleep(0.5)  # past the drawing of its 20000 orbits (milliseconds): stepping
                r = run(d, *self.config(d, 100, 10))
                self.assertEqual(r.returncode, 3, r.stderr)
                self.assertIn(f"output 'out.h5': another qmaps run (process {first.pid}) is "
                              "writing it", r.stderr)
            finally:
                first.send_signal(signal.SIGINT)
                _, err = first.communicate(timeout=120)
            self.assertEqual(first.returncode, 5, err)
            # The first run's checkpoint is whole and its lock gone; the refused runs left nothing.
            names = sorted(p.name for p in pathlib.Path(d).iterdir())
            self.assertEqual(names, ["config.toml", "out.h5.ckpt"])

    def test_a_signal_while_drawing_ends_the_process_by_it_and_leaves_nothing(self):
        with tempfile.TemporaryDirectory() as d:
            # No draw reaches H = -1 and max_draws is beyond reach: the first orbit draws forever.
            config = pathlib.Path(d) / "config.toml"
            text = small_run.PRESET.read_text().replace('kind = "box"', 'kind = "shell"')
            text = text.replace("p2 = [-0.5, 0.5]\n", "energy = -1.0\nmax_draws = 9000000000000000000\n", 1)
            config.write_text(text)
            process = subprocess.Popen(
                [str(small_run.BINARY), "run", str(config), "--set", "ensemble.orbits=100",
                 "--out", "out.h5", "--quiet"], cwd=d, stderr=subprocess.PIPE, text=True)
            time.sleep(1.0)
            process.send_signal(signal.SIGINT)
            _, err = process.communicate(timeout=30)
            self.assertEqual(process.returncode, -signal.SIGINT, err)
            self.assertIn("SIGINT while drawing the shell's initial conditions: stopped before "
                          "the run began; nothing was written", err)
            self.assertEqual(sorted(p.name for p in pathlib.Path(d).iterdir()), ["config.toml"])

    def test_a_shell_grid_beyond_memory_is_refused_before_it_is_enumerated(self):
        with tempfile.TemporaryDirectory() as d:
            config = pathlib.Path(d) / "config.toml"
            text = small_run.PRESET.read_text().replace('kind = "box"', 'kind = "shell"')
            text = text.replace("orbits = ", "# orbits = ").replace(
                "p2 = [-0.5, 0.5]\n", 'energy = 0.1\nsampling = "grid"\npoints = 3000\n', 1)
            config.write_text(text)
            t = time.monotonic()
            r = run(d, "run", str(config), "--out", "out.h5", "--quiet")
            self.assertLess(time.monotonic() - t, 10)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("[ensemble] points: 27000000000 grid points, each of which may become "
                          "an orbit, need more than", r.stderr)
            self.assertEqual(sorted(p.name for p in pathlib.Path(d).iterdir()), ["config.toml"])


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
