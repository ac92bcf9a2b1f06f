"""A run continued from an earlier run's final state (`[ensemble] kind = "file"`, `group =
"final"`) as docs/cli.md documents it: its states are bit for bit those of one longer run, while its
clock (steps, `time`, `/final/t`, a trajectory's `step` and `t`) restarts at 0, except case3's
physical time, which is part of its state."""
import pathlib
import re
import tempfile
import unittest

import h5py
import numpy as np

import small_run

FIRST, MORE, EVERY = 100, 100, 50
TRAJECTORY = f"""
[[trajectory]]
name = "tr"
first = 2
every = {EVERY}
"""
STATE_DATASETS = ("final/q1", "final/q2", "final/p1", "final/p2")


def continuation_preset(directory, preset, earlier):
    """`preset` with its [ensemble] replaced by the final state of the file `earlier`."""
    text = re.sub(r"^\[ensemble\]\n.*?\n(?=\n)",
                  f'[ensemble]\nkind = "file"\npath = "{earlier}"\ngroup = "final"\n',
                  preset.read_text(), count=1, flags=re.S | re.M)
    path = directory / f"continue-{preset.name}"
    path.write_text(text)
    return path


def rows_from(f, first_step):
    """The trajectory's rows (step, t, q1) of steps ≥ first_step, orbit by orbit."""
    g = f["trajectories/tr"]
    keep = g["step"][()] >= first_step
    return g["step"][()][keep], g["t"][()][keep], g["q1"][()][keep]


class ContinuedRun(unittest.TestCase):
    def runs(self, preset, orbits):
        """The longer run, and the continuation of the first FIRST steps by MORE, as h5py files."""
        directory = pathlib.Path(self.tmp.name) / preset.stem
        directory.mkdir()
        run = lambda **kw: small_run.small_run(directory, preset=kw.pop("preset", preset),
                                               extra=TRAJECTORY, **kw)
        longer = run(orbits=orbits, steps=FIRST + MORE, name="longer.h5")
        run(orbits=orbits, steps=FIRST, name="first.h5")
        continued = run(orbits=None, steps=MORE, name="continued.h5",
                        preset=continuation_preset(directory, preset, "first.h5"))
        return h5py.File(longer), h5py.File(continued)

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def check_states(self, longer, continued):
        names = [*STATE_DATASETS, *(f"final/state/{k}" for k in longer["final/state"]),
                 *(f"invariants/{k}/final" for k in longer["invariants"] if k != "image")]
        for name in names:
            self.assertEqual(longer[name][()].tobytes(), continued[name][()].tobytes(), name)
        _, _, longer_q1 = rows_from(longer, FIRST)
        _, _, continued_q1 = rows_from(continued, 0)
        self.assertEqual(longer_q1.tobytes(), continued_q1.tobytes())

    def test_suris_states_continue_and_its_clock_restarts(self):
        longer, continued = self.runs(small_run.PRESET, orbits=200)
        with longer, continued:
            self.check_states(longer, continued)
            h = continued.attrs["param.h"]
            self.assertEqual(continued.attrs["steps"], MORE)
            self.assertEqual(continued["final/state"].attrs["step"], MORE)
            self.assertEqual(continued.attrs["time"], MORE * h)
            self.assertTrue(np.all(continued["final/t"][()] == MORE * h))
            self.assertEqual(longer.attrs["time"], (FIRST + MORE) * h)
            step, t, _ = rows_from(continued, 0)
            self.assertEqual(sorted(set(step)), list(range(0, MORE + 1, EVERY)))
            np.testing.assert_array_equal(t, step * h)

    def test_case3_keeps_its_physical_time(self):
        longer, continued = self.runs(small_run.PRESET.with_name("case3.toml"), orbits=200)
        with longer, continued:
            self.check_states(longer, continued)
            self.assertNotIn("time", continued.attrs)
            self.assertEqual(continued["final/state"].attrs["step"], MORE)
            self.assertEqual(longer["final/t"][()].tobytes(), continued["final/t"][()].tobytes())
            longer_step, longer_t, _ = rows_from(longer, FIRST)
            step, t, _ = rows_from(continued, 0)
            np.testing.assert_array_equal(step, longer_step - FIRST)
            self.assertEqual(t.tobytes(), longer_t.tobytes())


if __name__ == "__main__":
    unittest.main()
