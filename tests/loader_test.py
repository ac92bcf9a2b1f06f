"""qmaps.load (python/qmaps/runfile.py): every object docs/hdf5-schema.md lists comes back under its name, datasets
with the file's values, dtype and shape, attributes as str, int or float by their documented type;
skipped datasets are not read; unreadable files are clear errors. The Python examples of the README,
docs/getting-started.md, docs/python.md and docs/hdf5-schema.md run as written on a run named
suris.h5."""
import os
import re
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

import schema_doc
import small_run

import qmaps  # noqa: E402

PYTHON_TYPE = {"string": str, "int64": int, "float64": float}
NUMPY_TYPE = {"int64": np.int64, "float64": np.float64, "uint8": np.uint8}


class Loader(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.paths = small_run.every_layout(cls.tmp.name)
        cls.path = cls.paths[0]
        cls.schema = schema_doc.Schema(small_run.SOURCE_DIR / "docs" / "hdf5-schema.md")
        cls.loaded = qmaps.load(cls.path)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_every_documented_object_round_trips(self):
        seen = set()
        for path in self.paths:
            with self.subTest(file=path.name):
                self.round_trip(path, qmaps.load(path), seen)
        self.assertEqual(seen, set(self.schema.entries), "the runs cover every documented object")

    def round_trip(self, path, run, seen):
        with h5py.File(path, "r") as f:
            def check(h5group):
                loaded = run[h5group.name] if h5group.name != "/" else run
                self.assertIsInstance(loaded, qmaps.Group)
                self.assertEqual(loaded.path, h5group.name)
                self.assertEqual(set(loaded.attrs), set(h5group.attrs))
                for name, value in h5group.attrs.items():
                    entry = self.schema.entry(h5group.name, name, "attribute")
                    seen.add(entry)
                    with self.subTest(group=h5group.name, attribute=name):
                        self.assertIs(type(loaded.attrs[name]), PYTHON_TYPE[entry.dtype])
                        expected = value.decode() if entry.dtype == "string" else value
                        self.assertEqual(loaded.attrs[name], expected)
                for name, child in h5group.items():
                    if isinstance(child, h5py.Group):
                        seen.add(self.schema.entry(h5group.name, name, "group"))
                        check(child)
                        continue
                    entry = self.schema.entry(h5group.name, name, "dataset")
                    seen.add(entry)
                    with self.subTest(group=h5group.name, dataset=name):
                        data = loaded.datasets[name]
                        self.assertIs(data, run[h5group.name + "/" + name])
                        self.assertIsInstance(data, np.ndarray)
                        self.assertEqual(data.dtype, NUMPY_TYPE[entry.dtype])
                        self.assertEqual(data.shape, child.shape)
                        np.testing.assert_array_equal(data, child[()])
            check(f)

    def test_run_helpers(self):
        self.assertEqual(self.loaded.params, {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1})
        self.assertEqual(self.loaded.invariants, ["H", "I1", "I2"])
        self.assertEqual(self.loaded.file, str(self.path))
        self.assertIn("invariants/H/initial", self.loaded)
        self.assertNotIn("invariants/H/nothing", self.loaded)
        self.assertIsNone(self.loaded.get("histograms/none"))
        with self.assertRaises(KeyError):
            self.loaded["invariants/H/initial/more"]

    def test_histogram_of_a_group(self):
        for path, counts in (("histograms/q1q2", "counts"), ("histograms/p1", "counts"),
                             ("sections/q1up", "density"), ("invariants/image", "counts")):
            g = self.loaded[path]
            h = qmaps.Histogram.of(g, counts)
            with self.subTest(path=path):
                self.assertIs(h.counts, g.datasets[counts])
                self.assertEqual(len(h.edges), h.counts.ndim)
                self.assertEqual([len(e) for e in h.edges], [n + 1 for n in h.counts.shape])
                self.assertEqual(h.axes, [g.attrs[a] for a in "xy"[:h.counts.ndim]])
                self.assertEqual(h.samples, h.counts.sum() + h.underflow + h.overflow)

    def test_every_histogram_by_its_path(self):
        found = self.loaded.histograms()
        expected = set()
        with h5py.File(self.path) as f:
            f.visititems(lambda name, obj: expected.add(name.rsplit("/", 1)[0])
                         if name.endswith("/x_edges") else None)
        self.assertEqual(set(found), expected)
        self.assertIn("invariants/H/drift_histogram", found)
        self.assertIn("sections/q1up", found)
        for path, h in found.items():
            with self.subTest(path=path):
                self.assertEqual(h.samples, h.counts.sum() + h.underflow + h.overflow)

    def test_skipped_datasets_are_not_read(self):
        run = qmaps.load(self.path, skip=("final/*", "invariants/*/max_abs_drift"))
        self.assertEqual(run["final"].datasets, {})
        self.assertEqual(run["final/state"].datasets, {})
        self.assertEqual(run["final/state"].attrs, self.loaded["final/state"].attrs)
        self.assertNotIn("max_abs_drift", run["invariants/H"].datasets)
        self.assertIn("initial", run["invariants/H"].datasets)

    def test_per_orbit_data_as_pandas_and_xarray(self):
        orbits = self.loaded.attrs["orbits"]
        frame = self.loaded.to_pandas()
        self.assertEqual(frame.index.name, "orbit")
        self.assertEqual(len(frame), orbits)
        for column in ("initial.q1", "final.p2", "final.state.q1_n+1", "escape.step",
                       "escape.reason", "invariants.I2.max_abs_drift", "chaos.megno"):
            with self.subTest(column=column):
                np.testing.assert_array_equal(frame[column].to_numpy(),
                                              self.loaded[column.replace(".", "/")])
        self.assertNotIn("sections.q1up.x", frame.columns)  # points, not orbits
        data = self.loaded.to_xarray()
        self.assertEqual(data.sizes["orbit"], orbits)
        self.assertEqual(sorted(data.data_vars), sorted(frame.columns))
        np.testing.assert_array_equal(data["invariants.H.initial"].values,
                                      self.loaded["invariants/H/initial"])
        self.assertEqual(data.attrs["map"], "suris")

    def test_a_run_without_per_orbit_data_says_so(self):
        path = f"{self.tmp.name}/summary.h5"
        small_run.qmaps(self.tmp.name, "run", small_run.PRESET, "--set", "output.per_orbit=false",
                        "--set", "ensemble.orbits=100", "--set", "run.steps=10", "--out", path,
                        "--quiet").check_returncode()
        with qmaps.load(path) as run, self.assertRaises(qmaps.FileError) as caught:
            run.to_pandas()
        self.assertEqual(str(caught.exception), f"{path}: no per-orbit datasets (the run was "
                         "written with [output] per_orbit = false)")

    def test_slices_read_from_the_file_and_close_ends_reading(self):
        run = qmaps.load(self.path)
        x = run.dataset("sections/q1up/x")
        np.testing.assert_array_equal(x[:10], self.loaded["sections/q1up/x"][:10])
        with self.assertRaises(KeyError):
            run.dataset("sections/q1up/nothing")
        run.close()
        with self.assertRaises(Exception):
            run["initial/q1"]

    def test_opening_a_million_orbit_file_reads_no_dataset(self):
        """Opening reads the tree and the attributes only: under 50 MB more than the interpreter
        with numpy and h5py until a dataset is read; reading one 8 MB dataset shows in RSS."""
        path = f"{self.tmp.name}/million.h5"
        small_run.qmaps(self.tmp.name, "run", small_run.PRESET, "--set", "ensemble.orbits=1000000",
                        "--set", "run.steps=4", "--set", "output.per_orbit=true", "--out", path,
                        "--quiet").check_returncode()
        self.assertGreater(os.path.getsize(path), 150e6)
        script = f"""
import sys
import numpy, h5py, qmaps
def rss():
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
start = rss()
run = qmaps.load({path!r})
opened = rss()
run["initial/q1"].sum()
read = rss()
print(opened - start, read - opened)
"""
        r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        opened, read = map(int, r.stdout.split())
        print(f"opening a 1e6-orbit file: +{opened / 2**20:.1f} MB; reading one dataset: "
              f"+{read / 2**20:.1f} MB")
        self.assertLess(opened, 50 * 2**20)
        self.assertGreater(read, 7 * 2**20)

    def test_unreadable_files_are_clear_errors(self):
        missing = f"{self.tmp.name}/missing.h5"
        text = f"{self.tmp.name}/text.h5"
        foreign = f"{self.tmp.name}/foreign.h5"
        with open(text, "w") as out:
            out.write("not hdf5\n")
        with h5py.File(foreign, "w") as f:
            f.attrs["something"] = 1
        for path, why in ((missing, "no such file"), (text, "not an HDF5 file"),
                          (foreign, "not a qmaps run (no schema_version attribute)")):
            with self.subTest(why=why), self.assertRaises(qmaps.FileError) as caught:
                qmaps.load(path)
            self.assertEqual(str(caught.exception), f"{path}: {why}")


class DocumentedExamples(unittest.TestCase):
    def test_every_python_block_runs(self):
        """Every python block of the pages runs as written. A build without the Python module
        (QMAPS_PYTHON_ENGINE=0: the sanitized one) runs only the blocks that need no engine."""
        engine = os.environ.get("QMAPS_PYTHON_ENGINE", "1") == "1"
        pages = [small_run.SOURCE_DIR / p for p in ("README.md", "docs/getting-started.md",
                                                     "docs/python.md", "docs/hdf5-schema.md")]
        with tempfile.TemporaryDirectory() as tmp:
            small_run.small_run(tmp, orbits=200, steps=50, name="suris.h5")
            ran = left = 0
            for page in pages:
                for block in re.findall(r"^```python\n(.*?)^```", page.read_text(), re.M | re.S):
                    if not engine and re.search(r"qmaps\.(run|orbit|maps)\(", block):
                        left += 1
                        continue
                    with self.subTest(page=page.name, block=block[:60]):
                        r = subprocess.run([sys.executable, "-B", "-c", block], cwd=tmp,
                                           capture_output=True, text=True)
                        self.assertEqual(r.returncode, 0, r.stderr)
                        ran += 1
            print(f"ran {ran} blocks" + (f", left {left} that need the engine" if left else ""))
            self.assertGreaterEqual(ran, 8 if engine else 3)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
