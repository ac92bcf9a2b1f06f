"""Limits checked before any work, and messages that name the right place and the true rule:
a sweep beyond the memory limit is refused before its points' observers are made; threads beyond
the bound, the user's process limit or what the system can start are refused with nothing left;
ranges whose width overflows are refused naming the key; numbers the command line gives are
judged by their own rules; a sweep's points name their keys' lines; a drift that is not a number
is never reported as a number."""
import os
import pathlib
import resource
import subprocess
import tempfile
import unittest

import h5py
import numpy as np

import small_run

SANITIZED = "ASAN_OPTIONS" in os.environ  # AddressSanitizer reserves terabytes of address space

SWEEP = """
[map]
name = "suris"
A = 0.7
B = 0.3
alpha = 0.9
h = 0.1

[ensemble]
orbits = 128
q1 = [-0.5, 0.5]
q2 = [-0.5, 0.5]
p1 = [-0.5, 0.5]
p2 = [-0.5, 0.5]

[run]
steps = 10

[output]
file = "out.h5"

[[histogram]]
name = "q1q2"
x = "q1"
y = "q2"
x_range = [-1.0, 1.0]
y_range = [-1.0, 1.0]
bins = [1024, 1024]

[[sweep]]
parameter = "A"
from = 0.5
to = 0.9
points = 100

[[sweep]]
parameter = "alpha"
from = 0.5
to = 1.0
points = 100
"""


def run(directory, *args, address_space=None, processes=None):
    def limit():
        if address_space is not None:
            resource.setrlimit(resource.RLIMIT_AS, (address_space, address_space))
        if processes is not None:
            resource.setrlimit(resource.RLIMIT_NPROC, (processes, processes))
    return subprocess.run([str(small_run.BINARY), *args], capture_output=True, text=True,
                          cwd=directory, preexec_fn=limit, timeout=300)


