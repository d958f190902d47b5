//! Rosenbrock-W methods as data: ROS34PW2 (Rang and Angermann, BIT Numer. Math. 45, 2005,
//! not read; the coefficients are PETSc's `TSROSWRA34PW2` table, read) and ROS34PRw (PETSc's
//! `TSROSWR34PRW`), their coefficients and their form in the transformed variables the
//! stepper ([`super::rosenbrock`]) works in.

// the tableau keeps the digits as published
#![allow(clippy::excessive_precision)]
// the transformation indexes rows and columns as the matrix formulas do
#![allow(clippy::needless_range_loop)]

/// Stages.
pub const S: usize = 4;

/// A Rosenbrock-W method as published: propagation table `A` (strictly lower), stage table
/// `Gamma` (lower, the same `gamma` on its whole diagonal), completion weights `b` and
/// embedded weights `b2`.
pub struct RosenbrockTable {
    /// The diagonal of `Gamma`, -.
    pub gamma: f64,
    /// Propagation coefficients `alpha_ij`, strictly lower, -.
    pub a: [[f64; S]; S],
    /// Stage coefficients `gamma_ij`, lower, `gamma` on the diagonal, -.
    pub g: [[f64; S]; S],
    /// Weights of the propagated solution, -.
    pub b: [f64; S],
    /// Weights of the embedded solution the error estimate compares with, -.
    pub b2: [f64; S],
}

/// The `gamma` both 4-stage tables share, and their first propagation coefficient `2 gamma`.
const GAMMA_34: f64 = 4.358_665_215_084_590_0e-1;
const A21_34: f64 = 8.717_330_430_169_180_1e-1;

/// ROS34PW2 (Rang and Angermann 2005): L-stable, order 3 with an order-2 embedded solution.
/// Its explicit part (the method with the Jacobian's columns left out) is stable on the
/// imaginary axis up to `h |lambda| = 1.50`.
pub const ROS34PW2: RosenbrockTable = RosenbrockTable {
    gamma: GAMMA_34,
    a: [
        [0.0; S],
        [A21_34, 0.0, 0.0, 0.0],
        [
            8.445_706_001_536_942_3e-1,
            -1.129_906_423_648_418_5e-1,
            0.0,
            0.0,
        ],
        [0.0, 0.0, 1.0, 0.0],
    ],
    g: [
        [GAMMA_34, 0.0, 0.0, 0.0],
        [-A21_34, GAMMA_34, 0.0, 0.0],
        [
            -9.033_805_701_304_408_2e-1,
            5.418_067_238_809_532_6e-2,
            GAMMA_34,
            0.0,
        ],
        [
            2.421_238_070_609_534_6e-1,
            -1.223_250_583_904_514_7,
            5.452_602_553_351_021_4e-1,
            GAMMA_34,
        ],
    ],
    b: [
        2.421_238_070_609_534_6e-1,
        -1.223_250_583_904_514_7,
        1.545_260_255_335_102_0,
        GAMMA_34,
    ],
    b2: [
        3.781_090_314_581_936_9e-1,
        -9.604_229_221_242_317_8e-2,
        0.5,
        2.179_332_607_542_295_0e-1,
    ],
};

