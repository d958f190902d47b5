"""The exponential Runge-Kutta stages a third of the step apart that `ode::etd_rk4` takes:
their weights derived, their order checked, and the method set beside Cox and Matthews'
ETDRK4 (stages `h/2` apart), which it replaced on 2026-12-01 (issue 34).

The method, in the form of differences `D_i = N(U_i) - N_n` (as V. T. Luan states it, BIT
Numer. Math. 61, 2021, eqs. 1.2-1.3), for `u' = L u + g(u)` with `N(v) = f(v) - L (v - u_n)`:

    U_2 = u + h/3 phi_1(hL/3) N_n
    U_3 = u + 2h/3 phi_1(2hL/3) N_n + 2h phi_2(2hL/3) D_2
    U_4 = u + h phi_1(hL) N_n + 2h phi_2(hL) (D_3 - D_2)
    u+  = u + h [phi_1(hL) N_n + b_2 D_2 + b_3 D_3 + b_4 D_4]

With `L` = 0 the stages are Kutta's 3/8 rule (nodes 0, 1/3, 2/3, 1; `a_32 = 1`,
`a_42 = -1`, `a_43 = 1`), the only classical fourth-order method with those nodes.

1. The weights. Write `b_i = sum_k beta_ik phi_k(hL)`, k = 1..3, and ask for every `L`
   the two quadrature conditions `sum b_i c_i = phi_2` and `sum b_i c_i^2 / 2 = phi_3`
   (a remainder quadratic in time integrated exactly), at `L` = 0 the 3/8 rule's
   `b = (3/8, 3/8, 1/8)`, and the one condition of classical order four that involves the
   weights' first derivative in `hL`: with `psi_i = sum_j a_ij c_j - c_i^2 / 2` (the
   stages' defects at `L` = 0) the local error carries `h^3 (sum_i b_i'(0) psi_i) hL J`,
   `J` the remainder's Jacobian, so `sum b_i'(0) psi_i = 0` (its companion
   `sum b_i(0) psi_i'(0) = 0` holds for the stages above). Printed: the family's exact
   solution, one free parameter; the member kept has no `phi_1` in any `b_i`:
   `b_2 = 15/4 phi_2 - 9 phi_3`, `b_3 = 3/4 phi_2`, `b_4 = 3 phi_3 - 3/4 phi_2`. The
   exact cubic quadrature weights (with `phi_4`) fail the derivative condition
   (`sum b_i'(0) psi_i = -1/90`): that variant is third order.
2. Order: errors at the end of a nonlinear problem with `L` and the Jacobian not
   commuting, halving `h`, against a tight `solve_ivp`; the thirds and Cox and Matthews.
3. A contact mode near the alias bounds: an undamped oscillator exact in `L` with the
   Hertz law's quadratic term and a damping ratio of 0.0707 in the remainder (the Table-1
   case's stiff contact mode, docs/lab/benchmarks.md), 30 periods at fixed `omega h`:
   the state's error against `solve_ivp`, and the decay rate of the damping left to the
   remainder against the exact one.

Needs numpy and scipy: `python3 scripts/research/etd_thirds.py`.
"""

from fractions import Fraction as Fr
from math import factorial

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import expm

NODES = [Fr(0), Fr(1, 3), Fr(2, 3), Fr(1)]
B38 = [Fr(1, 8), Fr(3, 8), Fr(3, 8), Fr(1, 8)]
# psi_i = sum_j a_ij c_j - c_i^2 / 2 of the 3/8 rule's stages
PSI = [Fr(0), Fr(0) - Fr(1, 18), Fr(1, 3) - Fr(2, 9), Fr(-1, 3) + Fr(2, 3) - Fr(1, 2)]


