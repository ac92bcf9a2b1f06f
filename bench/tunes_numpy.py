#!/usr/bin/python3
"""Peer of the tunes: what a NumPy user without [tunes] writes, one thread, against tunes_bench.

    stepping  Suris' map by bench/peers/numpy_suris.py (its step and its Euler start
              q_1 = q_0 + h p; tunes_bench starts by Taylor, which changes no cost), all orbits
              at once, q1, q2 of steps 1 .. 2N kept: windows 1 .. N and N + 1 .. 2N
    NAFF      per window and signal x_n (q1 or q2), as core/observers/tunes/naff.hpp:
                y_n = w_n x_n, w_n = sin^(2p)(π n/N),  F(ω) = Σ_n y_n e^{−iωm}, m = n − (N − 1)/2;
              the peak bin of |numpy.fft.rfft(y)| over k = 1 .. N/2 − 1, moved by the ratio r of
              its larger neighbour, δ = ((p + 1) r − p)/(1 + r) bins; then Newton's steps on |F|²
              with F, S1 = Σ m y e^{−iωm}, S2 = Σ m² y e^{−iωm} (all orbits still moving at once),
                g'/2 = Re F Im S1 − Im F Re S1,   g''/2 = |S1|² − Re(conj F S2),
              each at most half a bin, folded into [0, π], until a step is below 1e-7 bins;
              ν = ω/2π in [0, 1/2], and D = log10 ‖ν(second) − ν(first)‖ (at least log10 2⁻⁵³)

Same parameters and box [−0.5, 0.5]⁴ as tunes_bench (bench/bench_maps.hpp). Times, each the
median of --repetitions: (a) the stepping of 2N steps with q1, q2 kept, (b) the analysis of both
windows; rates in orbit-steps/s (orbits × 2N per second, tunes_bench's items_per_second) and
microseconds per orbit. Memory: orbits × 2N × 2 doubles. --check first measures orbits of the
linear map (α = 0), whose tunes are arccos(1 − A h²)/2π and arccos(1 − B h²)/2π, and stops if
the largest error exceeds 1e-11.

    tunes_numpy.py [--orbits 4096] [--window 2048] [--repetitions 3] [--check] [--json F]
"""
import argparse
import json
import os
import pathlib
import statistics
import sys
import time

for variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(variable, "1")  # the peer runs on one thread, as numpy_suris

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent / "peers"))
import numpy_suris  # noqa: E402

ORDER = 2           # the Hann window's, as [tunes]' default
TOLERANCE = 1e-7    # Newton's last step, in bins
MOST_STEPS = 16     # as naff.hpp
CHUNK = 512         # signals analysed at once: 8 MB temporaries at N = 2048
CHECK_TOLERANCE = 1e-11
FLOOR = np.log10(2.0 ** -53)


def record(points, window):
    """q1, q2 after steps 1 .. 2 window of the orbits (rows of points): array [step, d, orbit]."""
    state = numpy_suris.start(points)
    q = np.empty((2 * window, 2, len(points)))
    for n in range(2 * window):
        state = numpy_suris.step(state, 1)  # state = [q_n, q_{n+1}]
        q[n, 0] = state[0]
        q[n, 1] = state[1]
    return q