/// ROS34PRw (Rang, J. Comput. Appl. Math. 286, 2015, not read; `A`, `Gamma` and `b` are
/// PETSc's `TSROSWR34PRW` table, read): L-stable, order 3, a W-method with the same `gamma`
/// as ROS34PW2. Its explicit part is stable on the imaginary axis up to `h |lambda| = 2.78`,
/// near RK4's 2.83 (test below): the method for a Jacobian that leaves undamped
/// oscillations explicit.
///
/// The embedded weights `b2` are this project's, not the table's. The table's are of order 2
/// only with the exact Jacobian (`sum b2 (alpha + beta) = 1/2`, `beta_i` the row sums of
/// `Gamma`); on components the Jacobian leaves out they are of order 1, so the estimate there
/// scales as `h^2` and overstates the error of an order-3 step by orders of magnitude at small
/// steps (`h omega = 0.05`: 2.7e-4 against ROS34PW2's 7.1e-6). Here `b2 = b - t v` with `v`
/// spanning the weights that meet none of the order-2 conditions of a W-method (`sum v = 0`,
/// `sum v alpha = 0`, `sum v beta = 0`), so the embedded solution has order 2 for any
/// Jacobian, and the scale `t` gives it ROS34PW2's `R2(infinity) = -0.478`. With the exact
/// Jacobian the estimate then equals ROS34PW2's at every `h lambda` (the two methods share
/// `gamma` and the stability function), so the stiff components this method is implicit in
/// are controlled as before; on the components the Jacobian leaves out the estimate is 1.90
/// times ROS34PW2's (tests below). Scaled instead to ROS34PW2's estimate on the explicit
/// part, it was half ROS34PW2's on the stiff part, and the mean cage speed of a 2000 rpm
/// run at 1e-7 moved 1.5e-5 from `rk4_fsal`'s, past issue 34's 1e-5.
pub const ROS34PRW: RosenbrockTable = RosenbrockTable {
    gamma: GAMMA_34,
    a: [
        [0.0; S],
        [A21_34, 0.0, 0.0, 0.0],
        [
            1.472_202_287_943_591_4,
            -3.184_025_056_809_028_9e-1,
            0.0,
            0.0,
        ],
        [
            8.150_519_201_669_493_8e-1,
            0.5,
            -3.150_519_201_669_493_8e-1,
            0.0,
        ],
    ],
    g: [
        [GAMMA_34, 0.0, 0.0, 0.0],
        [-A21_34, GAMMA_34, 0.0, 0.0],
        [
            -1.285_534_738_208_987_2,
            5.050_700_554_155_068_7e-1,
            GAMMA_34,
            0.0,
        ],
        [
            -4.820_144_918_286_434_8e-1,
            2.179_332_607_542_295_0e-1,
            -1.717_852_904_340_450_3e-1,
            GAMMA_34,
        ],
    ],
    b: [
        3.330_374_283_383_059_1e-1,
        7.179_332_607_542_294_7e-1,
        -4.868_372_106_009_943_9e-1,
        GAMMA_34,
    ],
    b2: [
        4.075_259_600_834_746e-1,
        5.320_667_392_457_709e-1,
        -1.575_259_600_834_752_5e-1,
        2.179_332_607_542_298_4e-1,
    ],
};

/// The tableau in transformed variables.
#[derive(Debug, Clone, Copy)]
pub struct Tableau {
    /// The diagonal of Gamma.
    pub gamma: f64,
    /// Stage abscissae, row sums of A.
    pub alpha: [f64; S],
    /// `A Gamma^-1`, strictly lower.
    pub a: [[f64; S]; S],
    /// `diag(1/gamma) - Gamma^-1`, strictly lower.
    pub c: [[f64; S]; S],
    /// `b Gamma^-1`.
    pub m: [f64; S],
    /// `(b - b2) Gamma^-1`: the error estimate's weights.
    pub e: [f64; S],
}

impl Tableau {
    /// ROS34PW2 in transformed variables.
    pub fn ros34pw2() -> Tableau {
        Tableau::new(&ROS34PW2)
    }

    /// ROS34PRw in transformed variables.
    pub fn ros34prw() -> Tableau {
        Tableau::new(&ROS34PRW)
    }

    /// A published table in transformed variables.
    pub fn new(table: &RosenbrockTable) -> Tableau {
        let (gamma, a_pub, g_pub, b_pub, b2_pub) =
            (table.gamma, &table.a, &table.g, &table.b, &table.b2);
        // inverse of the lower-triangular Gamma by forward substitution
        let mut gi = [[0.0; S]; S];
        for col in 0..S {
            for row in col..S {
                let mut v = if row == col { 1.0 } else { 0.0 };
                for k in col..row {
                    v -= g_pub[row][k] * gi[k][col];
                }
                gi[row][col] = v / g_pub[row][row];
            }
        }
        let mut t = Tableau {
            gamma,
            alpha: [0.0; S],
            a: [[0.0; S]; S],
            c: [[0.0; S]; S],
            m: [0.0; S],
            e: [0.0; S],
        };
        for i in 0..S {
            t.alpha[i] = a_pub[i].iter().sum();
            for j in 0..S {
                t.a[i][j] = (0..S).map(|k| a_pub[i][k] * gi[k][j]).sum();
                if j < i {
                    t.c[i][j] = -gi[i][j];
                }
            }
            t.m[i] = (0..S).map(|k| b_pub[k] * gi[k][i]).sum();
            t.e[i] = (0..S).map(|k| (b_pub[k] - b2_pub[k]) * gi[k][i]).sum();
        }
        t
    }
}