def weight_family():
    """Row-reduce the conditions on beta_ik (stages 2..4, phi_1..phi_3) over the rationals."""
    unknowns = 9
    col = lambda i, k: 3 * i + k  # i: stage 2..4 as 0..2, k: phi_1..phi_3 as 0..2
    rows = []
    for k in range(3):
        for power, want in ((1, 1 if k == 1 else 0), (2, 1 if k == 2 else 0)):
            r = [Fr(0)] * unknowns + [Fr(want)]
            for i in range(3):
                r[col(i, k)] = NODES[i + 1] ** power / factorial(power)
            rows.append(r)
    for i in range(3):
        r = [Fr(0)] * unknowns + [B38[i + 1]]
        for k in range(3):
            r[col(i, k)] = Fr(1, factorial(k + 1))  # phi_k(0) = 1/k!
        rows.append(r)
    r = [Fr(0)] * (unknowns + 1)
    for i in range(3):
        for k in range(3):
            r[col(i, k)] = PSI[i + 1] / factorial(k + 2)  # phi_k'(0) = 1/(k+1)!
    rows.append(r)
    pivots, top = [], 0
    for c in range(unknowns):
        p = next((j for j in range(top, len(rows)) if rows[j][c] != 0), None)
        if p is None:
            continue
        rows[top], rows[p] = rows[p], rows[top]
        rows[top] = [x / rows[top][c] for x in rows[top]]
        for j in range(len(rows)):
            if j != top and rows[j][c] != 0:
                f = rows[j][c]
                rows[j] = [a - f * b for a, b in zip(rows[j], rows[top])]
        pivots.append(c)
        top += 1
    assert all(r[-1] == 0 for r in rows[top:]), "inconsistent"
    free = [c for c in range(unknowns) if c not in pivots]
    print(f"1. weights: rank {top} of {unknowns} unknowns, free: "
          + ", ".join(f"b_{c // 3 + 2}'s phi_{c % 3 + 1} (call it g)" for c in free))
    for r, c in zip(rows, pivots):
        terms = " ".join(("+ " if -r[f] > 0 else "- ") + f"{abs(r[f])} g" for f in free if r[f] != 0)
        print(f"   b_{c // 3 + 2}: phi_{c % 3 + 1} coefficient {r[-1]} {terms}")
    # the exact cubic quadrature (nodes 0, 1/3, 2/3, 1) against the derivative condition
    lag = []
    for i in range(4):
        others = [NODES[j] for j in range(4) if j != i]
        # integral of (1 - t) l_i(t) over [0, 1] by expanding the cubic l_i
        poly = [Fr(1)]
        for o in others:
            poly = [a - o * b for a, b in zip([Fr(0)] + poly, poly + [Fr(0)])]
        den = Fr(1)
        for o in others:
            den *= NODES[i] - o
        lag.append(sum(p * (Fr(1, n + 1) - Fr(1, n + 2)) for n, p in enumerate(poly)) / den)
    print("   g = 3 leaves no phi_1 in any b_i; the exact cubic quadrature's sum b_i'(0) psi_i =",
          sum(w * p for w, p in zip(lag, PSI)))


def phis(m, count=3):
    """e^M and phi_1..phi_count of a square matrix from one augmented exponential."""
    n = m.shape[0]
    aug = np.zeros(((count + 1) * n, (count + 1) * n))
    aug[:n, :n] = m
    for k in range(count):
        aug[k * n:(k + 1) * n, (k + 1) * n:(k + 2) * n] = np.eye(n)
    e = expm(aug)
    return [e[:n, k * n:(k + 1) * n] for k in range(count + 1)]


class Thirds:
    def __init__(self, lin, h):
        self.lin, self.h = lin, h
        _, p1, p2, p3 = phis(h * lin)
        self.p1, self.p2 = p1, p2
        self.third = phis(h * lin / 3)[1]
        _, self.two1, self.two2, _ = phis(2 * h * lin / 3)
        self.b2, self.b3, self.b4 = 3.75 * p2 - 9 * p3, 0.75 * p2, 3 * p3 - 0.75 * p2

    def step(self, u, g):
        h, lin = self.h, self.lin
        rem = lambda v: lin @ u + g(v)  # N(v) = f(v) - L (v - u)
        n1 = rem(u)
        n2 = rem(u + h / 3 * self.third @ n1)
        n3 = rem(u + 2 * h / 3 * self.two1 @ n1 + 2 * h * self.two2 @ (n2 - n1))
        n4 = rem(u + h * self.p1 @ n1 + 2 * h * self.p2 @ (n3 - n2))
        return u + h * (self.p1 @ n1 + self.b2 @ (n2 - n1) + self.b3 @ (n3 - n1)
                        + self.b4 @ (n4 - n1))


