"""Exact tunes of Suris' map (docs/maps.md §3) where they have closed forms, for the tunes' tests.

The tune of a degree of freedom is the fundamental frequency of the real signal q_j(n) in cycles
per step, folded to [0, 1/2]: fold(ρ) = min(ρ, 1 − ρ) with ρ taken mod 1.

Suris' step (kernels/suris.hpp), with x = q_{n−1}, y = q_n, z = q_{n+1}:
    D = 1 + g(y1² + y2²),   z1 = 2a y1 / D − x1,   z2 = 2b y2 / D − x2,
    a = 1 − Ah²,  b = 1 − Bh²,  g = 2αh².
Every reference takes a, b and g as the kernel rounds them (suris_coefficients); they differ from
the real values by about 1e-17, far below any tolerance.

1. Linear map (α = 0). Each degree of freedom is z = 2a y − x, whose multipliers λ solve
   λ² − 2aλ + 1 = 0: λ = e^{±iθ}, cos θ = a, so for 0 < Ah² < 2
       ν1 = arccos(1 − Ah²)/(2π),   ν2 = arccos(1 − Bh²)/(2π),   both already in (0, 1/2).

2. The invariant plane q2 = p2 = 0 (z2 = 0 forever): McMillan's map
       T(x, y) = (y, z),   z = 2a y/(1 + g y²) − x,
   which preserves dx∧dy (its Jacobian [[0, 1], [−1, ∂z/∂y]] has determinant 1) and keeps
       K(x, y) = g x²y² + x² + y² − 2a xy
   (the kernel's I1 on the plane; as a quadratic in x, K(·, y) = K has the roots x and z, whose
   sum is 2a y/(1 + g y²)). By Danilov's theorem T is the time-τ map of the flow of K,
       dx/dt = ∂K/∂y,   dy/dt = −∂K/∂x,
   and its rotation number on the curve K = const is ρ = τ(K)/T(K), T the curve's period.
   Along the curve dt = dx/K_y, and K_y = 2[(1 + gx²)y − ax] = ±2√Δ(x²) with
       Δ(s) = K + (a² − 1 + gK) s − g s²        (s = x²).
   x runs over [−x_m, x_m], s_m = x_m² the smallest positive root of Δ, and Δ(s) = (s_m − s)P(s)
   with P(s) = c + g s, c = K/s_m, positive on [0, s_m] on the bounded curve around the origin.
   The substitution x = x_m sin φ removes the turning points: dt = dφ / (2√P(x_m² sin²φ)), φ
   increases along the flow, one turn is φ → φ + 2π, and the angle of a point is
       φ(x, y) = atan2(x √P(x²), (1 + gx²) y − a x).
   So, with d = g s_m,
       T = ∫_0^{2π} dφ / (2√(c + d sin²φ)) = π / AGM(√c, √(c + d)),
       τ = ∫_{φ(x,y)}^{φ(x,y) + Δφ} dφ / (2√(c + d sin²φ)),   Δφ = φ(y, z) − φ(x, y) mod 2π,
   the first by the arithmetic–geometric mean, the second by quadrature of an analytic integrand.
   For g = 0 this is T = π/sin θ, τ = θ/(2 sin θ), ρ = θ/(2π): item 1.

Run as /usr/bin/python3 -B tests/tune_references.py: it checks these against direct iteration of
the map (the angle accumulated around the fixed point), against the elliptic-integral forms of T
and τ, and that τ is the same at every point of an orbit, as Danilov's theorem says.
"""
import math
import sys
import unittest

import mpmath
from mpmath import mp, mpf

DIGITS = 40  # working precision; the references are good to well over 25 digits


def suris_coefficients(A, B, alpha, h):
    """(a, b, g) = (1 − Ah², 1 − Bh², 2αh²) rounded to doubles as the kernel forms them."""
    h2 = h * h
    return 1 - A * h2, 1 - B * h2, 2 * alpha * h2


def suris_start(q1, q2, p1, p2, A, B, alpha, h, start="taylor"):
    """The two-step state (q1_0, q2_0, q1_1, q2_1) the engine starts from (q, p) with, computed
    in the same double operations (Suris::from_phase_space): q_1 = q_0 + hp, plus (h²/2)F(q_0)
    for `taylor`."""
    y1, y2 = q1 + h * p1, q2 + h * p2
    if start == "taylor":
        r2 = q1 * q1 + q2 * q2
        f1 = -2 * A * q1 - 4 * alpha * q1 * r2
        f2 = -2 * B * q2 - 4 * alpha * q2 * r2
        y1 += 0.5 * h * h * f1
        y2 += 0.5 * h * h * f2
    elif start != "euler":
        raise ValueError(f"unknown start rule {start!r}")
    return q1, q2, y1, y2


