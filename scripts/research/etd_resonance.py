"""ETDRK4 on a single contact mode near the alias bound (omega h = pi), independent of the engine.

Two checks behind docs/lab/benchmarks.md, "The cage speed's offset follows the step at
the contacts' alias bound" (issue 34):

1. A damped mode whose damping is left to the explicit remainder, as `linear_part` leaves
   the contact damping (ratio 0.0707 on a ball's stiff mode, 58 kHz): ETDRK4 takes the
   undamped oscillator exactly and integrates `-c v` through its stages. Printed: the
   numerical decay rate per unit time against the exact `zeta omega`, by `omega h`.
2. A quadratic oscillator `x'' = -omega^2 x - beta x^2` (the Hertz law's leading
   nonlinearity about a loaded contact) under the same splitting: the linear oscillator
   exact (fixed about `x = 0`; the engine differences its `L` at each linearisation's
   state), `-beta x^2` in the remainder, which rings at twice the mode's frequency and at
   zero frequency. Printed: the error of the long-run mean of `x` (the mode's rectified
   offset, which carries the mean contact force) against a tight `solve_ivp` reference,
   by `omega h`.

The formulas are Cox and Matthews' ETDRK4 in the remainder form the engine states in
`ode::etd_rk4` (`f(u) = L (u - u_n) + N(u)`), and beside it Krogstad's (the same final
weights; inner stages `b = u + h/2 phi_1(hL/2) N_n + h phi_2(hL/2) (N_a - N_n)` and
`c = u + h phi_1(hL) N_n + 2h phi_2(hL) (N_b - N_n)`), written out here with dense matrix
exponentials; nothing is shared with the Rust code.

3. The dense output inside one step of a damped mode forced at twice its frequency and at
   zero frequency (the remainder's content under 2.): the engine's interpolant until
   2026-12-01 (`refine_dense` of `ode::etd_rk4`: `v = e^{-sigma L} (y - y*)` by a cubic
   Hermite from the step's ends, then rotated forward; it now takes the step's continuous
   extension through the stages instead), with the damping in `L` or in the
   remainder, against a quintic that also takes `v` and `v'` at the middle of the step
   (from the exact solution there: the best a midpoint could give). Printed: the largest
   velocity error over the step, against the mode's velocity amplitude.

Needs numpy (2 or later, for `trapezoid`) and scipy: `python3 scripts/research/etd_resonance.py`.
Below `omega h` = 0.4 pi the printed errors reach the check's own resolution (its
trapezoid mean over the steps, about 1e-4 of the mean).
"""

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import expm


def phi_functions(m):
    """e^M, phi_1(M), phi_2(M), phi_3(M) of a square matrix, from one augmented exponential."""
    n = m.shape[0]
    eye = np.eye(n)
    aug = np.zeros((4 * n, 4 * n))
    aug[:n, :n] = m
    aug[:n, n : 2 * n] = eye
    aug[n : 2 * n, 2 * n : 3 * n] = eye
    aug[2 * n : 3 * n, 3 * n :] = eye
    e = expm(aug)
    return e[:n, :n], e[:n, n : 2 * n], e[:n, 2 * n : 3 * n], e[:n, 3 * n :]


class Etdrk4:
    """ETDRK4 around the constant linear part `lin` for `u' = lin u + g(u)`, with Cox and
    Matthews' inner stages or Krogstad's."""

    def __init__(self, lin, h, krogstad=False):
        self.lin, self.h, self.krogstad = lin, h, krogstad
        _, p1, p2, p3 = phi_functions(h * lin)
        self.p1, self.p2 = p1, p2
        self.e_half, self.p1_half, self.p2_half, _ = phi_functions(0.5 * h * lin)
        self.f1 = p1 - 3 * p2 + 4 * p3
        self.f2 = p2 - 2 * p3
        self.f3 = 4 * p3 - p2

    def step(self, u, g):
        h, lin = self.h, self.lin

        def rem(v):  # N(v) = f(v) - L (v - u)
            return lin @ u + g(v)

        n0 = rem(u)
        a = u + 0.5 * h * self.p1_half @ n0
        na = rem(a)
        if self.krogstad:
            b = u + 0.5 * h * self.p1_half @ n0 + h * self.p2_half @ (na - n0)
            nb = rem(b)
            c = u + h * self.p1 @ n0 + 2 * h * self.p2 @ (nb - n0)
        else:
            b = u + 0.5 * h * self.p1_half @ na
            nb = rem(b)
            c = u + self.e_half @ (a - u) + 0.5 * h * self.p1_half @ (2 * nb - n0)
        nc = rem(c)
        return u + h * (self.f1 @ n0 + 2 * self.f2 @ (na + nb) + self.f3 @ nc)


def damping_in_the_remainder():
    omega = 2 * np.pi * 58e3  # rad/s, a loaded ball's stiff contact mode (benchmarks.md)
    zeta = 0.0707  # its measured damping ratio: 0.05 on each of two contacts in line
    c = 2 * zeta * omega
    lin = np.array([[0.0, 1.0], [-omega * omega, 0.0]])
    damping = np.array([[0.0, 0.0], [0.0, -c]])
    print("1. damping left to the remainder: decay rate against the exact zeta omega "
          "(Cox-Matthews, Krogstad)")
    for wh in [0.47, 0.6, 0.7, 0.8, 0.87, 0.9, 0.95, 0.98]:
        h = wh * np.pi / omega
        rates = []
        for krogstad in (False, True):
            m = Etdrk4(lin, h, krogstad)
            # the step is linear in u: its matrix from the two unit vectors
            step = np.column_stack([m.step(col, lambda v: damping @ v) for col in np.eye(2)])
            rates.append(-np.log(np.abs(np.linalg.eigvals(step)).max()) / h / (zeta * omega))
        print(f"   omega h = {wh:.2f} pi ({h * 1e6:.2f} us): {rates[0]:.4f}, {rates[1]:.4f} of it")