class CoxMatthews:
    def __init__(self, lin, h):
        self.lin, self.h = lin, h
        _, p1, p2, p3 = phis(h * lin)
        self.e_half, self.p1_half, _, _ = phis(0.5 * h * lin)
        self.f1, self.f2, self.f3 = p1 - 3 * p2 + 4 * p3, p2 - 2 * p3, 4 * p3 - p2

    def step(self, u, g):
        h, lin = self.h, self.lin
        rem = lambda v: lin @ u + g(v)
        n0 = rem(u)
        a = u + 0.5 * h * self.p1_half @ n0
        na = rem(a)
        nb = rem(u + 0.5 * h * self.p1_half @ na)
        nc = rem(u + self.e_half @ (a - u) + 0.5 * h * self.p1_half @ (2 * nb - n0))
        return u + h * (self.f1 @ n0 + 2 * self.f2 @ (na + nb) + self.f3 @ nc)


METHODS = [("Cox-Matthews", CoxMatthews), ("thirds", Thirds)]


def order():
    lin = np.array([[0.0, 1.0], [-4.0, -0.3]])
    g = lambda v: np.array([0.1 * np.sin(v[1]) + 0.3 * v[0] * v[1],
                            -0.5 * v[0] ** 2 + 0.2 * np.cos(v[0])])
    u0, t_end = np.array([0.7, -0.2]), 2.0
    ref = solve_ivp(lambda t, u: lin @ u + g(u), (0, t_end), u0, rtol=1e-13, atol=1e-14).y[:, -1]
    print("2. order: error at t = 2 for 10, 20, 40, 80, 160 steps, and log2 of each halving")
    for name, method in METHODS:
        errors = []
        for n in [10, 20, 40, 80, 160]:
            m, u = method(lin, t_end / n), u0.copy()
            for _ in range(n):
                u = m.step(u, g)
            errors.append(np.linalg.norm(u - ref))
        slopes = [np.log2(errors[i] / errors[i + 1]) for i in range(4)]
        print(f"   {name:13s}" + " ".join(f"{e:.2e}" for e in errors)
              + "  slopes " + " ".join(f"{s:.2f}" for s in slopes))


def contact_mode():
    zeta = 0.0707
    lin = np.array([[0.0, 1.0], [-1.0, 0.0]])  # omega = 1: time in units of 1/omega
    g = lambda v: np.array([0.0, -0.3 * v[0] ** 2 - 2 * zeta * v[1]])
    u0, t_end = np.array([0.3, 0.0]), 60 * np.pi
    ref = solve_ivp(lambda t, u: lin @ u + g(u), (0, t_end), u0, rtol=1e-12, atol=1e-14).y[:, -1]
    damping = np.array([[0.0, 0.0], [0.0, -2 * zeta]])
    print("3. contact mode: state error after 30 periods (relative), and the remainder's damping")
    print("   decay rate over the exact zeta omega; Cox-Matthews, then thirds")
    for wh in [0.5, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.35, 1.5]:
        n = int(round(t_end / (wh * np.pi)))
        out = []
        for _, method in METHODS:
            m, u = method(lin, t_end / n), u0.copy()
            for _ in range(n):
                u = m.step(u, g)
            lm = method(lin, wh * np.pi)
            step = np.column_stack([lm.step(c, lambda v: damping @ v) for c in np.eye(2)])
            rate = -np.log(np.abs(np.linalg.eigvals(step)).max()) / (wh * np.pi) / zeta
            out.append(f"{np.linalg.norm(u - ref) / np.linalg.norm(u0):.2e} {rate:.3f}")
        print(f"   omega h = {wh:.2f} pi: " + ", ".join(out))


if __name__ == "__main__":
    weight_family()
    order()
    contact_mode()
