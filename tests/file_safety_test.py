"""The file system as a hostile user or a busy cluster leaves it: nothing is written through a
planted link or onto a device, FIFO or another user's file; a live run's temporary is never
removed; non-regular inputs are refused at once; an interrupted run's checkpoint is never lost;
tampered or mixed files of a run are refused; bad output names are usage errors; a merge holds
one shard open at a time; a closed pipe does not change a run's outcome. Each case checks the
exit code, the message and what the folder holds afterwards."""
import fcntl
import os
import pathlib
import resource
import shutil
import stat
import subprocess
import tempfile
import time
import unittest

import h5py
import numpy as np

import small_run

BINARY = str(small_run.BINARY)
ROOT = os.geteuid() == 0
NOBODY = 65534


def others_can_run_the_binary():
    """Whether user nobody can reach and execute the binary (every folder on its path o+x)."""
    path = pathlib.Path(BINARY).resolve()
    folders_ok = all(os.stat(p).st_mode & stat.S_IXOTH for p in path.parents)
    return folders_ok and os.stat(path).st_mode & stat.S_IXOTH != 0


AS_NOBODY = ROOT and others_can_run_the_binary()


def qmaps(directory, *args, timeout=60, as_nobody=False, nproc=None, nofile=None, **kw):
    def limits():
        if nofile is not None:
            resource.setrlimit(resource.RLIMIT_NOFILE, (nofile, nofile))
        if as_nobody:
            os.setgid(NOBODY)
            os.setuid(NOBODY)
        if nproc is not None:
            resource.setrlimit(resource.RLIMIT_NPROC, (nproc, nproc))
    return subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True,
                          cwd=directory, timeout=timeout, preexec_fn=limits, **kw)


def config(directory, orbits=500, steps=40, extra=""):
    path = pathlib.Path(directory) / "config.toml"
    path.write_text(small_run.PRESET.read_text() + extra)
    return ["run", "config.toml", "--set", f"ensemble.orbits={orbits}", "--set",
            f"run.steps={steps}", "--out", "out.h5", "--quiet"]


def names(directory):
    return sorted(p.name for p in pathlib.Path(directory).iterdir())