def quadratic_oscillator():
    omega, beta, amp = 1.0, 0.3, 0.3
    lin = np.array([[0.0, 1.0], [-omega * omega, 0.0]])

    def g(v):
        return np.array([0.0, -beta * v[0] ** 2])

    periods = 400
    t_end = periods * 2 * np.pi / omega
    u0 = np.array([amp, 0.0])
    ref = solve_ivp(lambda t, u: lin @ u + g(u), (0, t_end), u0, rtol=1e-11, atol=1e-13,
                    dense_output=True)
    ts = np.linspace(0, t_end, 400_001)
    exact = np.trapezoid(ref.sol(ts)[0], ts) / t_end
    print(f"2. quadratic oscillator, beta x / omega^2 = {beta * amp:.2f}, {periods} periods: "
          f"mean x {exact:.6e} (reference)")
    print("   error of the mean against it (Cox-Matthews, Krogstad)")
    for wh in [0.1, 0.2, 0.4, 0.6, 0.7, 0.8, 0.87, 0.9, 0.95, 0.99, 1.0, 1.01, 1.05, 1.1]:
        h = wh * np.pi / omega
        errors = []
        for krogstad in (False, True):
            m = Etdrk4(lin, h, krogstad)
            u, total = u0.copy(), 0.0
            for _ in range(int(round(t_end / h))):
                nxt = m.step(u, g)
                total += 0.5 * (u[0] + nxt[0])  # trapezoid: the samples' phases spread evenly
                u = nxt
            errors.append((total / round(t_end / h) - exact) / abs(exact))
        print(f"   omega h = {wh:.2f} pi: {errors[0]:+.2e}, {errors[1]:+.2e}")


def hermite(y0, d0, y1, d1, h, s):
    """The cubic through `y0`, `y1` with slopes `d0`, `d1` (per unit time) at fraction `s`."""
    s2, s3 = s * s, s * s * s
    return ((2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * h * d0 + (-2 * s3 + 3 * s2) * y1
            + (s3 - s2) * h * d1)


def dense_output():
    omega = 2 * np.pi * 58e3
    zeta = 0.0707
    c = 2 * zeta * omega
    scale = omega * omega * 1e-6  # forcing per unit mass for a 1 um mode

    def force(t):
        return 0.3 * scale * np.sin(2 * omega * t + 0.7) + 0.1 * scale

    def rhs(t, y):
        return [y[1], -omega * omega * y[0] - c * y[1] + force(t)]

    y0 = np.array([1e-6, 0.3e-6 * omega])

    def interpolate(damping, h, s, ends, mid=None):
        """The mode's state at `s` of the step; `damping` the part of `c` taken in `L`."""
        lin = np.array([[0.0, 1.0], [-omega * omega, -damping]])
        (ya, aa), (yb, ab) = ends
        qs = ya[0] + (aa + damping * ya[1]) / omega**2  # L's equilibrium at the start

        def v_and_slope(y, acc, tau):
            back = expm(-tau * lin)
            v = back @ np.array([y[0] - qs, y[1]])
            slope = back @ np.array([0.0, acc + omega**2 * (y[0] - qs) + damping * y[1]])
            return v, slope

        v0 = np.array([ya[0] - qs, ya[1]])
        v1, d1 = v_and_slope(yb, ab, h)
        if mid is None:
            v = [hermite(v0[k], 0.0, v1[k], d1[k], h, s) for k in range(2)]
        else:
            vm, dm = v_and_slope(mid[0], mid[1], 0.5 * h)
            # quintic: values and slopes at 0, 1/2 and 1 (of the fraction)
            rows = [[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [1, 1, 1, 1, 1, 1],
                    [0, 1, 2, 3, 4, 5], [1, .5, .25, .125, .0625, .03125],
                    [0, 1, 1, .75, .5, .3125]]
            v = []
            for k in range(2):
                coef = np.linalg.solve(rows, [v0[k], 0.0, v1[k], h * d1[k], vm[k], h * dm[k]])
                v.append(sum(coef[j] * s**j for j in range(6)))
        q, u = expm(s * h * lin) @ np.array(v)
        return qs + q, u

    print("3. dense output inside one step, forced damped mode: largest velocity error "
          "(ends only: damping in L, in the remainder; with the middle: in L, in the remainder)")
    for wh in [0.5, 0.7, 0.87, 1.0]:
        h = wh * np.pi / omega
        sol = solve_ivp(rhs, (0, h), y0, rtol=1e-12, atol=1e-20, dense_output=True,
                        method="DOP853")
        y1 = sol.y[:, -1]
        ends = ((y0, rhs(0, y0)[1]), (y1, rhs(h, y1)[1]))
        ym = sol.sol(0.5 * h)
        mid = (ym, rhs(0.5 * h, ym)[1])
        worst = np.zeros(4)
        for s in np.linspace(0.05, 0.95, 19):
            exact = sol.sol(s * h)[1]
            got = [interpolate(c, h, s, ends)[1], interpolate(0.0, h, s, ends)[1],
                   interpolate(c, h, s, ends, mid)[1], interpolate(0.0, h, s, ends, mid)[1]]
            worst = np.maximum(worst, np.abs(np.array(got) - exact))
        w = worst / abs(y0[1])
        print(f"   omega h = {wh:.2f} pi: {w[0]:.2e}, {w[1]:.2e}; {w[2]:.2e}, {w[3]:.2e}")


if __name__ == "__main__":
    damping_in_the_remainder()
    quadratic_oscillator()
    dense_output()
