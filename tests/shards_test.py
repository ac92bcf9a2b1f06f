"""Shards through the qmaps binary: a run split with --shard k/K (K = 1, 2 and 3, over an orbit
count none of them divides) and joined by qmaps merge, in any order, equals the run done at once,
dataset for dataset and byte for byte, with every kind of observer, trajectories across shards,
escaping orbits and a shell ensemble's rejections; a shard interrupted and resumed is the same
shard; a missing, duplicated or foreign shard, or a file that is no shard, is refused with
nothing written."""
import os
import pathlib
import random
import sys
import tempfile
import unittest

import h5py

import small_run

TRAJECTORIES = small_run.fixture("trajectory-across.toml")


run = small_run.qmaps


def datasets(group):
    out = {}
    group.visititems(lambda name, item: out.__setitem__(name, item[()])
                     if isinstance(item, h5py.Dataset) else None)
    return out


class Shards(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        text = small_run.PRESET.read_text() + small_run.EXTRA_OBSERVERS + small_run.TUNES + TRAJECTORIES
        (cls.dir / "c.toml").write_text(text.replace('file = "suris.h5"', 'file = "whole.h5"'))
        cls.sets = ["--set", "ensemble.orbits=1001", "--set", "run.steps=120", "--set",
                    "run.escape_bound=0.6", "--quiet"]
        r = run(cls.dir, "run", "c.toml", *cls.sets)
        assert r.returncode == 0, r.stderr

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def assert_same_datasets(self, merged, single):
        with h5py.File(merged) as m, h5py.File(single) as s:
            mine, theirs = datasets(m), datasets(s)
            self.assertEqual(sorted(mine), sorted(theirs))
            for path, value in theirs.items():
                self.assertEqual(mine[path].tobytes(), value.tobytes(), path)
                self.assertEqual(mine[path].dtype, value.dtype, path)
            for name in ("orbits", "escaped", "rejected", "steps", "seed"):
                self.assertEqual(m.attrs[name], s.attrs[name], name)

    def test_merged_shards_equal_the_run_done_at_once(self):
        with h5py.File(self.dir / "whole.h5") as f:
            self.assertGreater(f.attrs["escaped"], 0)
            self.assertEqual(sorted(set(f["trajectories/across/orbit"][()])),
                             [2, 333, 500, 667, 1000])
            self.assertIn("q2both", f["sections"])
        for count in (1, 2, 3):
            names = []
            for k in range(1, count + 1):
                r = run(self.dir, "run", "c.toml", *self.sets, "--shard", f"{k}/{count}",
                        "--threads", str(1 + k % 2))
                self.assertEqual(r.returncode, 0, r.stderr)
                names.append(f"whole.h5.shard-{k}-of-{count}")
                self.assertTrue((self.dir / names[-1]).exists())
            random.Random(count).shuffle(names)
            r = run(self.dir, "merge", *names, "--out", f"merged-{count}.h5")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn(f"merged {count} shards, 1001 orbits", r.stderr)
            self.assert_same_datasets(self.dir / f"merged-{count}.h5", self.dir / "whole.h5")

    def test_a_shell_ensemble_counts_its_rejections_once(self):
        d = pathlib.Path(tempfile.mkdtemp(dir=self.dir))
        preset = small_run.SOURCE_DIR / "ensembles" / "presets" / "suris-equal.toml"
        sets = ["--set", "ensemble.orbits=777", "--set", "run.steps=50", "--quiet"]
        self.assertEqual(run(d, "run", str(preset), *sets, "--out", "single.h5").returncode, 0)
        for k in (1, 2):
            r = run(d, "run", str(preset), *sets, "--shard", f"{k}/2", "--out", f"s{k}.h5")
            self.assertEqual(r.returncode, 0, r.stderr)
        r = run(d, "merge", "s2.h5", "s1.h5", "--out", "merged.h5")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(d / "single.h5") as f:
            self.assertGreater(f.attrs["rejected"], 0)
        self.assert_same_datasets(d / "merged.h5", d / "single.h5")

    def test_an_interrupted_shard_resumes_into_the_same_shard(self):
        d = pathlib.Path(tempfile.mkdtemp(dir=self.dir))
        (d / "c.toml").write_text((self.dir / "c.toml").read_text())
        for k in (1, 2):
            env = {"QMAPS_SIGNAL_AT_STEP": "60:INT"} if k == 2 else None
            r = run(d, "run", "c.toml", *self.sets, "--shard", f"{k}/2", env=env)
            if k == 2:
                self.assertEqual(r.returncode, 5, r.stderr)
                r = run(d, "run", "--resume", "whole.h5.shard-2-of-2.ckpt", "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
        r = run(d, "merge", "whole.h5.shard-1-of-2", "whole.h5.shard-2-of-2", "--out", "m.h5")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assert_same_datasets(d / "m.h5", self.dir / "whole.h5")

    def refused(self, *args, code=2):
        before = sorted(os.listdir(self.dir))
        r = run(self.dir, "merge", *args, "--out", "bad.h5")
        self.assertEqual(r.returncode, code, r.stderr)
        self.assertEqual(sorted(os.listdir(self.dir)), before, "nothing written")
        return r.stderr

    def test_bad_merges_are_refused_with_nothing_written(self):
        for k in (1, 2, 3):
            r = run(self.dir, "run", "c.toml", *self.sets, "--shard", f"{k}/3")
            self.assertEqual(r.returncode, 0, r.stderr)
        s = [f"whole.h5.shard-{k}-of-3" for k in (1, 2, 3)]
        self.assertIn("1 of the 3 shards is missing: 2", self.refused(s[0], s[2]))
        self.assertIn(f"'{s[0]}' and '{s[0]}' are both shard 1/3", self.refused(s[0], s[0], s[1], s[2]))
        self.assertIn("'whole.h5' is not a shard file", self.refused("whole.h5", s[1]))
        r = run(self.dir, "run", "c.toml", *self.sets, "--set", "ensemble.seed=2", "--shard", "2/3",
                "--out", "foreign.h5")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("'foreign.h5' is a shard of another run than", self.refused(s[0], "foreign.h5", s[2]))
        r = run(self.dir, "run", "c.toml", *self.sets, "--shard", "2/2", "--out", "other-split.h5")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("not one split", self.refused(s[0], "other-split.h5", s[2]))
        self.assertIn("no such file", self.refused(s[0], s[1], "absent.h5", code=3).lower()
                      .replace("cannot open", "no such file"))

    def test_bad_shard_options_are_refused(self):
        for shard in ("0/3", "4/3", "a/b", "3", "1/0", "2/2/2"):
            r = run(self.dir, "run", "c.toml", *self.sets, "--shard", shard, "--out", "x.h5")
            self.assertEqual(r.returncode, 2, (shard, r.stderr))
            self.assertIn(f"--shard {shard}: expected k/K", r.stderr)
        r = run(self.dir, "run", "c.toml", "--set", "ensemble.orbits=2", "--shard", "1/3", "--quiet",
                "--out", "x.h5")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("leave this shard none", r.stderr)
        self.assertFalse((self.dir / "x.h5").exists())


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
