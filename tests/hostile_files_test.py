"""Hostile input files: a run file or a checkpoint altered as an attacker (or a broken disk) would
alter it. `qmaps info`, an ensemble of `kind = "file"` and `qmaps run --resume` refuse each with
exit 3 and a message that names the file and what is wrong: never a signal, exit 1 (bad_alloc),
a success with garbage, or a new file left behind. Sizes are checked before anything is read."""
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

import small_run

# A run of 16 orbits with a section, the one the HDF5 fuzz targets alter (fuzz/fuzz_files.hpp).
BASE = small_run.fixture("small-suris-box.toml")


def qmaps(directory, *args, env=None):
    return subprocess.run([str(small_run.BINARY), *args], capture_output=True, text=True,
                          cwd=directory, env={**os.environ, **(env or {})}, timeout=60)


class HostileFiles(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp()
        d = pathlib.Path(cls.dir)
        (d / "base.toml").write_text(BASE)
        r = qmaps(d, "run", "base.toml", "--out", "good.h5", "--quiet")
        assert r.returncode == 0, r.stderr
        r = qmaps(d, "run", "base.toml", "--out", "stopped.h5", "--quiet",
                  env={"QMAPS_SIGNAL_AT_STEP": "10:TERM"})
        assert r.returncode == 5 and (d / "stopped.h5.ckpt").exists(), r.stderr

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir)

    def altered(self, source, name, change):
        path = pathlib.Path(self.dir) / name
        shutil.copy(pathlib.Path(self.dir) / source, path)
        with h5py.File(path, "r+") as f:
            change(f)
        return path.name

    def refused(self, r, *parts):
        self.assertEqual(r.returncode, 3, r.stdout + r.stderr)
        self.assertTrue(r.stderr.startswith("qmaps: error: "), r.stderr)
        for part in parts:
            self.assertIn(part, r.stderr)

    def info(self, change, *parts):
        name = self.altered("good.h5", "bad.h5", change)
        self.refused(qmaps(self.dir, "info", name), "'bad.h5'", *parts)

    def test_info_lists_a_histogram_it_knows_no_more_of_and_passes_links_by(self):
        def extra(f):  # a run observer's histogram that info does not name, and a dangling link
            g = f.create_group("extra/radius")
            g["counts"] = np.array([3, 1], dtype=np.int64)
            g["x_edges"] = np.array([0.0, 0.5, 1.0])
            g.attrs["x"] = np.bytes_(b"radius")
            for k, v in (("underflow", 0), ("overflow", 0), ("samples", 4)):
                g.attrs[k] = np.int64(v)
            f["extra/link"] = h5py.SoftLink("/nowhere")
        r = qmaps(self.dir, "info", self.altered("good.h5", "extra.h5", extra))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("other histograms:\n  extra/radius: 2 bins over radius, 4 samples "
                      "(0 underflow, 0 overflow)\n", r.stdout)
        self.assertNotIn("other histograms", qmaps(self.dir, "info", "good.h5").stdout)

    def from_file(self, change, *parts):
        name = self.altered("good.h5", "source.h5", change)
        config = pathlib.Path(self.dir) / "again.toml"
        config.write_text(BASE.replace('kind = "box"', f'kind = "file"\npath = "{name}"'))
        r = qmaps(self.dir, "run", "again.toml", "--out", "again.h5", "--quiet")
        self.refused(r, "'source.h5'", *parts)
        self.assertFalse((pathlib.Path(self.dir) / "again.h5").exists())

    def resume(self, change, *parts):
        def same_checkpoint(f):
            change(f)
        ckpt = pathlib.Path(self.dir) / "copy.h5.ckpt"
        shutil.copy(pathlib.Path(self.dir) / "stopped.h5.ckpt", ckpt)
        with h5py.File(ckpt, "r+") as f:
            same_checkpoint(f)
        r = qmaps(self.dir, "run", "--resume", ckpt.name, "--quiet")
        self.refused(r, *parts)
        self.assertFalse((pathlib.Path(self.dir) / "copy.h5").exists())

    # Attributes that hold arrays where one value belongs.
    def test_an_array_attribute_is_refused(self):
        def orbits_array(f):
            f.attrs["orbits"] = np.arange(10)
        self.info(orbits_array, "attribute 'orbits'", "holds 10 values, not one")
        self.from_file(orbits_array, "attribute 'orbits'", "not one")

    def test_a_map_name_as_an_array_of_strings_is_refused(self):
        def map_array(f):
            f.attrs["map"] = np.array([b"suris", b"case2"])
        self.info(map_array, "attribute 'map'", "holds 2 values, not one")
        self.from_file(map_array, "attribute 'map'")

    def test_a_negative_or_enormous_orbit_count_is_refused_before_any_read(self):
        def negative(f):
            f.attrs["orbits"] = np.int64(-5)
        self.info(negative, "attribute orbits is -5")
        def enormous(f):
            f.attrs["orbits"] = np.int64(1 << 50)
        self.info(enormous, "orbits = 1125899906842624 would need")

    def test_a_configuration_that_cannot_be_read_is_the_files_fault(self):
        # qmaps info reads the run's configuration for its optional measurements' columns.
        def garbage(f):
            f.attrs["config_resolved"] = np.bytes_(b"[map]\nname = 'nomap'\n")
        self.info(garbage, "attribute config_resolved: ", "nomap")

    # Datasets whose length disagrees with the file's orbit count.
    def test_short_empty_or_scalar_per_orbit_datasets_are_refused(self):
        def replace(path, data):
            def change(f):
                del f[path]
                f[path] = data
            return change
        self.info(replace("escape/reason", np.zeros(3, np.int64)), "/escape/reason",
                  "holds 3 elements, not 16")
        self.info(replace("invariants/H/max_abs_drift", np.zeros(0)), "max_abs_drift",
                  "holds 0 elements, not 16")
        self.info(replace("invariants/H/max_abs_drift", 1.0), "holds 1 elements, not 16")
        self.from_file(replace("final/state/q1_n", np.zeros(7)), "holds 7 elements, not 16")

    def test_a_huge_declared_dataset_is_refused_without_reading_it(self):
        def huge(f):
            del f["final/state/q1_n"]
            f.create_dataset("final/state/q1_n", shape=(1 << 36,), dtype="f8", chunks=(1 << 16,))
        self.from_file(huge, "holds 68719476736 elements, not 16")

    def test_unknown_escape_reasons_are_refused(self):
        def reason(f):
            f["escape/step"][0] = 3
            f["escape/reason"][0] = 77
        self.from_file(reason, "unknown reason 77")

    # Checkpoints altered.
    def test_a_checkpoint_with_a_nan_state_is_refused(self):
        def nan(f):
            q = f["final/state/q1_n"][...]
            q[0] = np.nan
            f["final/state/q1_n"][...] = q
        self.resume(nan, "has not escaped but its q1_n is not finite")

    def test_a_checkpoint_with_a_negative_drift_is_refused(self):
        def negative(f):
            d = f["invariants/H/max_abs_drift"][...]
            d[0] = -1e-300
            f["invariants/H/max_abs_drift"][...] = d
        self.resume(negative, "its invariants/H/max_abs_drift is -1e-300, below its least value 0")

    def test_a_checkpoint_with_enormous_counts_is_refused(self):
        def counts(f):
            c = f["sections/s/density"][...]
            c.flat[0] = 1 << 62
            f["sections/s/density"][...] = c
        self.resume(counts, "holds the count 4611686018427387904")

    def test_a_checkpoint_whose_points_exceed_their_cap_is_refused(self):
        def kept(f):
            k = f["sections/s/kept"][...]
            k[0] = 1000
            f["sections/s/kept"][...] = k
        self.resume(kept, "an orbit keeps 1000 points")

    def test_a_checkpoint_with_an_escape_after_its_step_is_refused(self):
        def later(f):
            s = f["escape/step"][...]
            s[0] = 10 ** 6
            f["escape/step"][...] = s
        self.resume(later, "escaped at step 1000000")


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
