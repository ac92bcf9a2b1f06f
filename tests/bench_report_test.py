#!/usr/bin/python3
"""bench/report --smoke on tiny sizes: its JSON rows have exactly the documented keys and types,
and every map appears on the scalar path and on every ISA compiled and supported here, on 1 and 2
threads; every peer appears; the default preset's peer appears on each of its ISAs the CPU has, on
1 and 2 threads, in the rows and in the report's table against qmaps' preset. Speeds are not
checked.

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
PRESET_ISAS = ("avx512", "avx2")  # bench/peers/preset_isa.cpp's
PRESET_TABLE = "against its hand-written peer"  # in the heading of the report's table


def table_after(report, heading):
    """The rows of the first markdown table after the line containing `heading`: their cells."""
    lines = report.splitlines()
    start = next((i for i, line in enumerate(lines) if heading in line), None)
    if start is None:
        return []
    rows = []
    for line in lines[start + 1:]:
        if not line.strip() and rows:
            break
        if line.startswith("|") and not line.startswith("|---"):
            rows.append([c.strip() for c in line.strip().strip("|").split("|")])
    return rows[1:]  # past the header


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
    preset_isas = [i for i in PRESET_ISAS if CPU_FLAGS[i] <= flags]
    preset = {(r.get("path"), r.get("threads")) for r in rows
              if isinstance(r, dict) and r.get("map") == "peer-preset" and r.get("observers")}
    table = {(c[0], c[1]): c for c in table_after((out / "report.md").read_text(), PRESET_TABLE)
             if len(c) == 7}
    for i in preset_isas:
        for t in (1, 2):
            if (i, t) not in preset:
                errors.append(f"no row for peer-preset on {i}, {t} thread(s)")
            # qmaps' preset, the peer and their ratio, each a number
            cells = table.get((i, str(t)), [])
            if not cells or any(c == "–" for c in cells[2:5]):
                errors.append(f"the preset's table has no figures for {i}, {t} thread(s): {cells}")
    for e in errors:
        print(e, file=sys.stderr)
    print(f"{len(rows)} rows; maps {args.maps}; paths scalar + {isas}; preset peer on "
          f"{preset_isas}")
    sys.exit(1 if errors else 0)


if __name__ == "__main__":
    main()
