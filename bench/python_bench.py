#!/usr/bin/python3
"""The Python package against the program, in one process and one run of this script:
  run    qmaps.run in process against `qmaps run` as a subprocess, the same configuration (the
         default preset, --orbits and --steps): each one's stepping rate from its own summary line
         (particle-steps/s, the items_per_second of the C++ benchmarks) and its whole time,
         alternated --repetitions times; medians and their ratio
  orbit  qmaps.orbit over 10^6 steps of Suris' map, keeping every 1000th row and every row
Run from a build: PYTHONPATH=build/python bench/python_bench.py [--qmaps build/qmaps] [--json F]"""
import argparse
import json
import os
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile
import time

import qmaps

ROOT = pathlib.Path(__file__).resolve().parent.parent
RATE = re.compile(r"\(([0-9.e+]+) particle-steps/s")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--qmaps", default=str(ROOT / "build" / "qmaps"))
    parser.add_argument("--orbits", type=int, default=1_000_000)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--json", help="also write the rows as JSON")
    args = parser.parse_args()
    preset = ROOT / "ensembles" / "presets" / "suris.toml"
    sets = {"ensemble": {"orbits": args.orbits}, "run": {"steps": args.steps}}
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        cli, python = [], []
        for _ in range(args.repetitions):
            began = time.perf_counter()
            r = subprocess.run([args.qmaps, "run", str(preset), "--set",
                                f"ensemble.orbits={args.orbits}", "--set", f"run.steps={args.steps}",
                                "--threads", str(args.threads), "--out", f"{tmp}/cli.h5"],
                               capture_output=True, text=True, check=True)
            cli.append((float(RATE.search(r.stderr).group(1)), time.perf_counter() - began))
            began = time.perf_counter()
            with qmaps.run(preset, threads=args.threads, tmpdir=tmp, **sets) as run:
                python.append((float(RATE.search(run.log).group(1)), time.perf_counter() - began))
        for name, samples in (("qmaps run", cli), ("qmaps.run", python)):
            rows.append({"name": f"run/{name}", "items_per_second": statistics.median(s[0] for s in samples),
                         "seconds": statistics.median(s[1] for s in samples)})
    for every in (1000, 1):
        times = []
        for _ in range(args.repetitions):
            began = time.perf_counter()
            qmaps.orbit("suris", {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1}, (0.1, 0.2, 0.0, 0.1),
                        steps=1_000_000, every=every, frame=False)
            times.append(time.perf_counter() - began)
        t = statistics.median(times)
        rows.append({"name": f"orbit/every:{every}", "items_per_second": 1e6 / t, "seconds": t})
    print(f"{args.orbits} orbits x {args.steps} steps of {preset.name}, "
          f"threads {args.threads}, medians of {args.repetitions}")
    for row in rows:
        print(f"  {row['name']:<20} {row['items_per_second']:10.3g} particle-steps/s  "
              f"{row['seconds']:8.3f} s")
    ratio = rows[1]["items_per_second"] / rows[0]["items_per_second"]
    whole = rows[0]["seconds"] / rows[1]["seconds"]
    print(f"  qmaps.run / qmaps run: stepping {ratio:.3f}x, whole run {whole:.3f}x (time ratio)")
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps({"benchmarks": rows}, indent=1))


if __name__ == "__main__":
    sys.exit(main())
