"""docs/hdf5-schema.md and the writer agree: on a run with every kind of observer, every group,
dataset and attribute in the file is documented with its type and shape, and every documented one
is there (a name with a placeholder, at least once). The page names suris' invariants as a run
writes them, for A != B and A = B, and gives I1 as docs/maps.md does."""
import pathlib
import re
import sys
import tempfile
import unittest

import h5py

import schema_doc
import small_run

DOC = small_run.SOURCE_DIR / "docs" / "hdf5-schema.md"


def objects(path):
    """(group path, name, kind, h5py value or object) of everything in the file."""
    out = []
    with h5py.File(path, "r") as f:
        def visit(group):
            gpath = group.name
            for name, value in group.attrs.items():
                out.append((gpath, name, "attribute", value, group))
            for name, child in group.items():
                kind = "group" if isinstance(child, h5py.Group) else "dataset"
                out.append((gpath, name, kind, child[()] if kind == "dataset" else None, group))
                if kind == "group":
                    visit(child)
        visit(f)
    return out


def sizes(f, gpath):
    """The values of the symbols of the page's shapes in the file's group `gpath`."""
    group = f[gpath]
    out = {"N_o": int(f.attrs["orbits"])}
    if "orbit" in group:  # a section's points, or a trajectory's rows
        out["N_p"] = out["N_r"] = group["orbit"].shape[0]
    counts = group["counts"] if "counts" in group else group.get("density")
    if counts is not None:
        out["nx"] = counts.shape[0]
        out["ny"] = counts.shape[1] if counts.ndim == 2 else 0
    return out


class SchemaMatchesWriter(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.paths = small_run.every_layout(cls.tmp.name)
        cls.path = cls.paths[0]
        cls.schema = schema_doc.Schema(DOC)
        cls.written = {path: objects(path) for path in cls.paths}
        cls.objects = [o for written in cls.written.values() for o in written]

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_the_run_has_every_kind_of_observer(self):
        with h5py.File(self.path, "r") as f:
            ndims = {f["histograms"][n]["counts"].ndim for n in f["histograms"]}
            self.assertEqual(ndims, {1, 2})
            capped = [s.attrs["crossings"] > s["orbit"].shape[0] for s in f["sections"].values()]
            self.assertEqual(sorted(capped), [False, True])
            self.assertIn("image", f["invariants"])

    def test_the_page_lists_every_group(self):
        self.assertGreater(len(self.schema.entries), 60)
        for group in {e.group for e in self.schema.entries}:
            if group != "/":
                parent, _, name = group.rpartition("/")
                self.assertTrue(any(e.group == (parent or "/") and e.name == name
                                    and e.kind == "group" for e in self.schema.entries), group)

    def test_every_object_written_is_documented_with_its_type_and_shape(self):
        for path, written in self.written.items():
            self.check_documented(path, written)

    def check_documented(self, path, written):
        with h5py.File(path, "r") as f:
            for gpath, name, kind, value, _ in written:
                with self.subTest(file=path.name, group=gpath, name=name, kind=kind):
                    entry = self.schema.entry(gpath, name, kind)
                    self.assertIsNotNone(entry, f"{kind} {name} of {gpath} is not in {DOC.name}")
                    if kind == "group":
                        continue
                    self.assertEqual(schema_doc.dtype_name(value), entry.dtype)
                    if kind == "dataset":
                        self.assertTrue(
                            schema_doc.shape_matches(value.shape, entry.shapes, sizes(f, gpath)),
                            f"shape {value.shape}, documented {entry.shapes}")

    def test_every_documented_object_is_written(self):
        written = {(self.schema.group(g), self.schema.entry(g, n, k)) for g, n, k, _, _ in
                   self.objects}
        for entry in self.schema.entries:
            with self.subTest(entry=entry):
                self.assertTrue((entry.group, entry) in written,
                                f"{entry.kind} {entry.name} of {entry.group} is not in the file")

    def test_the_page_names_suris_invariants_for_both_cases(self):
        # "For `suris` these are `H`, `I1` and `I2`, but `H` and `L` when `A = B`."
        sentence = re.search(r"For `suris` these are (.*?),\s+but\s+(.*?)\s+when `A = B`",
                             DOC.read_text(), re.S)
        self.assertIsNotNone(sentence)
        documented = [set(re.findall(r"`(\w+)`", part)) for part in sentence.groups()]
        directory = pathlib.Path(self.tmp.name)
        for b, expected in (("0.3", documented[0]), ("0.7", documented[1])):
            out = directory / f"suris-B{b}.h5"
            run = small_run.qmaps(directory, "run", small_run.PRESET, "--set", "map.A=0.7",
                                  "--set", f"map.B={b}", "--set", "ensemble.orbits=10",
                                  "--set", "run.steps=10", "--set", "invariant_image.y=H",
                                  "--out", out, "--quiet")
            self.assertEqual(run.returncode, 0, run.stderr)
            with h5py.File(out, "r") as f:
                self.assertEqual(set(f["invariants"]) - {"image"}, expected, f"B = {b}")

    def test_the_page_gives_suris_I1_as_docs_maps_does(self):
        page = re.search(r"`I1 = (.*?)`", DOC.read_text(), re.S).group(1)
        maps_page = (DOC.parent / "maps.md").read_text()
        maps = re.search(r"^\| `I1` \| (.*?) \|", maps_page, re.M).group(1)
        squeeze = lambda formula: re.sub(r"\s+", "", formula)
        self.assertEqual(squeeze(page), squeeze(maps))


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