def fold(rho):
    """The tune of a real signal whose rotation number is rho: min(ρ, 1 − ρ), ρ mod 1."""
    rho = rho % 1
    return min(rho, 1 - rho)


def linear_tune(a):
    """The tune of z = 2a y − x (|a| < 1): arccos(a)/(2π), in (0, 1/2)."""
    with mp.workdps(DIGITS):
        a = mpf(a)
        if not -1 < a < 1:
            raise ValueError(f"a = {a}: the linear map is not elliptic (needs 0 < Ah^2 < 2)")
        return mpmath.acos(a) / (2 * mp.pi)


def suris_linear_tunes(A, B, h):
    """(ν1, ν2) of Suris' map at α = 0, from the kernel's a and b."""
    a, b, _ = suris_coefficients(A, B, 0.0, h)
    return linear_tune(a), linear_tune(b)


def mcmillan_invariant(x, y, a, g):
    """K(x, y) = g x²y² + x² + y² − 2a xy, exactly for the given numbers."""
    with mp.workdps(max(DIGITS, mp.dps)):
        x, y, a, g = map(mpf, (x, y, a, g))
        return g * x * x * y * y + x * x + y * y - 2 * a * x * y


def mcmillan_step(x, y, a, g):
    """T(x, y) = (y, 2a y/(1 + g y²) − x) in the current precision."""
    return y, 2 * a * y / (1 + g * y * y) - x