def search(y):
    """The first estimate of ω of each row of y (windowed signals): the peak bin and its neighbour."""
    n = y.shape[1]
    spectrum = np.abs(np.fft.rfft(y, axis=1))
    k = 1 + np.argmax(spectrum[:, 1:n // 2], axis=1)
    rows = np.arange(len(y))
    here, left, right = spectrum[rows, k], spectrum[rows, k - 1], spectrum[rows, k + 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        r = np.maximum(left, right) / here
    delta = ((ORDER + 1) * r - ORDER) / (1 + r)
    return 2 * np.pi * (k + np.where(right >= left, delta, -delta)) / n


def refine(y, omega):
    """Newton's steps on |F(ω)|² from omega, in place, for the rows still moving; the steps taken."""
    n = y.shape[1]
    m = np.arange(n) - 0.5 * (n - 1)
    moments = np.stack([np.ones(n), m, m * m], axis=1)  # F, S1, S2 from one product
    bin_width = 2 * np.pi / n
    limit, tolerance = bin_width / 2, TOLERANCE * bin_width
    active = np.flatnonzero(np.isfinite(omega))
    steps = 0
    while active.size and steps < MOST_STEPS:
        steps += 1
        ya = y if active.size == len(y) else y[active]
        phase = np.multiply.outer(omega[active], m)
        fr, s1r, s2r = ((ya * np.cos(phase)) @ moments).T  # e^{−iωm} = cos ωm − i sin ωm
        fi, s1i, s2i = (-(ya * np.sin(phase)) @ moments).T
        slope = fr * s1i - fi * s1r
        curvature = s1r * s1r + s1i * s1i - (fr * s2r + fi * s2i)
        uphill = np.where(slope > 0, limit, -limit)
        with np.errstate(invalid="ignore", divide="ignore"):
            move = np.where(curvature < 0, -slope / curvature, uphill)
        move = np.clip(move, -limit, limit)
        next_omega = np.abs(omega[active] + move)
        omega[active] = np.where(next_omega > np.pi, 2 * np.pi - next_omega, next_omega)
        active = active[np.abs(move) > tolerance]
    return steps


def naff(x):
    """The tune (cycles per step, in [0, 1/2]) of each row of x; NaN for a zero signal."""
    n = x.shape[1]
    weight = np.sin(np.pi * np.arange(n) / n) ** (2 * ORDER)
    nu = np.empty(len(x))
    steps = 0
    for begin in range(0, len(x), CHUNK):
        y = weight * x[begin:begin + CHUNK]
        omega = search(y)
        omega[np.einsum("ij,ij->i", y, y) == 0] = np.nan
        steps = max(steps, refine(y, omega))
        nu[begin:begin + CHUNK] = omega / (2 * np.pi)
    return nu, steps


def tunes(q, window):
    """ν1, ν2 of both windows ([window, d, orbit]) and the diffusion; the most Newton steps taken."""
    orbits = q.shape[2]
    nu, steps = [], 0
    for first in (0, window):
        signals = np.ascontiguousarray(q[first:first + window].reshape(window, 2 * orbits).T)
        values, taken = naff(signals)  # rows: q1 of every orbit, then q2
        nu.append(values.reshape(2, orbits))
        steps = max(steps, taken)
    with np.errstate(divide="ignore"):
        diffusion = np.maximum(np.log10(np.hypot(*(nu[1] - nu[0]))), FLOOR)
    return nu[0], nu[1], diffusion, steps


def check(points, window):
    """Largest |ν − exact| over both windows and signals of the orbits under the linear map."""
    params = numpy_suris.PARAMS
    numpy_suris.PARAMS = dict(params, alpha=0.0)
    try:
        two_a, two_b, _ = numpy_suris.coefficients()
        first, second, _, _ = tunes(record(points, window), window)
    finally:
        numpy_suris.PARAMS = params
    exact = np.arccos(np.array([two_a / 2, two_b / 2]))[:, None] / (2 * np.pi)
    return max(np.max(np.abs(first - exact)), np.max(np.abs(second - exact)))


def timed(repetitions, work):
    """The median time of work() over the repetitions, and its last result."""
    times = []
    for _ in range(repetitions):
        began = time.perf_counter()
        result = work()
        times.append(time.perf_counter() - began)
    return statistics.median(times), result


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--orbits", type=int, default=4096)
    parser.add_argument("--window", type=int, default=2048, help="N, a power of two")
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--check", action="store_true",
                        help="first compare the tunes of the linear map (alpha = 0) with the exact")
    parser.add_argument("--json", help="also write the numbers as JSON")
    args = parser.parse_args()
    window = args.window
    if window < 8 or window & (window - 1):
        sys.exit(f"tunes_numpy: --window {window} is not a power of two >= 8")

    points = np.random.default_rng(args.seed).uniform(-0.5, 0.5, size=(args.orbits, 4))
    result = {"peer": "numpy", "orbits": args.orbits, "window": window, "steps": 2 * window,
              "order": ORDER, "threads": 1, "repetitions": args.repetitions,
              "numpy": np.__version__, "params": numpy_suris.PARAMS}
    if args.check:
        error = check(points, window)
        result["check_max_error"] = error
        print(f"check: alpha = 0, {args.orbits} orbits, both windows: largest |nu - exact| "
              f"{error:.3g} cycles/step (tolerance {CHECK_TOLERANCE:g})")
        if not error <= CHECK_TOLERANCE:
            sys.exit("tunes_numpy: the tunes of the linear map are wrong")

    stepping, q = timed(args.repetitions, lambda: record(points, window))
    analysis, (_, _, diffusion, newton) = timed(args.repetitions, lambda: tunes(q, window))
    orbit_steps = args.orbits * 2 * window
    rows = {"stepping": stepping, "naff": analysis, "stepping+naff": stepping + analysis}
    result["benchmarks"] = [{"name": name, "seconds": seconds,
                             "items_per_second": orbit_steps / seconds,
                             "microseconds_per_orbit": 1e6 * seconds / args.orbits}
                            for name, seconds in rows.items()]
    result["newton_steps"] = newton
    result["median_diffusion"] = float(np.nanmedian(diffusion))
    print(f"{args.orbits} orbits x {2 * window} steps of Suris' map, NAFF of q1, q2 over 2 windows "
          f"of {window} (order {ORDER}), numpy {np.__version__}, 1 thread, medians of "
          f"{args.repetitions}")
    for row in result["benchmarks"]:
        print(f"  {row['name']:<14} {row['items_per_second']:10.3g} orbit-steps/s "
              f"{row['seconds']:8.3f} s {row['microseconds_per_orbit']:9.1f} us/orbit")
    print(f"  Newton steps at most {newton}; median diffusion {result['median_diffusion']:.2f}")
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    sys.exit(main())