/// How far ROS34PRw's explicit part is stable on the imaginary axis, `h |lambda|`
/// (2.783 measured by `the_explicit_part_of_ros34prw_is_stable_on_the_imaginary_axis_as_far_as_rk4`,
/// rounded down): a mode faster than this for the step has to be in the Jacobian. Off the
/// axis the region's edge may come a little closer (a review computed about 2.74 near
/// 123 degrees; not tested here).
pub const ROS34PRW_EXPLICIT_STABILITY: f64 = 2.78;

#[cfg(test)]
mod tests {
    use super::*;

    /// `R(i y)` of the method's explicit part (the Jacobian's columns left out, so each stage
    /// is `k_i = h f(y + sum_j a_ij k_j)`): `R(z) = 1 + z b^T (I - z A)^-1 1`, with `A`
    /// strictly lower, by forward substitution in complex arithmetic. Returns (re, im).
    fn explicit_r(t: &RosenbrockTable, y: f64) -> (f64, f64) {
        // v = (I - z A)^-1 1: v_i = 1 + z sum_j a_ij v_j, z = i y
        let mut v = [(0.0, 0.0); S];
        for i in 0..S {
            let (mut sr, mut si) = (0.0, 0.0);
            for j in 0..i {
                sr += t.a[i][j] * v[j].0;
                si += t.a[i][j] * v[j].1;
            }
            // 1 + i y (sr + i si)
            v[i] = (1.0 - y * si, y * sr);
        }
        let (br, bi) = (0..S).fold((0.0, 0.0), |(r, i), k| {
            (r + t.b[k] * v[k].0, i + t.b[k] * v[k].1)
        });
        (1.0 - y * bi, y * br)
    }

    /// Largest `y` (to 1e-3) up to which `|R(i y)| <= 1`.
    fn imaginary_stability(t: &RosenbrockTable) -> f64 {
        let mut y = 0.0;
        while y < 10.0 {
            let (r, i) = explicit_r(t, y + 1e-3);
            if r.hypot(i) > 1.0 + 1e-12 {
                break;
            }
            y += 1e-3;
        }
        y
    }

    /// `(sum w, sum w alpha, sum w beta)` of weights `w`: 1, 1/2, 0 for order 2 with any
    /// Jacobian (`alpha`, `beta` the row sums of `A` and `Gamma`).
    fn w_order_2(t: &RosenbrockTable, w: &[f64; S]) -> (f64, f64, f64) {
        let alpha: Vec<f64> = t.a.iter().map(|r| r.iter().sum()).collect();
        let beta: Vec<f64> = t.g.iter().map(|r| r.iter().sum()).collect();
        (
            w.iter().sum(),
            (0..S).map(|i| w[i] * alpha[i]).sum(),
            (0..S).map(|i| w[i] * beta[i]).sum(),
        )
    }

    /// Leading coefficient of the estimate on the explicit part, `(b - b2)^T A alpha`.
    fn estimate_constant(t: &RosenbrockTable) -> f64 {
        let alpha: Vec<f64> = t.a.iter().map(|r| r.iter().sum()).collect();
        (0..S)
            .map(|i| (t.b[i] - t.b2[i]) * (0..S).map(|j| t.a[i][j] * alpha[j]).sum::<f64>())
            .sum()
    }

    /// `R2(infinity) = 1 - b2^T (A + Gamma)^-1 1` of the embedded solution.
    fn embedded_r_infinity(t: &RosenbrockTable) -> f64 {
        // (A + Gamma) w = 1, lower triangular
        let mut w = [0.0; S];
        for i in 0..S {
            let s: f64 = (0..i).map(|j| (t.a[i][j] + t.g[i][j]) * w[j]).sum();
            w[i] = (1.0 - s) / t.g[i][i];
        }
        1.0 - (0..S).map(|i| t.b2[i] * w[i]).sum::<f64>()
    }

