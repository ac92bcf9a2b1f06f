#!/usr/bin/python3
"""Peer: the Suris map as a Python user writes it, NumPy vectorised over the orbits, one thread.

    D = 1 + g (y1² + y2²),  z1 = two_a y1 / D − x1,  z2 = two_b y2 / D − x2   (kernels/suris.hpp)

Same parameters as bench/bench_maps.hpp. Before timing, a few orbits are checked against
`qmaps orbit` (the scalar reference path). Prints one JSON object: particle_steps_per_second
(median of the repetitions), orbits, steps, the agreement.

    numpy_suris.py --qmaps build/qmaps [--orbits N] [--steps S] [--repetitions R]
"""
import argparse
import json
import statistics
import subprocess
import sys
import time

import numpy as np

PARAMS = {"A": 0.7, "B": 0.3, "alpha": 0.9, "h": 0.1}
TOLERANCE = 1e-10


def coefficients():
    h2 = PARAMS["h"] * PARAMS["h"]
    return 2 * (1 - PARAMS["A"] * h2), 2 * (1 - PARAMS["B"] * h2), 2 * PARAMS["alpha"] * h2


def step(state, steps):
    """Advances state = [q1_n, q2_n, q1_{n+1}, q2_{n+1}] (arrays) by `steps` steps."""
    two_a, two_b, g = coefficients()
    x1, x2, y1, y2 = state
    for _ in range(steps):
        inv = 1.0 / (1.0 + g * (y1 * y1 + y2 * y2))
        x1, x2, y1, y2 = y1, y2, two_a * y1 * inv - x1, two_b * y2 * inv - x2
    return [x1, x2, y1, y2]


def start(points):
    """The Euler start of qmaps (q_1 = q_0 + h p) from rows (q1, q2, p1, p2)."""
    h = PARAMS["h"]
    return [points[:, 0], points[:, 1], points[:, 0] + h * points[:, 2], points[:, 1] + h * points[:, 3]]


def check(qmaps, steps=1000):
    """Largest difference of q at step `steps` from `qmaps orbit`, relative to max(1, |q|)."""
    points = np.array([[0.3, -0.2, 0.1, 0.4], [-0.45, 0.1, -0.3, 0.2], [0.05, 0.49, 0.5, -0.5]])
    final = step(start(points), steps)
    worst = 0.0
    for i, p in enumerate(points):
        command = [qmaps, "orbit", "--map", "suris", "--ic", ",".join(repr(float(v)) for v in p),
                   "--start", "euler", "--steps", str(steps), "--every", str(steps)]
        for name, value in PARAMS.items():
            command += ["--set", f"{name}={value!r}"]
        rows = subprocess.run(command, check=True, capture_output=True, text=True).stdout.split()
        last = rows[-1].split(",")  # n, q1, q2, p1, p2, invariants
        if int(last[0]) != steps:
            sys.exit(f"numpy_suris: qmaps orbit did not reach step {steps}: {rows[-1]}")
        for k in (0, 1):
            q = float(last[1 + k])
            worst = max(worst, abs(final[k][i] - q) / max(1.0, abs(q)))
    return worst


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--qmaps", required=True, help="the qmaps executable, for the check")
    parser.add_argument("--orbits", type=int, default=1 << 18)
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--repetitions", type=int, default=5)
    args = parser.parse_args()

    difference = check(args.qmaps)
    if not difference <= TOLERANCE:
        sys.exit(f"numpy_suris: differs from qmaps by {difference:.3g} (tolerance {TOLERANCE:g})")
    rng = np.random.default_rng(1)
    state = start(rng.uniform(-0.5, 0.5, size=(args.orbits, 4)))
    rates = []
    for _ in range(args.repetitions):
        t0 = time.perf_counter()
        state = step(state, args.steps)
        rates.append(args.orbits * args.steps / (time.perf_counter() - t0))
    print(json.dumps({"peer": "numpy", "particle_steps_per_second": statistics.median(rates),
                      "orbits": args.orbits, "steps": args.steps, "threads": 1,
                      "repetitions": args.repetitions, "numpy": np.__version__,
                      "agreement": f"max relative difference to qmaps orbit {difference:.3g} "
                                   f"after 1000 steps of {3} orbits (tolerance {TOLERANCE:g})"}))


if __name__ == "__main__":
    main()
