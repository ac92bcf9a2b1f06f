"""[output] compression = "gzip": every dataset holds the same bytes as without it, chunked,
shuffled and deflated, in a smaller file; a bad compression or level is a usage error (exit 2)
naming its key, and leaves no file."""
import pathlib
import subprocess
import sys
import tempfile
import unittest

import h5py

import small_run


def datasets(f):
    out = {}
    f.visititems(lambda name, obj: out.__setitem__(name, obj) if isinstance(obj, h5py.Dataset) else None)
    return out


class Compression(unittest.TestCase):
    def run_qmaps(self, directory, name, *sets):
        config = directory / "config.toml"
        config.write_text(small_run.PRESET.read_text() + small_run.EXTRA_OBSERVERS)
        args = [str(small_run.BINARY), "run", str(config), "--set", "ensemble.orbits=20000",
                "--set", "run.steps=200", "--out", str(directory / name), "--quiet"]
        for s in sets:
            args += ["--set", s]
        return subprocess.run(args, capture_output=True, text=True, cwd=directory)

    def test_gzip_keeps_every_dataset_byte_for_byte_in_fewer_bytes(self):
        with tempfile.TemporaryDirectory() as d:
            d = pathlib.Path(d)
            plain = self.run_qmaps(d, "plain.h5")
            packed = self.run_qmaps(d, "gzip.h5", "output.compression=gzip",
                                    "output.compression_level=6")
            self.assertEqual(plain.returncode, 0, plain.stderr)
            self.assertEqual(packed.returncode, 0, packed.stderr)
            with h5py.File(d / "plain.h5") as a, h5py.File(d / "gzip.h5") as b:
                da, db = datasets(a), datasets(b)
                self.assertEqual(sorted(da), sorted(db))
                compressed = 0
                for name in da:
                    with self.subTest(dataset=name):
                        self.assertEqual(da[name][()].tobytes(), db[name][()].tobytes())
                        self.assertIsNone(da[name].compression)
                        if db[name].size > 0:
                            self.assertEqual(db[name].compression, "gzip")
                            self.assertEqual(db[name].compression_opts, 6)
                            self.assertTrue(db[name].shuffle)
                            compressed += 1
                self.assertGreater(compressed, 20)
            small, large = (d / "gzip.h5").stat().st_size, (d / "plain.h5").stat().st_size
            print(f"20000 orbits: {large} bytes uncompressed, {small} with gzip level 6")
            self.assertLess(small, large)

    def test_bad_compression_is_a_usage_error_naming_the_key(self):
        cases = [(["output.compression=zstd"], "output.compression: 'zstd' is not a compression"),
                 (["output.compression=gzip", "output.compression_level=10"],
                  "output.compression_level must be 1 to 9 (got 10)"),
                 (["output.compression_level=3"], "needs compression = \"gzip\"")]
        for sets, message in cases:
            with self.subTest(sets=sets), tempfile.TemporaryDirectory() as d:
                r = self.run_qmaps(pathlib.Path(d), "out.h5", *sets)
                self.assertEqual(r.returncode, 2, r.stderr)
                self.assertIn(message, r.stderr)
                self.assertEqual([p.name for p in pathlib.Path(d).iterdir()], ["config.toml"])


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