    #[test]
    fn both_solutions_have_order_2_with_any_jacobian_and_the_estimates_match() {
        for (name, t) in [("ROS34PW2", &ROS34PW2), ("ROS34PRw", &ROS34PRW)] {
            for w in [&t.b, &t.b2] {
                let (s1, sa, sb) = w_order_2(t, w);
                assert!((s1 - 1.0).abs() < 1e-14, "{name}: {s1}");
                assert!((sa - 0.5).abs() < 1e-14, "{name}: {sa}");
                assert!(sb.abs() < 1e-14, "{name}: {sb}");
            }
        }
        // the table's own b2 is not: sum b2 alpha = 0.606, sum b2 beta = -0.106
        let petsc_b2 = [
            2.5e-1,
            7.427_611_960_831_918_0e-1,
            -3.147_292_297_006_621_9e-1,
            3.219_680_336_174_703_4e-1,
        ];
        let (_, sa, sb) = w_order_2(&ROS34PRW, &petsc_b2);
        assert!(
            (sa - 0.606).abs() < 1e-3 && (sb + 0.106).abs() < 1e-3,
            "{sa} {sb}"
        );
        let (r_prw, r_pw2) = (
            embedded_r_infinity(&ROS34PRW),
            embedded_r_infinity(&ROS34PW2),
        );
        assert!((r_pw2 + 0.478).abs() < 1e-3, "{r_pw2}");
        assert!((r_prw - r_pw2).abs() < 1e-13, "{r_prw} against {r_pw2}");
        // with the exact Jacobian, `R(z) - R2(z)` on the negative real axis
        let exact_j_estimate = |t: &RosenbrockTable, z: f64| {
            let mut w = [0.0; S];
            for i in 0..S {
                let s: f64 = (0..i).map(|j| (t.a[i][j] + t.g[i][j]) * w[j]).sum();
                w[i] = (1.0 + z * s) / (1.0 - z * t.g[i][i]);
            }
            z * (0..S).map(|i| (t.b[i] - t.b2[i]) * w[i]).sum::<f64>()
        };
        for z in [-0.01, -1.0, -3.0, -100.0, -1e4] {
            let (e_prw, e_pw2) = (
                exact_j_estimate(&ROS34PRW, z),
                exact_j_estimate(&ROS34PW2, z),
            );
            assert!(
                (e_prw / e_pw2 - 1.0).abs() < 1e-9,
                "z {z}: {e_prw} against {e_pw2}"
            );
        }
        let (c_prw, c_pw2) = (estimate_constant(&ROS34PRW), estimate_constant(&ROS34PW2));
        assert!(
            (c_prw / c_pw2 - 1.898).abs() < 1e-3,
            "{c_prw} against {c_pw2}"
        );
    }

    #[test]
    fn weights_sum_to_one_and_gamma_is_the_diagonal() {
        for t in [&ROS34PW2, &ROS34PRW] {
            assert!((t.b.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!((t.b2.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            for i in 0..S {
                assert_eq!(t.g[i][i], t.gamma);
            }
        }
    }

    /// Why `slip_implicit` takes ROS34PRw: its Jacobian leaves the contact's elastic modes
    /// out, so the explicit part integrates them, and they are lightly damped oscillations
    /// on the imaginary axis. ROS34PRw's explicit part is stable there up to `h omega = 2.78`
    /// (RK4: 2.83), ROS34PW2's up to 1.50 only; at `h omega = 0.5` ROS34PRw loses 3.0e-4 of
    /// an undamped mode's amplitude per step (RK4 1.0e-4, ROS34PW2 4.7e-3).
    #[test]
    fn the_explicit_part_of_ros34prw_is_stable_on_the_imaginary_axis_as_far_as_rk4() {
        let prw = imaginary_stability(&ROS34PRW);
        let pw2 = imaginary_stability(&ROS34PW2);
        assert!((prw - 2.783).abs() < 2e-3, "ROS34PRw: {prw}");
        assert!((pw2 - 1.503).abs() < 2e-3, "ROS34PW2: {pw2}");
        let (r, i) = explicit_r(&ROS34PRW, 0.5);
        let loss = 1.0 - r.hypot(i);
        assert!((loss - 3.0e-4).abs() < 0.1e-4, "{loss}");
    }
}