class Files(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def refused(self, r, code, *texts):
        self.assertEqual(r.returncode, code, r.stderr)
        for text in texts:
            self.assertIn(text, r.stderr)

    # 1. The lock is never written through a link, nor one of another user's.
    def test_a_planted_lock_link_is_refused_and_its_target_untouched(self):
        self.make_checkpoint()
        victim = self.dir / "bashrc"
        victim.write_text("alias ls='ls -F'\n")
        (self.dir / "out.h5.lock").symlink_to(victim)
        shards = self.shards(count=1)
        for args in (["run", "--resume", "out.h5.ckpt", "--quiet"],
                     ["merge", *shards, "--out", "out.h5"]):
            r = qmaps(self.dir, *args)
            self.refused(r, 3, "its lock 'out.h5.lock' is a symbolic link")
            self.assertEqual(victim.read_text(), "alias ls='ls -F'\n")
        (self.dir / "out.h5.ckpt").unlink()
        self.refused(qmaps(self.dir, *config(self.dir)), 3, "is a symbolic link")
        self.assertEqual(victim.read_text(), "alias ls='ls -F'\n")
        self.assertFalse((self.dir / "out.h5").exists())

    @unittest.skipUnless(ROOT, "needs a second user")
    def test_a_lock_of_another_user_is_refused(self):
        lock = self.dir / "out.h5.lock"
        lock.write_text("")
        os.chown(lock, NOBODY, NOBODY)
        self.refused(qmaps(self.dir, *config(self.dir)), 3, "not a regular file of this user")
        self.assertEqual(lock.read_text(), "")

    # 2. An output that is not a regular file is refused before any work.
    def test_an_output_that_is_no_regular_file_is_refused_at_once(self):
        os.mkfifo(self.dir / "fifo.h5")
        target = self.dir / "precious.h5"
        target.write_bytes(b"precious")
        (self.dir / "link.h5").symlink_to(target)
        for out, kind in (("fifo.h5", "a FIFO"), ("link.h5", "a symbolic link")):
            args = config(self.dir, orbits=200000, steps=100000)
            args[args.index("--out") + 1] = out
            start = time.monotonic()
            r = qmaps(self.dir, *args, timeout=20)
            self.refused(r, 3, f"output '{out}' is {kind}")
            self.assertLess(time.monotonic() - start, 10)
        self.assertTrue(stat.S_ISFIFO(os.lstat(self.dir / "fifo.h5").st_mode))
        self.assertTrue((self.dir / "link.h5").is_symlink())
        self.assertEqual(target.read_bytes(), b"precious")
        self.assertEqual(names(self.dir), ["config.toml", "fifo.h5", "link.h5", "precious.h5"])

    @unittest.skipUnless(ROOT and os.path.exists("/dev/null"), "needs a device node")
    def test_a_device_as_output_is_refused(self):
        before = os.stat("/dev/null")
        args = config(self.dir)
        args[args.index("--out") + 1] = "/dev/null"
        self.refused(qmaps(self.dir, *args), 3, "output '/dev/null' is a character device")
        after = os.stat("/dev/null")
        self.assertEqual((before.st_ino, before.st_rdev), (after.st_ino, after.st_rdev))

    # 3. The lock comes first: a live run's temporary stays; stale ones go only under the lock.
    def test_a_live_runs_temporary_survives_a_second_run(self):
        temporary = self.dir / "out.h5.tmp-999999999"  # another node's pid: unknown here
        temporary.write_bytes(b"the first run's work")
        with open(self.dir / "out.h5.lock", "w") as held:
            fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
            r = qmaps(self.dir, *config(self.dir))
            self.refused(r, 3, "another qmaps run")
            self.assertEqual(temporary.read_bytes(), b"the first run's work")
        # Unlocked, the temporary is a dead writer's, whatever its pid, and goes.
        alive = self.dir / f"out.h5.tmp-{os.getpid()}"
        alive.write_bytes(b"stale")
        (self.dir / "out.h5.ckpt.tmp-999999999").write_bytes(b"a killed checkpoint write")
        r = qmaps(self.dir, *config(self.dir))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(names(self.dir), ["config.toml", "out.h5"])

    # 4. A rename the folder forbids is found at the start, and at the end keeps the work.
    @unittest.skipUnless(AS_NOBODY, "needs a second user who can run the binary")
    def test_another_users_output_in_a_sticky_folder(self):
        os.chmod(self.dir, 0o1777)
        args = config(self.dir)
        os.chmod(self.dir / "config.toml", 0o644)
        theirs = self.dir / "out.h5"
        theirs.write_bytes(b"theirs")
        r = qmaps(self.dir, *args, as_nobody=True)
        self.refused(r, 3, "belongs to another user", "sticky folder")
        self.assertEqual(theirs.read_bytes(), b"theirs")
        theirs.unlink()
        # Created while the run steps, it fails the rename: the run's checkpoint keeps the work.
        args = config(self.dir, orbits=200000, steps=200)
        os.chmod(self.dir / "config.toml", 0o644)
        p = subprocess.Popen([BINARY, *args], cwd=self.dir, stderr=subprocess.PIPE, text=True,
                             preexec_fn=lambda: (os.setgid(NOBODY), os.setuid(NOBODY)))
        while not any(n.startswith("out.h5.tmp-") for n in names(self.dir)):
            time.sleep(0.01)
        theirs.write_bytes(b"theirs")
        _, err = p.communicate(timeout=300)
        self.assertEqual(p.returncode, 3, err)
        self.assertIn("is kept in its checkpoint out.h5.ckpt", err)
        self.assertEqual(theirs.read_bytes(), b"theirs")
        self.assertEqual(names(self.dir), ["config.toml", "out.h5", "out.h5.ckpt"])
        theirs.unlink()
        r = qmaps(self.dir, "run", "--resume", "out.h5.ckpt", "--quiet", as_nobody=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(names(self.dir), ["config.toml", "out.h5"])

    @unittest.skipUnless(AS_NOBODY, "needs a second user, able to run the binary")
    @unittest.skipIf("ASAN_OPTIONS" in os.environ, "the sanitizers' runtime has threads of its own")
    def test_a_writer_without_threads_still_writes(self):
        os.chmod(self.dir, 0o777)
        args = config(self.dir) + ["--threads", "1"]
        # One process of that user, and no OpenMP team: only the writer would start threads.
        r = qmaps(self.dir, *args, as_nobody=True, nproc=1,
                  env={**os.environ, "OMP_NUM_THREADS": "1"})
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(names(self.dir), ["config.toml", "out.h5"])

    # 5. Inputs that are no regular files are refused at once, and read with a bound.
    def test_non_regular_inputs_are_refused_at_once(self):
        fifo = self.dir / "fifo"
        os.mkfifo(fifo)
        config(self.dir)
        cases = [
            (["run", "fifo"], "'fifo' is a FIFO"),
            (["run", "/dev/zero"], "'/dev/zero' is a character device"),
            (["run", str(self.dir)], "is a directory"),
            (["info", "fifo"], "'fifo' is a FIFO"),
            (["merge", "fifo", "--out", "m.h5"], "'fifo' is a FIFO"),
            (["run", "config.toml", "--set", 'ensemble.kind="file"', "--set",
              'ensemble.path="fifo"', "--out", "x.h5"], "'fifo' is a FIFO"),
            (["run", "--resume", "fifo.ckpt"], "'fifo.ckpt' is a FIFO"),
        ]
        os.mkfifo(self.dir / "fifo.ckpt")
        for args, text in cases:
            start = time.monotonic()
            r = qmaps(self.dir, *args, timeout=20)
            self.refused(r, 3, text)
            self.assertLess(time.monotonic() - start, 10, args)

    def test_a_config_is_read_with_a_bound(self):
        big = self.dir / "big.toml"
        big.write_text("# padding\n" * 200000)
        r = qmaps(self.dir, "run", "big.toml")
        self.refused(r, 2, "more than 1048576 bytes")

    # 6. An interrupted run's checkpoint is never lost to a fresh run.
    def make_checkpoint(self):
        args = config(self.dir, orbits=300, steps=300) + ["--set", "run.checkpoint_every=100"]
        r = qmaps(self.dir, *args, env={**os.environ, "QMAPS_SIGNAL_AT_STEP": "100:TERM"})
        self.assertEqual(r.returncode, 5, r.stderr)

    def test_a_fresh_run_keeps_an_interrupted_runs_checkpoint(self):
        self.make_checkpoint()
        ckpt = (self.dir / "out.h5.ckpt").read_bytes()
        r = qmaps(self.dir, *config(self.dir))
        self.refused(r, 3, "has the checkpoint 'out.h5.ckpt' of an interrupted run",
                     "qmaps run --resume out.h5.ckpt")
        self.assertEqual((self.dir / "out.h5.ckpt").read_bytes(), ckpt)
        self.assertEqual(qmaps(self.dir, "run", "--resume", "out.h5.ckpt", "--quiet").returncode, 0)
        self.assertEqual(names(self.dir), ["config.toml", "out.h5"])

    # 7. Tampered and mixed files of a run are refused.
    def tampered(self, path, change):
        with h5py.File(path, "r+") as f:
            change(f)

    def test_a_tampered_checkpoint_is_refused(self):
        self.make_checkpoint()
        pristine = self.dir / "pristine.ckpt"
        shutil.copy(self.dir / "out.h5.ckpt", pristine)
        changes = {
            "attribute map": lambda f: f.attrs.__setitem__("map", "case2"),
            "attribute param.h": lambda f: f.attrs.__setitem__("param.h", f.attrs["param.h"] * 2),
            "schema 2": lambda f: f.attrs.__setitem__("schema_version", np.int64(2)),
            "/initial/q1": lambda f: f["initial/q1"].__setitem__(3, np.nan),
            "escape reason": lambda f: f["escape/reason"].__setitem__(
                int(np.flatnonzero(f["escape/step"][()] < 0)[0]), 7),
        }
        for text, change in changes.items():
            shutil.copy(pristine, self.dir / "out.h5.ckpt")
            self.tampered(self.dir / "out.h5.ckpt", change)
            r = qmaps(self.dir, "run", "--resume", "out.h5.ckpt", "--quiet")
            self.refused(r, 3, text)
            self.assertFalse((self.dir / "out.h5").exists())

    def shards(self, count=2, orbits=300):
        args = config(self.dir, orbits=orbits, steps=20)[:-3]
        for k in range(1, count + 1):
            r = qmaps(self.dir, *args, "--shard", f"{k}/{count}", "--out", f"s{k}.h5", "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
        return [f"s{k}.h5" for k in range(1, count + 1)]

    def test_mixed_or_tampered_shards_are_refused(self):
        shards = self.shards()
        pristine = (self.dir / "s2.h5").read_bytes()
        changes = {
            "attribute seed": lambda f: f.attrs.__setitem__("seed", np.int64(f.attrs["seed"] + 1)),
            "attribute param.h": lambda f: f.attrs.__setitem__("param.h", f.attrs["param.h"] / 2),
            "attribute schema_version":
                lambda f: f.attrs.__setitem__("schema_version", np.int64(2)),
            "/initial/p2": lambda f: f["initial/p2"].__setitem__(0, np.inf),
            "escape reason": lambda f: f["escape/reason"].__setitem__(
                int(np.flatnonzero(f["escape/step"][()] < 0)[0]), 9),
        }
        for text, change in changes.items():
            (self.dir / "s2.h5").write_bytes(pristine)
            self.tampered(self.dir / "s2.h5", change)
            r = qmaps(self.dir, "merge", *shards, "--out", "m.h5")
            self.refused(r, 3, "'s2.h5'", text)
            self.assertFalse((self.dir / "m.h5").exists())

    def test_a_newer_schema_is_refused_by_info_and_file_ensembles(self):
        r = qmaps(self.dir, *config(self.dir))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.tampered(self.dir / "out.h5",
                      lambda f: f.attrs.__setitem__("schema_version", np.int64(2)))
        self.refused(qmaps(self.dir, "info", "out.h5"), 3, "schema 2, newer than the schema 1")
        r = qmaps(self.dir, "run", "config.toml", "--set", 'ensemble.kind="file"', "--set",
                  'ensemble.path="out.h5"', "--out", "next.h5", "--quiet")
        self.refused(r, 3, "schema 2, newer than the schema 1")

    # 8. Output names.
    def test_bad_output_names_are_usage_errors(self):
        args = config(self.dir)
        cases = [
            (args[:-3] + ["--out", "", "--quiet"], "--out: the output's name is empty"),
            (args[:-3] + ["--out", "sub/", "--quiet"], "'sub/' names a folder"),
        ]
        for a, text in cases:
            self.refused(qmaps(self.dir, *a), 2, text)
        # A NUL in the configured name (without --out, which would replace it).
        r = qmaps(self.dir, "run", "config.toml", "--set", 'output.file="a\\u0000b.h5"')
        self.refused(r, 2, "NUL byte at position 1")
        self.assertEqual(names(self.dir), ["config.toml"])
        shards = self.shards()
        before = (self.dir / shards[0]).read_bytes()
        self.refused(qmaps(self.dir, "merge", *shards, "--out", shards[0]), 2,
                     f"--out '{shards[0]}' is the shard")
        os.link(self.dir / shards[1], self.dir / "alias.h5")
        self.refused(qmaps(self.dir, "merge", *shards, "--out", "alias.h5"), 2, "is the shard")
        self.refused(qmaps(self.dir, "merge", *shards, "--out", ""), 2, "name is empty")
        self.assertEqual((self.dir / shards[0]).read_bytes(), before)

    # 16. A merge holds one shard open at a time.
    def test_a_merge_of_more_shards_than_open_files(self):
        shards = self.shards(count=40, orbits=400)
        r = qmaps(self.dir, "merge", *shards, "--out", "m.h5", nofile=30)
        self.assertEqual(r.returncode, 0, r.stderr)
        if "ASAN_OPTIONS" in os.environ:
            return  # the sanitizers' runtime itself needs descriptors to report anything
        r = qmaps(self.dir, "merge", *shards, "--out", "n.h5", nofile=4)
        self.refused(r, 3, "Too many open files", "ulimit -n")

    # 20. A closed pipe for the summary changes nothing.
    def test_a_closed_pipe_does_not_change_the_outcome(self):
        args = config(self.dir)
        args.remove("--quiet")
        p = subprocess.Popen([BINARY, *args], cwd=self.dir, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE)
        p.stdout.close()
        p.stderr.close()
        self.assertEqual(p.wait(timeout=60), 0)
        self.assertEqual(names(self.dir), ["config.toml", "out.h5"])


if __name__ == "__main__":
    unittest.main()
