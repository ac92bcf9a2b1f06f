"""What the documentation says of the program and the package, checked against them:

- docs/cli.md's synopsis names every command of `qmaps --help` and every option of each
  command's --help (a line ending in "..." may leave some out), and nothing they lack;
- `qmaps check` is named for what it does (invariant drift and reversibility), and its report
  names the invariants it checked: H alone on the chaotic flow, which it passes;
- `qmaps orbit --help` names every column --chaos adds;
- the flow's default order is the one docs/maps.md advises at every preset's step (order 8 wins
  only below the h it gives) and states, and the one the flow presets use;
- GALI's deviations, and the spectrum's, start as the unit vectors (docs/chaos.md);
- a sweep's point k takes its axes' values by index, the first axis slowest (docs/sweeps.md);
- pandas reads `qmaps orbit`'s 17 digits exactly with float_precision="round_trip" (docs/cli.md);
- `import qmaps` reaches qmaps.plot, without importing matplotlib before it is used.
"""
import io
import re
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import small_run

DOCS = small_run.SOURCE_DIR / "docs"
PRESETS = small_run.SOURCE_DIR / "ensembles" / "presets"
SURIS = ["--set", "A=0.7", "--set", "B=0.3", "--set", "alpha=0.9", "--set", "h=0.1"]
CHAOTIC_FLOW = ["--set", "A=0", "--set", "B=0", "--set", "alpha=0.25", "--set", "beta=0.25",
                "--set", "delta=3", "--set", "h=0.05"]


def help_text(*command):
    r = small_run.qmaps(".", *command, "--help")
    assert r.returncode == 0, r.stderr
    return r.stdout


def help_options(text):
    """The long options a --help text lists, but --help."""
    return set(re.findall(r"^\s+(?:-\w,)?(--[\w-]+)", text, re.M)) - {"--help"}


def subcommands(text):
    """The subcommands of `qmaps --help`, with their one-line descriptions."""
    section = text.split("Subcommands:", 1)[1]
    return dict(re.findall(r"^  (\w[\w-]*)\s{2,}(.+)$", section, re.M))


def synopsis():
    """docs/cli.md's synopsis: for each command, the options its lines name and whether a line
    of it ends in "..." (leaving options out)."""
    block = re.search(r"^```\n(.*?)^```", (DOCS / "cli.md").read_text(), re.M | re.S).group(1)
    commands = {}
    for line in block.splitlines():
        words = line.split()
        if len(words) < 2 or words[1].startswith("-"):
            continue  # qmaps --help | --version
        options, abridged = commands.setdefault(words[1], (set(), False))
        commands[words[1]] = (options | set(re.findall(r"(--[\w-]+)", line)),
                              abridged or line.rstrip().endswith("..."))
    return commands


def prose(page):
    """The text of `page` (a docs/*.md) with its line breaks and runs of spaces as one space."""
    return " ".join((DOCS / page).read_text().split())


def section_of(page, heading):
    """The text of `page` (a docs/*.md) under the heading that starts with `heading`."""
    text = (DOCS / page).read_text()
    start = text.index("\n" + heading)
    end = text.find("\n## ", start + 1)
    return text[start:end if end >= 0 else None]


