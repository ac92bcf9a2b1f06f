"""`qmaps integrability` and qmaps.integrability (docs/integrability.md), through the binary and the
Python package: the file's schema as the page gives it, the Python function's verdict and evidence
equal to the file's, a map written in Python (qmaps.Map), qmaps-plot's picture of the evidence,
and bad arguments as ConfigError.
"""
import os
import pathlib
import subprocess
import sys
import tempfile
import unittest

import h5py

import small_run

run = small_run.qmaps
PRESETS = small_run.SOURCE_DIR / "ensembles" / "presets"
ENGINE = os.environ.get("QMAPS_PYTHON_ENGINE", "1") == "1"
FAST = ["--field-primes", "1009", "--orbits", "200", "--steps", "20", "--height-steps", "20"]


def attrs(group):
    return {k: (v.decode() if isinstance(v, bytes) else v) for k, v in group.attrs.items()}


class Integrability(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        cls.out = cls.dir / "mcmillan.h5"
        cls.result = run(cls.dir, "integrability", "--map", str(PRESETS / "mcmillan.toml"), *FAST,
                         "--out", str(cls.out))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_the_file_holds_what_the_page_says(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        self.assertIn("verdict: integrable", self.result.stdout)
        page = (small_run.SOURCE_DIR / "docs" / "integrability.md").read_text()
        with h5py.File(self.out) as f:
            top = f["integrability"]
            for name in attrs(top):
                self.assertIn(f"`{name}`", page)
            self.assertEqual(attrs(top)["verdict"], "integrable")
            self.assertEqual(attrs(top)["coordinates"], "p1,q1")
            for group in ("degrees", "finite_fields", "heights"):
                for name in attrs(top[group]):
                    self.assertIn(f"`{name}`", page, group)
            run0 = top["degrees/run0"]
            self.assertEqual(list(run0["degrees"][:6]), [1, 3, 7, 13, 21, 31])
            field = top["finite_fields/p1009"]
            for name in attrs(field):
                self.assertIn(f"`{name}`", page)
            self.assertEqual(len(field["periods"]) + attrs(field)["singular"]
                             + attrs(field)["past_max_period"], attrs(field)["orbits"])
            self.assertGreaterEqual(attrs(field)["orbits"], 200)  # more where most are singular
            self.assertEqual(attrs(field)["level_kept"], attrs(field)["level_checked"])
            self.assertEqual(len(top["heights/log_heights"]), 21)

    def test_the_plot_draws_the_evidence(self):
        plot = small_run.SOURCE_DIR / "tools" / "qmaps-plot"
        done = subprocess.run([sys.executable, str(plot), str(self.out), "-o", str(self.dir)],
                              capture_output=True, text=True)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertTrue((self.dir / "mcmillan-integrability.png").stat().st_size > 10000)

    @unittest.skipUnless(ENGINE, "no engine module")
    def test_the_python_function_gives_the_files_evidence(self):
        import qmaps

        r = qmaps.integrability(PRESETS / "mcmillan.toml", field_primes=[1009], orbits=200,
                                steps=20, height_steps=20)
        self.assertEqual(r.verdict, "integrable")
        self.assertIn("verdict: integrable", str(r))
        with h5py.File(self.out) as f:
            self.assertEqual(list(r.degrees["sequence"]),
                             list(f["integrability/degrees/run0/degrees"][()]))
            self.assertEqual(list(r.fields[1009]["periods"]),
                             list(f["integrability/finite_fields/p1009/periods"][()]))
        # A map written in Python: the quadratic Henon map, entropy log 2.
        henon = qmaps.Map("henon", "phase", {"a": 0.3}, step="x = q1; q1 = p1; p1 = -x + a - p1^2")
        h = qmaps.integrability(henon, field_primes=[1009], orbits=200, height_steps=15)
        self.assertEqual(h.verdict, "not integrable")
        self.assertAlmostEqual(h.degrees["entropy"], 0.6931471805599453, places=9)

    @unittest.skipUnless(ENGINE, "no engine module")
    def test_bad_arguments_are_config_errors(self):
        import qmaps

        for kwargs, says in [({"field_primes": [100]}, "--field-primes: 100 is not prime"),
                             ({"orbits": 1}, "orbits=1"),
                             ({"degree_primes": "x"}, "degree_primes")]:
            with self.assertRaisesRegex(qmaps.ConfigError, says):
                qmaps.integrability(PRESETS / "mcmillan.toml", **kwargs)
        with self.assertRaisesRegex(qmaps.ConfigError, "case3"):
            qmaps.integrability("case3")


if __name__ == "__main__":
    unittest.main()
