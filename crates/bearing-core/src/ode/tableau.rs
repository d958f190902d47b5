//! Explicit Runge-Kutta methods as data: Butcher tableaux with their error estimates.
//!
//! A row of weights is stored over a common denominator, `w_j = num_j / den`, and a stage
//! combination is evaluated as `y + (h / den) * sum_j num_j k_j`: classical RK4's final
//! row is `1/6 (1, 2, 2, 1)`, so `h / 6` multiplies the integer-weighted sum. How that sum
//! is formed is part of the method ([`Sum`]): the tableaux reproduce, bit for bit, the
//! hand-written steppers whose results the project's reference outputs were made with.

/// A row of weights `num_j / den` over the stages `j = 0, 1, ...`.
#[derive(Debug, Clone, Copy)]
pub struct Row {
    pub den: f64,
    pub num: &'static [f64],
}

impl Row {
    /// Weight `j` (0 past the stored entries).
    pub fn weight(&self, j: usize) -> f64 {
        self.num.get(j).map_or(0.0, |n| n / self.den)
    }
}

/// How the weighted sum of a row's stages is formed. Both are the plain sum in stage
/// order; they differ only where IEEE arithmetic can tell them apart: the sign of an
/// all-zero sum, and a zero weight on a non-finite stage (NaN with every entry).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sum {
    /// `0 + num_0 k_0 + num_1 k_1 + ...` over every stored entry.
    EveryEntry,
    /// `num_j k_j + ...` over the nonzero entries only, from the first.
    NonzeroEntries,
}

impl Sum {
    /// The terms `(stage, num)` of `row` this rule adds, in order.
    pub fn terms(self, row: &Row) -> Vec<(usize, f64)> {
        row.num
            .iter()
            .copied()
            .enumerate()
            .filter(|&(_, n)| self == Sum::EveryEntry || n != 0.0)
            .collect()
    }

    /// The value the sum starts from: `-0 + x` is `x` for every `x`, `+0 + x` turns `-0`
    /// into `+0`.
    pub fn start(self) -> f64 {
        match self {
            Sum::EveryEntry => 0.0,
            Sum::NonzeroEntries => -0.0,
        }
    }
}

/// The local error estimate a tableau carries.
#[derive(Debug, Clone, Copy)]
pub enum Estimate {
    /// None: a fixed-step method.
    None,
    /// A second solution with weights `b_hat` (over the same denominator as `b`); the
    /// estimate is `(h / den) * (sum b_hat_j k_j - sum b_j k_j)`.
    Embedded { b_hat: Row, order: u32 },
    /// First same as last: `f(t + h, y_new)` is stage `s` (numbered from 0), evaluated at
    /// the step's end whether or not the step is accepted, and reused as the next step's
    /// first stage; `e` holds the weights `b - b_hat` over stages `0..=s` and the estimate
    /// is `(h / e.den) * sum e_j k_j`.
    Fsal { e: Row, order: u32 },
}

impl Estimate {
    /// The power of `h` the estimate scales as (the local error of the lower-order
    /// solution), for the step-size controller; `None` without an estimate.
    pub fn order(&self) -> Option<u32> {
        match *self {
            Estimate::None => None,
            Estimate::Embedded { order, .. } | Estimate::Fsal { order, .. } => Some(order),
        }
    }
}

/// An explicit Runge-Kutta method of `s = c.len()` stages.
#[derive(Debug, Clone, Copy)]
pub struct ExplicitTableau {
    /// Stage abscissae.
    pub c: &'static [f64],
    /// Stage rows: `a[i]` holds the weights of stages `0..i` for stage `i` (`a[0]` empty).
    pub a: &'static [Row],
    /// Weights of the advanced solution.
    pub b: Row,
    /// Order of the advanced solution.
    pub order: u32,
    pub estimate: Estimate,
    pub sum: Sum,
}

impl ExplicitTableau {
    pub fn stages(&self) -> usize {
        self.c.len()
    }
}

const RK4_C: &[f64] = &[0.0, 0.5, 0.5, 1.0];
const RK4_A: &[Row] = &[
    Row { den: 1.0, num: &[] },
    Row {
        den: 2.0,
        num: &[1.0],
    },
    Row {
        den: 2.0,
        num: &[0.0, 1.0],
    },
    Row {
        den: 1.0,
        num: &[0.0, 0.0, 1.0],
    },
];
const RK4_B: Row = Row {
    den: 6.0,
    num: &[1.0, 2.0, 2.0, 1.0],
};

/// Classical fourth-order Runge-Kutta, without an error estimate.
pub const CLASSICAL_RK4: ExplicitTableau = ExplicitTableau {
    c: RK4_C,
    a: RK4_A,
    b: RK4_B,
    order: 4,
    estimate: Estimate::None,
    sum: Sum::NonzeroEntries,
};

/// Classical RK4 with step-size control from its first-same-as-last stage: the 4th-order
/// solution is advanced, and `f(t + h, y_new)`, which the next step and the dense output
/// need anyway, gives an embedded 3rd-order solution with weights
/// `[1/6, 1/3, 1/3, 0, 1/6]` (the order-3 conditions leave `b4 + b5 = 1/6` free), so the
/// error estimate `h/6 (k4 - k5)` costs no evaluation: 4 per step against Cash-Karp's 6,
/// at the same stability limit (2.83 on the imaginary axis, any 4-stage 4th-order method).
pub const RK4_FSAL: ExplicitTableau = ExplicitTableau {
    estimate: Estimate::Fsal {
        e: Row {
            den: 6.0,
            num: &[0.0, 0.0, 0.0, 1.0, -1.0],
        },
        order: 4,
    },
    ..CLASSICAL_RK4
};

