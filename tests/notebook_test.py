"""docs/notebooks/quickstart.ipynb runs from top to bottom in a fresh kernel (nbclient, with the
build tree's package) and shows what it says: the run's summary, a section of the orbits of an 8 x 8 grid on one energy shell, a
density, a map written as formulas (Henon-Heiles' leapfrog) with its section coloured by MEGNO, and the
two maps' energy errors, the integrable map's own invariant kept to round-off; and its stored
outputs, which the documentation site shows, are those it shows now."""
import importlib.machinery
import importlib.util
import re
import sys
import unittest

import nbformat

import small_run

NOTEBOOK = small_run.SOURCE_DIR / "docs" / "notebooks" / "quickstart.ipynb"
# tools/notebook-outputs runs the notebooks as this test does, and stores their outputs.
_loader = importlib.machinery.SourceFileLoader("notebook_outputs",
                                               str(small_run.TOOLS / "notebook-outputs"))
notebook_outputs = importlib.util.module_from_spec(
    importlib.util.spec_from_loader("notebook_outputs", _loader))
_loader.exec_module(notebook_outputs)


def text_of(cell):
    return "".join(o.get("text", "") for o in cell.get("outputs", []) if o["output_type"] == "stream")


class Quickstart(unittest.TestCase):
    def test_it_runs_and_shows_each_result(self):
        notebook = notebook_outputs.executed(NOTEBOOK, small_run.PACKAGE_DIR)
        code = [c for c in notebook.cells if c.cell_type == "code"]
        for cell in code:
            self.assertFalse([o for o in cell.outputs if o["output_type"] == "error"], cell.source)
        figures = [c for c in code if any("image/png" in o.get("data", {}) for o in c.outputs)]
        self.assertEqual(len(figures), 4)  # the section, the density, the formula map's section, the energy errors
        written = text_of(figures[2])
        points, chaotic = re.search(r"^(\d+) section points; chaotic \(MEGNO > 4\): (\d+)%", written, re.M).groups()
        self.assertGreater(int(points), 300 * 20)  # every orbit crosses many times
        self.assertTrue(5 <= int(chaotic) <= 95, written)  # tori and a chaotic sea
        summary = text_of(code[1])
        self.assertIn("particle-steps/s", summary)
        orbits, points = map(int, re.search(r"^(\d+) orbits, (\d+) section points", summary, re.M).groups())
        self.assertTrue(30 <= orbits <= 64)  # the 8 x 8 grid's points on the shell
        self.assertGreater(points, orbits * 100)
        errors = dict(re.findall(r"^(\w+): largest energy error (\S+)", text_of(code[-1]), re.M))
        own = float(re.search(r"its own invariant H (\S+)", text_of(code[-1])).group(1))
        print({k: float(v) for k, v in errors.items()}, "own", own)
        self.assertEqual(sorted(errors), ["leapfrog", "suris"])
        self.assertTrue(all(0 < float(v) < 1e-2 for v in errors.values()))
        self.assertLess(own, 1e-12)  # H about 0.1, 2000 rows
        # The outputs stored for the documentation site are the ones it shows now.
        stored = nbformat.read(NOTEBOOK, as_version=4)
        self.assertEqual(shown(stored), shown(notebook),
                         "the notebook's stored outputs are stale: tools/notebook-outputs")


def shown(notebook):
    """Each code cell's outputs: their kinds, their text and whether each is a figure. The engine's
    log (its "qmaps: " lines: time, rate, ISA, threads, temporary file) is the machine's."""
    def text(output):
        return [line for line in output.get("text", "").splitlines()
                if not line.startswith("qmaps: ")]
    return [[(o["output_type"], o.get("name"), text(o), "image/png" in o.get("data", {}))
             for o in cell.outputs] for cell in notebook.cells if cell.cell_type == "code"]


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