class Documented(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def run_ok(self, *args):
        r = small_run.qmaps(self.dir, *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        return r.stdout

    def test_the_synopsis_names_every_command_and_option_of_the_help(self):
        commands = subcommands(help_text())
        documented = synopsis()
        self.assertEqual(set(documented), set(commands))
        for command, (options, abridged) in documented.items():
            with self.subTest(command=command):
                helped = help_options(help_text(command))
                self.assertLessEqual(options, helped, "the synopsis names options the help lacks")
                if not abridged:
                    self.assertEqual(options, helped)

    def test_check_is_named_for_what_it_does_and_names_what_it_checked(self):
        summary = subcommands(help_text())["check"].strip()
        self.assertEqual(help_text("check").splitlines()[0], summary)
        self.assertIn("drift and reversibility", summary)
        check = section_of("cli.md", "## `qmaps check")
        self.assertIn(summary.lower(), check.lower())
        self.assertIn("invariants checked:", check)
        for page in (small_run.SOURCE_DIR / "README.md", DOCS / "cli.md"):
            self.assertNotIn("integrability report", page.read_text(), page.name)
        small = ["--orbits", "50", "--steps", "100"]
        for args, invariants in ((["suris", *SURIS], ["H", "I1", "I2"]),
                                 (["flow", *CHAOTIC_FLOW], ["H"])):
            with self.subTest(map=args[0]):
                out = self.run_ok("check", "--map", *args, *small)
                named = re.search(r"^invariants checked: (.*?) \(", out, re.M)
                self.assertIsNotNone(named, out)
                self.assertEqual(named.group(1).split(", "), invariants)
                rows = out.split("worst\n", 1)[1].split("reversibility:", 1)[0].split("\n")
                self.assertEqual([row.split()[0] for row in rows if row.strip()], invariants)

    def test_orbit_help_names_every_column_chaos_adds(self):
        base = ["orbit", "--map", "suris", *SURIS, "--ic", "0.1,0.2,0.3,0.4", "--steps", "1"]
        plain = self.run_ok(*base).splitlines()[0].split(",")
        chaos = self.run_ok(*base, "--chaos").splitlines()[0].split(",")
        self.assertEqual(chaos[:len(plain)], plain)
        described = next(line for line in help_text("orbit").splitlines() if "--chaos" in line)
        named = set(re.findall(r"\b[a-z]+(?:_\d)?\b", described))
        spans = re.findall(r"\b(\w+)_(\d) to \1_(\d)\b", described)
        named |= {f"{stem}_{k}" for stem, first, last in spans
                  for k in range(int(first), int(last) + 1)}
        added = chaos[len(plain):]
        self.assertTrue(added)
        self.assertLessEqual(set(added), named, described)

    def test_the_flows_default_order_is_the_one_the_docs_advise(self):
        listed = self.run_ok("list")
        flow = listed[listed.index("\nflow:"):]
        default = int(re.search(r"^\s+order\s.*\(default (\d+)\)$", flow, re.M).group(1))
        row = f"| `flow` | any | A, B, alpha, beta, delta, h, order ({default}) |"
        self.assertTrue(row in (DOCS / "maps.md").read_text(), f"docs/maps.md lacks {row}")
        flow_section = section_of("maps.md", "## 8.")
        stated = f"order ∈ {{2, 4, 6, 8}} (default {default}"
        self.assertTrue(stated in flow_section, f"docs/maps.md §8 lacks {stated}")
        # "order 8 wins only below h ≈ 1/140": above it the advice is order 6
        below = int(re.search(r"order 8 wins only below h ≈ 1/(\d+)", flow_section).group(1))
        presets = [p for p in sorted(PRESETS.glob("*.toml"))
                   if re.search(r'^name = "flow"$', p.read_text(), re.M)]
        self.assertTrue(presets)
        for preset in presets:
            with self.subTest(preset=preset.name):
                text = preset.read_text()
                h = float(re.search(r"^h = (\S+)$", text, re.M).group(1))
                self.assertGreater(h, 1 / below)
                self.assertEqual(int(re.search(r"^order = (\d+)$", text, re.M).group(1)), default)
        self.assertEqual(default, 6)

    def test_gali_and_the_spectrum_start_from_the_unit_vectors(self):
        import h5py
        text = prose("chaos.md")
        self.assertIn("GALI's four deviations (`w5` … `w8`", text)
        self.assertIn("as the spectrum's (`w1` … `w4`) do, as the unit vectors e_1 … e_4", text)
        out = small_run.small_run(self.dir, orbits=3, steps=0, extra="[chaos]\nspectrum = true\n")
        with h5py.File(out) as f:
            state = f["final/state"]
            components = ["q1_n", "q2_n", "q1_n+1", "q2_n+1"]
            for first in (1, 5):
                for j in range(4):
                    vector = [state[f"w{first + j}.{c}"][0] for c in components]
                    self.assertEqual(vector, [float(k == j) for k in range(4)], (first, j))

    def test_a_sweeps_point_takes_its_axes_values_by_index(self):
        import h5py
        self.assertIn("point k of a 16 × 25 grid (from 0) takes the first axis's value of index "
                      "⌊k / 25⌋ and the second's of index k mod 25", prose("sweeps.md"))
        axes = {"A": [0.5, 0.6], "alpha": [0.7, 0.8, 0.9]}
        extra = "".join(f'\n[[sweep]]\nparameter = "{name}"\nvalues = {values}\n'
                        for name, values in axes.items())
        (self.dir / "sweep.toml").write_text(
            re.sub(r"\n\[invariant_image\].*", "\n", small_run.PRESET.read_text(), flags=re.S)
            + extra)
        self.run_ok("run", "sweep.toml", "--set", "ensemble.orbits=4", "--set", "run.steps=2",
                    "--out", "sweep.h5", "--quiet")
        with h5py.File(self.dir / "sweep.h5") as f:
            for k in range(6):
                self.assertEqual(f["sweep/parameters/A"][k], axes["A"][k // 3], k)
                self.assertEqual(f["sweep/parameters/alpha"][k], axes["alpha"][k % 3], k)

    def test_pandas_reads_the_orbit_csv_exactly_with_round_trip(self):
        try:
            import pandas
        except ImportError:
            self.skipTest("pandas is not installed")
        self.assertIn('float_precision="round_trip"', section_of("cli.md", "## `qmaps orbit`"))
        text = self.run_ok("orbit", "--map", "suris", *SURIS, "--ic", "0.3,-0.2,0.1,0.4",
                           "--steps", "500", "--chaos")
        rows = [line.split(",") for line in text.splitlines()]
        table = pandas.read_csv(io.StringIO(text), float_precision="round_trip")
        for i, row in enumerate(rows[1:]):
            for j, value in enumerate(row):
                exact, read = float(value), float(table.iat[i, j])
                self.assertTrue(exact == read or (exact != exact and read != read),
                                (rows[0][j], i, value, read))

    def test_import_qmaps_reaches_plot_without_importing_matplotlib_first(self):
        code = ("import sys, qmaps\n"
                "assert 'matplotlib' not in sys.modules, 'import qmaps imported matplotlib'\n"
                "assert callable(qmaps.plot.plot) and callable(qmaps.plot.main)\n"
                "assert 'matplotlib' in sys.modules\n")
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
