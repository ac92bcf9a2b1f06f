#!/usr/bin/python3
"""MPI ranks against threads, in one run of this script: the default preset (suris.toml, per-orbit
output on), --orbits orbits per worker.
  weak scaling  1 process x 1 thread on n orbits, then 2 on 2n as 1 process x 2 threads and as
                2 ranks x 1 thread (mpirun): each efficiency is rate(2) / (2 rate(1)), from the
                runs' own summary lines (particle-steps/s, the items_per_second of the C++
                benchmarks); the target is ranks' efficiency >= 0.9 x the threads'
  writing       the file of the 2n orbits written by 2 ranks together (parallel HDF5) and by one
                process: MB/s from the file's size and the summary's writing time
The three runs alternate --repetitions times; the figures are medians.
Run from a build: bench/mpi_bench.py [--qmaps build/qmaps] [--orbits N] [--steps N] [--json F]"""
import argparse
import json
import os
import pathlib
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
RATE = re.compile(r"\(([0-9.e+]+) particle-steps/s")
WRITING = re.compile(r"writing ([0-9.]+) s")
# mpirun as root, oversubscribed where the machine has fewer cores than ranks.
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}


def run(command, directory, out):
    """One run into `out`: its rate, writing time (s) and file size (bytes)."""
    r = subprocess.run(list(map(str, command)), cwd=directory, text=True, capture_output=True,
                       env={**os.environ, **MPI_ENV})
    if r.returncode != 0:
        sys.exit(f"{' '.join(map(str, command))}: exit {r.returncode}\n{r.stderr}")
    size = (directory / out).stat().st_size
    (directory / out).unlink()
    return float(RATE.search(r.stderr).group(1)), float(WRITING.search(r.stderr).group(1)), size


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--qmaps", default=str(ROOT / "build" / "qmaps"))
    parser.add_argument("--orbits", type=int, default=1_000_000, help="orbits per worker")
    parser.add_argument("--steps", type=int, default=500)
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--json", help="also write the figures as JSON")
    args = parser.parse_args()
    mpirun = shutil.which("mpirun")
    if not mpirun:
        sys.exit("mpirun is not on PATH (Debian: openmpi-bin)")
    preset = ROOT / "ensembles" / "presets" / "suris.toml"

    def command(orbits, threads, out):
        return [args.qmaps, "run", preset, "--set", f"ensemble.orbits={orbits}", "--set",
                f"run.steps={args.steps}", "--threads", threads, "--quiet", "--out", out]

    n = args.orbits
    cases = {
        "1 process x 1 thread": command(n, 1, "one.h5"),
        "1 process x 2 threads": command(2 * n, 2, "threads.h5"),
        "2 ranks x 1 thread": [mpirun, "--oversubscribe", "-np", 2, *command(2 * n, 1, "ranks.h5")],
    }
    outs = {"1 process x 1 thread": "one.h5", "1 process x 2 threads": "threads.h5",
            "2 ranks x 1 thread": "ranks.h5"}
    samples = {name: [] for name in cases}
    with tempfile.TemporaryDirectory(dir=".") as tmp:
        for _ in range(args.repetitions):
            for name, c in cases.items():
                samples[name].append(run(c, pathlib.Path(tmp), outs[name]))
    median = {name: [statistics.median(s[k] for s in rows) for k in range(3)]
              for name, rows in samples.items()}
    one = median["1 process x 1 thread"][0]
    threads, ranks = median["1 process x 2 threads"], median["2 ranks x 1 thread"]
    figures = {
        "orbits_per_worker": n, "steps": args.steps,
        "rate": {name: m[0] for name, m in median.items()},
        "threads_efficiency": threads[0] / (2 * one),
        "ranks_efficiency": ranks[0] / (2 * one),
        "serial_write_MBps": threads[2] / threads[1] / 1e6,
        "collective_write_MBps": ranks[2] / ranks[1] / 1e6,
        "file_MB": ranks[2] / 1e6,
    }
    figures["ranks_over_threads"] = figures["ranks_efficiency"] / figures["threads_efficiency"]
    print(f"Suris preset, {n} orbits per worker x {args.steps} steps, medians of "
          f"{args.repetitions}:")
    for name, m in median.items():
        print(f"  {name:22s} {m[0]:.3g} particle-steps/s, writing {m[1]:.3f} s, "
              f"{m[2] / 1e6:.0f} MB")
    print(f"  weak scaling 1 -> 2: threads {figures['threads_efficiency']:.3f}, ranks "
          f"{figures['ranks_efficiency']:.3f}, ranks / threads {figures['ranks_over_threads']:.3f}")
    print(f"  writing the 2n-orbit file: 1 process {figures['serial_write_MBps']:.0f} MB/s, "
          f"2 ranks together {figures['collective_write_MBps']:.0f} MB/s")
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(figures, indent=1) + "\n")


if __name__ == "__main__":
    main()