class Curve:
    """The level curve of K through (x, y): its s_m, c, d and period T (working precision)."""

    def __init__(self, x, y, a, g):
        x, y, a, g = map(mpf, (x, y, a, g))
        self.a, self.g = a, g
        self.K = g * x * x * y * y + x * x + y * y - 2 * a * x * y
        if self.K <= 0:
            raise ValueError("K <= 0: the point is the fixed point, or the map is not elliptic")
        b = a * a - 1 + g * self.K
        root = b * b + 4 * g * self.K
        if root < 0:
            raise ValueError(f"K = {self.K}: the level curve is not a closed curve around 0")
        self.s_m = 2 * self.K / (mpmath.sqrt(root) - b)  # the smallest positive root of Δ
        if not (self.s_m > 0 and x * x <= self.s_m * (1 + mpf(10) ** (-mp.dps // 2))
                and y * y <= self.s_m * (1 + mpf(10) ** (-mp.dps // 2))):
            raise ValueError(f"({x}, {y}) is not on the bounded curve around the fixed point")
        self.c = self.K / self.s_m
        self.d = self.g * self.s_m
        if not (self.c > 0 and self.c + self.d > 0):
            raise ValueError(f"K = {self.K}: the level curve has no bounded branch here")
        self.period = mp.pi / mpmath.agm(mpmath.sqrt(self.c), mpmath.sqrt(self.c + self.d))

    def angle(self, x, y):
        """φ(x, y) in (−π, π], with x = x_m sin φ along the flow of K."""
        P = self.c + self.g * x * x
        return mpmath.atan2(x * mpmath.sqrt(P), (1 + self.g * x * x) * y - self.a * x)

    def rate(self, phi):
        """dt/dφ = 1/(2√(c + d sin²φ))."""
        return 1 / (2 * mpmath.sqrt(self.c + self.d * mpmath.sin(phi) ** 2))

    def flow_time(self, phi0, phi1):
        """The flow time from angle phi0 forward to phi1 (taken mod 2π into [0, 2π))."""
        delta = (phi1 - phi0) % (2 * mp.pi)
        return mpmath.quad(self.rate, [phi0, phi0 + delta / 2, phi0 + delta])


def mcmillan_rotation(x, y, a, g):
    """Danilov's ρ = τ/T in [0, 1) of McMillan's map through the state (x, y) of two consecutive
    positions (q_n, q_{n+1}), counted in the direction of the flow of K."""
    with mp.workdps(DIGITS):
        x, y, a, g = map(mpf, (x, y, a, g))
        if x == 0 and y == 0:
            return mpmath.acos(a) / (2 * mp.pi)  # the limit K → 0: the linear part's
        curve = Curve(x, y, a, g)
        _, z = mcmillan_step(x, y, a, g)
        tau = curve.flow_time(curve.angle(x, y), curve.angle(y, z))
        return tau / curve.period


def mcmillan_tune(x, y, a, g):
    """The tune of q1(n) on Suris' plane q2 = p2 = 0 from the state (q1_n, q1_{n+1}) = (x, y)."""
    return fold(mcmillan_rotation(x, y, a, g))


# Independent checks --------------------------------------------------------------------------


def iterated_rotation(x, y, a, g, steps):
    """ρ by direct iteration in doubles, two ways: the plain and the weighted average of the turn
    of ζ = y − e^{−iθ}x (cos θ = a: the linear part's normal form, in which the linear map turns
    by θ each step) over `steps` steps, each turn taken in [0, 2π). The plain average's error is
    O(1/steps), since the angle stays within a bounded distance of a uniform rotation; the weighted
    one (weights exp(−1/(t(1 − t))), t = n/steps: Das, Sander and Yorke's weighted Birkhoff
    average) converges faster than any power of 1/steps on an invariant curve, down to the
    doubles' round-off."""
    x, y, a, g = float(x), float(y), float(a), float(g)
    theta = math.acos(a)
    cr, ci = math.cos(theta), -math.sin(theta)
    plain = weighted = weights = 0.0
    before = math.atan2(-ci * x, y - cr * x)
    for n in range(steps):
        x, y = y, 2 * a * y / (1 + g * y * y) - x
        after = math.atan2(-ci * x, y - cr * x)
        turn = (after - before) % (2 * math.pi)
        before = after
        t = (n + 0.5) / steps
        w = math.exp(-1 / (t * (1 - t)))
        plain += turn
        weighted += w * turn
        weights += w
    return plain / (2 * math.pi * steps), weighted / (2 * math.pi * weights)


class SelfTest(unittest.TestCase):
    STEPS = 200_000
    WEIGHTED = 1e-12  # the weighted average against the references: round-off of the doubles
    # (a, g): the preset's A = 0.7, α = 0.9 at h = 0.1 and 0.5, a defocusing α < 0, and a map
    # turning by more than a quarter per step.
    MAPS = [suris_coefficients(0.7, 0.3, 0.9, 0.1)[::2], suris_coefficients(0.7, 0.3, 0.9, 0.5)[::2],
            suris_coefficients(0.7, 0.3, -0.4, 0.5)[::2], suris_coefficients(1.3, 0.3, 2.0, 1.0)[::2]]
    AMPLITUDES = [0.05, 0.3, 0.8, 1.5]

    def points(self, a, g):
        for q in self.AMPLITUDES:
            x, y = q, q * a  # a state through (q, 0) of the linear map, any amplitude
            if g < 0 and abs(q) > 0.5:
                continue  # beyond the separatrix of the defocusing map
            yield x, y

    def test_linear_tunes_match_iteration(self):
        for A, B, h in [(0.5, 0.8, 0.1), (0.7, 0.3, 0.5), (1.3, 0.3, 1.0), (1.5, 0.2, 1.1)]:
            a, b, _ = suris_coefficients(A, B, 0.0, h)
            exact = suris_linear_tunes(A, B, h)
            for coefficient, nu in zip((a, b), exact):
                with self.subTest(A=A, B=B, h=h, a=coefficient):
                    plain, weighted = iterated_rotation(0.3, 0.1, coefficient, 0.0, self.STEPS)
                    self.assertLessEqual(abs(plain - float(nu)), 1 / self.STEPS)
                    self.assertLessEqual(abs(weighted - float(nu)), self.WEIGHTED)
                    # the Danilov route reduces to it at g = 0
                    self.assertLessEqual(abs(mcmillan_rotation(0.3, 0.1, coefficient, 0.0) - nu),
                                         mpf(10) ** -30)
                    print(f"linear a = {coefficient:+.17g}: arccos(a)/2pi = "
                          f"{mpmath.nstr(nu, 27)}; iterated: plain {plain - float(nu):+.1e}, "
                          f"weighted {weighted - float(nu):+.1e}")

    def test_danilov_rotation_matches_iteration(self):
        for a, g in self.MAPS:
            for x, y in self.points(a, g):
                with self.subTest(a=a, g=g, x=x):
                    rho = mcmillan_rotation(x, y, a, g)
                    plain, weighted = iterated_rotation(x, y, a, g, self.STEPS)
                    self.assertLessEqual(abs(plain - float(rho)), 1 / self.STEPS)
                    self.assertLessEqual(abs(weighted - float(rho)), self.WEIGHTED)
                    print(f"a = {a:+.6f}, g = {g:+.4f}, q = {x:4}: Danilov rho = "
                          f"{mpmath.nstr(rho, 27)}; iterated: plain {plain - float(rho):+.1e}, "
                          f"weighted {weighted - float(rho):+.1e}")

    def test_tau_is_the_same_at_every_point_of_an_orbit(self):
        # Danilov's theorem: the map is the flow of K for one time τ on the whole curve.
        with mp.workdps(60):
            for a, g in self.MAPS:
                x, y = mpf(0.8) if g > 0 else mpf(0.4), mpf(0.1)
                curve = Curve(x, y, mpf(a), mpf(g))
                taus = []
                for _ in range(12):
                    _, z = mcmillan_step(x, y, mpf(a), mpf(g))
                    taus.append(curve.flow_time(curve.angle(x, y), curve.angle(y, z)))
                    x, y = y, z
                with self.subTest(a=a, g=g):
                    self.assertLess(max(taus) - min(taus), mpf(10) ** -45)

    def test_elliptic_integral_forms_agree(self):
        # T by quadrature against the AGM; τ against incomplete elliptic integrals F(φ|m),
        # ∫ dφ/√(c + d sin²φ) = F(φ | −d/c)/√c.
        with mp.workdps(DIGITS):
            for a, g in self.MAPS:
                for x, y in self.points(a, g):
                    x, y = mpf(x), mpf(y)
                    curve = Curve(x, y, mpf(a), mpf(g))
                    quad_period = mpmath.quad(curve.rate, mpmath.linspace(0, 2 * mp.pi, 5))
                    phi0 = curve.angle(x, y)
                    phi1 = phi0 + (curve.angle(*mcmillan_step(x, y, mpf(a), mpf(g))) - phi0) % (
                        2 * mp.pi)
                    m = -curve.d / curve.c
                    tau_f = (mpmath.ellipf(phi1, m) - mpmath.ellipf(phi0, m)) / (
                        2 * mpmath.sqrt(curve.c))
                    with self.subTest(a=a, g=g, x=x):
                        self.assertLess(abs(quad_period / curve.period - 1), mpf(10) ** -32)
                        tau = curve.flow_time(phi0, phi1)
                        self.assertLess(abs(tau_f / tau - 1), mpf(10) ** -30)

    def test_precision_is_well_beyond_25_digits(self):
        for a, g in self.MAPS[:2]:
            rho = mcmillan_rotation(0.8, 0.3, a, g)
            global DIGITS
            saved, DIGITS = DIGITS, 70
            try:
                finer = mcmillan_rotation(0.8, 0.3, a, g)
            finally:
                DIGITS = saved
            with mp.workdps(70):
                self.assertLess(abs(rho - finer), mpf(10) ** -35)

    def test_invariant_is_kept_by_the_map(self):
        with mp.workdps(50):
            for a, g in self.MAPS:
                x, y = mpf("0.3"), mpf("-0.2")
                k0 = mcmillan_invariant(x, y, a, g)
                for _ in range(200):
                    x, y = mcmillan_step(x, y, mpf(a), mpf(g))
                self.assertLess(abs(mcmillan_invariant(x, y, a, g) - k0), mpf(10) ** -45)

    def test_start_rule_is_the_kernels(self):
        # euler: q_1 = q_0 + hp; taylor adds (h²/2)F with F = −2Aq − 4αq|q|².
        s = suris_start(0.5, 0.0, 0.0, 0.0, 0.7, 0.3, 0.9, 0.1)
        self.assertEqual(s[2], 0.5 + 0.5 * 0.1 * 0.1 * (-2 * 0.7 * 0.5 - 4 * 0.9 * 0.5 * 0.25))
        self.assertEqual(suris_start(0.5, 0.1, 0.2, 0.3, 0.7, 0.3, 0.9, 0.1, "euler"),
                         (0.5, 0.1, 0.5 + 0.1 * 0.2, 0.1 + 0.1 * 0.3))

    def test_fold(self):
        self.assertEqual(fold(0.3), 0.3)
        self.assertAlmostEqual(fold(0.8), 0.2, delta=1e-16)
        self.assertAlmostEqual(fold(1.25), 0.25, delta=1e-16)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1] + ["-v"] + sys.argv[1:])
