#!/usr/bin/python3
"""bench/report --smoke on tiny sizes: its JSON rows have exactly the documented keys and types,
and every map appears on the scalar path and on every ISA compiled and supported here, on 1 and 2
threads; every peer appears. Speeds are not checked.

    bench_report_test.py REPORT BUILD_DIR OUT_DIR --qmaps BINARY --isas I...

The maps are those `qmaps list` names (kernels/maps.hpp).
"""
import argparse
import json
import math
import pathlib
import subprocess
import sys

KEYS = {"map", "path", "threads", "orbits", "steps", "observers", "particle_steps_per_second"}
CPU_FLAGS = {"sse2": {"sse2"}, "avx2": {"avx2", "fma"}, "avx512": {"avx512f"}}
PEERS = {"peer-limit", "peer-naive", "peer-eigen", "peer-numpy"}


def cpu_flags():
    for line in open("/proc/cpuinfo"):
        if line.startswith("flags"):
            return set(line.split(":", 1)[1].split())
    return set()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("report")
    parser.add_argument("build_dir")
    parser.add_argument("out_dir")
    parser.add_argument("--qmaps", required=True)
    parser.add_argument("--isas", nargs="+", required=True)
    args = parser.parse_args()
    listing = subprocess.run([args.qmaps, "list"], check=True, capture_output=True, text=True)
    args.maps = [line.split(":", 1)[0] for line in listing.stdout.splitlines()
                 if line and not line[0].isspace()]
    out = pathlib.Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rows_file = out / "smoke.json"
    rows_file.unlink(missing_ok=True)
    subprocess.run(["/usr/bin/python3", args.report, "--smoke", "--build-dir", args.build_dir,
                    "--out-dir", str(out), "--json", str(rows_file)], check=True,
                   stdout=subprocess.DEVNULL)
    rows = json.loads(rows_file.read_text())
    errors = []
    if not isinstance(rows, list) or not rows:
        sys.exit("the JSON is not a non-empty list")
    for r in rows:
        if not isinstance(r, dict) or set(r) != KEYS:
            errors.append(f"keys {sorted(r) if isinstance(r, dict) else r} are not {sorted(KEYS)}")
            continue
        ok = (isinstance(r["map"], str) and isinstance(r["path"], str)
              and all(isinstance(r[k], int) and not isinstance(r[k], bool) and r[k] > 0
                      for k in ("threads", "orbits", "steps"))
              and (r["observers"] is False or (isinstance(r["observers"], str) and r["observers"]))
              and isinstance(r["particle_steps_per_second"], float)
              and math.isfinite(r["particle_steps_per_second"])
              and r["particle_steps_per_second"] > 0)
        if not ok:
            errors.append(f"bad values in {r}")
    flags = cpu_flags()
    isas = [i for i in args.isas if CPU_FLAGS[i] <= flags]
    seen = {(r.get("map"), r.get("path"), r.get("threads")) for r in rows
            if isinstance(r, dict) and r.get("observers") is False}
    for m in args.maps:
        wanted = [(m, "scalar", 1)] + [(m, i, t) for i in isas for t in (1, 2)]
        errors += [f"no row for map {w[0]}, path {w[1]}, {w[2]} thread(s)" for w in wanted
                   if w not in seen]
    errors += [f"no row for {p}" for p in PEERS if p not in {s[0] for s in seen}]
    if not any(isinstance(r, dict) and r.get("observers") for r in rows):
        errors.append("no row with observers")
    for e in errors:
        print(e, file=sys.stderr)
    print(f"{len(rows)} rows; maps {args.maps}; paths scalar + {isas}")
    sys.exit(1 if errors else 0)


if __name__ == "__main__":
    main()