/// The Cash-Karp embedded 4(5) pair (coefficients as in open `rkck` routines, read;
/// Numerical Recipes itself not read),
/// advancing with the 4th-order solution; the difference to the 5th-order one is the
/// local error estimate of the 4th-order solution (`h^5`).
pub const CASH_KARP: ExplicitTableau = ExplicitTableau {
    c: &[0.0, 0.2, 0.3, 0.6, 1.0, 0.875],
    a: &[
        Row { den: 1.0, num: &[] },
        Row {
            den: 1.0,
            num: &[0.2],
        },
        Row {
            den: 1.0,
            num: &[3.0 / 40.0, 9.0 / 40.0],
        },
        Row {
            den: 1.0,
            num: &[0.3, -0.9, 1.2],
        },
        Row {
            den: 1.0,
            num: &[-11.0 / 54.0, 2.5, -70.0 / 27.0, 35.0 / 27.0],
        },
        Row {
            den: 1.0,
            num: &[
                1631.0 / 55296.0,
                175.0 / 512.0,
                575.0 / 13824.0,
                44275.0 / 110592.0,
                253.0 / 4096.0,
            ],
        },
    ],
    b: Row {
        den: 1.0,
        num: &[
            2825.0 / 27648.0,
            0.0,
            18575.0 / 48384.0,
            13525.0 / 55296.0,
            277.0 / 14336.0,
            0.25,
        ],
    },
    order: 4,
    estimate: Estimate::Embedded {
        b_hat: Row {
            den: 1.0,
            num: &[
                37.0 / 378.0,
                0.0,
                250.0 / 621.0,
                125.0 / 594.0,
                0.0,
                512.0 / 1771.0,
            ],
        },
        order: 5,
    },
    sum: Sum::EveryEntry,
};

#[cfg(test)]
mod tests {
    use super::*;

    type Coef<'a> = &'a dyn Fn(usize) -> f64;
    type Matrix<'a> = &'a dyn Fn(usize, usize) -> f64;

    /// Residuals of the order conditions up to `order` (at most 4) of the weights `b`
    /// over `s` stages with abscissae `c` and stage weights `a`: all vanish for a
    /// method of that order.
    fn residuals(c: Coef, a: Matrix, b: Coef, s: usize, order: u32) -> Vec<f64> {
        let sum = |f: &dyn Fn(usize) -> f64| (0..s).map(f).sum::<f64>();
        let ac = |i: usize| (0..i).map(|j| a(i, j) * c(j)).sum::<f64>();
        let ac2 = |i: usize| (0..i).map(|j| a(i, j) * c(j) * c(j)).sum::<f64>();
        let aac = |i: usize| (0..i).map(|j| a(i, j) * ac(j)).sum::<f64>();
        let mut r = vec![sum(&|i| b(i)) - 1.0];
        if order >= 2 {
            r.push(sum(&|i| b(i) * c(i)) - 0.5);
        }
        if order >= 3 {
            r.push(sum(&|i| b(i) * c(i) * c(i)) - 1.0 / 3.0);
            r.push(sum(&|i| b(i) * ac(i)) - 1.0 / 6.0);
        }
        if order >= 4 {
            r.push(sum(&|i| b(i) * c(i).powi(3)) - 0.25);
            r.push(sum(&|i| b(i) * c(i) * ac(i)) - 1.0 / 8.0);
            r.push(sum(&|i| b(i) * ac2(i)) - 1.0 / 12.0);
            r.push(sum(&|i| b(i) * aac(i)) - 1.0 / 24.0);
        }
        r
    }

    /// The data are the published methods: stage rows sum to their abscissae, and each
    /// solution meets the order conditions of its order, to rounding (1e-14; the
    /// conditions of order 5 for Cash-Karp's embedded solution are not checked).
    #[test]
    fn tableaux_meet_their_order_conditions() {
        for t in [CLASSICAL_RK4, RK4_FSAL, CASH_KARP] {
            let s = t.stages();
            assert_eq!(t.a.len(), s);
            for (i, row) in t.a.iter().enumerate() {
                assert!(row.num.len() <= i, "stage {i} uses a later stage");
                let sum: f64 = (0..i).map(|j| row.weight(j)).sum();
                assert!((sum - t.c[i]).abs() < 1e-14, "row {i}: {sum} vs {}", t.c[i]);
            }
            let c = |i: usize| t.c[i];
            let a = |i: usize, j: usize| t.a[i].weight(j);
            let check = |r: Vec<f64>| r.iter().for_each(|v| assert!(v.abs() < 1e-14, "{r:?}"));
            check(residuals(&c, &a, &|j| t.b.weight(j), s, t.order));
            match t.estimate {
                Estimate::None => {}
                Estimate::Embedded { b_hat, order } => {
                    assert_eq!(order, t.order + 1, "estimate of the advanced solution");
                    check(residuals(&c, &a, &|j| b_hat.weight(j), s, 4));
                }
                Estimate::Fsal { e, order } => {
                    // the step-end stage s sits at c = 1 with row b; b_hat = b - e over
                    // the s + 1 stages is a 3rd-order solution, so the estimate is O(h^4)
                    assert_eq!(order, 4);
                    let c1 = |i: usize| if i == s { 1.0 } else { c(i) };
                    let a1 = |i: usize, j: usize| if i == s { t.b.weight(j) } else { a(i, j) };
                    let b_hat = |j: usize| t.b.weight(j) - e.weight(j);
                    check(residuals(&c1, &a1, &b_hat, s + 1, 3));
                }
            }
        }
    }
}
