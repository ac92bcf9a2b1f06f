"""Maps written as formulas, through the qmaps binary (docs/formulas.md).

Suris written as formulas (ensembles/presets/suris-formulas.toml) writes the built-in suris map's
file byte for byte, every dataset, with every kind of observer; its file records the formulas; a
formula map's run interrupted and resumed, and run in shards and merged, equals the run done at
once; a sweep runs over a formula's own parameter; `qmaps list` and `qmaps check` take a formula
map's file; bad formulas exit 2 naming key, line and column.
"""
import os
import pathlib
import tempfile
import tomllib
import unittest

import h5py

import small_run

run = small_run.qmaps
PRESETS = small_run.SOURCE_DIR / "ensembles" / "presets"


def text(f, name):
    """A string attribute of f (h5py gives fixed-length strings as bytes)."""
    value = f.attrs[name]
    return value.decode() if isinstance(value, bytes) else value


def map_table(config):
    """The [map] table of a configuration's text, and the rest."""
    start = config.index("[map]")
    end = config.index("\n[", start + 1)
    return config[start:end], config[:start] + config[end:]


class FormulaMaps(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        built_in = small_run.PRESET.read_text() + small_run.EXTRA_OBSERVERS + small_run.TUNES
        formulas, _ = map_table((PRESETS / "suris-formulas.toml").read_text())
        _, rest = map_table(built_in)
        (cls.dir / "built-in.toml").write_text(built_in.replace('"suris.h5"', '"built-in.h5"'))
        (cls.dir / "formulas.toml").write_text(formulas + "\n" + rest.replace('"suris.h5"', '"formulas.h5"'))
        cls.sets = ["--set", "ensemble.orbits=1001", "--set", "run.steps=120", "--set",
                    "run.escape_bound=0.6", "--quiet"]
        for name in ("built-in", "formulas"):
            r = run(cls.dir, "run", f"{name}.toml", *cls.sets)
            assert r.returncode == 0, r.stderr

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def assert_same_datasets(self, a, b):
        differences, count = small_run.dataset_differences(a, b)
        self.assertEqual(differences, [])
        return count

    def test_suris_as_formulas_writes_the_built_in_file_byte_for_byte(self):
        count = self.assert_same_datasets(self.dir / "formulas.h5", self.dir / "built-in.h5")
        self.assertGreater(count, 40)
        with h5py.File(self.dir / "formulas.h5") as f, h5py.File(self.dir / "built-in.h5") as g:
            self.assertGreater(f.attrs["escaped"], 0)
            self.assertIn("chaos", f)
            self.assertIn("tunes", f)
            self.assertEqual(text(f, "map"), "suris-formulas")
            self.assertEqual(text(g, "map"), "suris")
            # the file says which map made it: its formulas and parameters
            self.assertIn("q1_next = fma(2*(1 - A*h^2)*q1, inv, -q1_prev)", text(f, "formula.step"))
            self.assertEqual(text(f, "formula.form"), "two_step")
            for key in ("parameters", "momentum", "start", "invariants", "continuous"):
                self.assertIn("formula." + key, f.attrs)
            self.assertNotIn("formula.step", g.attrs)
            for name in ("A", "B", "alpha", "h"):
                self.assertEqual(f.attrs["param." + name], g.attrs["param." + name])

    def test_interrupted_and_resumed_and_sharded_runs_equal_the_run_done_at_once(self):
        d = pathlib.Path(tempfile.mkdtemp(dir=self.dir))
        (d / "formulas.toml").write_text((self.dir / "formulas.toml").read_text())
        r = run(d, "run", "formulas.toml", *self.sets, env={"QMAPS_SIGNAL_AT_STEP": "60:INT"})
        self.assertEqual(r.returncode, 5, r.stderr)
        r = run(d, "run", "--resume", "formulas.h5.ckpt", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assert_same_datasets(d / "formulas.h5", self.dir / "formulas.h5")
        for k in (1, 2):
            r = run(d, "run", "formulas.toml", *self.sets, "--shard", f"{k}/2")
            self.assertEqual(r.returncode, 0, r.stderr)
        r = run(d, "merge", "formulas.h5.shard-2-of-2", "formulas.h5.shard-1-of-2", "--out",
                "merged.h5")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assert_same_datasets(d / "merged.h5", self.dir / "formulas.h5")

    def test_a_sweep_runs_over_a_formula_parameter(self):
        d = pathlib.Path(tempfile.mkdtemp(dir=self.dir))
        preset = PRESETS / "suris-kicked.toml"
        (d / "kicked.toml").write_text(preset.read_text() + """
[[sweep]]
parameter = "eps"
values = [0.0, 0.3]
""")
        r = run(d, "run", "kicked.toml", "--set", "ensemble.orbits=200", "--set",
                "run.steps=200", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(d / "suris-kicked.h5") as f:
            runs = f["sweep/runs"]
            self.assertEqual(len(runs), 2)
            megno = [runs[name]["chaos/megno"][()] for name in sorted(runs)]
            self.assertIn("formula.step", f.attrs)
        # the kick makes chaos: MEGNO grows with eps
        self.assertGreater(float(sorted(megno[1])[len(megno[1]) * 9 // 10]),
                           float(sorted(megno[0])[len(megno[0]) * 9 // 10]))

    @unittest.skipUnless(os.environ.get("QMAPS_PYTHON_ENGINE", "1") == "1", "no engine module")
    def test_a_map_written_in_python_runs_as_the_configurations_map(self):
        import qmaps
        d = pathlib.Path(tempfile.mkdtemp(dir=self.dir))
        preset = tomllib.loads((PRESETS / "froeschle.toml").read_text())
        written = preset["map"]
        defaults = {k.strip(): float(v) for k, v in
                    (item.split("=") for item in written["parameters"].split(";"))}
        kick = qmaps.Map("froeschle", "phase", defaults, step=written["step"], b=0.08)
        small = {"orbits": 300}
        r = run(d, "run", PRESETS / "froeschle.toml", "--set", "ensemble.orbits=300", "--set",
                "run.steps=200", "--set", "map.b=0.08", "--out", "cli.h5", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        config = {k: v for k, v in preset.items() if k != "output"}
        config["map"] = kick
        config["run"] = {**preset["run"], "steps": 200}
        with qmaps.run(config, ensemble=small) as result:
            result.save(d / "python.h5")
        self.assert_same_datasets(d / "python.h5", d / "cli.h5")
        with h5py.File(d / "python.h5") as f:
            self.assertEqual(f.attrs["param.b"], 0.08)
            self.assertEqual(text(f, "formula.step"), written["step"])
        with self.assertRaises(qmaps.ConfigError) as bad:
            qmaps.run({**config, "map": qmaps.Map("m", "phase", step="p1 = p1 - q3")})
        self.assertIn("[map] step: line 1, column 11: unknown symbol 'q3'", str(bad.exception))

    @unittest.skipUnless(os.environ.get("QMAPS_PYTHON_ENGINE", "1") == "1", "no engine module")
    def test_one_orbit_of_a_map_written_in_python(self):
        import qmaps
        mcmillan = qmaps.Map("mcmillan", "phase", {"mu": 0.6},
                             step="q = p1; p1 = -q1 + 2*mu*q/(1 + q^2); q1 = q",
                             invariants="I = q1^2*p1^2 + q1^2 + p1^2 - 2*mu*q1*p1")
        rows = qmaps.orbit(mcmillan, {"mu": 0.4}, (0.5, 0.0, 0.2, 0.0), steps=1000, frame=False)
        self.assertEqual(len(rows), 1001)
        drift = abs(rows["I"] - rows["I"][0]).max()
        self.assertLess(drift, 1e-14)  # conserved to round-off
        self.assertNotIn("H_cont", rows.dtype.names)  # no continuous system named
        r = run(self.dir, "orbit", "--map", PRESETS / "mcmillan.toml", "--ic", "0.5,0,0.2,0",
                "--steps", "3", "--set", "mu=0.4")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("I", r.stdout.splitlines()[0])

    def test_list_and_check_take_a_map_written_as_formulas(self):
        r = run(self.dir, "list", PRESETS / "mcmillan.toml", PRESETS / "suris-kicked.toml")
        self.assertEqual(r.returncode, 0, r.stderr)
        lines = r.stdout.splitlines()
        self.assertTrue(lines[0].startswith("mcmillan: a map written as formulas ("), lines[0])
        for line in ("  form: phase", "  parameters: mu = 0.6", "  step: q = p1",
                     "        p1 = -q1 + 2*mu*q/(1 + q^2)", "  invariants tracked: I",
                     "  invariants tracked: H0"):
            self.assertIn(line, lines)
        self.assertTrue(any(l.startswith("suris-kicked: a map written as formulas") for l in lines))
        r = run(self.dir, "check", "--map", PRESETS / "mcmillan.toml", "--set", "mu=0.4",
                "--orbits", "200", "--steps", "500")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("map mcmillan (mu = 0.4): 200 orbits", r.stdout)
        drift = next(l for l in r.stdout.splitlines() if l.split()[:1] == ["I"])
        self.assertLess(float(drift.split()[-1]), 1e-12)  # the worst orbit's, to round-off
        self.assertIn("reversibility: 500 steps forward", r.stdout)
        # a built-in map's preset is no formula map; a bad formula names its key
        r = run(self.dir, "check", "--map", PRESETS / "suris.toml")
        self.assertEqual(r.returncode, 2)
        self.assertIn("is not written as formulas", r.stderr)
        r = run(self.dir, "list", PRESETS / "suris.toml")
        self.assertEqual(r.returncode, 2)

    def test_bad_formulas_exit_2_naming_key_line_and_column(self):
        d = pathlib.Path(tempfile.mkdtemp(dir=self.dir))
        text, rest = map_table((PRESETS / "henon-heiles.toml").read_text())
        bad = text.replace("q2 = q2 + h*p2", "q2 = q2 + h*p2)")
        (d / "bad.toml").write_text(bad + "\n" + rest)
        r = run(d, "run", "bad.toml", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertRegex(r.stderr, r"bad\.toml:\d+: \[map\] step: line 4, column 15: ")
        self.assertNotIn("terminate", r.stderr)


if __name__ == "__main__":
    unittest.main()