class Limits(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)
        (self.dir / "run.toml").write_text(small_run.PRESET.read_text())

    def tearDown(self):
        self.tmp.cleanup()

    def small(self, *extra, out="out.h5"):
        return ["run", "run.toml", "--set", "ensemble.orbits=64", "--set", "run.steps=10",
                "--out", out, "--quiet", *extra]

    def refused(self, r, code, *parts):
        self.assertEqual(r.returncode, code, r.stderr)
        for part in parts:
            self.assertIn(part, r.stderr)

    def nothing_left(self):
        self.assertEqual(sorted(p.name for p in self.dir.iterdir()), ["run.toml"])

    # A sweep's memory: known from its first point, checked before any other point's observers.
    @unittest.skipIf(SANITIZED, "AddressSanitizer reserves terabytes of address space")
    def test_the_largest_sweep_is_refused_before_its_points_are_allocated(self):
        (self.dir / "run.toml").write_text(SWEEP)
        # 10^4 points of 2^20 cells, 10 bytes each in each of 3 copies: about 293 GiB; one
        # point's observers (30 MiB) fit the 2 GiB limit, some hundred points' would not.
        r = run(self.dir, "run", "run.toml", "--threads", "2", "--quiet",
                address_space=2 << 30)
        self.refused(r, 2, "[sweep[0]]: 10000 points, 1280000 orbits in all, with their observers, "
                     "need about", "address-space limit (ulimit -v)")
        self.nothing_left()

    # Threads: a bound, the user's process limit, and what can start.
    def test_threads_beyond_the_bound_are_refused(self):
        r = run(self.dir, *self.small("--threads", "5000"))
        self.refused(r, 2, "--threads 5000: the threads must be 1 to 1024")
        self.nothing_left()

    def test_threads_beyond_the_process_limit_are_refused(self):
        r = run(self.dir, *self.small("--threads", "8"), processes=4)
        self.refused(r, 2, "--threads 8: 8 threads pass the limit of 4 processes and threads "
                           "of this user (ulimit -u)")
        self.nothing_left()

    @unittest.skipIf(SANITIZED, "AddressSanitizer reserves terabytes of address space")
    def test_threads_that_cannot_start_are_refused_with_nothing_left(self):
        # 1000 stacks of the default 8 MiB are more than the 2 GiB the process may map.
        r = run(self.dir, *self.small("--threads", "1000"), address_space=2 << 30)
        self.refused(r, 2, "--threads 1000: 1000 threads cannot be started: only ",
                     "use fewer threads")
        self.nothing_left()

    @unittest.skipIf(SANITIZED, "AddressSanitizer reserves terabytes of address space")
    def test_a_tiny_address_space_limit_is_refused_with_nothing_left(self):
        # The least limit under which qmaps starts at all, then a little more: too little for a
        # second thread's stack or the run's estimate, which are checked before any work.
        least = next(m << 20 for m in range(16, 1024, 2)
                     if run(self.dir, "list", address_space=m << 20).returncode == 0)
        r = run(self.dir, *self.small("--threads", "2"), address_space=least + (2 << 20))
        self.refused(r, 2, "ulimit -v")
        self.nothing_left()

    # Ranges whose width overflows would draw infinite points.
    def test_a_range_whose_width_overflows_is_refused_naming_the_key(self):
        r = run(self.dir, *self.small("--set", "ensemble.q1=[-1e308, 1e308]"))
        self.refused(r, 2, "--set ensemble.q1 = [-1e+308, 1e+308]: its width hi - lo overflows")
        self.nothing_left()
        # The same rule for the other kinds with ranges: a shell's, a grid's axes.
        shell = small_run.PRESET.read_text().replace('p2 = [-0.5, 0.5]\n', '').replace(
            'kind = "box"', 'kind = "shell"\nenergy = 0.1').replace(
            'q2 = [-0.5, 0.5]', 'q2 = [-1.5e308, 1.5e308]')
        (self.dir / "run.toml").write_text(shell)
        r = run(self.dir, *self.small())
        self.refused(r, 2, "run.toml:", "[ensemble] q2 = [-1.5e+308, 1.5e+308]: its width")
        grid = small_run.PRESET.read_text().replace('kind = "box"\norbits = 1000000', (
            'kind = "grid"\naxes = ["q1", "p1"]\npoints = 8')).replace(
            'q1 = [-0.5, 0.5]', 'q1 = [-1e308, 1e308]').replace(
            'q2 = [-0.5, 0.5]', 'q2 = 0').replace('p2 = [-0.5, 0.5]', 'p2 = 0')
        (self.dir / "run.toml").write_text(grid)
        r = run(self.dir, "run", "run.toml", "--set", "run.steps=1", "--out", "out.h5",
                "--quiet")
        self.refused(r, 2, "[ensemble] q1 = [-1e+308, 1e+308]: its width hi - lo overflows")
        self.nothing_left()

    # Messages that name the right place and say the true rule.
    def test_a_map_value_given_by_set_is_named_as_such(self):
        r = run(self.dir, *self.small("--set", "map.h=-0.1"))
        self.refused(r, 2, "run.toml:4: [map] with --set map.h: suris: h must be > 0")

    def test_orbit_takes_a_subnormal_as_a_number_and_names_its_rule(self):
        r = run(self.dir, "orbit", "--map", "suris", "--set", "A=0.7", "--set", "B=0.3",
                "--set", "alpha=0.9", "--set", "h=1e-320", "--ic", "0.1,0,0,0.1", "--steps", "1")
        self.refused(r, 2, "suris: h = 1e-320 is too small: h^2 must be a normal number")
        self.assertNotIn("is not a number", r.stderr)

    def test_orbit_energy_must_be_finite(self):
        for energy in ("inf", "nan"):
            r = run(self.dir, "orbit", "--map", "flow", "--set", "A=0.7", "--set", "B=0.3",
                    "--set", "alpha=0.9", "--set", "beta=0.9", "--set", "delta=1.8",
                    "--set", "h=0.01", "--ic", "0.1,0,0,0.1", "--steps", "1", "--energy", energy)
            self.refused(r, 2, f"--energy {energy}: the energy must be finite")
            self.assertNotIn("below the energy", r.stderr)

    def test_an_integer_beyond_64_bits_is_named_as_one(self):
        r = run(self.dir, *self.small("--set", "ensemble.orbits=9223372036854775808"))
        self.refused(r, 2, "--set ensemble.orbits=9223372036854775808: an integer must be "
                           "-2^63 to 2^63 - 1")
        self.assertNotIn("not a string", r.stderr)

    def test_an_output_that_names_a_folder_is_refused_as_such(self):
        (self.dir / "sub").mkdir()
        r = run(self.dir, *self.small(out="sub/"))
        self.refused(r, 2, "'sub/' names a folder; the output is a file in it (sub/run.h5, say)")
        self.assertNotIn("0 bytes", r.stderr)

    def test_a_sweep_point_names_the_line_of_its_key(self):
        # A sweep's points are copies of the configuration, which keep its lines.
        text = SWEEP.replace("orbits = 128\n", 'orbits = 128\ngroup = "middle"\n')
        (self.dir / "run.toml").write_text(text)
        line = text.splitlines().index('group = "middle"') + 1
        r = run(self.dir, "run", "run.toml", "--set", "ensemble.kind=file", "--set",
                "ensemble.path=earlier.h5", "--quiet")
        self.refused(r, 2, f"run.toml:{line}: [ensemble] group must be")
        self.assertNotIn(":0:", r.stderr)

    # A drift that cannot be measured is never reported as a number.
    def test_info_reports_an_invariant_that_is_not_a_number(self):
        r = run(self.dir, *self.small())
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(self.dir / "out.h5", "r+") as f:
            initial = f["invariants/I1/initial"]
            initial[...] = np.full(initial.shape, np.nan)
        r = run(self.dir, "info", "out.h5")
        self.assertEqual(r.returncode, 0, r.stderr)
        line = next(l for l in r.stdout.splitlines() if l.strip().startswith("I1"))
        self.assertIn("worst nan", line)
        self.assertIn("(64 of 64 orbits' I1 is not a number: no drift can be measured)", line)


if __name__ == "__main__":
    unittest.main()
